"""The default look (#21 "default look", #23 item 4): renders in the default studio have no
pitch-black pixels on the object, and the default microfacet angular map is not clipped to white;
the display changes, the scene-referred values do not."""
from __future__ import annotations

import colour
import numpy as np
import pytest

from swatch.render import render_swatch
from swatch.render.angular import angular_map
from swatch.render.display import KNEE, display_encode, display_encode_hue, tone


@pytest.mark.parametrize("shape", ["flat", "cylinder", "sphere"])
def test_default_studio_renders_have_no_black_on_the_object(shape):
    """`swatch render`'s default lighting for GGX is the studio: every pixel fully on the object
    is brighter than sRGB 8/255 (no black crescent), at a dark, a saturated and a pale film."""
    for d in (35.0, 50.8, 170.0, 75.0):
        img = render_swatch(d, shape, 96, environment="studio", roughness_alpha=0.2)
        on = img.coverage >= 1.0
        assert on.sum() > 500
        assert img.display_rgb[on].max(axis=-1).min() > 8, (shape, d)


def test_default_microfacet_angular_map_is_not_clipped_to_white():
    """Over 20–300 nm no more than 1 % of the default microfacet map is near white (all channels
    ≥ 250; it was over a third at 50.8 nm with the per-channel shoulder), and the linear values are
    the scene's (the display alone changed)."""
    for d in (30.0, 50.8, 120.0, 210.0, 280.0):
        m = angular_map(d, model="microfacet")
        assert (m.display_rgb.min(axis=-1) >= 250).mean() <= 0.01, d
        assert "hue-preserving" in m.metadata["exposure_rule"]
    raw = np.asarray(m.linear_rgb, dtype=np.float64)
    assert raw.max() > 5.0  # the mirror region is far above white in the EXR: scene-referred


def test_hue_preserving_shoulder():
    """Identity (as the render's display) below the knee; above it the largest channel follows the
    shoulder and the chromaticity is kept (colour-science's xy of the decoded pixel)."""
    rng = np.random.default_rng(2)
    low = rng.uniform(0.0, KNEE, size=(500, 3))
    diff = display_encode_hue(low).astype(int) - display_encode(low.astype(np.float32)).astype(int)
    assert np.abs(diff).max() <= 1  # the render's lookup table is within a fraction of a code
    high = rng.uniform(0.2, 1.0, size=(500, 3)) * rng.uniform(2.0, 40.0, size=(500, 1))
    out = display_encode_hue(high).astype(np.float64) / 255.0
    lin = colour.cctf_decoding(out, "sRGB")
    np.testing.assert_allclose(lin.max(axis=-1), tone(high.max(axis=-1)), atol=6e-3)
    xy_in = colour.XYZ_to_xy(colour.sRGB_to_XYZ(high, apply_cctf_decoding=False))
    xy_out = colour.XYZ_to_xy(colour.sRGB_to_XYZ(lin, apply_cctf_decoding=False))
    np.testing.assert_allclose(xy_out, xy_in, atol=6e-3)
