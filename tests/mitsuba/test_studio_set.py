"""The heroes' studio set (swatch.render.studio_set) against Mitsuba's own scene, and its baked cyclorama
(swatch.render.mitsuba.bake) against an independent quadrature of the direct light (#46).

References we did not write: Mitsuba's ray intersection of the scene it renders the heroes in (the cyclorama mesh and
the soft boxes' rectangles), and the irradiance of the set's emitters integrated here over the hemisphere by the
midpoint rule in numpy (not Mitsuba's sampling).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from swatch.render import studio_set as ss
from tests.helpers import random_directions
from tests.mitsuba_setup import jit_of, mitsuba_variant


@pytest.mark.parametrize("floor_y", [-1.0, -0.02])
def test_the_set_is_where_mitsuba_traces_it(floor_y):
    """From the object's centre and from a camera, the first thing of the set each ray meets (cyclorama or which soft
    box) and how far, as Mitsuba's ray intersection of the scene the heroes are rendered in finds it."""
    mi = mitsuba_variant()
    from swatch.render.mitsuba.scene import lighting, load_scene

    entries = lighting("studio", floor_y)
    scene = load_scene({"type": "scene", **entries})
    assert sorted(s.id() for s in scene.shapes()) == sorted(["cyclorama", *(b.name for b in ss.SOFT_BOXES)])
    frames = ss.box_frames()
    for origin in (np.zeros(3), np.array([0.0, 1.368, 3.759])):
        d = random_directions(np.random.default_rng(3), 4000)
        o = np.broadcast_to(origin, d.shape)
        si = scene.ray_intersect(mi.Ray3f(jit_of(mi.Point3f, o.T), jit_of(mi.Vector3f, d.T)))
        t_mi = np.asarray(si.t, dtype=np.float64)
        hit_mi = np.asarray(si.is_valid())
        t_cyc, _, _ = ss.cyclorama_hit(origin, d, floor_y)
        t_box = np.full(len(d), np.inf)
        for c, hu, hv, n in frames:
            dn = d @ n
            with np.errstate(divide="ignore", invalid="ignore"):
                t = ((c - origin) @ n) / dn
            p = origin + d * t[:, None] - c
            inside = (np.abs(p @ hu) <= hu @ hu) & (np.abs(p @ hv) <= hv @ hv) & (t > 0)
            t_box = np.where(inside, np.minimum(t_box, t), t_box)
        t_ours = np.minimum(t_cyc, t_box)
        assert np.array_equal(np.isfinite(t_ours), hit_mi) or np.mean(np.isfinite(t_ours) != hit_mi) < 0.002
        both = np.isfinite(t_ours) & hit_mi
        # the cove is faceted in Mitsuba's mesh (16 facets): up to r (1 - cos(pi / 64)) = 2.4e-3 off the circle
        assert np.quantile(np.abs(t_ours[both] - t_mi[both]), 0.998) < 0.02
        assert np.median(np.abs(t_ours[both] - t_mi[both])) < 1e-4


def test_the_box_frames_are_mitsubas():
    """Each soft box's corners where Mitsuba puts the rectangle (its to_world applied to the unit square's corners)."""
    mitsuba_variant()
    from swatch.render.mitsuba.scene import lighting

    entries = lighting("studio", -1.0)
    for box, (c, hu, hv, n) in zip(ss.SOFT_BOXES, ss.box_frames(), strict=True):
        m = np.asarray(entries[box.name]["to_world"].matrix, dtype=np.float64)
        for a, b in ((1, 1), (-1, 1), (1, -1)):
            corner = (m @ np.array([a, b, 0.0, 1.0]))[:3]
            assert np.allclose(corner, c + a * hu + b * hv, atol=1e-5)
        normal = (m @ np.array([0.0, 0.0, 1.0, 0.0]))[:3]
        assert np.allclose(normal / np.linalg.norm(normal), n, atol=1e-6)
        assert box.radiance > 0 and np.dot(n, -c) > 0  # facing the object


def test_lightmap_lookup_inverts_its_axes():
    """The page's lookup (the inverse sinh warp, bilinear in texels) of a map sampled on the axes returns a linear
    function, within the warp's curvature over a texel (1e-4 of values near 0.5)."""
    x, s = ss.lightmap_axes(96, 128)
    f = lambda xx, sv: 0.3 + 0.01 * xx + 0.02 * sv  # noqa: E731
    lm = f(x[None, :], s[:, None])
    rng = np.random.default_rng(1)
    xq = rng.uniform(x[0], x[-1], 500)
    sq = rng.uniform(s[0], s[-1], 500)
    from swatch.render.studio_set import _lightmap_lookup  # (the lookup the page mirrors)

    assert np.allclose(_lightmap_lookup(lm, xq, sq), f(xq, sq), atol=3e-4)
    assert not np.allclose(_lightmap_lookup(lm, xq, sq + 0.5), f(xq, sq), atol=3e-4)  # (it can fail)


def _direct_quadrature(p: np.ndarray, floor_y: float, scale: float, n_theta: int = 400, n_phi: int = 800) -> float:
    """Radiance leaving a floor point ``p`` lit directly by the set (boxes and fill; the cyclorama itself black) around
    a black unit sphere at the origin: albedo / π × ∫ L cos θ dω by the midpoint rule on the upper hemisphere."""
    th = (np.arange(n_theta) + 0.5) * (0.5 * math.pi / n_theta)
    ph = (np.arange(n_phi) + 0.5) * (2 * math.pi / n_phi)
    T, P = np.meshgrid(th, ph, indexing="ij")
    d = np.stack([np.sin(T) * np.cos(P), np.cos(T), np.sin(T) * np.sin(P)], -1).reshape(-1, 3)
    t_cyc, _, _ = ss.cyclorama_hit(p + np.array([0.0, 1e-6, 0.0]), d, floor_y)
    # the object: the unit sphere at the origin, black while the shadow map is baked
    b = d @ p
    disc = b * b - (p @ p - 1.0)
    t_obj = np.where(disc > 0, -b - np.sqrt(np.maximum(disc, 0.0)), np.inf)
    t_obj = np.where(t_obj > 0, t_obj, np.inf)
    L = np.where(np.isfinite(t_cyc) | np.isfinite(t_obj), 0.0, ss.FILL_RADIANCE)
    best = np.minimum(t_cyc, t_obj)
    for (c, hu, hv, n), box in zip(ss.box_frames(), ss.SOFT_BOXES, strict=True):
        dn = d @ n
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((c - p) @ n) / dn
        q = p + d * t[:, None] - c
        hit = (np.abs(q @ hu) <= hu @ hu) & (np.abs(q @ hv) <= hv @ hv) & (t > 0) & (t < best)
        L = np.where(hit, np.where(dn < 0, box.radiance, 0.0), L)
        best = np.where(hit, t, best)
    w = (np.cos(T) * np.sin(T)).reshape(-1) * (0.5 * math.pi / n_theta) * (2 * math.pi / n_phi)
    return float(ss.CYCLORAMA_ALBEDO / math.pi * (L * w).sum() * scale)


@pytest.mark.slow
def test_baked_floor_is_the_direct_light_of_the_set():
    """Direct light only (path depth 2), the baked floor around the object (in its soft shadow and out of it) is the
    set's irradiance integrated here, within 6 % (the noise of the bake's 256 samples a texel, smoothed over a texel:
    at 1024 samples the same points agree within 3 %)."""
    mitsuba_variant()
    from swatch.render.mitsuba.bake import cyclorama_lightmap

    shadow, bounce, scale, floor = cyclorama_lightmap("sphere", max_depth=2)
    x, s = ss.lightmap_axes(shadow.shape[1], shadow.shape[0])
    y, z, _, _ = ss.profile_point(s, floor)
    for sv, xv in ((4.0, 2.5), (9.5, -3.0), (6.0, 0.0), (2.0, -1.0)):  # floor points around the sphere
        i, j = np.argmin(np.abs(s - sv)), np.argmin(np.abs(x - xv))
        ref = _direct_quadrature(np.array([x[j], y[i], z[i]]), floor, scale)
        assert shadow[i, j] == pytest.approx(ref, rel=0.06)
    # under the object: its shadow; and a white metal object only adds light
    i0, j0 = np.argmin(np.abs(s - ss.FRONT_Z)), np.argmin(np.abs(x))
    assert shadow[i0, j0] < 0.3 * shadow[np.argmin(np.abs(s - 4.0)), np.argmin(np.abs(x - 2.5))]
    assert np.all(bounce >= 0)
