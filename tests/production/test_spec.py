"""``swatch spec`` (issue 20): spec.json and the one-page PDF spec card."""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess

import colour
import numpy as np
import pytest

from tests.cli_helpers import assert_one_line_error, run_json, run_swatch
from tests.synthetic import tmm_half_vector_reflectance


@pytest.fixture(autouse=True)
def _poppler():
    """pdftotext / pdfinfo (poppler-utils) read the card: skip without them, fail in CI (SWATCH_REQUIRE_TOOLS=1)."""
    if shutil.which("pdftotext") is None or shutil.which("pdfinfo") is None:
        if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
            pytest.fail("pdftotext is missing and SWATCH_REQUIRE_TOOLS=1 (.ci/run installs poppler-utils)")
        pytest.skip("pdftotext (poppler-utils) not installed")


def _numbers(obj):
    if isinstance(obj, bool) or obj is None:
        return
    if isinstance(obj, (int, float)):
        yield obj
    elif isinstance(obj, dict):
        for v in obj.values():
            yield from _numbers(v)
    elif isinstance(obj, list):
        for v in obj:
            yield from _numbers(v)


@pytest.fixture(scope="module")
def bronze(tmp_path_factory):
    out = tmp_path_factory.mktemp("spec")
    proc = run_swatch("spec", "--hex", "b08d57", "--tolerance", "dE00:2", "--out", out)
    assert proc.returncode == 1, proc.stderr  # out of reach (issue 35): written, stamped, exit 1
    return out, json.loads((out / "spec.json").read_text(encoding="utf-8"))


def test_pdf_card_shows_every_number_of_spec_json(bronze):
    out, spec = bronze
    text = subprocess.run(["pdftotext", "-layout", str(out / "spec.pdf"), "-"], capture_output=True, text=True,
                          check=True).stdout
    missing = [v for v in _numbers(spec) if str(v) not in text]
    assert not missing, missing
    info = subprocess.run(["pdfinfo", str(out / "spec.pdf")], capture_output=True, text=True, check=True).stdout
    assert re.search(r"^Pages:\s+1$", info, re.MULTILINE), info
    assert "not approval standards" in text and "Sign-off" in text


def test_unreachable_target_reports_the_closest_colour_and_how_far(bronze):
    _, spec = bronze
    r = spec["reach"]
    assert r["metric"] == "dE00" and r["within_tolerance"] is False and r["delta_E"] > 2
    assert r["closest_thickness_nm"] == spec["nominal"]["thickness_nm"]


def test_multi_angle_and_flop_agree_with_tmm_and_colour_science(tmp_path):
    """The flop (view 0° vs 60°, light 45°) and the 45as15 Lab by tmm + colour.sd_to_XYZ, not our code."""
    assert run_swatch("spec", "--thickness", "120", "--out", tmp_path).returncode == 0
    spec = json.loads((tmp_path / "spec.json").read_text(encoding="utf-8"))
    wl = np.arange(380.0, 781.0, 5.0)
    cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
    white = colour.CCS_ILLUMINANTS["CIE 1964 10 Degree Standard Observer"]["D65"]

    def lab(view):
        R = tmm_half_vector_reflectance(120.0, [45.0], [view], wl)[0]
        sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
        return colour.XYZ_to_Lab(colour.sd_to_XYZ(sd, cmfs, colour.SDS_ILLUMINANTS["D65"]) / 100, white)

    assert spec["flop"]["delta_E_00"] == pytest.approx(colour.delta_E(lab(0.0), lab(60.0), method="CIE 2000"),
                                                       abs=0.02)
    as15 = next(e for e in spec["multi_angle"] if e["geometry"] == "45as15")
    assert as15["view_deg"] == 30.0
    np.testing.assert_allclose(as15["Lab"], lab(30.0), atol=0.02)
    assert {k: spec["nominal"][k] for k in ("thickness_nm", "voltage_V")} == {"thickness_nm": 120.0, "voltage_V": 59.1}
    assert spec["nominal"]["voltage"]["basis"] == "preset" and not spec["nominal"]["voltage"]["calibrated"]
    assert spec["reach"] is None


def test_spec_rerun_is_byte_identical_and_refuses_to_overwrite(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    for d in (a, b):
        assert run_swatch("spec", "--voltage", "25", "--out", d).returncode == 0
    assert (a / "spec.pdf").read_bytes() == (b / "spec.pdf").read_bytes()
    assert (a / "spec.json").read_bytes() == (b / "spec.json").read_bytes()
    assert_one_line_error(run_swatch("spec", "--voltage", "25", "--out", a), "--force")
    assert run_swatch("spec", "--voltage", "25", "--out", a, "--force").returncode == 0


def test_spec_needs_exactly_one_target(tmp_path):
    assert_one_line_error(run_swatch("spec", "--out", tmp_path), "exactly one of --hex")
    assert_one_line_error(run_swatch("spec", "--hex", "ffffff", "--thickness", "50", "--out", tmp_path),
                          "exactly one")
    assert not any(tmp_path.iterdir())


def test_spec_with_angles_picks_the_best_worst_case_and_prints_it(tmp_path):
    """ "A bronze-gold close to #b08d57 that still reads gold at 60°": the nominal is the multi-angle
    match's minimax over 45:0 and 45:60, and the card shows every number (per angle too)."""
    proc = run_swatch("spec", "--hex", "b08d57", "--angles", "45:0,45:60", "--out", tmp_path)
    assert proc.returncode == 1, proc.stderr  # out of reach within dE00 2 at both angles
    spec = json.loads((tmp_path / "spec.json").read_text(encoding="utf-8"))
    m = run_json("match", "--hex", "b08d57", "--angles", "45:0,45:60", "--tolerance", "dE00:2")
    assert spec["nominal"]["thickness_nm"] == pytest.approx(m["candidates"][0]["thickness_nm"], abs=0.06)
    assert set(spec["reach"]["delta_E_per_geometry"]) == {"45:0", "45:60"}
    text = subprocess.run(["pdftotext", "-layout", str(tmp_path / "spec.pdf"), "-"], capture_output=True, text=True,
                          check=True).stdout
    assert not [v for v in _numbers(spec) if str(v) not in text]
    assert_one_line_error(run_swatch("spec", "--thickness", "50", "--angles", "45:0", "--out", tmp_path / "x"),
                          "colour target")
