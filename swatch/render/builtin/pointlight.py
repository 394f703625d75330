"""Swatch renders (flat plate, half cylinder, sphere): the table-lookup renderer.

Light and colour
----------------
A directional light whose spectrum is the colorimeter's illuminant (D65 by default, as the
paper's CG) lights the swatch; the camera records CIE XYZ, converted to linear RGB. Pixel values
are scene-referred with **1.0 = a perfect white diffuser lit by the same light at normal
incidence**: a pixel is ``XYZ(F(·; d, θ_d)) · s`` (see :mod:`swatch.render.builtin.shading`) with
``s = π D G cos θ_l / (4 cos θ_l cos θ_v)`` for the microfacet model and ``s = 1`` (lit and
seen) for the paper's model. The scenes (camera, shapes, light) are in :mod:`swatch.render.scene`; the
display image's exposure and tone shoulder in :mod:`swatch.render.display`.

Anti-aliasing: each pixel is shaded at its centre; pixels on or next to a silhouette edge are
re-rendered with 4 × 4 stratified sub-samples (colour averaged, coverage = fraction hit), so
edges are anti-aliased at a cost proportional to the outline, not the area. ``linear_rgb`` is
premultiplied by the ``coverage`` (background 0, as EXR expects); ``display_rgb`` is
composited on a neutral grey (linear 0.18, sRGB 118).
"""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from swatch.physics import microfacet
from swatch.render.builtin import shading
from swatch.render.display import BACKGROUND_LINEAR, display_encode, exposure
from swatch.render.image import BACKGROUND_WHITE, SUPERSAMPLE, SwatchImage, edge_pixels, mesh_metadata
from swatch.render.request import RenderRequest
from swatch.render.scene import Scene

__all__ = ["render_pointlight", "render_scene"]

#: Nodes of a render's cos θ_d table over the range its pixels span (refined 16× for lookups;
#: the range is narrow, so 129 nodes are far denser than the 1025 of the full [0, 1] table).
RENDER_TABLE_NODES = 129
TILE_ROWS = 64


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


def _fine_index(fine, cos_d) -> np.ndarray:
    """Nearest node of a refined table (:meth:`swatch.render.builtin.shading.FacetColourTable.refined`: linear
    interpolation of the coarse table to within 1/(2·factor) of a coarse node, at the cost of one gather)."""
    t32 = np.float32
    x = (cos_d - t32(fine.c0)) * t32((fine.nodes - 1) / max(fine.c1 - fine.c0, 1e-12)) + t32(0.5)
    return np.clip(x, t32(0), t32(fine.nodes - 1)).astype(np.int32)


def render_scene(scene: Scene, table, size_px: int, model: str, roughness_alpha: float, distribution: str,
                 display_table=None, workers: int | None = None, background_linear: float = BACKGROUND_LINEAR):
    """Render a scene with a facet colour table (the fast, table-lookup path of the point light).

    A pre-pass on every 4th pixel gives the cos θ_d range (for the table) and the display exposure;
    edge pixels are supersampled for their coverage.

    Parameters
    ----------
    scene : swatch.render.scene.Scene
        Camera, shape and light.
    table : callable or swatch.render.builtin.shading.FacetColourTable
        A factory ``table(c0, c1)`` called with the image's cos θ_d range, or a ready table (XYZ or
        linear RGB).
    size_px : int
        Image side, pixels.
    model : str
        ``"paper"`` or ``"microfacet"``.
    roughness_alpha : float
        Microfacet α.
    distribution : str
        ``ggx`` or ``beckmann``.
    display_table : callable, optional
        The same form, giving linear sRGB for the display when ``table`` is another space.
    workers : int, optional
        Threads.
    background_linear : float
        Linear value of the display background.

    Returns
    -------
    tuple
        (linear RGB premultiplied by coverage (H, W, 3), coverage (H, W), display sRGB uint8 (H, W, 3),
        exposure, its rule, (c0, c1)).
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
    edge = edge_pixels(coverage > 0.5)
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


def render_pointlight(request: RenderRequest, meta: dict) -> SwatchImage:
    """The point-light engine of :func:`swatch.render.dispatch.render_builtin` (the request checked).

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        The render (thickness, shape and scene, size, background, lobe, model, distribution, coating,
        colorimeter, space, light angle, threads), checked by :func:`swatch.render.request.render_request`.
    meta : dict
        The common metadata (:func:`swatch.render.metadata.common_metadata`).

    Returns
    -------
    swatch.render.image.SwatchImage
        Linear RGB premultiplied by coverage, scene-referred (1.0 = a white diffuser lit by the same light
        at normal incidence), its coverage, display sRGB and the fitted exposure.
    """
    d, shape, scene, size, background = (request.thickness_nm, request.shape, request.scene, request.size_px,
                                         request.background)
    model, distribution, coating, colorimeter = request.model, request.distribution, request.coating, request.colorimeter
    space, light_deg, roughness_alpha = request.space, request.light_deg, request.roughness_alpha
    bg_linear = BACKGROUND_LINEAR if background == "grey" else BACKGROUND_WHITE

    def table(c0, c1, sp=space):
        return shading.facet_colour_table(d, coating, colorimeter, RENDER_TABLE_NODES, (c0, c1)).to_rgb(colorimeter, sp)

    display_table = None if space == "srgb" else (lambda c0, c1: table(c0, c1, "srgb"))
    rgb, coverage, display, k, rule, crange = render_scene(scene, table, size, model, roughness_alpha, distribution,
                                                           display_table, request.workers, bg_linear)

    meta = dict(meta)
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
                    + ("; the mesh shadows it (shadow rays)" if request.mesh is not None else ""),
        "display": f"sRGB-encoded PNG: linear x exposure, composited on {background} ({bg_linear:g}), "
                   "shoulder above 0.8",
        "wavelength_grid_nm": f"{coating.wavelength_nm[0]:g}:{coating.wavelength_nm[-1]:g}:{coating.wavelength_nm[1] - coating.wavelength_nm[0]:g}",
    })
    return SwatchImage(rgb, coverage, display, meta | mesh_metadata(request.mesh), float(k))

