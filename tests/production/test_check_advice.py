"""``swatch check`` says only what the measurement and the model support (issue 35).

Parts made by tmm + colour-science (not our code) at known thickness offsets get a voltage correction
of −offset / growth rate in words; a part whose colour no thickness gives gets "not a thickness error"
and no correction, in text, JSON and the report; a part's chip is its own colour, checked against
colour-science's CIELAB → sRGB."""
from __future__ import annotations

import json

import colour
import numpy as np
import pytest
from PIL import Image

from tests.cli_helpers import assert_one_line_error, run_swatch
from tests.synthetic import tmm_half_vector_reflectance

O2, O10 = "CIE 1931 2 Degree Standard Observer", "CIE 1964 10 Degree Standard Observer"
RATE = 50.8 / 25.0  # the default profile's nm/V (Fujii et al. 2019)


def _lab(d, observer=O10):
    wl = np.arange(380.0, 781.0, 5.0)
    R = tmm_half_vector_reflectance(d, [45.0], [0.0], wl)[0]
    sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
    XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[observer], colour.SDS_ILLUMINANTS["D65"]) / 100
    return colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS[observer]["D65"])


def _csv(path, rows):
    path.write_text("id,light_deg,view_deg,L,a,b\n" + "".join(
        f"{k},45,0,{L:.4f},{a:.4f},{b:.4f}\n" for k, (L, a, b) in rows.items()), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def gold(tmp_path_factory):
    out = tmp_path_factory.mktemp("gold") / "s"
    assert run_swatch("spec", "--thickness", "22.2", "--tolerance", "dE00:2", "--out", out).returncode == 0
    return out / "spec.json"


def test_offset_parts_get_minus_offset_over_rate_in_words_and_a_foreign_colour_gets_none(tmp_path, gold):
    offsets = {"thin": -1.5, "thick": 2.5, "on": 0.0}
    rows = {k: _lab(22.2 + off) for k, off in offsets.items()}
    rows["wrong-alloy"] = (55.0, 12.0, 30.0)  # issue 35: a colour the model's gold does not give at any thickness
    rows["far"] = (40.0, -20.0, -30.0)
    parts = _csv(tmp_path / "parts.csv", rows)
    proc = run_swatch("check", parts, "--spec", gold, "--json", "--report", tmp_path / "qc")
    doc = json.loads(proc.stdout)
    got = {r["id"]: r for r in doc["measurements"]}
    for k, off in offsets.items():
        r = got[k]
        assert r["thickness_explains"] and r["max_residual_delta_E"] < 0.3
        if off:  # both outside the gold's window (-1.1 / +1.0 nm): they fail and get the correction
            assert not r["pass"] and r["action"] == "correct" and r["voltage_correction_reason"] is None
            assert r["voltage_correction_V"] == pytest.approx(-off / RATE, abs=0.2)
            assert r["voltage_advice"] == f"{'raise' if off < 0 else 'lower'} the voltage by {abs(off) / RATE:.1f} V"
        else:  # on the nominal: no nudge
            assert r["pass"] and r["action"] == "none" and r["voltage_correction_V"] is None
            assert r["voltage_advice"] is None and r["voltage_correction_reason"].startswith("no action")
    for k in ("wrong-alloy", "far"):
        r = got[k]
        assert r["voltage_correction_V"] is None and r["voltage_advice"] is None and not r["thickness_explains"]
        assert r["voltage_correction_reason"].startswith("not a thickness error")
        # the residual is the tolerance's metric between the part and the model at the fitted thickness
        assert r["max_residual_delta_E"] > 2.0
    assert got["wrong-alloy"]["max_residual_delta_E"] == pytest.approx(8.2, abs=0.3)  # the figure
    assert json.loads((tmp_path / "qc" / "check.json").read_text(encoding="utf-8")) == doc
    # the spec's voltage is the default preset's: said before any correction is read
    assert any("not a calibrated line" in n for n in doc["notes"])
    text = run_swatch("check", parts, "--spec", gold)
    assert text.returncode == 1
    lines = {ln.split(":")[0]: ln for ln in text.stdout.splitlines()}
    assert "not a thickness error" in lines["wrong-alloy"] and " V" not in lines["wrong-alloy"].split("residual")[1]
    assert f"lower the voltage by {2.5 / RATE:.1f} V" in lines["thick"]
    assert f"raise the voltage by {1.5 / RATE:.1f} V" in lines["thin"]


def test_a_lab_only_parts_chip_is_its_own_colour_by_colour_science(tmp_path):
    """Spec and parts under D65 / 2°: the chip is colour-science's CIELAB → sRGB of the part's own Lab."""
    assert run_swatch("spec", "--thickness", "22.2", "--observer", "2", "--out", tmp_path / "s").returncode == 0
    Lab = (55.0, 12.0, 30.0)
    parts = tmp_path / "p.cgats"
    parts.write_text("CGATS.17\nILLUMINANT\t\"D65\"\nOBSERVER\t\"2\"\nNUMBER_OF_FIELDS 4\nBEGIN_DATA_FORMAT\n"
                     "SAMPLE_ID LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\nNUMBER_OF_SETS 1\nBEGIN_DATA\n"
                     f"red {Lab[0]} {Lab[1]} {Lab[2]}\nEND_DATA\n", encoding="utf-8")
    proc = run_swatch("check", parts, "--spec", tmp_path / "s" / "spec.json", "--json", "--report", tmp_path / "qc")
    assert proc.returncode == 1, proc.stderr
    r = json.loads(proc.stdout)["measurements"][0]
    white = colour.CCS_ILLUMINANTS[O2]["D65"]
    want = colour.XYZ_to_sRGB(colour.Lab_to_XYZ(Lab, white), illuminant=white)
    got = np.array([int(r["srgb_hex"]["45:0"][i:i + 2], 16) for i in (1, 3, 5)])
    assert got == pytest.approx(np.round(want * 255), abs=1)
    assert r["srgb_in_gamut"]["45:0"] and r["srgb_from"].startswith("measured CIELAB")
    # not the model's colour at the fitted thickness (what the report used to show for it)
    spec = json.loads((tmp_path / "s" / "spec.json").read_text(encoding="utf-8"))
    assert np.abs(got - [int(spec["reference"]["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5)]).max() > 8
    # the report: the part's chip is drawn, and only the measured geometry (45:0) gets a column
    img = np.asarray(Image.open(tmp_path / "qc" / "check.png").convert("RGB")).reshape(-1, 3)
    colours = {tuple(c) for c in np.unique(img, axis=0)}
    assert tuple(got) in colours
    assert tuple(int(spec["reference"]["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5)) in colours
    for e in spec["multi_angle"]:
        if e["srgb_hex"] != spec["reference"]["srgb_hex"]:
            assert tuple(int(e["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5)) not in colours, e["geometry"]


def test_a_part_outside_srgb_is_marked_and_bad_input_writes_nothing(tmp_path, gold):
    parts = _csv(tmp_path / "p.csv", {"vivid": (50.0, -80.0, 60.0)})
    r = json.loads(run_swatch("check", parts, "--spec", gold, "--json").stdout)["measurements"][0]
    assert r["srgb_in_gamut"] == {"45:0": False} and r["voltage_correction_V"] is None
    bad = tmp_path / "bad.csv"
    bad.write_text("id,light_deg,view_deg,L,a,b\nx,45,0,55,12\n", encoding="utf-8")
    assert_one_line_error(run_swatch("check", bad, "--spec", gold, "--report", tmp_path / "qc"))
    assert not (tmp_path / "qc").exists() or not any((tmp_path / "qc").iterdir())


def test_a_check_against_an_out_of_reach_spec_says_what_the_parts_are_judged_against(tmp_path):
    for flag, word in (("", "was NOT accepted"), ("--accept-closest", "was accepted deliberately")):
        out = tmp_path / (flag or "plain")
        args = ["spec", "--hex", "b08d57", "--out", out] + ([flag] if flag else [])
        assert run_swatch(*args).returncode == (0 if flag else 1)
        spec = json.loads((out / "spec.json").read_text(encoding="utf-8"))
        parts = _csv(tmp_path / "p.csv", {"p": spec["reference"]["Lab"]})
        proc = run_swatch("check", parts, "--spec", out / "spec.json")
        assert proc.returncode == 0  # the part is the spec's (closest) colour
        note = next(ln for ln in proc.stdout.splitlines() if ln.startswith("note: the spec's target"))
        assert word in note and f"dE00 {spec['reach']['delta_E']:g}" in note and "not the target" in note
