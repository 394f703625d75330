"""Issue #22 groups 5–8: hangs, crashes (exit 70) and accepted-but-wrong inputs of the CLI; every case
answered by exit 0 or one line ``error: …`` with exit 2."""
from __future__ import annotations

import os
import signal

import pytest

from tests.cli_helpers import assert_one_line_error, run_swatch


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


@pytest.mark.parametrize("args, fragments", [
    (["color", "--thickness", "50", "--wavelengths", "380.5:780.5:5"], ["multiple of the 5 nm step", "380:780:5"]),
    (["color", "--thickness", "50", "--wavelengths", "382:782:5"], ["multiple of the 5 nm step"]),
    (["render", "--thickness", "50", "--size", "1", "--out", "{tmp}/r"], ["at least 8 pixels"]),
    (["render", "--thickness", "50", "--size", "4", "--out", "{tmp}/r"], ["at least 8 pixels"]),
    (["angular", "--thickness", "50", "--roughness", "1e-300", "--out", "{tmp}/a"], ["from 0.001 to 1"]),
    (["render", "--thickness", "50", "--roughness", "1e-300", "--out", "{tmp}/r"], ["from 0.001 to 1"]),
    (["fit", "examples/blue_sbrdf_percent.csv", "--percent", "--fraction"], ["--percent or --fraction, not both"]),
])
def test_issue22_inputs_that_crashed_or_were_ambiguous_get_one_line(tmp_path, args, fragments):
    """Issue #22 groups 5 and 7: an off-grid wavelength grid, a 1–4 px render, roughness 1e-300 (exit 70), and
    --percent --fraction together (the last silently won) are refused in one line, nothing written."""
    proc = run_swatch(*[a.replace("{tmp}", str(tmp_path)) for a in args])
    assert_one_line_error(proc, *fragments)
    assert proc.returncode == 2
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, fragments", [
    (["color", "--thickness", "50", "--process", ""], ["--process is an empty string"]),
    (["catalog", "build", "catalog/titanium.toml", "--out", ""], ["--out is an empty string"]),
    (["preset", "--thickness", "50", "--format", "gltf", "--out", ""], ["--out is an empty string"]),
    (["color", "--thickness", "50", *["--overcoat", "1.5:100"] * 11], ["at most 10"]),
    (["color", "--thickness", "50", "--overcoat", "1.5:600", "--overcoat", "1.5:500"], ["1100 nm", "1000 nm in all"]),
])
def test_issue22_empty_names_and_overcoat_stacks_are_refused(args, fragments):
    """Issue #22 group 7: '' silently took the default (or the current folder); eleven 100 nm overcoats passed."""
    proc = run_swatch(*args)
    assert_one_line_error(proc, *fragments)
    assert proc.returncode == 2


@pytest.mark.parametrize("name", ["", "two\nlines", "esc\x1b[31m", "x" * 100_000])
def test_issue22_calibrate_name_is_checked_as_a_profile_reads_it(tmp_path, name):
    """Issue #22 group 7: a --name with a newline, ESC or 100k characters wrote a profile --process then refused."""
    coupons = tmp_path / "c.csv"
    coupons.write_text("voltage_V,L,a,b\n10,60,5,30\n20,40,10,-40\n30,50,-20,-10\n", encoding="utf-8")
    proc = run_swatch("calibrate", coupons, "--out", tmp_path / "p.toml", "--name", name)
    assert_one_line_error(proc, "--name", "1 to 80 characters")
    assert proc.returncode == 2 and not (tmp_path / "p.toml").exists()
    assert len(proc.stderr) < 400


@pytest.mark.parametrize("bad", [["--film", "nope"], ["--substrate", "nope"], ["--roughness", "nan"]])
def test_issue22_preset_with_bad_input_creates_no_folder(tmp_path, bad):
    """Issue #22 group 8: a failing preset created --out first."""
    proc = run_swatch("preset", "--thickness", "50", "--format", "gltf", "--out", tmp_path / "new", *bad)
    assert_one_line_error(proc)
    assert proc.returncode == 2 and not (tmp_path / "new").exists()


def test_issue22_errors_quote_huge_input_cut_and_control_characters_escaped():
    """Issue #22 group 8: a 100 KB --illuminant gave a 100 KB line; what is allowed is still said."""
    proc = run_swatch("color", "--thickness", "50", "--illuminant", "X" * 100_000)
    assert_one_line_error(proc, "unknown illuminant", "characters]", "D65")
    assert len(proc.stderr) < 4200
    proc = run_swatch("color", "--thickness", "50", "--illuminant", "a\x1b[2Jb")
    assert "\x1b" not in proc.stderr and "\\x1b" in proc.stderr


def test_issue22_huge_wavelengths_are_not_reported_as_duplicates(tmp_path):
    """Issue #22 group 8: 1e300 and 2e300 nm were 'the same wavelength twice' (the rounding overflowed)."""
    p = tmp_path / "huge.csv"
    p.write_text("wavelength_nm,reflectance\n1e300,0.1\n2e300,0.2\n3e300,0.1\n", encoding="utf-8")
    proc = run_swatch("fit", p)
    assert_one_line_error(proc, "line 2: wavelength_nm: 1e+300 nm is outside the measured range")
    assert "twice" not in proc.stderr


def test_issue22_all_black_coupon_spectra_are_refused(tmp_path):
    """Issue #22 group 7: all-black spectra calibrated to 0.17 ± 5.6 nm/V (ΔE 32) and wrote a profile."""
    rows = "".join(f"{v},{w},0\n" for v in (10, 20, 30) for w in range(380, 781, 10))
    path = tmp_path / "black.csv"
    path.write_text("voltage_V,wavelength_nm,reflectance\n" + rows, encoding="utf-8")
    proc = run_swatch("calibrate", path, "--out", tmp_path / "p.toml")
    assert_one_line_error(proc, "implausibly dark", "at least")
    assert proc.returncode == 2 and not (tmp_path / "p.toml").exists()


def test_issue22_an_error_while_stopping_is_reported_as_the_stop(monkeypatch):
    """Issue #22 group 5: a pool broken by the signal that stops a build was exit 70 ("initialization failed")."""
    from swatch.core import procguard

    monkeypatch.setattr(procguard, "_RECEIVED", [])

    def broken(*a, **k):  # (the SIGTERM comes during the run: issue 38 counts a run's own signals only)
        procguard._RECEIVED.append(15)
        raise RuntimeError("A process in the process pool was terminated abruptly")

    monkeypatch.setattr("swatch.cli.cli.main", broken)
    proc = run_swatch("color", "--thickness", "50")
    assert_one_line_error(proc, "terminated")
    assert proc.returncode == 128 + 15
