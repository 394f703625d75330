"""Swatch records against independent references: tmm.coh_tmm spectra, colour.sd_to_XYZ, colour.delta_E."""
from __future__ import annotations

import dataclasses
import functools
import itertools

import colour
import numpy as np
import pytest

import swatch  # noqa: F401  (before colour: silences colour-science's plotting notice)
from swatch.catalog.context import catalog_context
from swatch.catalog.records import compute, hue_family
from swatch.catalog.spec import parse_spec
from swatch.colorimetry.tolerance import grade_bound
from swatch.physics.materials import load_material
from tests.tmm_reference import unpolarised_R

# colour.sd_to_XYZ notes that it aligns 380–780 nm spectra to its tables' shape: expected here.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

WL = np.arange(380.0, 781.0, 5.0)
OBSERVER = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
D65 = colour.SDS_ILLUMINANTS["D65"]


@functools.cache
def _indices():
    return load_material("TiO2-Siefke").nk(WL), load_material("Ti-Johnson").nk(WL)


def ref_spectrum(d_nm: float, theta_d_deg: float) -> np.ndarray:
    """Unpolarised reflectance of air / film / Ti at theta_d from tmm.coh_tmm."""
    nf, ns = _indices()
    return unpolarised_R([1.0, nf, ns], [np.inf, d_nm, np.inf], np.radians(theta_d_deg), WL)


@functools.lru_cache(maxsize=1)
def _white_xy():
    white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones_like(WL), WL), OBSERVER, D65)
    return colour.XYZ_to_xy(white / 100.0)


def ref_Lab(d_nm: float, theta_d_deg: float) -> np.ndarray:
    sd = colour.SpectralDistribution(ref_spectrum(d_nm, theta_d_deg), WL)
    return colour.XYZ_to_Lab(colour.sd_to_XYZ(sd, OBSERVER, D65) / 100.0, _white_xy())


SPEC = parse_spec({"name": "test", "thickness": {"list_nm": [30.0, 50.8, 87.5, 160.6, 264.4]},
                   "tolerance": {"grade": "B"}, "sheet": {"columns": 2, "rows": 2}})


@pytest.fixture(scope="module")
def data():
    return compute(catalog_context(SPEC))


def test_reference_Lab_matches_tmm_and_colour(data):
    for rec in data.records:
        ref = ref_Lab(rec["thickness_nm"], 22.5)  # 45°:0° in plane -> theta_d = 22.5°
        assert np.allclose(rec["Lab"], ref, atol=0.02), (rec["thickness_nm"], rec["Lab"], ref)
        L, C, h = colour.Lab_to_LCHab(np.array(rec["Lab"]))
        assert rec["LCh"] == pytest.approx([L, C, h], abs=1e-3)


def test_multi_angle_Lab_matches_tmm_at_each_theta_d(data):
    # aspecular -> theta_d worked by hand: the view is 45 - g from the normal, signed;
    # opposite side: theta_d = (45 + v)/2, light's side: theta_d = (45 - |v|)/2.
    theta_d = {"45as-15": 52.5, "45as15": 37.5, "45as25": 32.5, "45as45": 22.5, "45as75": 7.5, "45as110": 10.0}
    rec = data.records[1]
    assert set(rec["multi_angle"]) == set(theta_d)
    for name, td in theta_d.items():
        assert np.allclose(rec["multi_angle"][name], ref_Lab(rec["thickness_nm"], td), atol=0.02), name


def test_neighbour_delta_E(data):
    recs = data.records
    assert recs[0]["delta_E_00_to_neighbours"]["previous"] is None
    assert recs[-1]["delta_E_00_to_neighbours"]["next"] is None
    for a, b in itertools.pairwise(recs):
        e00 = colour.delta_E(np.array(a["Lab"]), np.array(b["Lab"]), method="CIE 2000")
        eab = np.linalg.norm(np.subtract(a["Lab"], b["Lab"]))
        assert a["delta_E_00_to_neighbours"]["next"] == pytest.approx(e00, abs=1e-3)
        assert b["delta_E_00_to_neighbours"]["previous"] == pytest.approx(e00, abs=1e-3)
        assert a["delta_E_ab_to_neighbours"]["next"] == pytest.approx(eab, abs=1e-3)


def _check_window(rec, bound: float, method: str, search_nm: float, rate: float):
    """The window's edges sit where the colour difference in ``method`` (colour-science, on tmm
    spectra) reaches ``bound``, and every deviation inside is within it."""
    d = rec["thickness_nm"]
    pw = rec["process_window"]
    Lab0 = ref_Lab(d, 22.5)
    for sign, width in ((-1, pw["thickness_minus_nm"]), (+1, pw["thickness_plus_nm"])):
        assert 0 < width < search_nm
        inside = colour.delta_E(Lab0, ref_Lab(d + sign * (width - 0.03), 22.5), method=method)
        outside = colour.delta_E(Lab0, ref_Lab(d + sign * (width + 0.03), 22.5), method=method)
        assert inside <= bound < outside, (d, sign, width, inside, outside)
        # and the whole interval up to the edge is inside (a coarse independent scan)
        for delta in np.linspace(0, width - 0.03, 6):
            assert colour.delta_E(Lab0, ref_Lab(d + sign * delta, 22.5), method=method) <= bound
    assert pw["voltage_minus_V"] == pytest.approx(pw["thickness_minus_nm"] / rate, abs=2e-3)
    assert pw["voltage_plus_V"] == pytest.approx(pw["thickness_plus_nm"] / rate, abs=2e-3)


def test_process_window_edges_where_delta_E_ab_reaches_the_csaj_bound(data):
    """A CSAJ grade bounds ΔE*ab (tables/tolerance_grades.csv): the window is judged in ΔE*ab."""
    bound = grade_bound("B", "csaj")
    for rec in data.records[1:4]:
        pw = rec["process_window"]
        assert pw["grade"] == "B" and pw["metric"] == "dEab" and pw["max"] == bound
        _check_window(rec, bound, "CIE 1976", SPEC.search_nm, SPEC.nm_per_V)


def test_process_window_in_a_written_dE00_tolerance():
    spec = parse_spec({"name": "t", "thickness": {"list_nm": [50.8, 121.4]},
                       "tolerance": {"metric": "dE00", "max": 2.0}})
    for rec in compute(catalog_context(spec)).records:
        pw = rec["process_window"]
        assert pw["metric"] == "dE00" and pw["max"] == 2.0 and pw["scheme"] is None
        _check_window(rec, 2.0, "CIE 2000", spec.search_nm, spec.nm_per_V)


def test_grade_c_window_is_not_the_dE00_window():
    """The old defect: grade C's 6.5 applied to ΔE2000 gave windows 1.2–1.8× wider than the grade."""
    ab = parse_spec({"name": "t", "thickness": {"list_nm": [87.5, 160.6]}, "tolerance": {"grade": "C"}})
    e00 = parse_spec({"name": "t", "thickness": {"list_nm": [87.5, 160.6]},
                      "tolerance": {"metric": "dE00", "max": 6.5}})
    for a, b in zip(compute(catalog_context(ab)).records, compute(catalog_context(e00)).records, strict=True):
        width_ab = a["process_window"]["thickness_minus_nm"] + a["process_window"]["thickness_plus_nm"]
        width_00 = b["process_window"]["thickness_minus_nm"] + b["process_window"]["thickness_plus_nm"]
        assert width_00 > 1.1 * width_ab


def test_process_window_capped_at_zero_thickness():
    spec = parse_spec({"name": "t", "thickness": {"list_nm": [2.0]}, "tolerance": {"grade": "E"}})
    pw = compute(catalog_context(spec)).records[0]["process_window"]
    assert pw["thickness_minus_nm"] <= 2.0 and pw["minus_capped"]


def test_voltages_and_layout(data):
    for i, rec in enumerate(data.records):
        assert rec["voltage_V"] == pytest.approx(rec["thickness_nm"] / SPEC.nm_per_V, abs=1e-4)
        assert rec["sheet"] == i // 4 + 1
        assert rec["sheet_png"] == f"sheets/sheet_{rec['sheet']:02d}.png"


def test_hue_families():
    assert hue_family(2.0, 250.0) == "neutral"
    assert hue_family(30.0, 350.0) == "red" and hue_family(30.0, 10.0) == "red"
    assert hue_family(30.0, 260.0) == "blue"
    assert hue_family(30.0, 90.0) == "yellow"


def _two_slope_voltage_V(t_nm: float, offset_nm: float, rate: float, knee_V: float, above: float) -> float:
    """The inverse of a two-slope growth law, by hand: rate nm/V up to knee_V, ``above`` nm/V beyond."""
    x = t_nm - offset_nm
    return x / rate if x <= rate * knee_V else knee_V + (x - rate * knee_V) / above


def test_process_window_voltages_follow_a_two_slope_growth_law():
    """Issue 17 (polish): the catalog's window in V goes through the profile's knee law, as ``swatch spec``
    does, not through the first slope alone."""
    base = parse_spec({"name": "knee", "thickness": {"list_nm": [125.5, 150.0, 240.0]},
                       "tolerance": {"grade": "B"}, "sheet": {"columns": 3, "rows": 1}})
    law = {"offset_nm": 5.0, "nm_per_V": 2.0, "knee_V": 60.0, "nm_per_V_above_knee": 1.2}  # knee at 125 nm
    spec = dataclasses.replace(base, **law)
    straddles = above = 0
    for rec in compute(catalog_context(spec)).records:
        pw, d = rec["process_window"], rec["thickness_nm"]
        lo, hi = d - pw["thickness_minus_nm"], d + pw["thickness_plus_nm"]
        v = _two_slope_voltage_V(d, 5.0, 2.0, 60.0, 1.2)
        assert rec["voltage_V"] == pytest.approx(v, abs=1e-4)
        assert pw["voltage_minus_V"] == pytest.approx(v - _two_slope_voltage_V(lo, 5.0, 2.0, 60.0, 1.2), abs=3e-3)
        assert pw["voltage_plus_V"] == pytest.approx(_two_slope_voltage_V(hi, 5.0, 2.0, 60.0, 1.2) - v, abs=3e-3)
        straddles += lo < 125.0 < hi
        above += lo > 125.0
    assert straddles >= 1 and above >= 1  # the cases the first-slope-only conversion got wrong
