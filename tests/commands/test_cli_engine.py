"""The engine commands' public contract: names, JSON keys, errors."""
from __future__ import annotations

import json

import numpy as np
import pytest

from swatch.physics.growth import DEFAULT_NM_PER_V
from tests.cli_helpers import assert_one_line_error, run_json, run_swatch, run_swatch_process


def test_color_json_contract_and_blue_sample():
    out = run_json("color", "--thickness", "20:300:1")
    assert {"illuminant", "observer", "film", "substrate", "rows"} <= set(out)
    assert out["illuminant"] == "D65" and out["observer"] == "10"
    assert out["film"] == "TiO2-Siefke" and out["substrate"] == "Ti-Johnson"
    rows = out["rows"]
    assert len(rows) == 281
    keys = {"thickness_nm", "XYZ", "Lab", "LCh", "srgb_hex", "in_srgb_gamut", "delta_E_ab_to_previous"}
    assert all(keys <= set(r) for r in rows)
    assert rows[0]["delta_E_ab_to_previous"] is None
    dE = np.linalg.norm(np.subtract(rows[1]["Lab"], rows[0]["Lab"]))
    assert rows[1]["delta_E_ab_to_previous"] == pytest.approx(dE)


def test_paper_blue_sample_is_blue():
    """The paper's blue sample (Fig. 3, 25 V) is estimated at 50.8 nm: it must come out blue."""
    row = run_json("color", "--thickness", "50.8")["rows"][0]
    _L, C, h = row["LCh"]
    assert 220.0 <= h <= 290.0 and C > 20.0, row
    r, g, b = (int(row["srgb_hex"][i : i + 2], 16) for i in (1, 3, 5))
    assert b > r and b > g


def test_voltage_uses_growth_rate():
    by_v = run_json("color", "--voltage", "25")["rows"][0]
    assert by_v["thickness_nm"] == pytest.approx(25 * DEFAULT_NM_PER_V)
    assert by_v["thickness_nm"] == pytest.approx(50.8)
    assert by_v["voltage_V"] == 25
    other = run_json("color", "--voltage", "10,20", "--nm-per-volt", "1.5")["rows"]
    assert [r["thickness_nm"] for r in other] == pytest.approx([15.0, 30.0])


def test_spectrum_json_contract():
    out = run_json("spectrum", "--thickness", "50", "--light", "10", "--view", "45")
    assert out["theta_d_deg"] == pytest.approx(27.5)
    for key in ("thickness_nm", "film", "substrate", "wavelength_nm", "reflectance", "reflectance_s", "reflectance_p"):
        assert key in out
    R = np.array(out["reflectance"])
    assert np.allclose(R, 0.5 * (np.array(out["reflectance_s"]) + np.array(out["reflectance_p"])))
    assert len(R) == len(out["wavelength_nm"]) == 81


def test_spectrum_azimuths_change_theta_d():
    out = run_json("spectrum", "--thickness", "50", "--light", "40", "--view", "40",
                   "--light-azimuth", "0", "--view-azimuth", "90")
    assert out["theta_d_deg"] == pytest.approx(0.5 * np.degrees(np.arccos(np.cos(np.radians(40)) ** 2)))


def test_color_with_overcoat_reports_it_and_changes_the_colour():
    bare = run_json("color", "--thickness", "50.8")["rows"][0]["Lab"]
    out = run_json("color", "--thickness", "50.8", "--overcoat", "1.5:200")
    assert out["overcoat"] == [{"layer": "n=1.5", "thickness_nm": 200.0}]
    assert np.linalg.norm(np.subtract(out["rows"][0]["Lab"], bare)) > 1.0


def test_materials_list_and_show():
    mats = run_json("materials", "list")
    names = {m["name"] for m in mats}
    assert {"Ti-Johnson", "TiO2-Siefke"} <= names
    show = run_json("materials", "show", "TiO2-Siefke")
    assert {"wavelength_nm", "n", "k", "source"} <= set(show)
    assert 2.3 < np.interp(550, show["wavelength_nm"], show["n"]) < 2.5


def test_roughness_paper_sample_is_rough():
    out = run_json("roughness", "--ra", "268")
    assert out["h_min_nm"] == pytest.approx(47.5)
    assert out["h_max_nm"] == pytest.approx(195.0)
    assert out["verdict"] == "rough"
    assert run_json("roughness", "--ra", "10")["verdict"] == "smooth"


def test_help_lists_every_command():
    proc = run_swatch("--help")
    assert proc.returncode == 0
    for name in ("spectrum", "color", "materials", "roughness", "angular", "render", "catalog", "fit", "match"):
        assert name in proc.stdout


@pytest.mark.parametrize(
    "args, fragments",
    [
        (["color", "--thickness", "-5"], ["thickness"]),
        (["color", "--thickness", "nan"], ["finite"]),
        (["color", "--thickness", "1e9"], ["thickness"]),
        (["color", "--thickness", "300:20:1"], ["reversed"]),
        (["color", "--thickness", "20:300:0"], ["step"]),
        (["color", "--thickness", ""], ["empty"]),
        (["color", "--thickness", "abc"], ["not a number"]),
        (["color", "--thickness", "50", "--light", "90"], ["[0, 90)"]),
        (["color", "--thickness", "50", "--view", "-1"], ["[0, 90)"]),
        (["color", "--thickness", "50", "--film", "unobtainium"], ["unknown material"]),
        (["color", "--thickness", "50", "--illuminant", "D66"], ["unknown illuminant"]),
        (["color", "--thickness", "50", "--wavelengths", "200:780:5"], ["outside"]),
        (["color", "--thickness", "50", "--voltage", "20"], ["exactly one"]),
        (["color"], ["exactly one"]),
        (["color", "--voltage", "-3"], ["voltage"]),
        (["spectrum", "--thickness", "10:20:5"], ["one thickness"]),
        (["materials", "show", "nope"], ["unknown material"]),
        (["roughness", "--ra", "-1"], ["--ra"]),
        (["color", "--bogus"], ["no such option"]),
        (["colr"], ["no such command"]),
        (["color", "--thickness", "50", "--light-azimuth", "nan"], ["--light-azimuth", "finite"]),
        (["spectrum", "--thickness", "50", "--view-azimuth", "inf", "--json"], ["--view-azimuth", "finite"]),
        (["color", "--thickness", "50", "--film", "Ti-Johnson"], ["substrate table"]),
        (["color", "--thickness", "50", "--substrate", "TiO2-Siefke"], ["film table"]),
        (["render", "--thickness", "50", "--out", ""], ["empty"]),
    ],
)
def test_bad_input_is_one_line_error(args, fragments):
    proc = run_swatch(*args)
    assert_one_line_error(proc, *fragments)
    assert proc.returncode == 2


def test_the_process_itself():
    # The other tests call the entry point in-process; here the real `python -m swatch.cli`.
    bad = run_swatch_process("color", "--thickness", "-5")
    assert_one_line_error(bad, "thickness")
    assert bad.returncode == 2
    ok = run_swatch_process("color", "--thickness", "50", "--json")
    assert ok.returncode == 0, ok.stderr
    assert ok.stderr == ""
    assert [r["thickness_nm"] for r in json.loads(ok.stdout)["rows"]] == [50.0]
