"""The half-vector model and its helpers."""
from __future__ import annotations

import numpy as np
import pytest
import tmm
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.core.errors import SwatchError
from swatch.physics import growth, model, overcoat


def test_half_vector_reflectance_equals_tmm_at_theta_d():
    """R(λ; d, θ_d) with θ_d = (θ_l + θ_v)/2 in plane: the paper's eq. 2–5, checked with tmm."""
    c = model.get_coating()
    refl, theta_d = c.half_vector(70.0, 10.0, 45.0)
    assert theta_d == pytest.approx(27.5)
    for w in (0, 40, 80):
        for pol, R in (("s", refl.R_s), ("p", refl.R_p)):
            ref = tmm.coh_tmm(pol, [1.0, c.n_film[w], c.n_substrate[w]], [np.inf, 70.0, np.inf],
                              np.radians(27.5), c.wavelength_nm[w])["R"]
            assert abs(R[w] - ref) <= 1e-10


def test_half_vector_vectorises_over_geometries():
    c = model.get_coating()
    light = np.array([0.0, 30.0, 60.0])
    view = np.array([60.0, 30.0, 0.0])
    refl, theta_d = c.half_vector(100.0, light, view)
    assert refl.R.shape == (3, c.wavelength_nm.size)
    assert np.allclose(theta_d, 30.0)
    assert np.allclose(refl.R[0], refl.R[1]) and np.allclose(refl.R[1], refl.R[2])


@settings(max_examples=100, deadline=None)
@given(scale=st.floats(0.01, 100.0), seed=st.integers(0, 1000))
def test_intensity_correction_matches_means(scale, seed):
    rng = np.random.default_rng(seed)
    sim = rng.random((4, 81)) + 0.01
    measured = scale * rng.random((4, 81))
    corrected = model.intensity_correction(sim, measured)
    assert np.allclose(corrected.mean(axis=-1), measured.mean(axis=-1))
    # Only a scale: the spectral shape is kept.
    assert np.allclose(corrected / corrected.mean(axis=-1, keepdims=True), sim / sim.mean(axis=-1, keepdims=True))


def test_voltage_conversion_round_trip():
    """The growth law on numbers worked by hand, and the default rate against the paper's preset
    profile as the file states it (read with tomllib, not through the code; #17: the old check
    ``voltage_to_thickness_nm(25) == 50.8`` was true by construction of the default)."""
    import tomllib

    from swatch.physics.materials import tables_dir

    profile = tomllib.loads((tables_dir() / "processes" / "titanium-fujii2019.toml").read_text(encoding="utf-8"))
    assert profile["nm_per_V"] == pytest.approx(growth.DEFAULT_NM_PER_V)  # the paper's 50.8 nm at 25 V
    assert growth.voltage_to_thickness_nm(10.0, 3.0) == pytest.approx(30.0)
    assert growth.voltage_to_thickness_nm(10.0, 3.0, offset_nm=5.0) == pytest.approx(35.0)
    assert growth.thickness_to_voltage_V(35.0, 3.0, offset_nm=5.0) == pytest.approx(10.0)
    volts = np.array([0.0, 7.5, 42.0, 110.0])
    assert growth.thickness_to_voltage_V(growth.voltage_to_thickness_nm(volts, 2.5, 3.0), 2.5, 3.0) == pytest.approx(volts)
    with pytest.raises(SwatchError, match="growth rate"):
        growth.voltage_to_thickness_nm(10.0, 0.0)
    with pytest.raises(SwatchError, match="voltage"):
        growth.voltage_to_thickness_nm(-1.0)


@pytest.mark.parametrize("bad", [-0.1, np.nan, 1000.5, np.inf])
def test_thickness_checked(bad):
    with pytest.raises(SwatchError, match="thickness"):
        model.check_thickness_nm(bad)


def test_overcoated_coating_equals_tmm_stack():
    """A clear overcoat over the oxide: the transfer-matrix path against tmm on the 4-medium stack."""
    c = model.get_coating()
    oc = overcoat.OvercoatedCoating(c, (overcoat.overcoat("1.5:200", c.wavelength_nm),
                                     overcoat.overcoat("TiO2-Jolivet-amorphous:15", c.wavelength_nm)))
    refl, theta_d = oc.half_vector(np.array([0.0, 50.8, 173.9]), 10.0, 45.0)
    assert theta_d == pytest.approx(27.5)
    jolivet = oc.overcoats[1].n
    for i, d in enumerate((0.0, 50.8, 173.9)):
        for w in (0, 37, 80):
            for pol, R in (("s", refl.R_s), ("p", refl.R_p)):
                ref = tmm.coh_tmm(pol, [1.0, 1.5, jolivet[w], c.n_film[w], c.n_substrate[w]],
                                  [np.inf, 200.0, 15.0, d, np.inf], np.radians(27.5), c.wavelength_nm[w])["R"]
                assert abs(R[i, w] - ref) <= 1e-10


@pytest.mark.parametrize("text, message", [
    ("1.5", "INDEX:THICKNESS_NM"), ("0.5:100", "index"), ("1.5:0", "thickness"), ("1.5:5000", "thickness"),
    ("1.5:abc", "not a number"), ("nope:10", "unknown material"),
])
def test_overcoat_parsing_errors(text, message):
    with pytest.raises(SwatchError, match=message):
        overcoat.overcoat(text, model.get_coating().wavelength_nm)
