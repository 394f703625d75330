"""The shipped outputs are what the code makes today from the shipped inputs (issue 45).

``examples/line.toml`` is the profile ``swatch calibrate examples/coupons.csv`` writes now, byte for byte
(the guides' voltages are computed from it); the guides' quoted output lines are checked in
tests/test_docs_commands.py and the pictures in tests/test_docs_pictures.py. Remake all three with
``python scripts/make_examples.py --outputs``.
"""
from __future__ import annotations

from pathlib import Path

from tests.cli_helpers import run_swatch

ROOT = Path(__file__).resolve().parents[1]


def test_the_example_line_profile_is_what_calibrate_writes_today(tmp_path):
    out = tmp_path / "examples" / "line.toml"
    out.parent.mkdir()
    (tmp_path / "examples" / "coupons.csv").write_bytes((ROOT / "examples" / "coupons.csv").read_bytes())
    proc = run_swatch("calibrate", "examples/coupons.csv", "--out", "examples/line.toml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert out.read_text(encoding="utf-8") == (ROOT / "examples" / "line.toml").read_text(encoding="utf-8"), (
        "examples/line.toml is stale: run `python scripts/make_examples.py --outputs`")
