"""Swatch renders (flat plate, half cylinder, sphere): the table-lookup renderer.

Light and colour
----------------
A directional light whose spectrum is the colorimeter's illuminant (D65 by default, as the
paper's CG) lights the swatch; the camera records CIE XYZ, converted to linear RGB. Pixel values
are scene-referred with **1.0 = a perfect white diffuser lit by the same light at normal
incidence**: a pixel is ``XYZ(F(·; d, θ_d)) · s`` (see :mod:`swatch.shading`) with
``s = π D G cos θ_l / (4 cos θ_l cos θ_v)`` for the microfacet model and ``s = 1`` (lit and
seen) for the paper's model. The scenes (camera, shapes, light) are in :mod:`swatch.scene`; the
display image's exposure and tone shoulder in :mod:`swatch.display`.

Anti-aliasing: each pixel is shaded at its centre; pixels on or next to a silhouette edge are
re-rendered with 4 × 4 stratified sub-samples (colour averaged, coverage = fraction hit), so
edges are anti-aliased at a cost proportional to the outline, not the area. ``linear_rgb`` is
premultiplied by the ``coverage`` (background 0, as EXR expects); ``display_rgb`` is
composited on a neutral grey (linear 0.18, sRGB 118).
"""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from swatch import microfacet, shading
from swatch.colorimetry import check_rgb_space
from swatch.display import BACKGROUND_LINEAR, display_encode, exposure
from swatch.errors import SwatchError
from swatch.limits import MAX_ANISO_RENDER_PX, MAX_SIZE_PX
from swatch.metadata import coating_and_colorimeter, common_metadata
from swatch.scene import Scene, check_shape, make_scene

__all__ = ["SwatchImage", "render_swatch", "render_scene", "check_size_px", "check_finish_lighting", "finish_meta"]

SUPERSAMPLE = 4
#: Nodes of a render's cos θ_d table over the range its pixels span (refined 16× for lookups;
#: the range is narrow, so 129 nodes are far denser than the 1025 of the full [0, 1] table).
RENDER_TABLE_NODES = 129
TILE_ROWS = 64


def check_size_px(size_px) -> int:
    try:
        ok = float(size_px) == int(size_px)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(size_px) <= MAX_SIZE_PX:
        raise SwatchError(f"image size must be a whole number of pixels from 1 to {MAX_SIZE_PX}, got {size_px!r}")
    return int(size_px)


@dataclass
class SwatchImage:
    """A rendered swatch: scene-referred linear RGB (premultiplied), coverage, display sRGB, metadata."""

    linear_rgb: np.ndarray
    coverage: np.ndarray
    display_rgb: np.ndarray
    metadata: dict = field(default_factory=dict)
    exposure: float = 1.0

    @property
    def rgba(self) -> np.ndarray:
        return np.concatenate([self.linear_rgb, self.coverage[..., None]], axis=-1)


def _terms(scene: Scene, u, w, inv):
    """(hit, cos_l, cos_v, cos_h, cos_d) for the camera rays at window coordinates (u, w)."""
    cam = scene.camera
    t32 = inv.dtype.type
    hit, cos_l, cos_v = scene.shape.trace(cam, u, w, inv, scene.light)
    lv = cam.dot(u, w, inv, -scene.light)  # l·v with v = -d
    cos_d = np.sqrt(np.maximum((lv + t32(1.0)) * t32(0.5), t32(1e-12)))
    cos_h = (cos_l + cos_v) * (t32(0.5) / cos_d)  # n·(l+v)/|l+v|, |l+v| = 2 cos θ_d
    return hit, cos_l, cos_v, cos_h, cos_d


def _intensity(hit, cos_l, cos_v, cos_h, cos_d, model, roughness_alpha, distribution):
    """The render's intensity factor s (zero off the object)."""
    if model == "microfacet" and distribution == "ggx":
        s = microfacet.ggx_reflectance_factor_cos(cos_l, cos_v, cos_h, roughness_alpha)
        s *= hit
        return s
    s = shading.intensity(cos_l, cos_v, cos_h, cos_d, model, roughness_alpha, distribution, irradiance=True)
    return np.where(hit, s, s.dtype.type(0.0))


def _edge_pixels(hit: np.ndarray) -> np.ndarray:
    """Pixels whose centre differs from one of its 8 neighbours' (flat indices): the pixels a
    silhouette crosses (a corner clipped by less than a pixel's diagonal half is the only miss)."""
    e = np.zeros_like(hit)
    for a, b in (((slice(None), slice(1, None)), (slice(None), slice(None, -1))),
                 ((slice(1, None), slice(None)), (slice(None, -1), slice(None))),
                 ((slice(1, None), slice(1, None)), (slice(None, -1), slice(None, -1))),
                 ((slice(1, None), slice(None, -1)), (slice(None, -1), slice(1, None)))):
        d = hit[a] != hit[b]
        e[a] |= d
        e[b] |= d
    return np.flatnonzero(e)


def _fine_index(fine, cos_d) -> np.ndarray:
    """Nearest node of a refined table (linear interpolation of the coarse table, see
    :meth:`swatch.shading.FacetColourTable.lookup_nearest`)."""
    t32 = np.float32
    x = (cos_d - t32(fine.c0)) * t32((fine.nodes - 1) / max(fine.c1 - fine.c0, 1e-12)) + t32(0.5)
    return np.clip(x, t32(0), t32(fine.nodes - 1)).astype(np.int32)


def render_scene(scene: Scene, table, size_px: int, model: str, roughness_alpha: float, distribution: str,
                 display_table=None, workers: int | None = None, background_linear: float = BACKGROUND_LINEAR):
    """Render ``scene`` with the colour ``table`` (linear RGB; the fast, table-lookup path).

    Returns (linear_rgb premultiplied (H, W, 3), coverage (H, W), display uint8 (H, W, 3), exposure,
    rule, (c0, c1)). ``table`` is an XYZ or RGB :class:`swatch.shading.FacetColourTable` *factory*
    ``table(c0, c1)`` called with the cos θ_d range of the image, or a ready table.
    ``display_table`` (same form) gives linear sRGB for the display when ``table`` is another space.
    """
    size = int(size_px)
    dt = np.float32
    t32 = np.float32

    # Pre-pass on every 4th pixel centre: the cos θ_d range (for the table) and the exposure.
    sub = np.arange(0, size, 4, dtype=dt) + dt(0.5)
    edge_c = np.array([0.0, size / 2, size], dtype=dt)
    xs = np.concatenate([sub, edge_c])
    hit, cl, cv, ch, cd = _terms(scene, *scene.camera.window(xs[None, :], xs[:, None], size, dtype=dt))
    s = _intensity(hit, cl, cv, ch, cd, model, roughness_alpha, distribution)
    n_sub = sub.size
    k, rule = exposure(model, s[:n_sub, :n_sub], ch[:n_sub, :n_sub], hit[:n_sub, :n_sub], roughness_alpha, distribution)
    lo, hi = float(cd.min()), float(cd.max())
    pad = 0.05 * (hi - lo) + 2e-3
    c0, c1 = max(0.0, lo - pad), min(1.0, hi + pad)
    tab = table(c0, c1) if callable(table) else table
    fine = tab.refined(16)
    dfine = None
    if display_table is not None:
        dtab = display_table(c0, c1) if callable(display_table) else display_table
        dfine = dtab.refined(16)

    rgb = np.empty((size, size, 3), dtype=dt)
    coverage = np.empty((size, size), dtype=dt)
    display = np.empty((size, size, 3), dtype=np.uint8)
    cols = np.arange(size, dtype=dt) + dt(0.5)
    kk = t32(k)
    bg = t32(background_linear)

    def tile(r0, r1):
        rows = (np.arange(r0, r1, dtype=dt) + dt(0.5))[:, None]
        hit, cl, cv, ch, cd = _terms(scene, *scene.camera.window(cols[None, :], rows, size, dtype=dt))
        s = _intensity(hit, cl, cv, ch, cd, model, roughness_alpha, distribution)
        idx = _fine_index(fine, cd)
        s3 = s[..., None]
        np.multiply(np.take(fine.values, idx, axis=0), s3, out=rgb[r0:r1])
        coverage[r0:r1] = hit
        src = rgb[r0:r1] if dfine is None else np.take(dfine.values, idx, axis=0) * s3
        display_encode(src, k, (~hit, background_linear), out=display[r0:r1])

    bounds = [*list(range(0, size, TILE_ROWS)), size]
    n_workers = int(workers or 1)  # threads gain little for numpy ufuncs on 2 cores; opt-in
    if n_workers > 1 and len(bounds) > 2:
        with ThreadPoolExecutor(max_workers=n_workers) as pool:
            list(pool.map(lambda i: tile(bounds[i], bounds[i + 1]), range(len(bounds) - 1)))
    else:
        for i in range(len(bounds) - 1):
            tile(bounds[i], bounds[i + 1])

    # Anti-aliasing: re-render silhouette pixels with SUPERSAMPLE² stratified sub-samples.
    edge = _edge_pixels(coverage > 0.5)
    if edge.size:
        n = SUPERSAMPLE
        off = (np.arange(n, dtype=dt) + dt(0.5)) / dt(n)
        ox, oy = (a.reshape(-1) for a in np.meshgrid(off, off, indexing="xy"))
        ey, ex = np.divmod(edge, size)
        u, w, inv = scene.camera.window(ex[:, None].astype(dt) + ox[None, :],
                                        ey[:, None].astype(dt) + oy[None, :], size, dtype=dt)
        hit, cl, cv, ch, cd = _terms(scene, *np.broadcast_arrays(u, w, inv))
        s = _intensity(hit, cl, cv, ch, cd, model, roughness_alpha, distribution)
        idx = _fine_index(fine, cd)
        a = hit.mean(axis=1, dtype=np.float64).astype(dt)
        col = (np.take(fine.values, idx, axis=0) * s[..., None]).mean(axis=1)
        rgb.reshape(-1, 3)[edge] = col
        coverage.reshape(-1)[edge] = a
        if dfine is not None:
            col = (np.take(dfine.values, idx, axis=0) * s[..., None]).mean(axis=1)
        comp = col * kk + (t32(1.0) - a)[:, None] * bg
        display.reshape(-1, 3)[edge] = display_encode(comp)  # exposure and background already in
    return rgb, coverage, display, float(k), rule, (c0, c1)


def render_swatch(thickness_nm: float, shape: str, size_px: int = 512, light_deg: float = 45.0,
                  roughness_alpha: float = 0.3, model: str = "microfacet", coating=None, colorimeter=None,
                  space: str = "srgb", distribution: str = "ggx", workers: int | None = None,
                  environment=None, background: str = "grey", view_deg: float | None = None,
                  view_azimuth_deg: float = 0.0, mesh=None, finish=None) -> SwatchImage:
    """Render one swatch (see the module documentation for scene, units and exposure).

    Returns a :class:`SwatchImage`: ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in
    ``space`` (srgb or acescg), premultiplied by the ``coverage`` (H, W); ``display_rgb``
    (H, W, 3) uint8 sRGB, exposure applied and composited on neutral grey; ``metadata``.
    ``environment``: None (the point light) or an environment (name, path or
    :class:`swatch.environment.Environment`), rendered by :mod:`swatch.env_render`;
    ``background``: grey, white or (with an environment) environment; ``view_deg`` and
    ``view_azimuth_deg``: the camera (:func:`swatch.scene.make_scene`); ``mesh``: a
    :class:`swatch.mesh.MeshShape` rendered instead of ``shape`` (which is then ``"mesh"``);
    ``finish``: a :class:`swatch.finishes.Finish` (its roughness replaces ``roughness_alpha``; an
    anisotropic one, brushed, is rendered under an environment only).
    """
    from swatch.model import check_thickness_nm

    d = float(check_thickness_nm(float(thickness_nm)))
    shape = "mesh" if mesh is not None else check_shape(shape)
    size = check_size_px(size_px)
    if finish is not None:
        roughness_alpha = finish.roughness_alpha
        check_finish_lighting(finish, environment, model, distribution, size)
    model = shading.check_model(model)
    roughness_alpha = microfacet.check_roughness_alpha(roughness_alpha)
    distribution = microfacet.check_distribution(distribution)
    space = check_rgb_space(space)
    coating, colorimeter = coating_and_colorimeter(coating, colorimeter)
    scene = make_scene(shape, light_deg, view_deg, view_azimuth_deg, mesh)
    from swatch import env_render

    background = env_render.check_background(background)
    if environment is not None:
        return env_render.render_swatch_environment(
            d, shape, scene, size, environment, background, roughness_alpha, model, distribution, coating, colorimeter,
            space, common_metadata(d, coating, colorimeter, model, distribution, roughness_alpha) | finish_meta(finish),
            (light_deg, view_deg, view_azimuth_deg), finish)
    if background == "environment":
        raise SwatchError("background 'environment' needs an environment; use grey or white with the point light")
    bg_linear = BACKGROUND_LINEAR if background == "grey" else env_render.BACKGROUND_WHITE

    def table(c0, c1, sp=space):
        return shading.facet_colour_table(d, coating, colorimeter, RENDER_TABLE_NODES, (c0, c1)).to_rgb(colorimeter, sp)

    display_table = None if space == "srgb" else (lambda c0, c1: table(c0, c1, "srgb"))
    rgb, coverage, display, k, rule, crange = render_scene(scene, table, size, model, roughness_alpha, distribution,
                                                           display_table, workers, bg_linear)

    meta = common_metadata(d, coating, colorimeter, model, distribution, roughness_alpha)
    meta.update({
        "shadowing": "Smith height-correlated" if model == "microfacet" else "none",
        "shape": shape,
        "geometry": scene.description,
        "light_deg": float(light_deg),
        "size_px": size,
        "rgb_space": space,
        "units": "scene-referred linear; 1.0 = perfect white diffuser lit by the same light at normal incidence; "
                 "RGB premultiplied by alpha (coverage)",
        "exposure": round(float(k), 9),
        "exposure_rule": rule,
        "cos_theta_d_range": [round(crange[0], 6), round(crange[1], 6)],
        "lighting": f"one directional light at {float(light_deg):g} deg (the illuminant's spectrum)"
                    + ("; the mesh shadows it (shadow rays)" if mesh is not None else ""),
        "display": f"sRGB-encoded PNG: linear x exposure, composited on {background} ({bg_linear:g}), "
                   "shoulder above 0.8",
        "wavelength_grid_nm": f"{coating.wavelength_nm[0]:g}:{coating.wavelength_nm[-1]:g}:{coating.wavelength_nm[1] - coating.wavelength_nm[0]:g}",
    })
    return SwatchImage(rgb, coverage, display, meta | mesh_metadata(mesh) | finish_meta(finish), float(k))


def check_finish_lighting(finish, environment, model: str, distribution: str, size_px: int) -> None:
    """SwatchError unless the built-in engine can render ``finish`` so: an anisotropic finish
    (brushed) needs the GGX microfacet model under an environment, at most
    :data:`swatch.limits.MAX_ANISO_RENDER_PX` pixels per side (its gather is four times the
    isotropic one's)."""
    if finish is None or not finish.anisotropic:
        return
    if environment is None or model != "microfacet" or distribution != "ggx":
        raise SwatchError(f"the {finish.name} finish is anisotropic: the built-in engine renders it with the GGX "
                          "microfacet model under an environment (studio, uniform or an .exr), not the point "
                          "light; use an isotropic finish or --roughness there")
    if int(size_px) > MAX_ANISO_RENDER_PX:
        raise SwatchError(f"renders of the {finish.name} finish are at most {MAX_ANISO_RENDER_PX} pixels per side "
                          "(memory); use a smaller --size")


def finish_meta(finish) -> dict:
    """The ``finish`` entry of a render's metadata (name, roughness, basis), or nothing."""
    return {} if finish is None else {"finish": finish.metadata()}


def mesh_metadata(mesh) -> dict:
    """The ``mesh`` entry of a mesh render's metadata (file name, SHA-256, triangles), or nothing."""
    if mesh is None:
        return {}
    return {"mesh": {"file": mesh.file_name, "sha256": mesh.key.split(":", 1)[1], "triangles": mesh.triangles,
                     "placement": "bounding-box centre at the origin, farthest vertex at 1, +y up as written",
                     "shading_normals": "vertex normals interpolated; face normals across creases over 30 deg"}}
