"""``swatch spec`` says only what the model supports (issue 35): an unreachable target exits 1 with a
plain stamp on the card (or is accepted deliberately), the target's own chip sits beside the nominal's,
one observer per document, and the card says when the voltage is the default preset's."""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess

import colour
import numpy as np
import pytest
from PIL import Image

from tests.cli_helpers import assert_one_line_error, run_json, run_swatch

O10 = "CIE 1964 10 Degree Standard Observer"


@pytest.fixture(autouse=True)
def _poppler():
    if shutil.which("pdftotext") is None or shutil.which("pdftoppm") is None:
        if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
            pytest.fail("poppler-utils missing and SWATCH_REQUIRE_TOOLS=1")
        pytest.skip("pdftotext / pdftoppm (poppler-utils) not installed")


def _text(pdf):
    return subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True).stdout


def _raster(pdf, tmp_path, dpi=60):
    stem = tmp_path / f"r{dpi}"
    subprocess.run(["pdftoppm", "-r", str(dpi), "-png", "-singlefile", str(pdf), str(stem)], check=True)
    return np.asarray(Image.open(f"{stem}.png").convert("RGB")).astype(int)


def _rgb(hex_code):
    return np.array([int(hex_code.lstrip("#")[i:i + 2], 16) for i in (0, 2, 4)])


def _area(img, rgb, tol=2):
    return int(np.all(np.abs(img - rgb) <= tol, axis=-1).sum())


def test_unreachable_target_exits_1_is_stamped_and_accept_closest_makes_it_deliberate(tmp_path):
    out = tmp_path / "s"
    proc = run_swatch("spec", "--hex", "b08d57", "--tolerance", "dE00:2", "--out", out)
    assert proc.returncode == 1 and proc.stderr == ""
    assert "NOT REACHABLE" in proc.stdout and "--accept-closest" in proc.stdout
    spec = json.loads((out / "spec.json").read_text(encoding="utf-8"))
    assert spec["reach"]["within_tolerance"] is False and spec["reach"]["accepted_closest"] is False
    text = _text(out / "spec.pdf")
    assert "TARGET NOT REACHABLE WITHIN THE TOLERANCE" in text and "not the target" in text
    # the stamp is big: its title is set larger than any other text on the card (pdftotext -bbox)
    bbox = subprocess.run(["pdftotext", "-bbox", str(out / "spec.pdf"), "-"], capture_output=True, text=True,
                          check=True).stdout
    heights = {m.group(3): float(m.group(2)) - float(m.group(1)) for m in
               re.finditer(r'yMin="([\d.]+)" xMax="[\d.]+" yMax="([\d.]+)">([^<]+)</word>', bbox)}
    assert heights["REACHABLE"] >= 14 and heights["REACHABLE"] > 1.3 * heights["Nominal"]
    # the raster shows the stamp's red frame and the target's own chip beside the nominal's
    img = _raster(out / "spec.pdf", tmp_path)
    assert _area(img, (192, 0, 0), tol=30) > 1000
    assert _area(img, _rgb("#b08d57")) > 1500  # the target chip (60 pt square ≈ 50 × 50 px at 60 dpi)
    assert _area(img, _rgb(spec["reference"]["srgb_hex"])) > 1500  # the nominal's

    acc = tmp_path / "a"
    proc = run_swatch("spec", "--hex", "b08d57", "--tolerance", "dE00:2", "--accept-closest", "--out", acc)
    assert proc.returncode == 0 and "accepted deliberately" in proc.stdout
    spec_a = json.loads((acc / "spec.json").read_text(encoding="utf-8"))
    assert spec_a["reach"]["accepted_closest"] is True
    text = _text(acc / "spec.pdf")
    assert "CLOSEST COLOUR ACCEPTED" in text and "accepted the closest reachable colour deliberately" in text
    # a reachable target: exit 0, no stamp, --accept-closest changes nothing that is reachable
    ok = tmp_path / "ok"
    proc = run_swatch("spec", "--hex", spec["reference"]["srgb_hex"], "--tolerance", "dE00:2", "--out", ok)
    assert proc.returncode == 0, proc.stdout
    spec_ok = json.loads((ok / "spec.json").read_text(encoding="utf-8"))
    assert spec_ok["reach"]["within_tolerance"] and "REACHABLE" not in _text(ok / "spec.pdf")


def test_one_observer_per_document_and_the_hex_is_brought_into_it(tmp_path):
    out = tmp_path / "s"
    run_swatch("spec", "--hex", "b08d57", "--tolerance", "dE00:2", "--out", out)
    spec = json.loads((out / "spec.json").read_text(encoding="utf-8"))
    col = spec["colorimetry"]
    assert (col["illuminant"], col["observer"]) == ("D65", "10")
    assert spec["reach"]["colorimetry"]["observer"] == "10" and spec["target"]["colorimetry"]["observer"] == "10"
    # the closest colour is the nominal's 45:0 colour (the same 10° number, not a 2° one beside it)
    assert spec["reach"]["closest_Lab"] == pytest.approx(spec["reference"]["Lab"], abs=0.02)
    # and the reach distance is the 10° CIEDE2000 between them (colour-science)
    dE = colour.delta_E(spec["target"]["Lab"], spec["reach"]["closest_Lab"], method="CIE 2000")
    assert spec["reach"]["delta_E"] == pytest.approx(dE, abs=0.02)
    assert spec["target"]["srgb_hex"] == "#b08d57" and "smoothest reflectance" in spec["target"]["conversion"]
    text = _text(out / "spec.pdf")
    assert "Every CIELAB on this card: D65, 10° observer" in text and "2° observer" not in text
    # swatch match --hex states the same target Lab in the same observer: match and spec agree
    m = run_json("match", "--hex", "b08d57", "--top", "1")
    assert m["target_Lab"] == pytest.approx(spec["target"]["Lab"], abs=0.01)
    assert m["candidates"][0]["thickness_nm"] == pytest.approx(spec["nominal"]["thickness_nm"], abs=0.06)


def test_a_lab_targets_chip_is_its_own_colour_and_the_preset_voltage_is_said_in_the_main_text(tmp_path):
    out = tmp_path / "s"
    proc = run_swatch("spec", "--lab", "62,4,30", "--observer", "2", "--tolerance", "dE00:3", "--out", out)
    spec = json.loads((out / "spec.json").read_text(encoding="utf-8"))
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    want = np.round(colour.XYZ_to_sRGB(colour.Lab_to_XYZ([62, 4, 30], white), illuminant=white) * 255)
    assert _rgb(spec["target"]["srgb_hex"]) == pytest.approx(want, abs=1)
    assert "note: the nominal voltage comes from the default preset" in proc.stdout
    assert "swatch calibrate" in proc.stdout
    text = " ".join(_text(out / "spec.pdf").split())
    assert "Voltage not calibrated: the nominal voltage comes from the default preset titanium-fujii2019" in text
    assert "(swatch calibrate)" in text


def test_a_calibrated_line_says_so_and_the_rate_given_is_not_called_calibrated(tmp_path):
    coupons = os.path.join(os.path.dirname(__file__), "..", "data", "simulated-line-coupons.csv")
    assert run_swatch("calibrate", coupons, "--out", tmp_path / "line.toml").returncode == 0
    proc = run_swatch("spec", "--thickness", "60", "--process", tmp_path / "line.toml", "--out", tmp_path / "c")
    spec = json.loads((tmp_path / "c" / "spec.json").read_text(encoding="utf-8"))
    assert spec["nominal"]["voltage"]["basis"] == "calibrated" and "note:" not in proc.stdout
    assert "Voltage not calibrated" not in _text(tmp_path / "c" / "spec.pdf")
    proc = run_swatch("spec", "--thickness", "60", "--nm-per-volt", "2.5", "--out", tmp_path / "g")
    spec = json.loads((tmp_path / "g" / "spec.json").read_text(encoding="utf-8"))
    assert spec["nominal"]["voltage"]["basis"] == "given" and "note:" in proc.stdout


@pytest.mark.parametrize("args", [["--hex", "zz0000"], ["--lab", "50,1"], ["--thickness", "-5"],
                                  ["--thickness", "50", "--accept-closest"], ["--hex", "b08d57", "--tolerance", "x"]])
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, args):
    proc = run_swatch("spec", *args, "--out", tmp_path / "s")
    assert proc.returncode == 2
    assert_one_line_error(proc)
    assert not (tmp_path / "s").exists()
