"""swatch calibrate: coupons made by an independent route (tmm.coh_tmm + colour.sd_to_XYZ, another
film table than the profile's, noise, a mislabelled coupon) give a profile whose predictions at
held-out voltages agree within ΔE2000 1; bad coupon files get one-line errors with line numbers."""
from __future__ import annotations

import functools
import json

import colour
import numpy as np
import pytest

import swatch
from swatch.fit.calibration import calibrate
from swatch.io.coupons import read_coupons
from swatch.physics.materials import load_material
from swatch.physics.process import load_process
from tests.cli_helpers import assert_one_line_error, run_swatch
from tests.tmm_reference import unpolarised_R

pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

WL = np.arange(380.0, 781.0, 5.0)
OBSERVER = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
D65 = colour.SDS_ILLUMINANTS["D65"]
THETA_D = 22.5  # half-vector facet angle at 45°:0°
# The "line": TiO2 of Franta et al. (n 2.35 at 550 nm) on Ti, 2.45 nm/V from 6 nm of initial oxide.
# The profile being calibrated starts from TiO2-Siefke (n 2.44): the film index scale must take it up.
TRUE_RATE, TRUE_OFFSET, LINE_FILM = 2.45, 6.0, "TiO2-Franta"


@functools.cache
def _indices(film: str):
    return load_material(film).nk(WL), load_material("Ti-Johnson").nk(WL)


def tmm_spectrum(d_nm: float, film: str = LINE_FILM) -> np.ndarray:
    nf, ns = _indices(film)
    return unpolarised_R([1.0, nf, ns], [np.inf, d_nm, np.inf], np.radians(THETA_D), WL)


def ref_Lab(R: np.ndarray) -> np.ndarray:
    white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones_like(WL), WL), OBSERVER, D65)
    XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(R, WL), OBSERVER, D65)
    return colour.XYZ_to_Lab(XYZ / 100.0, colour.XYZ_to_xy(white / 100.0))


VOLTS = np.arange(10.0, 86.0, 5.0)  # 16 coupons
MISLABELLED = 7  # the coupon anodised at 20 V but labelled 45 V


@pytest.fixture(scope="module")
def lab_coupons(tmp_path_factory):
    rng = np.random.default_rng(8)
    rows = ["# coupons of a test line: 45:0, D65, 10°", "coupon,voltage_V,L,a,b"]
    for i, v in enumerate(VOLTS):
        grown = TRUE_OFFSET + TRUE_RATE * (20.0 if i == MISLABELLED else v)
        L, a, b = ref_Lab(tmm_spectrum(grown)) + rng.normal(0.0, 0.25, 3)
        rows.append(f"c{i:02d},{v:g},{L:.2f},{a:.2f},{b:.2f}")
    path = tmp_path_factory.mktemp("line") / "coupons.csv"
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("search_tables", [False, True])
def test_held_out_voltages_within_delta_E_00_1(lab_coupons, search_tables):
    """With the profile's tables fixed (TiO2-Siefke) the film index scale takes up the line's lower index;
    with the table search (issue 19) the line's own film table may be chosen instead."""
    cal = calibrate(read_coupons(lab_coupons), load_process("titanium-fujii2019"), search_tables=search_tables)
    assert list(np.flatnonzero(cal.outlier)) == [MISLABELLED]
    if not search_tables:
        assert cal.uncertainty["film_index_scale"] is not None  # determined by 16 coupons over 10–85 V
    p = cal.process
    held_out = np.array([12.5, 27.5, 42.5, 57.5, 72.5, 82.5])
    coating = p.coating(WL)
    cm = swatch.colorimetry.colorimeter.get_colorimeter(WL)
    ours = cm.Lab(cm.XYZ(coating.reflectance(p.thickness_nm(held_out), THETA_D).R))
    ref = np.array([ref_Lab(tmm_spectrum(TRUE_OFFSET + TRUE_RATE * v)) for v in held_out])
    dE = colour.delta_E(ours, ref, method="CIE 2000")
    assert dE.max() <= 1.0, dE
    # the optical growth (film index × thickness) is what the colours fix: within 2 %
    n_line = load_material(LINE_FILM).nk(np.array([550.0])).real[0]
    n_ours = p.film_index_scale * load_material(p.film).nk(np.array([550.0])).real[0]
    assert n_ours * p.nm_per_V == pytest.approx(n_line * TRUE_RATE, rel=0.02)


def test_cli_json_contract_and_profile_round_trip(lab_coupons, tmp_path):
    out, report = tmp_path / "line.toml", tmp_path / "report"
    proc = run_swatch("calibrate", lab_coupons, "--out", out, "--report", report, "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    for key in ("nm_per_V", "offset_nm", "film_index_scale", "uncertainty", "samples", "mean_delta_E_00",
                "max_delta_E_00"):
        assert key in d
    assert set(d["uncertainty"]) == {"nm_per_V", "offset_nm", "film_index_scale"}
    assert len(d["samples"]) == VOLTS.size
    for s in d["samples"]:
        assert {"voltage_V", "thickness_nm", "delta_E_00", "outlier"} <= set(s)
    assert [s["outlier"] for s in d["samples"]].count(True) == 1
    assert d["max_delta_E_00"] < 1.5 and (report / "calibration.png").stat().st_size > 10_000
    p = load_process(str(out))
    assert p.nm_per_V == pytest.approx(d["nm_per_V"]) and "calibrated from coupons.csv" in dict(p.sources)["nm_per_V"]
    again = run_json_color(out)
    assert again["process"]["process"] == p.name
    # never overwrite without --force
    assert_one_line_error(run_swatch("calibrate", lab_coupons, "--out", out), "exists")


def run_json_color(profile):
    proc = run_swatch("color", "--voltage", "30", "--process", profile, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_spectral_coupons_with_measured_thickness(tmp_path):
    rng = np.random.default_rng(3)
    rows = ["voltage_V,wavelength_nm,reflectance,thickness_nm"]
    for v in (15.0, 30.0, 45.0, 60.0, 75.0):
        d = TRUE_OFFSET + TRUE_RATE * v
        R = tmm_spectrum(d) * 100.0 + rng.normal(0.0, 0.2, WL.size)  # percent
        measured = d + rng.normal(0, 1.0)  # ellipsometry, ±1 nm
        rows += [f"{v:g},{w:g},{r:.3f},{measured:.1f}" for w, r in zip(WL, R, strict=True)]
    path = tmp_path / "spectra.csv"
    path.write_text("\n".join(rows) + "\n")
    coupons = read_coupons(path)
    assert coupons.kind == "spectrum" and coupons.reflectance.max() < 1.0
    cal = calibrate(coupons, load_process("titanium-fujii2019"), fit_scale=False)
    assert cal.uncertainty["film_index_scale"] is None and cal.process.film_index_scale == 1.0
    assert not cal.outlier.any()
    # measured thicknesses pin the line itself (the scale held at 1 leaves a small bias)
    assert cal.process.nm_per_V == pytest.approx(TRUE_RATE, abs=0.08)


@pytest.mark.parametrize("text, needles", [
    ("voltage_V,L,a,b\n20,45,-5,-30\n", ["one coupon cannot determine"]),
    ("voltage_V,L,a,b\n20,45,-5,-30\n20,46,-5,-31\n20,44,-4,-29\n", ["all 3 coupons", "20 V"]),
    ("voltage_V,L,a,b\n20,45,-5,-30\n30,x,1,2\n", ["coupons.csv:3:", "L 'x' is not a number"]),
    ("voltage_V,L,a,b\n20,45,-5,-30\n\n# note\n30,45,1\n", ["coupons.csv:5:", "3 cells", "4"]),
    ("voltage_V,L,a,b\n20,45,-5,-30\n-3,45,1,2\n", ["coupons.csv:3:", "voltage_V", "0 to 300"]),
    ("voltage,L,a,b\n20,45,-5,-30\n", ["coupons.csv:1:", "unknown column 'voltage'"]),
    ("voltage_V,L,a\n20,45,-5\n", ["coupons.csv:1:", "missing column 'b'"]),
    ("voltage_V,L,a,b\n", ["no coupons after the header"]),
    ("", ["empty"]),
    ("voltage_V,wavelength_nm,reflectance\n20,400,0.3\n20,400,0.3\n20,410,0.3\n", ["coupons.csv:3:", "repeats"]),
    ("voltage_V,wavelength_nm,reflectance\n20,400,0.3\n20,407,0.3\n20,410,0.3\n", ["evenly spaced"]),
    ("voltage_V,wavelength_nm,reflectance\n20,400,0.3\n20,410,0.3\n20,420,0.3\n"
     "30,400,0.3\n30,420,0.3\n30,440,0.3\n", ["coupons.csv:5:", "other wavelengths"]),
    ("coupon,voltage_V,L,a,b\nA,20,45,-5,-30\nA,30,45,-5,-30\n", ["coupons.csv:3:", "appears twice"]),
])
def test_bad_coupon_files_one_line_with_line_numbers(tmp_path, text, needles):
    path = tmp_path / "coupons.csv"
    path.write_text(text, encoding="utf-8")
    proc = run_swatch("calibrate", path, "--out", tmp_path / "p.toml")
    assert_one_line_error(proc, *needles)
    assert not (tmp_path / "p.toml").exists()


def test_oversized_coupon_file(tmp_path):
    from swatch.core.limits import MAX_COUPON_BYTES

    path = tmp_path / "big.csv"
    path.write_text("voltage_V,L,a,b\n" + "# x\n" * (MAX_COUPON_BYTES // 4 + 1))
    assert_one_line_error(run_swatch("calibrate", path, "--out", tmp_path / "p.toml"), "larger than 8 MB",
                          "at most 8 MB")
    assert not (tmp_path / "p.toml").exists()


def test_endless_coupon_file_is_refused_without_reading_it_all(tmp_path):
    """A device that never ends (``/dev/zero``) is read up to the cap, then refused (it used to be
    read whole before the cap was applied: the size of a device is 0)."""
    assert_one_line_error(run_swatch("calibrate", "/dev/zero", "--out", tmp_path / "p.toml"), "at most 8 MB")


def test_outlier_names_the_voltage_its_colour_matches(lab_coupons):
    """Issue 21: an outlier coupon was flagged with no hint of the voltage its colour matches (the
    mislabelled coupon was anodised at 20 V and labelled 45 V)."""
    d = calibrate(read_coupons(lab_coupons), load_process("titanium-fujii2019")).to_dict()
    s = d["samples"][MISLABELLED]
    assert s["outlier"] and abs(s["matches_voltage_V"] - 20.0) <= 1.0 and s["matches_delta_E_00"] < 2.0
    assert all(x["matches_voltage_V"] is None for x in d["samples"] if not x["outlier"])
