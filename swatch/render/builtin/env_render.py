"""Swatch renders lit by an environment (:mod:`swatch.render.environment`, :mod:`swatch.render.builtin.env_shading`).

The scene (shape, perspective camera) is the renderer's; every covered pixel is shaded at its
centre with the environment integral of the thin-film GGX BRDF (height-correlated Smith), and
pixels a silhouette crosses are re-shaded with 4 × 4 sub-samples (colour averaged, coverage =
fraction hit), as in the point-light path.

Units and display
-----------------
* Linear RGB (EXR) is scene-referred: **1.0 = a perfect white diffuser facing up (the plate's
  normal) under the same environment** (the environment is normalised to it), premultiplied by
  the coverage; with ``background="environment"`` the environment seen behind the object is
  included and the image is opaque.
* The PNG uses **exposure 1** (that white diffuser is display white) and the renderer's display
  shoulder (identity to 0.8, smooth roll-off to 1): no exposure fitted to the picture, so a
  render and the catalog's chip (the 45°:0° reflectance factor, also at exposure 1) are on one
  scale, and renders of a series of thicknesses are comparable.
* Backgrounds: ``grey`` (linear 0.18, display only), ``white`` (display white, display only),
  ``environment`` (the unblurred map along each camera ray, through the same display transform).

The environment gather (each covered pixel's samples of the map) does not depend on the
thickness: it is cached per scene (:func:`prepared`), so a catalog re-weights it per swatch.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import colour
import numpy as np

from swatch.colorimetry.colorimeter import RGB_SPACES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_ENV_RENDER_PX, MIN_ENV_RENDER_PX
from swatch.physics.finishes import brush_coordinates, brush_tangent, hairline_slope, tilt_normals
from swatch.render import environment as envmod
from swatch.render.builtin import env_shading, shading
from swatch.render.builtin.env_aniso import AnisoSampleSet, aniso_sample_set, combine_aniso, gather_aniso
from swatch.render.display import BACKGROUND_LINEAR, display_encode
from swatch.render.image import BACKGROUND_WHITE, SUPERSAMPLE, SwatchImage, edge_pixels, mesh_metadata

__all__ = ["check_env_size_px", "render_swatch_environment", "Prepared", "prepared", "render_environment"]

def check_env_size_px(size_px: int) -> int:
    """The size of an environment-lit render, checked.

    Parameters
    ----------
    size_px : int
        Pixels per side, from :data:`MIN_ENV_RENDER_PX` to :data:`MAX_ENV_RENDER_PX` (memory).

    Returns
    -------
    int
        ``size_px`` as an int.

    Raises
    ------
    SwatchError
        Outside that range (naming ```size_px```).
    """
    if int(size_px) < MIN_ENV_RENDER_PX:
        raise SwatchError(f"environment-lit renders are at least {MIN_ENV_RENDER_PX} pixels per side (got "
                          f"{int(size_px)}); use a larger `size_px`, or `environment='point'`")
    if int(size_px) > MAX_ENV_RENDER_PX:
        raise SwatchError(f"environment-lit renders are at most {MAX_ENV_RENDER_PX} pixels per side (memory); "
                          "use a smaller `size_px`, or `environment='point'`")
    return int(size_px)


#: Shading grid step (pixels): the environment integral is evaluated exactly on every
#: ``COARSE``-th pixel centre; a pixel between four such nodes is interpolated bilinearly when the
#: four are on the object and their normals are within :data:`SMOOTH_DEG` of its own (the
#: radiance is smooth there: the lobe blurs the environment over tens of degrees); every other
#: covered pixel (limbs, the cylinder's inner face, corners) is evaluated exactly.
COARSE = 4
SMOOTH_DEG = 2.0


@dataclass
class _Points:
    """Gathered environment samples of some shading points: E (P, N, 3) and view bins j (P,)
    (anisotropic: four bins per point, E (4·P, N, 3), j (4·P,), their weights ``mix`` (4, P))."""

    E: np.ndarray
    j: np.ndarray
    mix: np.ndarray | None = None

    def radiance(self, weights) -> np.ndarray:
        if self.E.shape[0] == 0:
            return np.zeros((0, 3), dtype=np.float32)
        if self.mix is not None:
            return combine_aniso(self.E, self.j, self.mix, weights)
        return env_shading.combine(self.E, self.j, weights)


@dataclass
class _Hair:
    """The hairlines of a brushed finish on the interpolated pixels, to first order in the slope: the nodes'
    samples with their normals tilted by ``+eps`` and ``-eps`` across the grain, and each interpolated pixel's
    slope (:func:`swatch.physics.finishes.hairline_slope`); the pixel's radiance is the interpolated radiance
    plus its slope times the interpolated central difference."""

    plus: _Points
    minus: _Points
    eps: float
    slope: np.ndarray  # (I,) the interpolated pixels' slopes


#: Tilt (tan) of the central difference of the hairlines' first-order term (:class:`_Hair`).
HAIR_EPS = 0.05


@dataclass
class Prepared:
    """A scene's thickness-independent part (see the module doc): which pixels are shaded how,
    their gathered environment samples, coverage and the background.

    Attributes
    ----------
    size : int
        Pixels per side.
    coverage : numpy.ndarray
        Fraction of each pixel the object covers, shape (H, W).
    nodes, exact, edge
        The coarse shading nodes, the pixels shaded exactly at their centre, and the silhouette
        pixels (shaded at the centroid of their covered sub-samples), with their gathered samples.
    interp_pixels, interp_nodes, interp_weights : numpy.ndarray
        Flat indices of the pixels interpolated from nodes (I,), their four nodes (I, 4) and
        bilinear weights (I, 4).
    exact_pixels, edge_pixels : numpy.ndarray
        Flat pixel indices (X,), (Q,).
    background : numpy.ndarray or None
        The environment behind the object (H, W, 3), or None.
    samples : swatch.render.builtin.env_shading.SampleSet or swatch.render.builtin.env_aniso.AnisoSampleSet
        The fixed GGX visible-normal samples per pixel.
    """

    size: int
    coverage: np.ndarray  # (H, W)
    nodes: _Points  # the coarse shading nodes on the object
    interp_pixels: np.ndarray  # (I,) flat pixel indices interpolated from nodes
    interp_nodes: np.ndarray  # (I, 4) indices into nodes
    interp_weights: np.ndarray  # (I, 4) bilinear weights
    exact_pixels: np.ndarray  # (X,) flat indices shaded exactly at their centre
    exact: _Points
    edge_pixels: np.ndarray  # (Q,) silhouette pixels, shaded at the centroid of their covered sub-samples
    edge: _Points
    background: np.ndarray | None  # (H, W, 3) environment behind the object, or None
    samples: env_shading.SampleSet | AnisoSampleSet
    hair: _Hair | None = None  # brushed: the hairlines of the interpolated pixels (first order)


def _surface_points(scene, x, y, size, n) -> np.ndarray:
    """Points (float32, (…, 3)) where the rays through pixel coordinates x, y meet the scene's plate, cylinder
    or sphere (unit radius), from the hits' unit normals ``n`` (the cylinder's inner face has them reversed)."""
    name = getattr(scene.shape, "name", "")
    if name == "sphere":
        return n
    o = np.asarray(scene.camera.position, dtype=np.float32)
    d = np.stack(np.broadcast_arrays(*scene.camera.directions(x, y, size, dtype=np.float32)), -1)
    if name == "flat":
        t = -o[1] / np.minimum(d[..., 1], np.float32(-1e-30))
    else:  # the cylinder's points lie at ±n in x and z: the sign that the ray passes through
        dd = np.maximum(d[..., 0] ** 2 + d[..., 2] ** 2, np.float32(1e-12))
        tr = []
        for sign in (1.0, -1.0):
            tt = ((sign * n[..., 0] - o[0]) * d[..., 0] + (sign * n[..., 2] - o[2]) * d[..., 2]) / dd
            tr.append((tt, np.hypot(o[0] + tt * d[..., 0] - sign * n[..., 0], o[2] + tt * d[..., 2] - sign * n[..., 2])))
        t = np.where(tr[0][1] <= tr[1][1], tr[0][0], tr[1][0])
    return o + t[..., None] * d


def _hair_slope(scene, x, y, size, n) -> np.ndarray | None:
    """The hairline slope at pixel coordinates x, y with hit normals n, or None for a shape without them."""
    name = getattr(scene.shape, "name", "")
    coords = brush_coordinates(name, _surface_points(scene, x, y, size, n))
    return None if coords is None else hairline_slope(*coords).astype(np.float32).reshape(-1)


def _normals_views(scene, x, y, size):
    """Hit, unit normals and views (float32, (…, 3)) for pixel coordinates x, y (broadcast)."""
    dx, dy, dz = scene.camera.directions(x, y, size, dtype=np.float32)
    hit, nx, ny, nz = scene.shape.intersect(scene.camera.position, dx, dy, dz)
    shape = hit.shape
    n = np.stack([np.broadcast_to(np.asarray(c, dtype=np.float32), shape) for c in (nx, ny, nz)], -1)
    n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), np.float32(1e-12))
    d = np.stack([np.broadcast_to(c, shape) for c in (dx, dy, dz)], -1)
    return hit, n, -d


def _self_occlusion(scene, v):
    """For a mesh, ``occluded(rows, directions)`` of :func:`swatch.render.builtin.env_shading.gather`: the sample
    directions the mesh hides from the points seen along ``-v`` (each camera ray cast again to find its point);
    None for the built-in shapes (convex, or the bent sheet, whose inner face sees the map as before)."""
    shape = scene.shape
    if not hasattr(shape, "blocked"):
        return None
    hit, where, geo = shape.surface(scene.camera.position, -np.asarray(v, dtype=np.float64).reshape(-1, 3))

    def occluded(rows, directions):
        return shape.blocked(where[rows], geo[rows], directions) & hit[rows, None]

    return occluded


_CACHE: dict = {}


def prepared(scene, scene_key, size: int, env, roughness_alpha: float, background: str, finish=None) -> Prepared:
    """The thickness-independent part of a render (cached on ``scene_key``, the environment
    object, the roughness α (or an anisotropic ``finish``'s two), the size and whether the
    background is the environment).

    Parameters
    ----------
    scene : swatch.render.scene.Scene
        Camera and shape.
    scene_key : tuple
        Identifies the scene in the cache (shape key and camera angles).
    size : int
        Pixels per side.
    env : swatch.render.environment.Environment
        The lighting (normalised: a white diffuser facing up reflects 1).
    roughness_alpha : float
        GGX α (ignored for an anisotropic finish).
    background : str
        ``grey``, ``white`` or ``environment``.
    finish : swatch.physics.finishes.Finish, optional
        An anisotropic finish's lobe (brushed); None: the isotropic ``roughness_alpha``.

    Returns
    -------
    Prepared
        The scene's thickness-independent gather (cached on ``scene_key``).
    """

    aniso = finish is not None and finish.anisotropic
    lobe = (finish.alpha_u, finish.alpha_v) if aniso else float(roughness_alpha)
    key = (scene_key, env, lobe, int(size), background == "environment")  # env hashes by identity
    if key in _CACHE:
        return _CACHE[key]
    ss: Any = aniso_sample_set(finish.alpha_u, finish.alpha_v) if aniso else env_shading.sample_set(roughness_alpha)
    maps = envmod.levels(env)
    table = env_shading.level_table(ss, maps)
    shape_name = getattr(scene.shape, "name", "sphere")

    def points(n, v, slope=None):  # slope: the hairlines' tilt of the normals (brushed)
        hidden = _self_occlusion(scene, v)
        if aniso:
            t = brush_tangent(shape_name, n)
            if slope is not None:
                n = tilt_normals(n, t, slope)
            return _Points(*gather_aniso(n, v, maps, ss, table, t, hidden))
        return _Points(*env_shading.gather(n, v, maps, ss, table, hidden))

    hairy = aniso and brush_coordinates(shape_name, np.zeros((1, 3))) is not None  # brushed plate, cylinder, sphere

    def slope_at(x, y, n):
        return _hair_slope(scene, x, y, size, n) if hairy else None

    c = np.arange(size, dtype=np.float32) + np.float32(0.5)
    rays = scene.camera.directions(c[None, :], c[:, None], size, dtype=np.float32)
    hit = np.broadcast_to(scene.shape.intersect(scene.camera.position, *rays)[0], (size, size))
    px = np.flatnonzero(hit)  # covered pixels, row-major
    iy, ix = np.divmod(px, size)
    _, n, v = _normals_views(scene, ix + np.float32(0.5), iy + np.float32(0.5), size)  # (P, 3)
    # coarse nodes: every COARSE-th row and column, and the last
    grid = np.unique(np.append(np.arange(0, size, COARSE), size - 1))
    g_hit = hit[np.ix_(grid, grid)]
    node_id = np.full(g_hit.shape, -1, dtype=np.int64)
    node_id[g_hit] = np.arange(int(g_hit.sum()))
    gy, gx = np.nonzero(g_hit)
    _, gn, gv = _normals_views(scene, grid[gx] + np.float32(0.5), grid[gy] + np.float32(0.5), size)
    nodes = points(gn, gv)
    hair_nodes = None
    if hairy:  # brushed: the nodes tilted both ways
        ones = np.ones(len(gn), dtype=np.float32)
        hair_nodes = (points(gn, gv, HAIR_EPS * ones), points(gn, gv, -HAIR_EPS * ones))
    # each covered pixel's cell (between grid[k] and grid[k + 1]) and bilinear weights
    k = np.clip(np.searchsorted(grid, np.arange(size), side="right") - 1, 0, grid.size - 2)
    f = ((np.arange(size) - grid[k]) / (grid[k + 1] - grid[k])).astype(np.float32)
    ky, kx, fy, fx = k[iy], k[ix], f[iy], f[ix]
    ids = np.stack([node_id[ky, kx], node_id[ky, kx + 1], node_id[ky + 1, kx], node_id[ky + 1, kx + 1]], -1)
    smooth = (ids >= 0).all(axis=1)
    cos_lim = np.float32(np.cos(np.radians(SMOOTH_DEG)))
    for q in range(4):
        smooth &= np.einsum("pi,pi->p", n, gn[np.maximum(ids[:, q], 0)]) >= cos_lim
    interp = px[smooth]
    ids = ids[smooth]
    fy, fx = fy[smooth, None], fx[smooth, None]
    wts = np.concatenate([(1 - fy) * (1 - fx), (1 - fy) * fx, fy * (1 - fx), fy * fx], -1).astype(np.float32)
    exact_px = px[~smooth]
    ix_f, iy_f = ix.astype(np.float32) + np.float32(0.5), iy.astype(np.float32) + np.float32(0.5)
    slope = slope_at(ix_f, iy_f, n)
    exact = points(n[~smooth], v[~smooth], None if slope is None else slope[~smooth])
    hair = None if hair_nodes is None or slope is None else _Hair(*hair_nodes, HAIR_EPS, slope[smooth])
    coverage = hit.astype(np.float32)
    # silhouettes: coverage from SUPERSAMPLE² sub-samples, colour at their covered centroid
    edge = edge_pixels(hit)
    S = SUPERSAMPLE
    off = (np.arange(S, dtype=np.float32) + np.float32(0.5)) / np.float32(S)
    ox, oy = (a.reshape(-1) for a in np.meshgrid(off, off, indexing="xy"))
    ey, ex = np.divmod(edge, size)
    sx = ex[:, None].astype(np.float32) + ox[None, :]
    sy = ey[:, None].astype(np.float32) + oy[None, :]
    dx, dy, dz = scene.camera.directions(sx, sy, size, dtype=np.float32)
    eh = scene.shape.intersect(scene.camera.position, dx, dy, dz)[0]
    cover = eh.mean(axis=1)
    keep = cover > 0
    cnt = np.maximum(eh.sum(axis=1), 1)
    cxs = (np.where(eh, sx, 0).sum(axis=1) / cnt)[keep]
    cys = (np.where(eh, sy, 0).sum(axis=1) / cnt)[keep]
    ch, cn, cv = _normals_views(scene, cxs, cys, size)
    if not ch.all():  # a centroid off a thin object: use its first covered sub-sample
        first = np.argmax(eh[keep], axis=1)
        bad = ~ch
        _ch2, cn2, cv2 = _normals_views(scene, sx[keep][bad, first[bad]], sy[keep][bad, first[bad]], size)
        cn[bad], cv[bad] = cn2, cv2
    coverage.reshape(-1)[edge] = cover
    edge_points = points(cn, cv, slope_at(cxs, cys, cn))
    bg = None
    if background == "environment":
        bg = np.empty((size, size, 3), dtype=np.float32)
        for r0 in range(0, size, 128):  # bounded temporaries
            d = np.stack([np.broadcast_to(t, (size, size))[r0:r0 + 128] for t in rays], -1)
            bg[r0:r0 + 128] = env.radiance_at(d)
    prep = Prepared(size, coverage, nodes, interp, ids, wts, exact_px, exact, edge[keep], edge_points, bg, ss, hair)
    if len(_CACHE) >= 4:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = prep
    return prep


@functools.lru_cache(maxsize=4)
def _srgb_to(space: str) -> np.ndarray | None:
    """3 × 3 matrix from linear sRGB to ``space`` (white to white, Bradford), None for sRGB."""
    if space == "srgb":
        return None

    return np.asarray(colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["sRGB"],
                                               colour.RGB_COLOURSPACES[RGB_SPACES[space]], "Bradford"))


def render_environment(prep: Prepared, f_table_srgb: np.ndarray, background: str, space: str = "srgb"):
    """Shade a prepared scene for one thickness.

    Parameters
    ----------
    prep : Prepared
        :func:`prepared`.
    f_table_srgb : numpy.ndarray
        Linear sRGB of the film's reflectance ``F`` on a uniform grid of ``cos θ_d`` over [0, 1], shape (K, 3).
    background : str
        ``grey``, ``white`` or ``environment``.
    space : str, optional
        RGB space of the linear result (``srgb`` or ``acescg``).

    Returns
    -------
    linear : numpy.ndarray
        Linear RGB in ``space`` (scene-referred, 1 = white diffuser), shape (H, W, 3) float32.
    coverage : numpy.ndarray
        Shape (H, W).
    display : numpy.ndarray
        sRGB uint8, shape (H, W, 3).
    """

    size = prep.size
    w = env_shading.band_weights(prep.samples, np.asarray(f_table_srgb, dtype=np.float64))
    flat = np.zeros((size * size, 3), dtype=np.float32)
    nodes = prep.nodes.radiance(w)
    if prep.interp_pixels.size:
        flat[prep.interp_pixels] = np.einsum("ik,ikc->ic", prep.interp_weights, nodes[prep.interp_nodes])
        if prep.hair is not None:  # the hairlines, to first order in the slope (_Hair)
            diff = (prep.hair.plus.radiance(w) - prep.hair.minus.radiance(w)) / np.float32(2 * prep.hair.eps)
            flat[prep.interp_pixels] += prep.hair.slope[:, None] * np.einsum("ik,ikc->ic", prep.interp_weights,
                                                                             diff[prep.interp_nodes])
            flat[prep.interp_pixels] = np.maximum(flat[prep.interp_pixels], np.float32(0))
    flat[prep.exact_pixels] = prep.exact.radiance(w)
    flat[prep.edge_pixels] = prep.edge.radiance(w) * prep.coverage.reshape(-1)[prep.edge_pixels, None]
    rgb = flat.reshape(size, size, 3)
    coverage = prep.coverage
    if background == "environment":
        assert prep.background is not None, "prepared() keeps the background for background='environment'"
        comp = rgb + (1.0 - coverage)[..., None] * prep.background
        display = display_encode(comp, 1.0)
        linear = comp
        coverage = np.ones_like(coverage)
    else:
        bgv = BACKGROUND_LINEAR if background == "grey" else BACKGROUND_WHITE
        comp = rgb + (1.0 - coverage)[..., None] * np.float32(bgv)
        display = display_encode(comp, 1.0)
        linear = rgb
    m = _srgb_to(space)
    if m is not None:
        linear = np.einsum("ij,...j->...i", m.astype(np.float32), linear).astype(np.float32)
    return linear, coverage, display


#: Nodes of the F table over cos θ_d in [0, 1] for environment renders (linear interpolation;
#: every sample of the lobe has its own θ_d, so the whole range is tabulated).
F_TABLE_NODES = 257


def render_swatch_environment(request, meta: dict) -> SwatchImage:
    """The environment engine of :func:`swatch.render.dispatch.render_builtin` (the request checked).

    The lighting comes resolved and checked in the request (:func:`swatch.render.lighting.resolve_lighting`:
    GGX microfacet, the environment renderer's size range), and the background checked; nothing is loaded here.

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        The render: thickness, shape and scene, size, background, α, coating, colorimeter, space, the
        camera (keys the prepared scene), the finish, and ``lighting.environment`` (the map).
    meta : dict
        The common metadata (:func:`swatch.render.metadata.common_metadata`).

    Returns
    -------
    swatch.render.image.SwatchImage
        Exposure 1 (the white diffuser under the same environment is display white).
    """
    d, scene, env, shape, size = (request.thickness_nm, request.scene, request.lighting.environment, request.shape,
                                  request.size_px)
    background, roughness_alpha, coating, colorimeter = (request.background, request.roughness_alpha,
                                                         request.coating, request.colorimeter)
    space, finish = request.space, request.finish
    light_deg, view_deg, view_azimuth_deg = request.light_deg, request.view_deg, request.view_azimuth_deg
    scene_key = (getattr(scene.shape, "key", shape), float(light_deg), None if view_deg is None else float(view_deg), float(view_azimuth_deg))
    prep = prepared(scene, scene_key, size, env, roughness_alpha, background, finish)
    tab = shading.facet_colour_table(d, coating, colorimeter, F_TABLE_NODES, (0.0, 1.0)).to_rgb(colorimeter, "srgb")
    linear, coverage, display = render_environment(prep, tab.values, background, space)
    meta = dict(meta)
    meta.update({
        "shadowing": "Smith height-correlated",
        "shape": shape,
        "geometry": scene.camera_description,
        "size_px": size,
        "rgb_space": space,
        "lighting": f"environment {env.name}: {env.description}",
        "environment": env.name,
        "environment_integration": (f"GGX visible-normal importance sampling, {prep.samples.n} fixed samples per "
                                    f"pixel, F at each sample's own theta_d, per-sample filtered environment; level "
                                    + (f"set by {prep.samples.dense_samples} samples per view bin (anisotropic: "
                                       "bins over the view's polar angle and azimuth to the brushing direction)"
                                       if isinstance(prep.samples, AnisoSampleSet)
                                       else f"set by {env_shading.DENSE_SAMPLES} samples per view angle")),
        "units": ("scene-referred linear; 1.0 = perfect white diffuser facing up (+y, the plate's normal) under the "
                  "same environment; " + ("environment behind the object included (opaque)"
                                           if background == "environment" else "RGB premultiplied by alpha (coverage)")),
        "exposure": 1.0,
        "exposure_rule": "k = 1: the white diffuser under the same environment is display white (comparable with "
                         "the 45:0 chip, which is a reflectance factor at k = 1)",
        "display": (f"sRGB-encoded PNG: linear x 1, composited on {background}"
                    + ("" if background == "environment" else
                       f" ({BACKGROUND_LINEAR if background == 'grey' else BACKGROUND_WHITE:g})")
                    + ", shoulder above 0.8 (identity below, smooth roll-off to 1)"),
        "wavelength_grid_nm": f"{coating.wavelength_nm[0]:g}:{coating.wavelength_nm[-1]:g}:"
                              f"{coating.wavelength_nm[1] - coating.wavelength_nm[0]:g}",
    })
    if shape == "mesh":
        meta["lighting"] += ("; the mesh hides the environment from itself (self-occlusion: what it hides is dark, "
                             "no interreflection)")
    return SwatchImage(linear, coverage, display, meta | mesh_metadata(scene.shape if shape == "mesh" else None), 1.0)
