"""Half-vector geometry (the paper's eq. 5) and tolerance grades."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.colorimetry import tolerance
from swatch.core.errors import SwatchError
from swatch.physics import geometry

polar = st.floats(0.0, 89.9)
azimuth = st.floats(0.0, 360.0)


@settings(max_examples=200, deadline=None)
@given(tl=polar, tv=polar)
def test_in_plane_theta_d_is_mean_angle(tl, tv):
    assert geometry.theta_d_deg(tl, tv) == pytest.approx((tl + tv) / 2.0, abs=1e-6)


@settings(max_examples=200, deadline=None)
@given(tl=polar, tv=polar, pl=azimuth, pv=azimuth)
def test_theta_d_is_angle_between_light_and_half_vector(tl, tv, pl, pv):
    l = geometry.direction(tl, pl)
    v = geometry.direction(tv, pv)
    h = (l + v) / np.linalg.norm(l + v)
    expected = np.degrees(np.arccos(np.clip(l @ h, -1, 1)))
    assert geometry.theta_d_deg(tl, tv, pl, pv) == pytest.approx(expected, abs=1e-5)
    assert geometry.cos_theta_d(tl, tv, pl, pv) == pytest.approx(l @ h, abs=1e-9)
    assert geometry.cos_theta_h(tl, tv, pl, pv) == pytest.approx(h[2], abs=1e-9)


def test_mirror_direction_has_vertical_half_vector():
    assert geometry.cos_theta_h(30.0, 30.0) == pytest.approx(1.0)
    assert geometry.theta_d_deg(30.0, 30.0) == pytest.approx(30.0)


def test_aspecular_angles():
    assert geometry.aspecular_view_deg(45.0, 15.0) == pytest.approx(30.0)
    assert geometry.aspecular_view_deg(45.0, 110.0) == pytest.approx(-65.0)


@pytest.mark.parametrize("bad", [-1.0, 90.0, np.nan, np.inf])
def test_polar_angle_checked(bad):
    with pytest.raises(SwatchError, match=r"\[0, 90\)"):
        geometry.check_polar_deg(bad, "light")


def test_grades_follow_the_table():
    assert tolerance.grade_for(0.4) == "AAA"
    assert tolerance.grade_for(0.41) == "AA"
    assert tolerance.grade_for(5.0) == "C"  # the paper's mean ΔE*ab
    assert tolerance.grade_for(25.0) == "E"
    assert tolerance.grade_for(25.01) == "beyond"
    assert list(tolerance.grade_for([1.0, 7.0])) == ["A", "D"]
    assert tolerance.grade_for(2.0, "nbs") == "noticeable"
    assert tolerance.grade_bound("c") == 6.5
    with pytest.raises(SwatchError, match="unknown tolerance scheme"):
        tolerance.grade_for(1.0, "iso")
    with pytest.raises(SwatchError, match="unknown grade"):
        tolerance.grade_bound("Z")


def test_grade_table_is_monotonic_and_cited():
    text = (tolerance.tables_dir() / "tolerance_grades.csv").read_text(encoding="utf-8")
    assert "Handbook of Color Science" in text and "Judd" in text
    for scheme in tolerance.schemes():
        bounds = [g.max for g in tolerance.grades(scheme)]
        assert bounds == sorted(bounds) and len(set(bounds)) == len(bounds)
        assert {g.metric for g in tolerance.grades(scheme)} == {"dEab"}  # both schemes bound ΔE*ab
        assert tolerance.grade_metric(scheme) == "dEab"


def test_written_tolerances():
    t = tolerance.parse_tolerance("dE00:2")
    assert (t.metric, t.max, t.grade, t.label) == ("dE00", 2.0, None, "dE00 ≤ 2")
    c = tolerance.parse_tolerance("csaj:C")
    assert (c.metric, c.max, c.grade) == ("dEab", 6.5, "C")
    # names in any case, as grades already were: the same tolerances
    assert tolerance.parse_tolerance("CSAJ:c") == c and tolerance.parse_tolerance("DE00:2") == t
    for bad in ("dE00", "dE00:x", "dE00:0", "dE76:2", "csaj:Z"):
        with pytest.raises(SwatchError):
            tolerance.parse_tolerance(bad)
