"""Issue #22 groups 5–8: hangs, crashes (exit 70) and accepted-but-wrong inputs of the CLI; every case
answered by exit 0 or one line ``error: …`` with exit 2."""
from __future__ import annotations

import os
import signal

import pytest
from cli_helpers import assert_one_line_error, run_swatch


@pytest.fixture
def no_hang():
    """Fail (instead of blocking forever) when a command does not return within 60 s."""
    def alarm(signum, frame):
        raise TimeoutError("the command blocked")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(60)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


@pytest.mark.parametrize("args", [["fit", "{fifo}"], ["calibrate", "{fifo}", "--out", "{tmp}/p.toml"],
                                  ["catalog", "build", "{fifo}", "--out", "{tmp}/out"],
                                  ["catalog", "validate", "{fifo}"]])
def test_issue22_a_pipe_is_refused_before_it_is_opened(tmp_path, no_hang, args):
    """Issue #22 group 6: fit, calibrate, catalog build and validate blocked forever on a FIFO."""
    fifo = tmp_path / "input.fifo"
    os.mkfifo(fifo)
    proc = run_swatch(*[a.format(fifo=fifo, tmp=tmp_path) for a in args])
    assert_one_line_error(proc, "pipe", "regular file")
    assert proc.returncode == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["input.fifo"]


def test_issue22_byte_order_mark_is_accepted_in_specs_and_profiles(tmp_path):
    """Issue #22 group 8: a UTF-8 BOM (Windows editors) broke TOML specs and profiles but not CSVs."""
    spec = tmp_path / "bom.toml"
    spec.write_bytes(b'\xef\xbb\xbfname = "BOM"\n[thickness]\nlist_nm = [50, 100]\n')
    proc = run_swatch("catalog", "validate", spec)
    assert proc.returncode == 0, proc.stderr
    profile = tmp_path / "p.toml"
    profile.write_bytes(b'\xef\xbb\xbfname = "bom"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\nnm_per_V = 2.5\n')
    proc = run_swatch("color", "--process", profile, "--voltage", "20")
    assert proc.returncode == 0, proc.stderr
