"""Brushed hairlines in the ``anodic_film`` plugin (#37): the lobe varies from line to line across the grain and
not along it; the mean roughness is kept; a brushed render shows lines along the axis, not grain."""
from __future__ import annotations

import numpy as np
import pytest

from tests.mitsuba_setup import jit_float, mitsuba_variant

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def _eval_at(mi, bsdf, points: np.ndarray) -> np.ndarray:
    """The plugin's value for one pair of directions (30° in, 30° out across the grain) at ``points`` (N, 3) of a
    plate facing +z (shading frame = world), 550 nm."""
    import drjit as dr

    n = points.shape[0]
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.p = mi.Point3f(*(jit_float(points[:, k]) for k in range(3)))
    si.sh_frame = mi.Frame3f(mi.Vector3f(1.0, 0.0, 0.0), mi.Vector3f(0.0, 1.0, 0.0), mi.Vector3f(0.0, 0.0, 1.0))
    s, c = np.sin(np.radians(30.0)), np.cos(np.radians(30.0))
    si.wi = mi.Vector3f(jit_float(np.full(n, 0.0)), jit_float(np.full(n, s)), jit_float(np.full(n, c)))
    si.wavelengths = mi.Spectrum(*(jit_float(np.full(n, 550.0)) for _ in range(4)))
    wo = mi.Vector3f(jit_float(np.full(n, 0.0)), jit_float(np.full(n, -s * 0.9)),
                     jit_float(np.full(n, np.sqrt(1 - 0.81 * s * s))))
    return np.asarray(bsdf.eval(mi.BSDFContext(), si, wo))[0]


def test_hairlines_vary_across_the_grain_only(mi):
    bsdf = mi.load_dict({"type": "anodic_film", "thickness_nm": 80.0, "alpha_u": 0.12, "alpha_v": 0.4,
                         "brush_axis": [1.0, 0.0, 0.0], "hairline_depth": 0.45})
    plain = mi.load_dict({"type": "anodic_film", "thickness_nm": 80.0, "alpha_u": 0.12, "alpha_v": 0.4,
                          "brush_axis": [1.0, 0.0, 0.0]})
    rng = np.random.default_rng(3)
    across = np.stack([np.zeros(400), rng.uniform(-1, 1, 400), np.zeros(400)], -1)  # y: across the x grain
    along = across + np.array([0.37, 0.0, 0.0])  # the same lines, further along the axis
    v_across, v_along = _eval_at(mi, bsdf, across), _eval_at(mi, bsdf, along)
    np.testing.assert_allclose(v_along, v_across, rtol=1e-5)  # constant along the brush axis
    ref = _eval_at(mi, plain, across)
    spread = v_across / ref
    assert spread.std() > 0.08  # lines differ from one another ...
    assert 0.85 < np.median(spread) < 1.15  # ... around the uniform lobe


def test_isotropic_or_axisless_lobes_have_no_hairlines(mi):
    iso = mi.load_dict({"type": "anodic_film", "thickness_nm": 80.0, "alpha": 0.2, "brush_axis": [1.0, 0.0, 0.0],
                        "hairline_depth": 0.45})
    pts = np.stack([np.zeros(64), np.linspace(-1, 1, 64), np.zeros(64)], -1)
    v = _eval_at(mi, iso, pts)
    np.testing.assert_allclose(v, v[0], rtol=1e-6)
    with pytest.raises(Exception, match="hairline_depth"):
        mi.load_dict({"type": "anodic_film", "alpha_u": 0.1, "alpha_v": 0.3, "brush_axis": [1.0, 0.0, 0.0],
                      "hairline_depth": 2.0})


def test_brushed_plate_shows_lines_along_the_axis(mi):
    """A brushed plate (brushed along x: image rows) rendered and denoised: brightness varies more from row to row
    across the grain than along a row (lines, not grain), far more than without hairlines."""
    from swatch.render.mitsuba.engine import render_swatch_mitsuba

    def streakiness(depth_on: bool) -> float:
        from swatch.render.mitsuba import engine

        saved = engine.HAIRLINE_DEPTH
        try:
            engine.HAIRLINE_DEPTH = saved if depth_on else 0.0
            img = render_swatch_mitsuba(80.0, "flat", 96, 32, 1, "studio", roughness_alpha=(0.12, 0.4))
        finally:
            engine.HAIRLINE_DEPTH = saved
        Y = img.linear_rgb[40:72, 24:72] @ np.array([0.2126, 0.7152, 0.0722])
        detail = Y - (np.roll(Y, 2, 0) + np.roll(Y, -2, 0) + np.roll(Y, 2, 1) + np.roll(Y, -2, 1)) / 4
        rows = detail.mean(axis=1).std()  # structure constant along each row: lines along x
        cols = detail.mean(axis=0).std()
        return rows / max(cols, 1e-12)

    with_lines, without = streakiness(True), streakiness(False)
    print(f"row/column detail ratio: with hairlines {with_lines:.2f}, without {without:.2f}")
    assert with_lines > 2.0 and with_lines > 1.5 * without
