"""Colorimetry against colour-science's own conversions (sd_to_XYZ, XYZ_to_Lab, ...)."""
from __future__ import annotations

import warnings
from pathlib import Path

import colour
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import swatch  # noqa: F401
from swatch.colorimetry import colorimeter as colorimetry
from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00
from swatch.core.errors import SwatchError
from swatch.physics.materials import wavelength_grid

GRIDS = [(380, 780, 5), (380, 780, 1), (380, 780, 10), (400, 700, 20), (360, 830, 5)]
SETUPS = [("D65", "10"), ("D65", "2"), ("A", "10"), ("D50", "2"), ("FL2", "10")]

DATA = Path(__file__).resolve().parents[1] / "data"


def reference_XYZ(R, wl, illuminant, observer):
    cmfs = colour.MSDS_CMFS[colorimetry.OBSERVERS[observer]]
    sd = colour.SpectralDistribution(R, wl)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", colour.utilities.ColourRuntimeWarning)
        return colour.sd_to_XYZ(sd, cmfs, colour.SDS_ILLUMINANTS[illuminant])


@pytest.mark.parametrize("grid", GRIDS)
@pytest.mark.parametrize("illuminant, observer", SETUPS)
def test_XYZ_and_Lab_agree_with_sd_to_XYZ(grid, illuminant, observer):
    wl = wavelength_grid(*grid)
    cm = Colorimeter(wl, illuminant, observer)
    rng = np.random.default_rng(hash((grid, illuminant, observer)) % 2**32)
    spectra = np.vstack([rng.random((6, wl.size)), np.ones(wl.size), 0.5 * np.ones(wl.size),
                         np.clip(np.sin(wl / 40.0), 0, 1)])
    ours = cm.XYZ(spectra)
    ref = np.array([reference_XYZ(R, wl, illuminant, observer) for R in spectra])
    assert np.max(np.abs(ours - ref)) < 1e-8
    # CIELAB relative to the illuminant's white, computed by colour-science itself.
    white = reference_XYZ(np.ones(wl.size), wl, illuminant, observer)
    ref_Lab = colour.XYZ_to_Lab(ref / 100.0, colour.XYZ_to_xy(white / 100.0))
    assert np.max(delta_E_00(cm.Lab(ours), ref_Lab)) <= 0.01


@settings(max_examples=50, deadline=None)
@given(arrays(np.float64, 81, elements=st.floats(0.0, 1.0)))
def test_any_spectrum_agrees_with_sd_to_XYZ(R):
    wl = wavelength_grid()
    cm = colorimetry.get_colorimeter(wl)
    ref = reference_XYZ(R, wl, "D65", "10")
    assert np.allclose(cm.XYZ(R), ref, atol=1e-9)


def test_perfect_white_is_L100_and_white_hex():
    cm = colorimetry.get_colorimeter(wavelength_grid())
    XYZ = cm.XYZ(np.ones(81))
    assert np.allclose(XYZ[1], 100.0)
    assert np.allclose(cm.Lab(XYZ), [100.0, 0.0, 0.0], atol=1e-9)
    enc, ok = cm.reflectance_display(np.ones(81))
    assert colorimetry.srgb_hex(enc) == "#ffffff" and bool(ok)
    enc, ok = cm.reflectance_display(np.zeros(81))
    assert colorimetry.srgb_hex(enc) == "#000000"


def test_srgb_matches_colour_science_for_d65_2deg():
    """With D65 and the 2° observer no adaptation happens: our sRGB equals colour's XYZ_to_sRGB."""
    cm = colorimetry.get_colorimeter(wavelength_grid(), "D65", "2")
    rng = np.random.default_rng(3)
    XYZ = cm.XYZ(rng.random((10, 81)))
    ref = colour.XYZ_to_RGB(XYZ / 100.0, "sRGB", illuminant=cm.white_xy, apply_cctf_encoding=False)
    assert np.allclose(cm.rgb_linear(XYZ, "srgb"), ref, atol=1e-6)


def test_out_of_gamut_flag():
    cm = colorimetry.get_colorimeter(wavelength_grid())
    wl = cm.wavelength_nm
    narrow = np.exp(-0.5 * ((wl - 520.0) / 8.0) ** 2)  # a saturated green, outside sRGB
    _, ok = cm.reflectance_display(narrow)
    assert not bool(ok)
    _, ok_p3 = cm.reflectance_display(0.5 * np.ones(81), "display-p3")
    assert bool(ok_p3)


def test_delta_E_ab_is_the_euclidean_distance():
    a, b = np.array([50.0, 10.0, -20.0]), np.array([52.0, 8.0, -25.0])
    assert colorimetry.delta_E_ab(a, b) == pytest.approx(np.sqrt(4 + 4 + 25))


def test_delta_E_00_reproduces_the_published_pairs_of_sharma_2005():
    """CIEDE2000 on the 34 test pairs of Sharma, Wu & Dalal 2005 (doi:10.1002/col.20070, Table 1;
    tests/data/ciede2000), both ways round, to the 4 published decimals (#17: the old test compared
    with the same colour.delta_E the code calls)."""
    rows = np.loadtxt(DATA / "ciede2000" / "sharma2005_pairs.txt", comments="#")
    assert rows.shape == (34, 7)
    np.testing.assert_allclose(colorimetry.delta_E_00(rows[:, :3], rows[:, 3:6]), rows[:, 6], atol=5e-5)
    np.testing.assert_allclose(colorimetry.delta_E_00(rows[:, 3:6], rows[:, :3]), rows[:, 6], atol=5e-5)


def test_hex_round_trip():
    cm = colorimetry.get_colorimeter(wavelength_grid())
    Lab = colorimetry.hex_to_Lab_2deg("#3366cc", cm)  # Lab under D65 and the 2° observer
    enc, _ = cm.display(cm.display_colorimeter.Lab_to_XYZ(Lab))
    assert colorimetry.srgb_hex(enc) == "#3366cc"
    # an independent path: colour-science's sRGB -> XYZ -> Lab (D65 white, 2° observer)
    rgb = colour.cctf_decoding(np.array([0x33, 0x66, 0xCC]) / 255.0, "sRGB")
    ref = colour.XYZ_to_Lab(colour.sRGB_to_XYZ(rgb, apply_cctf_decoding=False), cm.display_colorimeter.white_xy)
    assert float(delta_E_00(Lab, ref)) < 0.01


@pytest.mark.parametrize("illuminant", ["D65", "D50", "A"])
def test_display_rgb_comes_from_the_2_degree_observer(illuminant):
    """A 10° colorimeter's sRGB equals colour-science's sRGB of the spectrum's CIE 1931 2° XYZ."""
    wl = wavelength_grid()
    cm = colorimetry.get_colorimeter(wl, illuminant, "10")
    assert cm.display_colorimeter.observer == "2" and cm.display_colorimeter.illuminant == cm.illuminant
    rng = np.random.default_rng(7)
    spectra = rng.random((8, wl.size)) * 0.6
    XYZ_2 = np.array([reference_XYZ(R, wl, illuminant, "2") for R in spectra]) / 100.0
    white_2 = reference_XYZ(np.ones(wl.size), wl, illuminant, "2") / 100.0
    ref = colour.XYZ_to_RGB(XYZ_2, "sRGB", illuminant=colour.XYZ_to_xy(white_2),
                            chromatic_adaptation_transform="Bradford")
    assert np.allclose(cm.reflectance_rgb(spectra, "srgb"), ref, atol=1e-7)
    # ... and differs from what the 10° tristimulus values would give (the test can fail)
    wrong = colour.XYZ_to_RGB(cm.XYZ(spectra) / 100.0, "sRGB", illuminant=cm.white_xy,
                              chromatic_adaptation_transform="Bradford")
    assert np.max(np.abs(wrong - ref)) > 1e-3


@pytest.mark.parametrize(
    "args, message",
    [
        (((380, 780, 3), "D65", "10"), "1, 5, 10 or 20"),
        (((380, 780, 5), "D66", "10"), "unknown illuminant"),
        (((380, 780, 5), "D65", "4"), "unknown observer"),
        (((300, 780, 5), "D65", "10"), "outside the observer"),
    ],
)
def test_bad_setups_raise(args, message):
    grid, ill, obs = args
    with pytest.raises(SwatchError, match=message):
        Colorimeter(wavelength_grid(*grid), ill, obs)
