"""The observer bridge (issue 35): a hex target in the document's observer, a CIELAB-only part's chip.

References we did not write: colour-science's Meng et al. (2015) spectral recovery (``colour.XYZ_to_sd``)
and its plain CIELAB → sRGB conversion."""
from __future__ import annotations

import colour
import numpy as np
import pytest

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.colorimetry.observers import document_Lab_display, hex_to_document_Lab, smooth_basis
from swatch.core.errors import SwatchError

WL = np.arange(380.0, 781.0, 5.0)
SHAPE = colour.SpectralShape(380, 780, 5)
O2, O10 = "CIE 1931 2 Degree Standard Observer", "CIE 1964 10 Degree Standard Observer"


def _srgb_encoded(hex_code):
    h = hex_code.lstrip("#")
    return np.array([int(h[i:i + 2], 16) for i in (0, 2, 4)]) / 255.0


def test_hex_in_10_degrees_is_the_meng_2015_surface_seen_by_the_10_degree_observer():
    """colour-science recovers the spectrum (Meng 2015, bounded, by optimisation) and integrates it under 10°."""
    cm10 = get_colorimeter(WL, "D65", "10")
    white2 = colour.CCS_ILLUMINANTS[O2]["D65"]
    XYZ_2 = colour.sRGB_to_XYZ(_srgb_encoded("#b08d57"), illuminant=white2)
    sd = colour.XYZ_to_sd(XYZ_2, method="Meng 2015", cmfs=colour.MSDS_CMFS[O2].copy().align(SHAPE),
                          illuminant=colour.SDS_ILLUMINANTS["D65"].copy().align(SHAPE))
    XYZ_10 = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[O10], colour.SDS_ILLUMINANTS["D65"]) / 100
    want = colour.XYZ_to_Lab(XYZ_10, colour.CCS_ILLUMINANTS[O10]["D65"])
    got = hex_to_document_Lab("b08d57", cm10)
    assert colour.delta_E(got, want, method="CIE 2000") < 0.1
    # and it is not the 2° value relabelled: the observers differ by more than the test's tolerance
    assert colour.delta_E(got, colour.XYZ_to_Lab(XYZ_2, white2), method="CIE 2000") > 0.5


def test_hex_in_2_degrees_is_its_own_cielab_and_white_stays_white():
    cm2 = get_colorimeter(WL, "D65", "2")
    for h in ("#b08d57", "#2275b5", "#a28bb0"):
        white2 = colour.xy_to_XYZ(cm2.white_xy)
        want = colour.XYZ_to_Lab(colour.sRGB_to_XYZ(_srgb_encoded(h), illuminant=cm2.white_xy), cm2.white_xy)
        assert hex_to_document_Lab(h, cm2) == pytest.approx(want, abs=1e-3), white2
    for obs in ("2", "10"):
        assert hex_to_document_Lab("ffffff", get_colorimeter(WL, "D65", obs))[0] == pytest.approx(100.0, abs=0.02)
    R_white = smooth_basis(WL) @ cm2.XYZ(np.ones(WL.size))
    assert R_white == pytest.approx(1.0, abs=1e-9)


def test_lab_chip_in_2_degrees_is_colour_sciences_lab_to_srgb_and_out_of_gamut_is_marked():
    cm2 = get_colorimeter(WL, "D65", "2")
    Lab = np.array([[55.0, 12.0, 30.0], [70.0, -5.0, 20.0], [50.0, -80.0, 60.0]])
    enc, ok = document_Lab_display(Lab, cm2)
    ref = colour.XYZ_to_sRGB(colour.Lab_to_XYZ(Lab, cm2.white_xy), illuminant=cm2.white_xy,
                             chromatic_adaptation_transform="Bradford")
    assert np.round(enc[:2] * 255) == pytest.approx(np.round(np.clip(ref[:2], 0, 1) * 255), abs=1)
    assert (ref[2] < 0).any()  # colour-science puts the third outside sRGB too
    assert ok.tolist() == [True, True, False]


def test_lab_chip_in_10_degrees_inverts_the_hex_bridge():
    cm10 = get_colorimeter(WL, "D65", "10")
    for h in ("#b08d57", "#a28bb0", "#2275b5"):
        enc, ok = document_Lab_display(hex_to_document_Lab(h, cm10), cm10)
        assert np.round(enc * 255) == pytest.approx(_srgb_encoded(h) * 255, abs=0.51) and bool(ok)


def test_bad_hex_is_one_error():
    with pytest.raises(SwatchError, match="six hex digits"):
        hex_to_document_Lab("zz0000", get_colorimeter(WL, "D65", "10"))
