"""The explorer page's colour table: colour over thickness × cos θ_d, computed by the engine.

The page (``index.html``) shades its live view and answers ``swatchCatalog.colorAt`` /
``match`` from numbers the build embeds here, so the browser never re-implements the optics or
the CIE tables:

* ``grid``: tristimulus values of the half-vector thin-film reflectance ``F(λ; d, θ_d)``
  (the model of ``swatch color``: Airy reflectance factor at ``θ_d``, no intensity term) on a
  uniform grid of thickness (``GRID_STEP_NM``, over the catalog's range) × ``cos θ_d``
  (``COS_NODES`` nodes on [0, 1]). Two sets: XYZ under the catalog's illuminant and observer
  (for L*a*b*) and XYZ under the illuminant and the CIE 1931 2° observer (for display RGB, which
  always comes from 2° colorimetry). Bilinear interpolation of this grid stays within
  ΔE2000 0.5 of the direct spectral computation (tests/catalog/test_catalog_explorer.py; measured
  max ≈ 0.3 on 20–300 nm, worst near grazing cos θ_d < 0.01).
* ``reference``: the same two XYZ sets at the catalog's reference geometry, every
  ``MATCH_STEP_NM`` (the step of ``swatch match``), so the page's colour search runs on the same
  samples as ``swatch match --range`` over the catalog's range.
* matrices (colour-science, applied to the unit vectors): XYZ (2°) → linear sRGB and linear
  Display P3 (XYZ on the Y = 100 scale; rows act on row vectors), linear sRGB → 2° XYZ and its
  white (as ``swatch match --hex`` reads a hex colour), and the white XYZ for L*a*b*.

The grid is stored as little-endian uint16 per channel with a per-channel scale
(``value = code × scale``; the quantisation error is below 1e-3 of the channel's maximum,
ΔE2000 < 0.01) and base64-encoded. The reference column is stored as little-endian float32
(``"type": "float32"``, base64): the page's colour search looks for local minima of ΔE2000 along it,
and the uint16 steps made false ones where the curve is flat (e.g. a candidate at 111.7 nm for
L*a*b* 70 5 30 that ``swatch match`` does not have; tests/js/match.test.mjs).

XYZ scale: Y = 100 for the perfect white diffuser (colour-science's convention).

``scene`` (:func:`scene_data`): the live view's shapes, cameras and point light are those of
``swatch render`` (:func:`swatch.render.scene.make_scene`), so the page's bent sheet *is* ``--shape cylinder``
(radius 1, height 2.2, the convex half towards the default camera): per shape the camera distance, the
default view angle, the framing (the shape's points, or for the sphere its view-independent window, filling
:data:`swatch.render.camera.FRAME_FILL` of the square, as :meth:`~swatch.render.camera.Camera.fitted`) and the
light's two axes (``light = cos θ c + sin θ w``). The page's world is z-up: a render's world vector
``(x, y, z)`` (y up) is ``(-z, -x, y)`` on the page (:data:`PAGE_FROM_RENDER`), the render's view azimuth φ
is the page's φ + 180°.
"""
from __future__ import annotations

import base64
import math

import colour
import numpy as np

from swatch.catalog.context import CatalogContext
from swatch.catalog.records import CatalogData
from swatch.catalog.sheet_layout import Layout
from swatch.catalog.tiles import AMAP_ANGLES_DEG
from swatch.colorimetry.names import NAME_RULES
from swatch.colorimetry.observers import srgb_to_document_XYZ
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_GRID_NODES, MAX_PAGE_MESH_TRIANGLES, MAX_THICKNESS_NM
from swatch.fit.matching import MATCH_MIN_SEPARATION_NM
from swatch.physics import geometry
from swatch.physics.finishes import HAIRLINE_OCTAVES, HAIRLINE_SLOPE, HAIRLINE_STRETCH, get_finish
from swatch.render.camera import FRAME_FILL
from swatch.render.scene import DEFAULT_VIEW_DEG, HalfCylinder, make_scene

__all__ = ["GRID_STEP_NM", "COS_NODES", "MATCH_STEP_NM", "MAX_GRID_NODES", "PAGE_FROM_RENDER", "explorer_data",
           "scene_data", "decode", "grid_lookup", "tile_rects", "chip_colours", "hairline_data"]

#: Thickness step of the shading grid (nm); 2 nm would give ΔE2000 up to 0.27 with 129 cos nodes, 1 nm keeps
#: the cos θ_d axis short (97 nodes) for the same accuracy.
GRID_STEP_NM = 1.0
#: Nodes of the cos θ_d axis (uniform on [0, 1]).
COS_NODES = 97
#: Thickness step of the reference-geometry column (= swatch match's default search step).
MATCH_STEP_NM = 0.1
#: Margin added on both sides of a one-thickness catalog so the slider still moves (nm).
SINGLE_MARGIN_NM = 10.0


def _encode(values: np.ndarray) -> dict:
    """uint16 codes per channel (last axis) with a per-channel scale, base64 of little-endian bytes."""
    v = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(v)) or v.min() < 0:
        raise SwatchError("explorer table: tristimulus values must be finite and >= 0")
    top = v.reshape(-1, v.shape[-1]).max(axis=0)
    scale = np.where(top > 0, top / 65535.0, 1.0)
    codes = np.round(v / scale).astype("<u2")
    return {"shape": list(v.shape), "scale": [float(s) for s in scale],
            "data": base64.b64encode(codes.tobytes()).decode("ascii")}


def _encode_float32(values: np.ndarray) -> dict:
    """Little-endian float32, base64 (the reference column: no quantisation steps along it)."""
    v = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(v)) or v.min() < 0:
        raise SwatchError("explorer table: tristimulus values must be finite and >= 0")
    return {"type": "float32", "shape": list(v.shape),
            "data": base64.b64encode(v.astype("<f4").tobytes()).decode("ascii")}


def decode(block: dict) -> np.ndarray:
    """The float64 array of an encoded block (uint16 codes × per-channel scale, or float32 where ``type`` says so;
    the page's decoder, in Python for tests).

    Parameters
    ----------
    block : dict
        ``data`` (base64), ``shape``, and ``scale`` or ``"type": "float32"``.

    Returns
    -------
    numpy.ndarray
        The block's values, float64, in its ``shape``.
    """
    raw = base64.b64decode(block["data"])
    if block.get("type") == "float32":
        return np.frombuffer(raw, dtype="<f4").astype(np.float64).reshape(block["shape"])
    codes = np.frombuffer(raw, dtype="<u2").astype(np.float64)
    return codes.reshape(block["shape"]) * np.asarray(block["scale"])


#: The page's z-up world from a render's y-up world: ``page = PAGE_FROM_RENDER @ render`` (a rotation).
PAGE_FROM_RENDER = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _page(v) -> list:
    """Render-world vectors (..., 3) in page coordinates, as nested lists."""
    return (np.asarray(v, dtype=np.float64) @ PAGE_FROM_RENDER.T).tolist()


def _float32_block(a) -> dict:
    a = np.ascontiguousarray(a, dtype="<f4")
    return {"type": "float32", "shape": list(a.shape), "data": base64.b64encode(a.tobytes()).decode("ascii")}


def scene_data(mesh=None) -> dict:
    """The live view's scene, from :func:`swatch.render.scene.make_scene` (see the module doc), page coordinates.

    Parameters
    ----------
    mesh : swatch.render.mesh.MeshShape, optional
        The catalog's part: an entry ``mesh`` as the other shapes', with its triangles (``corners`` and ``normals``,
        float32 blocks of shape (F, 3, 3): :meth:`~swatch.render.mesh.MeshShape.triangle_soup`, creases split) for the
        page's WebGL2 rasteriser; at most :data:`swatch.core.limits.MAX_PAGE_MESH_TRIANGLES`.

    Returns
    -------
    dict
        Per shape (``flat``, ``cylinder``, ``sphere``): ``distance`` (object units), ``default_view_deg``,
        ``light_axes`` ``[c, w]`` (unit vectors: the light at ``light_deg`` θ is ``cos θ c + sin θ w``),
        and ``points`` (float32 block, the points :meth:`~swatch.render.camera.Camera.fitted` frames) or, for
        the sphere, ``window_half`` (its framing does not depend on the view); ``cylinder`` adds ``radius``,
        ``half_height``, ``half_angle_deg`` (90: a half cylinder), ``axis`` and ``middle`` (the direction from the
        axis to the middle of the sheet);
        ``fill``.

    Examples
    --------
    >>> s = scene_data()
    >>> s["cylinder"]["distance"], s["cylinder"]["half_height"], s["cylinder"]["axis"], s["flat"]["light_axes"][0]
    (5.5, 1.1, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    """
    out: dict = {"fill": FRAME_FILL}
    c45 = math.cos(math.radians(45.0))
    for shape in ("flat", "cylinder", "sphere") + (("mesh",) if mesh is not None else ()):
        s0, s45 = make_scene(shape, 0.0, mesh=mesh), make_scene(shape, 45.0, mesh=mesh)
        c = s0.light
        w = (s45.light - c45 * c) / math.sin(math.radians(45.0))
        entry: dict = {"distance": round(float(np.linalg.norm(s0.camera.position)), 9),
                       "default_view_deg": DEFAULT_VIEW_DEG["sphere" if shape == "mesh" else shape],
                       "light_axes": [[round(x, 12) + 0.0 for x in v] for v in _page(np.stack([c, w]))]}
        if shape == "sphere":
            entry["window_half"] = float(s0.camera.half)
        else:
            entry["points"] = _float32_block(_page(s0.shape.points()))
        if shape == "mesh":
            assert mesh is not None
            if mesh.triangles > MAX_PAGE_MESH_TRIANGLES:
                raise SwatchError(f"{mesh.file_name}: {mesh.triangles} triangles; the catalog page draws at most "
                                  f"{MAX_PAGE_MESH_TRIANGLES} (MAX_PAGE_MESH_TRIANGLES): give a simplified part")
            corners, normals = mesh.triangle_soup()
            entry.update(file=mesh.file_name, triangles=int(corners.shape[0]),
                         corners=_float32_block(_page(corners)), normals=_float32_block(_page(normals)))
        if shape == "cylinder":
            entry.update(radius=1.0, half_height=HalfCylinder().h, half_angle_deg=90.0, axis=_page([0.0, 1.0, 0.0]),
                         middle=_page([0.0, 0.0, 1.0]))  # HalfCylinder: radius 1 about y, the half z >= 0
        out[shape] = entry
    return out


def _matrix(fn) -> list[list[float]]:
    """Row-vector matrix M of a linear map: ``fn(x) = x @ M`` (columns from the unit vectors)."""
    return [[float(v) for v in row] for row in np.asarray(fn(np.eye(3)), dtype=np.float64)]


def thickness_axis(thickness_nm, step_nm: float) -> tuple[float, float, int]:
    """A uniform thickness axis covering the catalog's thicknesses (a single thickness gets a margin; the
    axis never passes :data:`swatch.core.limits.MAX_THICKNESS_NM`).

    Parameters
    ----------
    thickness_nm : array_like
        nm.
    step_nm : float
        The axis step, nm.

    Returns
    -------
    (float, float, int)
        Start and stop (nm) and the node count.

    Raises
    ------
    swatch.core.errors.SwatchError
        More than :data:`swatch.core.limits.MAX_GRID_NODES` nodes.

    Examples
    --------
    >>> thickness_axis([20.0, 300.0], 2.0)
    (20.0, 300.0, 141)
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    lo, hi = float(d.min()), float(d.max())
    if hi - lo < 1e-9:
        lo, hi = max(0.0, lo - SINGLE_MARGIN_NM), hi + SINGLE_MARGIN_NM
    hi = min(hi, MAX_THICKNESS_NM)  # the margin never reaches past the thickest film the model takes
    count = math.ceil((hi - lo) / step_nm - 1e-9) + 1
    if lo + (count - 1) * step_nm > MAX_THICKNESS_NM + 1e-9:  # shift the axis down (or end it) at the limit
        lo = max(0.0, MAX_THICKNESS_NM - (count - 1) * step_nm)
        count = min(count, math.floor((MAX_THICKNESS_NM - lo) / step_nm + 1e-9) + 1)
    if count > MAX_GRID_NODES:
        raise SwatchError(f"explorer table: {count} thickness nodes exceed {MAX_GRID_NODES}")
    return lo, lo + (count - 1) * step_nm, count


def explorer_data(ctx: CatalogContext, reference_cos_d: float | None = None) -> dict:
    """The JSON block the page reads (see the module doc): the shading grid, the reference samples and
    the matrices, from the build's context.

    Parameters
    ----------
    ctx : swatch.catalog.context.CatalogContext
        The catalog's grid, coating and colorimeter (as the records).
    reference_cos_d : float, optional
        cos θ_d of the reference geometry (default: the spec's).

    Returns
    -------
    dict
        The page's colour table: format, colorimetry, the thickness × cos θ_d grids (XYZ, Y = 100 for
        the perfect white diffuser), the reference samples and the matrices (JSON-ready).
    """

    spec = ctx.spec
    coating, cm = ctx.coating, ctx.colorimeter  # as the records (the tiles' workers build the same)
    cm2 = cm.display_colorimeter  # display RGB from CIE 1931 2° colorimetry
    ref = spec.reference
    if reference_cos_d is None:
        reference_cos_d = float(geometry.cos_theta_d(ref.light_deg, ref.view_deg, 0.0, ref.view_azimuth_deg))

    d0, d1, nd = thickness_axis(spec.thickness_nm, GRID_STEP_NM)
    d_grid = np.linspace(d0, d1, nd)
    cos_grid = np.linspace(0.0, 1.0, COS_NODES)
    R = coating.reflectance_cos(d_grid[:, None], cos_grid[None, :]).R  # (D, C, W)
    grid = np.concatenate([cm.XYZ(R), cm2.XYZ(R)], axis=-1)  # (D, C, 6)

    m0, m1, nm = thickness_axis(spec.thickness_nm, MATCH_STEP_NM)
    m_grid = np.linspace(m0, m1, nm)
    Rr = coating.reflectance_cos(m_grid, reference_cos_d).R  # (M, W)
    column = np.concatenate([cm.XYZ(Rr), cm2.XYZ(Rr)], axis=-1)

    white = colour.xy_to_XYZ(cm.white_xy)  # the Lab white of Colorimeter.Lab (Y = 1)
    return {
        "format": "swatch-explorer-table",
        "format_version": 2,  # 2: the reference column as float32
        "model": "half-vector thin film: Airy reflectance factor of the film at theta_d (as swatch color)",
        "illuminant": cm.illuminant,
        "observer": cm.observer,
        "display_observer": "2",
        "xyz_scale": "Y = 100 for the perfect white diffuser",
        "channels": ["X", "Y", "Z", "X_2", "Y_2", "Z_2"],
        "thickness_nm": {"start": d0, "step": GRID_STEP_NM, "count": nd},
        "cos_theta_d": {"start": 0.0, "stop": 1.0, "count": COS_NODES},
        "grid": _encode(grid),
        "reference": {"geometry": ref.to_json(), "cos_theta_d": reference_cos_d,
                      "thickness_nm": {"start": m0, "step": MATCH_STEP_NM, "count": nm},
                      "values": _encode_float32(column)},
        "white_XYZ": [float(v) for v in white],
        "XYZ2_to_srgb_linear": _matrix(lambda e: cm2.rgb_linear(e, "srgb")),
        "XYZ2_to_p3_linear": _matrix(lambda e: cm2.rgb_linear(e, "display-p3")),
        # as swatch.colorimetry.colorimeter.hex_to_Lab_2deg: sRGB adapted (Bradford) to the illuminant's 2° white,
        # L*a*b* relative to that white (a hex code has no spectrum, so no 10° Lab)
        "srgb_linear_to_XYZ2": _matrix(lambda e: 100.0 * colour.RGB_to_XYZ(
            e, "sRGB", illuminant=cm2.white_xy, chromatic_adaptation_transform="Bradford")),
        "white_XYZ2": [float(v) for v in colour.xy_to_XYZ(cm2.white_xy)],
        # a hex target in the catalog's observer, as swatch match --hex and swatch spec --hex: through its smoothest
        # reflectance (swatch.colorimetry.observers; linear, so one matrix), L*a*b* against white_XYZ
        "srgb_linear_to_XYZ": _matrix(lambda e: srgb_to_document_XYZ(e, cm)),
        "nm_per_V": spec.nm_per_V,  # growth law: thickness_nm = offset_nm + nm_per_V * voltage_V (null: none)
        "offset_nm": spec.offset_nm,
        **({} if spec.knee_V is None else {"knee_V": spec.knee_V, "nm_per_V_above_knee": spec.nm_per_V_above_knee}),
        "match": {"min_separation_nm": MATCH_MIN_SEPARATION_NM, "step_nm": MATCH_STEP_NM},
        "name_rules": [list(r) for r in NAME_RULES],
        "render": {"model": spec.model, "roughness": spec.roughness, "shapes": list(spec.shapes),
                   # a brushed finish's hairlines, where the catalog's finish or one it offers is anisotropic
                   **({"hairlines": hairline_data()} if (spec.finish_spec is not None and spec.finish_spec.anisotropic)
                      or any(get_finish(f).anisotropic for f in spec.finishes) else {})},
        "scene": scene_data(ctx.mesh),
    }


def hairline_data() -> dict:
    """The hairlines of a brushed finish as the live view draws them (:func:`swatch.physics.finishes.hairline_slope`):
    the peak slope, the octaves (lines per object unit across the grain, weight) and the stretch along the grain.

    Returns
    -------
    dict
        ``slope``, ``octaves``, ``stretch``.
    """
    return {"slope": HAIRLINE_SLOPE, "octaves": [list(o) for o in HAIRLINE_OCTAVES], "stretch": HAIRLINE_STRETCH}


def grid_lookup(block: dict, thickness_nm, cos_d) -> np.ndarray:
    """Bilinear interpolation of the shading grid, as the page does it (for tests).

    Parameters
    ----------
    block : dict
        :func:`explorer_data`.
    thickness_nm, cos_d : array_like
        nm; facet incidence cosine.

    Returns
    -------
    numpy.ndarray, shape (..., 6)
        XYZ under the catalog's observer, then under CIE 1931 2°.
    """
    g = decode(block["grid"])
    t = block["thickness_nm"]
    x = np.clip((np.asarray(thickness_nm, dtype=np.float64) - t["start"]) / t["step"], 0, t["count"] - 1)
    y = np.clip(np.asarray(cos_d, dtype=np.float64) * (block["cos_theta_d"]["count"] - 1), 0,
                block["cos_theta_d"]["count"] - 1)
    i = np.minimum(x.astype(np.int64), t["count"] - 2)
    j = np.minimum(y.astype(np.int64), block["cos_theta_d"]["count"] - 2)
    fx = (x - i)[..., None]
    fy = (y - j)[..., None]
    return ((1 - fx) * (1 - fy) * g[i, j] + fx * (1 - fy) * g[i + 1, j]
            + (1 - fx) * fy * g[i, j + 1] + fx * fy * g[i + 1, j + 1])


def tile_rects(spec, records: list[dict]) -> dict:
    """Where each swatch's renders and angular map sit in its sheet PNG, for the page.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec. (sheet layout).
    records : list of dict
        The swatches' records (JSON view).

    Returns
    -------
    dict
        ``sheet_px`` [w, h], ``renders`` [[x, y, w, h] per shape, then the part] and ``amap`` ([x, y, w, h] or None)
        relative to the tile's origin, ``origins`` per swatch id, ``amap_deg``; pixels.
    """

    lay = Layout(spec)
    s = lay.size
    x = lay.PAD + (lay.tile_w - 2 * lay.PAD - lay.renders_w) // 2  # as sheets.compose_sheet centres them
    renders = [[x + k * (s + lay.GAP), lay.PAD, s, s] for k in range(len(spec.tile_renders))]  # the shapes, the part
    amap = None
    if lay.amap:
        amap = [lay.tile_w - lay.PAD - lay.amap, lay.PAD + s + lay.GAP, lay.amap, lay.amap]
    origins = {}
    for r in records:
        slot = (r["index"] - 1) % spec.per_sheet
        origins[r["id"]] = list(lay.tile_origin(slot))
    return {"sheet_px": [lay.width, lay.height], "renders": renders, "amap": amap, "origins": origins,
            "amap_deg": [float(AMAP_ANGLES_DEG[0]), float(AMAP_ANGLES_DEG[-1])]}


def chip_colours(data: CatalogData) -> list[dict]:
    """Per swatch: Display P3 encoded RGB at the reference geometry (``p3``, clipped to [0, 1]) and whether
    each multi-angle colour is inside sRGB (``multi_in_srgb_gamut``), both from CIE 1931 2°.

    Parameters
    ----------
    data : swatch.catalog.records.CatalogData
        The computed records.

    Returns
    -------
    list of dict
        One ``{"p3": [r, g, b], "multi_in_srgb_gamut": {geometry name: bool}}`` per swatch, in catalog order.
    """

    spec, cm = data.context.spec, data.context.colorimeter
    enc, _ = cm.reflectance_display(data.reflectance, "display-p3")
    enc = np.atleast_2d(enc)
    names = [g.name for g in spec.multi_angle]
    multi = (cm.reflectance_display(data.multi_reflectance, "srgb")[1] if names
             else np.zeros((0, enc.shape[0]), dtype=bool))  # (G, N)
    return [{"p3": [round(float(v), 4) for v in enc[i]],
             "multi_in_srgb_gamut": {n: bool(multi[j, i]) for j, n in enumerate(names)}}
            for i in range(enc.shape[0])]
