"""Brushed reads brushed (issue 37): the hairlines of :func:`swatch.physics.finishes.hairline_slope` in the
built-in engine. The field varies across the grain and hardly along it, within its bound, and is deterministic;
the tilt is a rotation of the facet normal about the grain; a brushed render shows lines along the grain (pixel
differences across the grain several times those along it) where satin does not, and the four finishes differ
at a glance; the first-order shading of the interpolated pixels (swatch.render.builtin.env_render._Hair) is close to
shading every pixel with its own tilted normal; reruns are byte-identical."""
from __future__ import annotations

import numpy as np
import pytest

from swatch.physics.finishes import (
    HAIRLINE_SLOPE,
    brush_coordinates,
    brush_tangent,
    get_finish,
    hairline_slope,
    tilt_normals,
)
from swatch.render import render_swatch
from swatch.render.builtin import env_render
from tests.cli_helpers import run_swatch
from tests.helpers import random_directions


def test_the_field_runs_along_the_grain_within_its_bound_and_is_deterministic():
    across = np.linspace(-1.0, 1.0, 4001)
    s_across = hairline_slope(across, 0.3)
    s_along = hairline_slope(0.3, across)
    assert np.abs(s_across).max() <= HAIRLINE_SLOPE and np.abs(s_along).max() <= HAIRLINE_SLOPE
    assert s_across.std() > 0.15 * HAIRLINE_SLOPE  # lines, not a flat field
    # per unit length the slope changes tens of times faster across the grain than along it
    rate_across = np.abs(np.diff(s_across)).sum() / 2.0
    rate_along = np.abs(np.diff(s_along)).sum() / 2.0
    assert rate_across > 20 * rate_along, (rate_across, rate_along)
    assert abs(s_across.mean()) < 0.2 * s_across.std()  # no net tilt: the mean normal is the surface's
    np.testing.assert_array_equal(hairline_slope(across, 0.3), s_across)
    # a few values against the lattice of the field (not a regression of arbitrary numbers: the same point, the
    # same slope, from any array shape)
    np.testing.assert_array_equal(hairline_slope(across[::7].reshape(-1, 1), [0.3]).ravel(), s_across[::7])


def test_tilt_is_a_rotation_about_the_grain():
    rng = np.random.default_rng(1)
    n = random_directions(rng, 200)
    t = brush_tangent("sphere", n)
    s = rng.uniform(-HAIRLINE_SLOPE, HAIRLINE_SLOPE, 200)
    m = tilt_normals(n, t, s)
    np.testing.assert_allclose(np.linalg.norm(m, axis=1), 1.0, atol=1e-6)
    np.testing.assert_allclose(np.einsum("pi,pi->p", m, t), 0.0, atol=1e-6)  # the grain stays a tangent
    # turned by atan(s) (the sine of the angle: float32 arccos is coarse at small angles)
    np.testing.assert_allclose(np.linalg.norm(np.cross(m, n), axis=1), np.sin(np.arctan(np.abs(s))), atol=1e-5)


def test_coordinates_follow_each_shape_s_grain():
    p = np.array([[0.2, 0.0, -0.4], [0.0, 0.5, 1.0]])
    across, along = brush_coordinates("flat", p)
    np.testing.assert_allclose(across, [-0.4, 1.0])
    np.testing.assert_allclose(along, [0.2, 0.0])  # the plate is brushed along x
    across, along = brush_coordinates("sphere", p)
    np.testing.assert_allclose(along, [0.0, 0.5])  # the sphere and the cylinder along the vertical
    assert brush_coordinates("mesh", p) is None


def _texture(img: np.ndarray) -> tuple[float, float]:
    """Fine texture in the middle of the object: the mean |second difference| of neighbouring pixels along the
    image's x and y (display codes, green channel; second differences leave out the smooth shading)."""
    g = img[..., 1].astype(np.float64)
    h, w = g.shape
    c = g[h // 4: 3 * h // 4, w // 3: 2 * w // 3]
    return float(np.abs(np.diff(c, 2, axis=1)).mean()), float(np.abs(np.diff(c, 2, axis=0)).mean())


@pytest.mark.parametrize("shape, axis", [("cylinder", 0), ("flat", 1)])
def test_brushed_shows_lines_along_the_grain_and_satin_does_not(shape, axis):
    """The cylinder is brushed along its (vertical) axis: lines run up the picture and the fine texture is across
    it, along x; the plate along x, left to right, its texture along y. Satin, isotropic, has hardly any."""
    brushed = _texture(render_swatch(50.8, shape, 192, environment="studio", finish=get_finish("brushed")).display_rgb)
    satin = _texture(render_swatch(50.8, shape, 192, environment="studio", finish=get_finish("satin")).display_rgb)
    print(shape, "brushed", brushed, "satin", satin)
    assert brushed[axis] > 3 * brushed[1 - axis], brushed  # lines: texture across the grain, not along it
    assert brushed[axis] > 4 * satin[axis] and brushed[axis] > 1.0, (brushed, satin)


def test_the_four_finishes_tell_apart():
    """The isotropic finishes differ on the cylinder by several display codes on average; brushed, whose
    hairlines are tilts about the surface (no net change of brightness), differs from each by its lines: a fine
    texture several times theirs (issue 37: brushed and satin differed by 3.75 / 255, no lines)."""
    imgs = {f: render_swatch(50.8, "cylinder", 128, environment="studio", finish=get_finish(f)).display_rgb
            for f in ("polished", "satin", "bead-blasted", "brushed")}
    iso = ["polished", "satin", "bead-blasted"]
    for i, a in enumerate(iso):
        for b in iso[i + 1:]:
            d = np.abs(imgs[a].astype(np.float64) - imgs[b]).mean()
            assert d > 4.0, (a, b, d)
    lines = _texture(imgs["brushed"])[0]
    for f in iso:
        print(f, _texture(imgs[f])[0], "brushed", lines)
        assert lines > 3 * _texture(imgs[f])[0], f


def test_first_order_hairlines_match_every_pixel_shaded_exactly(monkeypatch):
    """The interpolated pixels take the hairlines to first order (the nodes' central difference); shading every
    pixel with its own tilted normal (no interpolation: SMOOTH_DEG NaN, so no pixel counts as smooth) gives nearly
    the same picture. On the plate, where every pixel is interpolated (a curved shape at catalog sizes has its
    normals more than SMOOTH_DEG apart between nodes and is shaded exactly anyway)."""
    f = get_finish("brushed")
    env_render._CACHE.clear()
    fast = render_swatch(50.8, "flat", 160, environment="studio", finish=f).display_rgb.astype(np.float64)
    interpolated = next(iter(env_render._CACHE.values())).interp_pixels.size
    env_render._CACHE.clear()
    monkeypatch.setattr(env_render, "SMOOTH_DEG", float("nan"))
    exact = render_swatch(50.8, "flat", 160, environment="studio", finish=f).display_rgb.astype(np.float64)
    assert interpolated > 5000 and next(iter(env_render._CACHE.values())).interp_pixels.size < 0.01 * interpolated
    env_render._CACHE.clear()
    err = np.abs(fast - exact)
    print("interpolated", interpolated, "mean", err.mean(), "p99", np.percentile(err, 99), "max", err.max())
    assert err.mean() < 1.0 and np.percentile(err, 99) < 6.0


def test_brushed_render_is_byte_identical_on_rerun(tmp_path):
    for k in (1, 2):
        r = run_swatch("render", "--thickness", "50.8", "--shape", "sphere", "--finish", "brushed", "--size", "96",
                       "--out", tmp_path / str(k))
        assert r.returncode == 0, r.stderr
    for name in ("sphere_050.8nm.png", "sphere_050.8nm.exr"):
        assert (tmp_path / "1" / name).read_bytes() == (tmp_path / "2" / name).read_bytes()
