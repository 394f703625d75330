"""The studio set's cyclorama baked by the path tracer: its radiance on a grid, with the object's shadow.

For each texel of :func:`swatch.render.studio_set.lightmap_axes` a ray comes down onto the cyclorama along its
normal and Mitsuba's path integrator returns the radiance leaving that point (the soft boxes and the fill by
next-event estimation, the object's shadow, every bounce up to :data:`swatch.render.mitsuba.engine.PATH_BOUNCES`),
averaged over ``spp`` samples (a fixed seed: the same bytes every run). The cyclorama is diffuse, so that radiance
is the one every camera sees there: the catalog page draws the backdrop from it (:mod:`swatch.catalog.explorer_env`).
The object is in the place and shape of the renders, twice: black (:data:`SHADOW_BSDF`: the set with the object's
shadow and nothing from it) and a white rough metal (:data:`BOUNCE_BSDF`), whose difference is the light the object
throws onto the set per unit of its reflectance: the page tints it with the film's albedo, so the floor takes the
colour of the part as in the heroes. Each result is the luminance (the set is neutral; Rec.709 Y of the spectral
estimate) times the render's radiance scale (:func:`swatch.render.mitsuba.engine.studio_scale`), in the units of the
hero renders.
"""
from __future__ import annotations

import drjit as dr
import mitsuba as mi
import numpy as np
from scipy.ndimage import gaussian_filter

from swatch.render import studio_set as ss
from swatch.render.mitsuba.engine import PATH_BOUNCES, floor_y, studio_scale, use_variant
from swatch.render.mitsuba.scene import jit_float, lighting, load_scene, object_shapes

__all__ = ["SHADOW_BSDF", "BOUNCE_BSDF", "LIGHTMAP_TEXELS", "LIGHTMAP_SPP", "cyclorama_lightmap"]

#: The object while the set's shadow map is baked: black.
SHADOW_BSDF = {"type": "diffuse", "reflectance": 0.0}
#: The object while the bounce map is baked: white metal, satin (α 0.2).
BOUNCE_BSDF = {"type": "roughconductor", "material": "none", "specular_reflectance": 1.0, "alpha": 0.2}
#: The lightmap's texels (across, along the profile).
LIGHTMAP_TEXELS = (96, 128)
#: Samples per texel.
LIGHTMAP_SPP = 256
#: How far above the cyclorama a texel's ray starts (the cove is faceted in the scene by up to 2.4e-3).
_OFFSET = 5e-3
_REC709_Y = (0.2126, 0.7152, 0.0722)
#: The lightmaps' smoothing (Gaussian σ, texels): the bake's noise, below the shadow's softness.
_SMOOTH_TEXELS = 1.0


def cyclorama_lightmap(shape: str, mesh=None, texels: tuple[int, int] = LIGHTMAP_TEXELS, spp: int = LIGHTMAP_SPP,
                       seed: int = 0, max_depth: int = PATH_BOUNCES) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The cyclorama's radiance around ``shape`` (module doc).

    Parameters
    ----------
    shape : str
        ``flat``, ``cylinder``, ``sphere`` or ``mesh``.
    mesh : swatch.render.mesh.MeshShape, optional
        With ``shape="mesh"``.
    texels : (int, int), optional
        Texels across (``x``) and along the profile (``s``).
    spp : int, optional
        Paths per texel.
    seed : int, optional
        The sampler's seed.
    max_depth : int, optional
        Mitsuba's path depth (2: direct light only).

    Returns
    -------
    shadow : numpy.ndarray, shape (ns, nx), float32
        Radiance (grey) on the grid of :func:`swatch.render.studio_set.lightmap_axes` with a black object, in the
        renders' units.
    bounce : numpy.ndarray, shape (ns, nx), float32
        What a white metal object adds to it (multiplied by the part's albedo on the page).
    scale : float
        The render's radiance scale (the boxes' and the fill's radiance are multiplied by it).
    floor : float
        The floor's height under the shape.
    """
    use_variant()
    fy = floor_y(shape, mesh)
    lights = lighting("studio", fy)
    scale = studio_scale(lights)
    integrator = mi.load_dict({"type": "path", "max_depth": int(max_depth)})
    nx, ns = texels
    xs, s = ss.lightmap_axes(nx, ns)
    y, z, ny, nz = ss.profile_point(s, fy)
    n = nx * ns
    ox = np.broadcast_to(xs[None, :], (ns, nx)).reshape(-1)
    oy = np.broadcast_to((y + _OFFSET * ny)[:, None], (ns, nx)).reshape(-1)
    oz = np.broadcast_to((z + _OFFSET * nz)[:, None], (ns, nx)).reshape(-1)
    dy = np.broadcast_to(-ny[:, None], (ns, nx)).reshape(-1)
    dz = np.broadcast_to(-nz[:, None], (ns, nx)).reshape(-1)
    rep = lambda a: jit_float(np.repeat(a, spp))  # noqa: E731  (each texel's samples side by side)
    maps = []
    for bsdf in (SHADOW_BSDF, BOUNCE_BSDF):
        scene = load_scene({"type": "scene", **object_shapes(shape, bsdf, mesh), **lights})
        sampler = mi.load_dict({"type": "ldsampler", "sample_count": spp})  # low discrepancy over each texel's samples
        sampler.seed(seed, n * spp)
        ray = mi.Ray3f(mi.Point3f(rep(ox), rep(oy), rep(oz)), mi.Vector3f(dr.zeros(mi.Float, n * spp), rep(dy), rep(dz)))
        wavelengths, weight = mi.sample_rgb_spectrum(sampler.next_1d())
        ray.wavelengths = wavelengths
        L, _, _ = integrator.sample(scene, sampler, ray)
        rgb = np.asarray(mi.spectrum_to_srgb(L * weight, wavelengths), dtype=np.float64)  # (3, n·spp)
        maps.append((np.asarray(_REC709_Y) @ rgb).reshape(ns, nx, spp).mean(axis=-1) * scale)
    shadow = gaussian_filter(maps[0], _SMOOTH_TEXELS, mode="nearest")
    bounce = gaussian_filter(np.maximum(maps[1] - maps[0], 0.0), _SMOOTH_TEXELS, mode="nearest")
    return shadow.astype(np.float32), bounce.astype(np.float32), float(scale), float(fy)
