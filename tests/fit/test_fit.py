"""Thickness fitting, colour matching and ΔE reports (swatch.fit.fitting, swatch fit / swatch match).

Measurements are made by an independent route (tests/synthetic.py: tmm.coh_tmm reflectance on the
half-vector facet × a GGX intensity × an unknown scale + 1 % noise); colours of references by
colour.sd_to_XYZ. Timing is in benchmarks/bench_fit.py, not here.
"""
from __future__ import annotations

import json
import warnings

import colour
import numpy as np
import pytest
import tmm
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.cli import main
from swatch.core.errors import SwatchError
from swatch.fit.fitting import FacetModel, mirror_angle_deg
from swatch.fit.lab_fit import fit_lab
from swatch.fit.matching import match_colour
from swatch.fit.spectral_fit import fit_spectra
from swatch.io.measurements import LabMeasurement, SpectralMeasurement
from swatch.physics.model import get_coating
from tests.synthetic import (
    PAPER_THICKNESSES_NM,
    WAVELENGTHS_NM,
    grid_geometries,
    make_measurement,
    paper_dataset,
    tmm_half_vector_reflectance,
    write_long_csv,
)

CMFS = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
D65 = colour.SDS_ILLUMINANTS["D65"]


def reference_Lab(R, wl=WAVELENGTHS_NM):
    """CIELAB (D65, 10°) of spectra (G, W) by colour.sd_to_XYZ one by one (the reference route)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", colour.utilities.ColourRuntimeWarning)  # shape alignment notice
        return _reference_Lab(R, wl)


def _reference_Lab(R, wl):
    white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(len(wl)), wl), CMFS, D65) / 100
    white_xy = colour.XYZ_to_xy(white)
    out = []
    for row in np.atleast_2d(R):
        XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(row, wl), CMFS, D65) / 100
        out.append(colour.XYZ_to_Lab(XYZ, white_xy))
    return np.array(out)


def measurement(index):
    d, light, view, wl, R, _ = paper_dataset(index)
    return d, SpectralMeasurement.from_arrays(light, view, wl, R, source=f"sample{index + 1}")


# -- the model fast path -------------------------------------------------------------------------
def test_facet_model_matches_engine_and_tmm():
    coating = get_coating()
    cos_u = np.cos(np.radians([0.0, 22.5, 40.0, 71.0]))
    d = np.array([0.0, 15.9, 138.4, 399.0])
    fast = FacetModel(coating, cos_u)(d)
    np.testing.assert_allclose(fast, coating.reflectance_cos(d[:, None], cos_u).R, rtol=1e-12, atol=1e-14)
    wi = 30
    th = np.arccos(cos_u[2])
    nl = [1.0, coating.n_film[wi], coating.n_substrate[wi]]
    ref = 0.5 * sum(tmm.coh_tmm(p, nl, [np.inf, d[2], np.inf], th, coating.wavelength_nm[wi])["R"] for p in "sp")
    assert fast[2, 2, wi] == pytest.approx(ref, rel=1e-10)


def test_range_end_is_a_minimum_only_when_it_is_the_best():
    from swatch.fit.search import local_minima

    falling = np.array([3.0, 1.0, 2.0, 1.5, 1.2, 1.1])  # interior minimum at 1, falls towards the end
    assert list(local_minima(falling)) == [1]
    best_at_end = np.array([3.0, 1.0, 2.0, 0.5])
    assert list(local_minima(best_at_end)) == [3, 1]
    monotone = np.array([3.0, 2.0, 1.0])
    assert list(local_minima(monotone)) == [2]


def test_mirror_angle_independent():
    light, view = grid_geometries()
    np.testing.assert_allclose(mirror_angle_deg(light, view), np.abs(light - view), atol=1e-6)
    # light's side, in plane: the mirror is at light_deg on the far side
    assert mirror_angle_deg(30.0, 20.0, 0.0, 0.0) == pytest.approx(50.0)
    # out of plane: view at the normal, light at 40 -> 40
    assert mirror_angle_deg(40.0, 0.0, 0.0, 90.0) == pytest.approx(40.0)


# -- recovery (the validation) ------------------------------------------------------------
@pytest.mark.parametrize("index", range(len(PAPER_THICKNESSES_NM)))
def test_recovers_paper_thicknesses(index):
    d_true, m = measurement(index)
    res = fit_spectra(m)
    assert abs(res.thickness_nm - d_true) <= 0.5, (d_true, res.thickness_nm)
    assert res.uncertainty_nm is not None and 0 < res.uncertainty_nm < 0.5
    # the next-best minimum is a different interference solution, and worse
    assert res.second_best_thickness_nm is not None
    assert abs(res.second_best_thickness_nm - res.thickness_nm) > 5.0
    assert res.second_best_residual > res.residual
    # ... and a real minimum, not the end of the search range (0–400 nm)
    assert 0.0 < res.second_best_thickness_nm < 400.0
    # mirror region left out: |light - view| <= 10 in plane
    light, view = m.light_deg, m.view_deg
    np.testing.assert_array_equal(res.used, np.abs(light - view) > 10 + 1e-9)
    # the colour report agrees with the reference colorimetry of the measured spectra
    np.testing.assert_allclose(res.Lab_measured, reference_Lab(m.reflectance), atol=1e-6)
    # at the right thickness, with 1 % noise, colours agree closely (well within grade A)
    assert res.mean_delta_E_ab < 1.6 and res.grade in ("AAA", "AA", "A")


def test_coarse_curve_has_the_minimum_and_residual_is_mse():
    _d_true, m = measurement(5)
    res = fit_spectra(m)
    # residual is the mean over used samples of (a S - M)^2, recomputed with tmm spectra
    S = tmm_half_vector_reflectance(res.thickness_nm, m.light_deg, m.view_deg)
    M = m.reflectance
    a = M.mean(axis=1) / S.mean(axis=1)  # the paper's energy match
    mse = np.mean(((a[:, None] * S - M)[res.used]) ** 2)
    assert res.residual == pytest.approx(mse, rel=1e-6)
    np.testing.assert_allclose(res.scale, a, rtol=1e-9)


def test_uncertainty_is_calibrated():
    """Over noise seeds, the error divided by the reported sigma has a spread near 1."""
    light, view = grid_geometries(np.arange(0.0, 80.0, 16.0))
    z = []
    for seed in range(16):
        R, _ = make_measurement(121.4, light, view, seed=100 + seed)
        res = fit_spectra(SpectralMeasurement.from_arrays(light, view, WAVELENGTHS_NM, R))
        z.append((res.thickness_nm - 121.4) / res.uncertainty_nm)
    assert 0.4 < np.std(z) < 2.5


def test_global_scale_and_noise_free():
    light, view = grid_geometries(np.arange(0.0, 80.0, 16.0))
    R = tmm_half_vector_reflectance(87.5, light, view) * 0.37  # one scale, no GGX, no noise
    m = SpectralMeasurement.from_arrays(light, view, WAVELENGTHS_NM, R)
    for scale in ("global", "energy", "lsq"):
        res = fit_spectra(m, scale=scale)
        assert res.thickness_nm == pytest.approx(87.5, abs=1e-3)
    res = fit_spectra(m, scale="global")
    np.testing.assert_allclose(res.scale, 0.37, rtol=1e-6)
    assert res.mean_delta_E_ab < 1e-3
    # absolute reflectance would be wrong by the scale: "none" must fit worse
    assert fit_spectra(m, scale="none").residual > 100 * res.residual


def test_off_plane_geometries():
    rng = np.random.default_rng(7)
    light = rng.uniform(5, 70, 40)
    view = rng.uniform(5, 70, 40)
    la = rng.uniform(0, 360, 40)
    va = rng.uniform(0, 360, 40)
    R, _ = make_measurement(173.9, light, view, WAVELENGTHS_NM, la, va, seed=3)
    res = fit_spectra(SpectralMeasurement.from_arrays(light, view, WAVELENGTHS_NM, R, la, va))
    assert abs(res.thickness_nm - 173.9) <= 0.5


def test_uneven_measurement_grid_interpolated_for_colour():
    light, view = grid_geometries(np.arange(0.0, 80.0, 20.0))
    wl = np.arange(401.0, 751.0, 7.0)  # not an ASTM E308 grid
    R, _ = make_measurement(60.6, light, view, wl, seed=1)
    res = fit_spectra(SpectralMeasurement.from_arrays(light, view, wl, R))
    assert abs(res.thickness_nm - 60.6) <= 0.5
    assert res.colour_grid_interpolated
    assert wl[-1] == 744  # 5 nm grid inside 401–744 nm
    assert res.colour_wavelength_nm[0] == 405 and res.colour_wavelength_nm[-1] == 740
    assert np.all(np.diff(res.colour_wavelength_nm) == 5)


def test_all_geometries_in_mirror_region_is_an_error():
    m = SpectralMeasurement.from_arrays([30.0], [30.0], WAVELENGTHS_NM, np.full((1, 81), 0.3))
    with pytest.raises(SwatchError, match="within 10° of the mirror"):
        fit_spectra(m)
    res = fit_spectra(m, exclude_mirror_deg=0)
    assert res.used.all()


# -- Lab-only fit ----------------------------------------------------------------------------------
@pytest.mark.parametrize("index", [1, 4, 8])
def test_lab_only_fit(index):
    d_true, light, view, _wl, R, _ = paper_dataset(index)
    Lab = reference_Lab(R)
    m = LabMeasurement("lab", light, view, np.zeros_like(light), np.full_like(light, 180.0), Lab)
    res = fit_lab(m)
    assert abs(res.thickness_nm - d_true) <= 0.5, (d_true, res.thickness_nm)
    assert res.mean_delta_E_00 < 1.0
    assert res.second_best_thickness_nm is not None and abs(res.second_best_thickness_nm - res.thickness_nm) > 5


# -- match -----------------------------------------------------------------------------------------
def tmm_Lab_45_0(d):
    R = tmm_half_vector_reflectance(d, np.array([45.0]), np.array([0.0]))
    return reference_Lab(R)[0]


@settings(max_examples=12, deadline=None)
@given(st.floats(5.0, 395.0))
def test_match_round_trip(d0):
    target = tmm_Lab_45_0(d0)
    res = match_colour(target)
    ds = [c["thickness_nm"] for c in res.candidates]
    near = [c for c in res.candidates if abs(c["thickness_nm"] - d0) < 0.1]
    assert near, (d0, ds)
    assert near[0]["delta_E_00"] < 0.05 and near[0]["within_grade"]
    assert res.candidates[0]["delta_E_00"] <= near[0]["delta_E_00"] + 1e-9  # ranked by ΔE2000
    assert [c["delta_E_00"] for c in res.candidates] == sorted(c["delta_E_00"] for c in res.candidates)


def test_match_reports_orders_and_grade():
    res = match_colour(tmm_Lab_45_0(121.4), top=4)
    ds = sorted(c["thickness_nm"] for c in res.candidates)
    assert len(ds) == 4 and min(np.diff(ds)) > 5.0  # distinct orders
    far = match_colour([95.0, 70.0, 70.0], grade="B")
    assert not far.any_within_grade


def test_cli_match_json_and_hex(capsys):
    assert main(["match", "--lab", "50,0,-40", "--json", "--top", "3"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["candidates"]) == 3
    for c in out["candidates"]:
        assert set(c) >= {"thickness_nm", "voltage_V", "Lab", "delta_E_00"}
        assert c["voltage_V"] == pytest.approx(c["thickness_nm"] / (50.8 / 25))
    assert out["light_deg"] == 45 and out["view_deg"] == 0
    assert main(["match", "--hex", "1f4e9a", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["target_hex"] == "#1f4e9a" and out["candidates"]
    assert main(["match", "--lab", "95,70,70", "--grade", "B"]) == 0
    assert "no thickness" in capsys.readouterr().out
    assert main(["match", "--lab", "1,2"]) == 2
    assert main(["match"]) == 2


# -- CLI fit, JSON and report ------------------------------------------------------------------------
FIT_KEYS = {"thickness_nm", "uncertainty_nm", "residual", "second_best_thickness_nm", "mean_delta_E_ab",
            "mean_delta_E_00", "grade", "geometries"}
GEOM_KEYS = {"light_deg", "view_deg", "Lab_measured", "Lab_simulated", "delta_E_ab", "delta_E_00"}


@pytest.fixture(scope="module")
def sample_csv(tmp_path_factory):
    d, light, view, wl, R, _ = paper_dataset(1)
    p = tmp_path_factory.mktemp("meas") / "blue.csv"
    write_long_csv(p, light, view, wl, R, percent=True)
    return d, p


def test_cli_fit_json(sample_csv, capsys):
    d, p = sample_csv
    assert main(["fit", str(p), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= FIT_KEYS
    assert abs(out["thickness_nm"] - d) <= 0.5
    assert out["reflectance_unit"] == "percent" and out["reflectance_unit_detected"]
    assert len(out["geometries"]) == 100 and set(out["geometries"][0]) >= GEOM_KEYS
    used = [g for g in out["geometries"] if not g["excluded"]]
    assert out["mean_delta_E_ab"] == pytest.approx(np.mean([g["delta_E_ab"] for g in used]))
    # stated unit overrides detection: as fractions the values are 100x too bright, the fit still works
    assert main(["fit", str(p), "--fraction", "--json"]) == 0
    out2 = json.loads(capsys.readouterr().out)
    assert out2["reflectance_unit"] == "fraction" and not out2["reflectance_unit_detected"]


def test_cli_fit_text_states_percent(sample_csv, capsys):
    _, p = sample_csv
    assert main(["fit", str(p)]) == 0
    out = capsys.readouterr().out
    assert "reflectance in percent (detected" in out and "thickness" in out and "grade" in out


def test_cli_fit_lab_file(tmp_path, capsys):
    d, light, view, _wl, R, _ = paper_dataset(2)
    Lab = reference_Lab(R)
    p = tmp_path / "lab.csv"
    p.write_text("light_deg,view_deg,L,a,b\n" + "".join(
        f"{l:g},{v:g},{L!r},{a!r},{b!r}\n" for l, v, (L, a, b) in zip(light, view, Lab.tolist(), strict=True)))
    assert main(["fit", str(p), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["kind"] == "lab" and abs(out["thickness_nm"] - d) <= 0.5


def test_cli_report_files(sample_csv, tmp_path, capsys):
    import OpenImageIO as oiio

    _, p = sample_csv
    rep = tmp_path / "rep"
    assert main(["fit", str(p), "--report", str(rep)]) == 0
    names = sorted(f.name for f in rep.iterdir())
    assert names == ["delta_e_map.exr", "delta_e_map.png", "geometries.csv", "summary.csv", "summary.md"]
    png = oiio.ImageInput.open(str(rep / "delta_e_map.png"))
    assert png is not None and png.spec().nchannels == 3 and png.spec().width > 200
    png.close()
    exr = oiio.ImageInput.open(str(rep / "delta_e_map.exr"))
    spec = exr.spec()
    names = list(spec.channelnames)  # OpenEXR stores channels sorted by name
    assert sorted(names) == ["delta_E_00", "delta_E_ab", "excluded", "measured"]
    assert (spec.width, spec.height) == (10, 10)  # one pixel per (light, view) cell
    pix = exr.read_image("float")
    exr.close()
    capsys.readouterr()
    assert main(["fit", str(p), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    light, view = grid_geometries()
    ab = {(g["light_deg"], g["view_deg"]): g["delta_E_ab"] for g in out["geometries"]}
    for i, l in enumerate(np.unique(light)):
        for j, v in enumerate(np.unique(view)):
            assert pix[i, j, names.index("delta_E_ab")] == pytest.approx(ab[(l, v)], rel=1e-6)
            assert pix[i, j, names.index("excluded")] == float(abs(l - v) <= 10)
            assert pix[i, j, names.index("measured")] == 1.0
    summary = (rep / "summary.csv").read_text().splitlines()
    assert summary[0].startswith("sample,kind,thickness_nm") and summary[1].startswith("blue.csv,spectral,")
    assert "| blue.csv |" in (rep / "summary.md").read_text()
    assert len((rep / "geometries.csv").read_text().splitlines()) == 101

    # no overwrite without --force; deterministic with --force
    before = {f.name: f.read_bytes() for f in rep.iterdir()}
    capsys.readouterr()
    assert main(["fit", str(p), "--report", str(rep)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert main(["fit", str(p), "--report", str(rep), "--force"]) == 0
    after = {f.name: f.read_bytes() for f in rep.iterdir()}
    assert before == after


def test_cli_report_several_samples(tmp_path, capsys):
    paths = []
    for i in (0, 3):
        _d, light, view, wl, R, _ = paper_dataset(i)
        paths.append(write_long_csv(tmp_path / f"s{i + 1}.csv", light, view, wl, R))
    rep = tmp_path / "rep"
    assert main(["fit", *map(str, paths), "--report", str(rep), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["samples"]) == 2
    assert out["mean_delta_E_ab"] == pytest.approx(np.mean([s["mean_delta_E_ab"] for s in out["samples"]]))
    assert (rep / "delta_e_map_s1.png").exists() and (rep / "delta_e_map_s4.exr").exists()
    assert (rep / "summary.csv").read_text().splitlines()[-1].startswith("mean,")
