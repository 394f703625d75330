"""Thickness spread (issue 19): the reflectance averaged over a normal distribution of local thickness.

The reference is independent of the code under test: ``tmm.coh_tmm`` at the nodes of a Gauss–Legendre
rule (scipy) over the same distribution (censored at 0: the mass below 0 is bare metal), the colour by
``colour.sd_to_XYZ`` and ``colour.XYZ_to_Lab``, compared in CIEDE2000 (D65, CIE 1964 10°).
"""
from __future__ import annotations

import math
import warnings

import colour
import numpy as np
import pytest
from scipy.special import roots_legendre

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.core.errors import SwatchError
from swatch.physics import optics
from swatch.physics.model import get_coating
from swatch.physics.overcoat import OvercoatedCoating, overcoat
from swatch.physics.process import load_process, process_toml
from swatch.physics.spread import NO_SPREAD, ThicknessSpread, parse_spread, spread_sigma_nm
from tests.tmm_reference import unpolarised_R


def _reference_R(coating, mean_nm: float, sigma_nm: float, angle_deg: float, nodes: int = 48) -> np.ndarray:
    """Unpolarised R (W,) averaged over Normal(mean, sigma) censored at 0, by tmm at the nodes of a
    Gauss–Legendre rule (scipy) over mean ± 7 sigma (cut at 0)."""
    wl = coating.wavelength_nm
    th = math.radians(angle_deg)

    def R_at(t: float) -> np.ndarray:
        return unpolarised_R([1.0, coating.n_film, coating.n_substrate], [np.inf, t, np.inf], th, wl)

    # R(t) is analytic in t and varies on the scale of 10 nm over a range of at most 14 sigma (≤ 130 nm
    # here): 48 Gauss–Legendre nodes (exact for polynomials of degree 95; a rule unlike the library's
    # Gauss–Hermite one) integrate it far below the 2e-4 tolerance. Issue 17 item 7: this replaced a
    # 0.1 nm Riemann sum over tmm sampled every 0.5 nm (3–5× the tmm calls, 4–6 s CPU a case), whose own
    # error was ≤ 6e-5 in R; the model agrees with this rule to ≤ 1.4e-5 (measured, the four cases).
    lo, hi = max(mean_nm - 7.0 * sigma_nm, 0.0), mean_nm + 7.0 * sigma_nm
    x, w = roots_legendre(nodes)
    ts = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)
    weights = 0.5 * (hi - lo) * w * np.exp(-0.5 * ((ts - mean_nm) / sigma_nm) ** 2) / (sigma_nm * math.sqrt(2.0 * math.pi))
    below = 0.5 * math.erfc(mean_nm / (sigma_nm * math.sqrt(2.0)))  # mass below 0: bare metal
    total = sum(wt * R_at(float(t)) for wt, t in zip(weights, ts, strict=True))
    total = total + (below * R_at(0.0) if below > 0 else 0.0)
    return total / (weights.sum() + below)


def _reference_Lab(R: np.ndarray, wl: np.ndarray) -> np.ndarray:
    sd = colour.SpectralDistribution(R, wl)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", colour.utilities.ColourRuntimeWarning)
        XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"],
                               colour.SDS_ILLUMINANTS["D65"]) / 100.0
    white = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1964 10 Degree Standard Observer"]["D65"])
    return colour.XYZ_to_Lab(XYZ, colour.XYZ_to_xy(white))


@pytest.mark.slow
@pytest.mark.parametrize(("mean_nm", "spread", "angle_deg"), [
    (300.0, ThicknessSpread(0.0, 0.03), 0.0),   # third-order green, 9 nm
    (150.0, ThicknessSpread(6.0, 0.0), 0.0),    # second-order blue, 6 nm
    (226.6, ThicknessSpread(4.0, 0.02), 45.0),  # the paper's worst sample, oblique (s and p)
    (24.0, ThicknessSpread(15.0, 0.0), 0.0),    # thin: sigma capped at d/3 = 8 nm
])
def test_spread_colour_equals_tmm_over_independent_quadrature(mean_nm, spread, angle_deg):
    """Issue 19: the spread-averaged colour equals tmm integrated over the distribution, ΔE00 <= 0.05."""
    coating = get_coating(spread=spread)
    cm = get_colorimeter(coating.wavelength_nm, "D65", "10")
    ours = coating.reflectance(np.array([mean_nm]), np.array([angle_deg])).R[0]
    sigma = float(spread_sigma_nm(mean_nm, spread))
    ref = _reference_R(coating, mean_nm, sigma, angle_deg)
    assert np.max(np.abs(ours - ref)) < 2e-4
    dE = colour.delta_E(cm.Lab(cm.XYZ(ours)), _reference_Lab(ref, coating.wavelength_nm), method="CIE 2000")
    assert dE <= 0.05
    # and the spread matters: the uniform film's colour is visibly different
    flat = get_coating().reflectance(np.array([mean_nm]), np.array([angle_deg])).R[0]
    assert colour.delta_E(cm.Lab(cm.XYZ(flat)), cm.Lab(cm.XYZ(ours)), method="CIE 2000") > 0.5


def test_zero_spread_is_the_uniform_film_bit_for_bit():
    """Issue 19: spread 0 runs the uniform film's code path (outputs byte-identical to before)."""
    d = np.linspace(0.0, 400.0, 41)[:, None]
    cos = np.linspace(0.2, 1.0, 5)[None, :]
    c0 = get_coating()
    cz = get_coating(spread=ThicknessSpread(0.0, 0.0))
    assert cz is c0  # the same cached coating
    direct = optics.film_reflectance_cos(d, cos, c0.wavelength_nm, c0.n_film, c0.n_substrate)
    got = cz.reflectance_cos(d, cos)
    assert np.array_equal(got.R_s, direct.R_s) and np.array_equal(got.R_p, direct.R_p)


def test_profile_with_zero_spread_writes_and_records_nothing_new(tmp_path):
    """Issue 19: a profile saying spread_nm = 0 is the profile without it: same metadata, same TOML."""
    base = load_process("titanium-fujii2019")
    text = (tmp_path / "p.toml")
    text.write_text(process_toml(base).replace("offset_nm =", "spread_nm = 0.0\nspread_fraction = 0\noffset_nm =", 1),
                    encoding="utf-8")
    p = load_process(str(text))
    assert p.spread == NO_SPREAD
    assert p.metadata() == {**base.metadata(), "process_origin": "p.toml"}
    assert process_toml(p) == process_toml(base)


def test_profile_spread_round_trips_and_flows_into_the_coating(tmp_path):
    """Issue 19: [spread] keys in a profile reach the coating (and are written back)."""
    base = load_process("titanium-fujii2019")
    path = tmp_path / "p.toml"
    path.write_text(process_toml(base).replace("offset_nm =", "spread_nm = 4.0\nspread_fraction = 0.02\noffset_nm =", 1),
                    encoding="utf-8")
    p = load_process(str(path))
    assert p.spread == ThicknessSpread(4.0, 0.02)
    assert p.coating().spread == ThicknessSpread(4.0, 0.02)
    assert p.metadata()["spread_nm"] == 4.0 and p.metadata()["spread_fraction"] == 0.02
    path.write_text(process_toml(p), encoding="utf-8")
    assert load_process(str(path)).spread == p.spread


@pytest.mark.parametrize(("text", "message"), [
    ("spread_nm = -1", "spread_nm = -1 is out of range"),
    ("spread_nm = 80", "spread_nm = 80 is out of range"),
    ("spread_fraction = 0.5", "spread_fraction = 0.5 is out of range"),
    ("spread_nm = \"4\"", "spread_nm must be a number"),
])
def test_profile_spread_out_of_range_is_one_line_error(tmp_path, text, message):
    """Issue 19: a profile's spread is range-checked like every other number."""
    base = load_process("titanium-fujii2019")
    path = tmp_path / "p.toml"
    path.write_text(process_toml(base).replace("offset_nm =", f"{text}\noffset_nm =", 1), encoding="utf-8")
    with pytest.raises(SwatchError, match=message):
        load_process(str(path))


@pytest.mark.parametrize(("text", "want"), [("4", (4.0, 0.0)), ("3,0.02", (3.0, 0.02)), ("0,0.1", (0.0, 0.1)),
                                            ("0", (0.0, 0.0))])
def test_spread_option_parses_nm_and_fraction(text, want):
    assert parse_spread(text) == ThicknessSpread(*want)


@pytest.mark.parametrize(("text", "message"), [("a", "must be NM or NM,FRACTION"), ("1,2,3", "must be NM"),
                                               ("-1", "from 0 to 50 nm"), ("1,0.9", "from 0 to 0.3"),
                                               ("nan", "from 0 to 50"), (",1", "must be NM")])
def test_spread_option_rejects_bad_values(text, message):
    with pytest.raises(SwatchError, match=message):
        parse_spread(text)


def test_spread_sigma_is_capped_at_a_third_of_the_thickness():
    s = ThicknessSpread(10.0, 0.05)
    np.testing.assert_allclose(spread_sigma_nm([0.0, 15.0, 100.0, 400.0], s), [0.0, 5.0, 15.0, 30.0])


def test_spread_washes_out_the_higher_orders_more():
    """Issue 19: a fixed relative spread lowers chroma more at third order than at first (the point)."""
    cm = get_colorimeter(get_coating().wavelength_nm)
    d = np.array([60.0, 300.0])

    def chroma(c):
        Lab = cm.Lab(cm.XYZ(c.reflectance_cos(d, 1.0).R))
        return np.hypot(Lab[:, 1], Lab[:, 2])

    loss = chroma(get_coating()) - chroma(get_coating(spread=ThicknessSpread(0.0, 0.04)))
    assert loss[1] > 3.0 * max(loss[0], 0.1)


def test_spread_applies_under_an_overcoat_and_refuses_amplitudes():
    c = get_coating(spread=ThicknessSpread(5.0, 0.0))
    thin = OvercoatedCoating(c, (overcoat("1.5:1e-9", c.wavelength_nm),))
    a = thin.reflectance(np.array([120.0]), np.array([30.0])).R
    b = c.reflectance(np.array([120.0]), np.array([30.0])).R
    np.testing.assert_allclose(a, b, atol=1e-9)
    with pytest.raises(SwatchError, match="no single complex amplitude"):
        c.reflectance_cos(100.0, 1.0, amplitudes=True)


_CATALOG = """
name = "spread check"
process = "line.toml"
[thickness]
start_nm = 40
stop_nm = 100
step_nm = 60
[render]
size_px = 64
angular_map = false
[sheet]
columns = 2
rows = 1
[chips]
enabled = false
"""


def _catalog_files(root) -> dict:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and ".swatch-catalog" not in p.parts}


@pytest.mark.slow
def test_catalog_with_zero_spread_is_byte_identical_and_a_spread_changes_it(tmp_path):
    """Issue 19: a catalog whose profile says spread 0 is byte-identical to one without the key; a
    spread changes the colours and is recorded in catalog.json."""
    import json

    from swatch.catalog.build import build_catalog

    base = process_toml(load_process("titanium-fujii2019"))
    outs = {}
    for case, extra in (("plain", ""), ("zero", "spread_nm = 0.0\nspread_fraction = 0.0\n"),
                        ("spread", "spread_nm = 5.0\nspread_fraction = 0.03\n")):
        folder = tmp_path / case
        folder.mkdir()
        (folder / "line.toml").write_text(base.replace("offset_nm =", extra + "offset_nm =", 1), encoding="utf-8")
        (folder / "spec.toml").write_text(_CATALOG, encoding="utf-8")
        build_catalog(folder / "spec.toml", folder / "out", jobs=1)
        outs[case] = _catalog_files(folder / "out")
    assert outs["zero"] == outs["plain"]
    assert set(outs["spread"]) == set(outs["plain"])
    cat = json.loads(outs["spread"]["catalog.json"])
    assert cat["catalog"]["process"]["spread_nm"] == 5.0
    plain = json.loads(outs["plain"]["catalog.json"])
    assert "spread_nm" not in plain["catalog"]["process"]
    assert [s["Lab"] for s in cat["swatches"]] != [s["Lab"] for s in plain["swatches"]]


@pytest.mark.slow
def test_spread_option_reaches_colour_render_fit_and_preset(tmp_path):
    """Issue 19: ``--spread`` is one option on every command that takes a process; it changes the
    colour and is recorded; a bad value is a one-line error (exit 2)."""
    from tests.cli_helpers import assert_one_line_error, run_json, run_swatch

    flat = run_json("color", "--thickness", "300")
    wide = run_json("color", "--thickness", "300", "--spread", "4,0.03")
    assert np.hypot(*wide["rows"][0]["Lab"][1:]) < np.hypot(*flat["rows"][0]["Lab"][1:]) - 5
    assert wide["process"]["spread_nm"] == 4.0 and "spread_nm" not in flat["process"]
    for args in (("render", "--thickness", "300", "--size", "64", "--out", str(tmp_path / "r")),
                 ("preset", "--thickness", "300", "--format", "gltf", "--out", str(tmp_path / "p")),
                 ("match", "--lab", "60,-30,10")):
        assert run_swatch(*args, "--spread", "3").returncode == 0, args
    assert_one_line_error(run_swatch("color", "--thickness", "300", "--spread", "99"), "from 0 to 50 nm")


def test_fits_use_the_spread_of_the_profile():
    """Issue 19: the thickness fitters take the profile's spread (sweep and refinement paths). Spectra
    of a 3 % spread film at 260 nm (the spread model itself is checked against tmm above) are fitted
    back to 260 nm with the spread, and worse (a larger residual) by a uniform-film fit."""
    from swatch.fit.lab_fit import fit_lab
    from swatch.fit.spectral_fit import fit_spectra
    from swatch.io.measurements import LabMeasurement, SpectralMeasurement

    spread = ThicknessSpread(0.0, 0.03)
    light = np.array([45.0, 45.0, 45.0, 30.0])
    view = np.array([0.0, 15.0, 60.0, 10.0])
    coating = get_coating(spread=spread)
    R = np.stack([coating.half_vector(260.0, lv, vv)[0].R for lv, vv in zip(light, view, strict=True)])
    m = SpectralMeasurement.from_arrays(light, view, coating.wavelength_nm, R)
    with_spread = fit_spectra(m, spread=spread, exclude_mirror_deg=0)
    uniform = fit_spectra(m, exclude_mirror_deg=0)
    assert with_spread.thickness_nm == pytest.approx(260.0, abs=0.3)
    assert with_spread.mean_delta_E_00 < 0.1 < uniform.mean_delta_E_00
    cm = get_colorimeter(coating.wavelength_nm)
    lab = LabMeasurement("lab", light, view, np.zeros_like(light), np.full_like(light, 180.0), cm.Lab(cm.XYZ(R)))
    assert fit_lab(lab, get_coating(spread=spread), exclude_mirror_deg=0).thickness_nm == pytest.approx(260.0, abs=0.3)
