"""Catalog sheets: tiles of rendered swatches with their numbers, as a linear EXR and a display PNG.

A tile holds the swatch rendered flat and curved (``swatch.render.render_swatch``, the spec's
shapes, model and roughness, light 45°), a small angular map (``swatch.render.angular.angular_map``,
paper model: the colour over light × view angle, 0–85°, light up the side, view along the
bottom) and the labels: thickness and voltage, L*a*b* and L*C*h at the reference geometry, the
sRGB hex with a flat chip of that colour, ΔE2000 to the neighbours and the process window.

The PNG is the display image (8-bit sRGB; renders with their display exposure and shoulder).
The EXR (half float, linear sRGB primaries) is the same page in linear light: renders and map
in linear RGB with the same exposure applied (so the two files look alike; the exposure of each
render is in the metadata to recover scene-referred values), everything else (background,
chips, text) the sRGB-decoded display page. Both carry the catalog header, the sheet layout and
every swatch's record as JSON strings (EXR string attributes / PNG iTXt (UTF-8) chunks ``swatch:...``).

The tiles' renders come from :mod:`swatch.catalog.tiles` (cached per swatch), their geometry and
label text from :mod:`swatch.catalog.sheet_layout`.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from swatch.catalog.exports import ase_name
from swatch.catalog.sheet_layout import (
    CARD,
    INK,
    MUTED,
    PAGE,
    RULE,
    Layout,
    chip_line,
    fit_text,
    label_lines,
    label_width,
)
from swatch.catalog.spec import CatalogSpec
from swatch.catalog.tiles import LIGHT_DEG, TileRender, lighting_caption, load_tile, tile_environment
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_RUN_BYTES
from swatch.io.drawing import draw_rect, draw_text
from swatch.io.imageio import write_exr, write_png
from swatch.io.pngmeta import xmp_packet
from swatch.physics.growth import voltage_text
from swatch.render.display import BACKGROUND_LINEAR

__all__ = ["compose_sheet", "sheet_bytes", "plan_jobs", "PARENT_BYTES", "WORKER_SLACK_BYTES", "SHEET_DPI", "SHEET_BYTES_PER_PX", "WORKER_BASE_BYTES"]

#: Resolution written into sheet PNGs (pHYs): the page prints about 30 × 23 cm.
SHEET_DPI = 150

# -- text helpers ----------------------------------------------------------------------------

def _strip(w: int, h: int, color) -> np.ndarray:
    """An (h, w, 3) uint8 block of one colour: its first row filled, then copied down (a sheet's page of
    52 Mpx: 0.02 s, where broadcasting the colour over every pixel took 0.4 s)."""
    img = np.empty((h, w, 3), dtype=np.uint8)
    img[:1] = color
    img[1:] = img[:1]
    return img


def _tile_labels(rec: dict, spec: CatalogSpec, lay: Layout) -> np.ndarray:
    """The label block of a tile (uint8): numbers in DroidSansMono (it has Δ and the minus sign)."""
    w = label_width(lay)
    h = max(lay.label_h, lay.amap)
    img = _strip(w, h, CARD)
    mono, size, step = "DroidSansMono", 15, lay.LINE
    y = 17
    title, *lines = label_lines(rec)
    img = draw_text(img, fit_text(str(title), 18, w, "DroidSans-Bold"), 0, y, 18, INK, font="DroidSans-Bold")
    y += 3
    for line in lines:
        y += step
        if line is None:
            rgb = tuple(int(rec["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5))
            img = draw_rect(img, 0, y - 13, 40, y + 4, rgb)
            img = draw_rect(img, 0, y - 13, 40, y + 4, RULE, fill=False)
            img = draw_text(img, chip_line(rec), 48, y, size, INK, font=mono)
            continue
        img = draw_text(img, line, 0, y, size, INK, font=mono)
    return img


def _header(spec: CatalogSpec, header: dict, lay: Layout, number: int, of: int) -> np.ndarray:
    w = lay.width - 2 * lay.MARGIN
    img = _strip(w, lay.HEADER - 14, PAGE)
    ref = header["reference_geometry"]
    tol = header["tolerance"]
    img = draw_text(img, fit_text(spec.name, 28, w - 220, "DroidSans-Bold"), 0, 40, 28, INK, font="DroidSans-Bold")
    img = draw_text(img, f"sheet {number} of {of}", w, 40, 18, MUTED, align="right")
    line2 = (f"{spec.film} on {spec.substrate}  ·  illuminant {header['illuminant']}, CIE {header['observer_name']} "
             f"observer  ·  model: half-vector thin film (Fujii et al. 2019)  ·  process {spec.process}: "
             + (f"{spec.nm_per_V:g} nm/V + {spec.offset_nm:g} nm" if spec.nm_per_V is not None else "no growth rate")
             + (f" to {voltage_text(spec.knee_V)} V, then {spec.nm_per_V_above_knee:g} nm/V" if spec.knee_V is not None else "")
             + (f", spread {spec.spread.text().strip(' ±')}" if not spec.spread.is_zero else "")
             + (f", film index ×{spec.film_index_scale:g}" if spec.film_index_scale != 1 else "")
             + (f"  ·  finish {spec.finish_spec.label()}" if spec.finish_spec is not None else "")
             + (f", also offered: {', '.join(spec.finishes[1:])}" if len(spec.finishes) > 1 else ""))
    img = draw_text(img, fit_text(line2, 16, w, "DroidSans"), 0, 66, 16, INK)
    line3 = (f"L*a*b* at {ref['name']} (light {ref['light_deg']:g}°, view {ref['view_deg']:g}° from the normal)  ·  "
             f"window: the thickness and voltage deviations that keep the colour difference to the nominal "
             f"colour within " + (f"{tol['scheme']} grade {tol['grade']}: " if tol["scheme"] else "")
             + f"{tol['metric']} <= {tol['max']:g}")
    img = draw_text(img, fit_text(line3, 16, w, "DroidSans"), 0, 90, 16, INK)
    img = draw_rect(img, 0, img.shape[0] - 1, w, img.shape[0], RULE)
    return img


def _footer(spec: CatalogSpec, header: dict, lay: Layout) -> np.ndarray:
    w = lay.width - 2 * lay.MARGIN
    img = _strip(w, lay.FOOTER - 8, PAGE)
    names = {"flat": "flat plate", "cylinder": "half cylinder", "sphere": "sphere", "mesh": f"the part ({spec.mesh})"}
    shapes = ", ".join(names[s] for s in spec.tile_renders[:-1]) + (" and " if len(spec.tile_renders) > 1 else "") \
        + names[spec.tile_renders[-1]]
    model = ("paper model" if spec.model != "microfacet" else f"microfacet GGX, {spec.finish_spec.label()}"
             if spec.finish_spec is not None else f"microfacet GGX, roughness {spec.roughness:g}")
    line1 = (f"Renders: {shapes}, {model}, {lighting_caption(spec)}."
             + ("  Map: colour over light angle (up) × view angle (right), 0–85°, paper model." if spec.angular_map else ""))
    line2 = ("prev / next: CIEDE2000 to the neighbouring swatches.  glTF / Bl / MtlX: the 3-D material presets'"
             " largest CIEDE2000 from the swatch (glTF as three.js shows it, Blender, MaterialX)."
              "  Hex, chips and pictures: sRGB from CIE 1931 2° colorimetry."
              f"  swatch {header['swatch_version']}")
    img = draw_text(img, fit_text(line1, 13, w, "DroidSans"), 0, 15, 13, MUTED)
    return draw_text(img, fit_text(line2, 13, w, "DroidSans"), 0, 33, 13, MUTED)


# -- composition -----------------------------------------------------------------------------

def _srgb_decode(u8: np.ndarray) -> np.ndarray:
    """Linear float32 of sRGB-encoded uint8, through a 256-entry table (one output array, no temporaries)."""
    x = np.arange(256, dtype=np.float32) / np.float32(255.0)
    lut = np.where(x <= 0.04045, x / np.float32(12.92), ((x + np.float32(0.055)) / np.float32(1.055)) ** np.float32(2.4))
    lut = lut.astype(np.float32)
    out = np.empty(u8.shape, dtype=np.float32)
    src, dst = u8.reshape(-1), out.reshape(-1)
    # in chunks of 2^20 values: ``lut[u8]`` cast the whole page's indices to intp first (8 bytes a value,
    # 1.2 GB for the largest sheet) and took 2.8 s where the chunks take 0.45 s, same values (issue 17)
    for i in range(0, src.size, _DECODE_CHUNK):
        np.take(lut, src[i:i + _DECODE_CHUNK].astype(np.intp), out=dst[i:i + _DECODE_CHUNK])
    return out


#: Values decoded per chunk by :func:`_srgb_decode`.
_DECODE_CHUNK = 1 << 20


#: Working bytes per sheet pixel while a sheet is composed and written (measured ~20: 1.03 GB for a
#: 8650 × 6010 px sheet, 512 px tiles 8 × 8): the display page (3), its
#: linear float copy (12), the EXR's half buffer (6) and the PNG writer's (3), with a margin.
SHEET_BYTES_PER_PX = 24
#: A worker process before its first sheet (interpreter, numpy, colour-science, OpenImageIO).
WORKER_BASE_BYTES = 250 * 1024 ** 2


def sheet_bytes(spec: CatalogSpec) -> int:
    """Planned peak bytes of one worker composing one sheet of ``spec``.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    int
        ``width × height × SHEET_BYTES_PER_PX + WORKER_BASE_BYTES``.
    """
    lay = Layout(spec)
    return lay.width * lay.height * SHEET_BYTES_PER_PX + WORKER_BASE_BYTES


#: Leeway on the plan for one sheet composed in the building process (its base is counted twice there).
WORKER_SLACK_BYTES = 300 * 1024 ** 2
#: The building process itself (records, explorer tables, page) besides the sheets it composes.
PARENT_BYTES = 600 * 1024 ** 2


def plan_jobs(spec: CatalogSpec, jobs: int) -> int:
    """Workers composing sheets at once, chosen from the memory budget (:data:`swatch.core.limits.MAX_RUN_BYTES`
    for the whole build: the parent, :data:`PARENT_BYTES`, and its workers, :func:`sheet_bytes` each).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    jobs : int
        The workers asked for.

    Returns
    -------
    int
        At least 1, at most ``jobs``.

    Raises
    ------
    swatch.core.errors.SwatchError
        A sheet too big for the budget even alone.
    """
    per = sheet_bytes(spec)
    if per + PARENT_BYTES > MAX_RUN_BYTES + WORKER_SLACK_BYTES:
        lay = Layout(spec)
        raise SwatchError(f"a sheet of {lay.width} × {lay.height} px ({spec.per_sheet} tiles at size_px "
                          f"{spec.size_px}) needs ~{(per + PARENT_BYTES) / 1024 ** 3:.1f} GB to compose, more than "
                          f"the {MAX_RUN_BYTES / 1024 ** 3:g} GB a build may use; use fewer [sheet] columns or rows, "
                          "fewer shapes or a smaller size_px")
    return max(1, min(jobs, (MAX_RUN_BYTES - PARENT_BYTES) // per))


def _sheet_xmp(header: dict, records: list[dict], number: int, of: int) -> str:
    """XMP for a sheet: title, description and each swatch's thickness and Lab."""

    cs = f"{header['illuminant']}/{header['observer']}°"
    metal = header["substrate"].split("-")[0]
    swatches = "; ".join(f"{ase_name(r, metal)}: L*a*b* ({cs}) " + " ".join(f"{x:.2f}" for x in r["Lab"])
                         for r in records)
    description = (f"{header['film']} on {header['substrate']}. L*a*b* at {header['reference_geometry']['name']} "
                   f"under {header['illuminant']}, CIE {header['observer_name']} observer; hex and pixels: sRGB from "
                   f"CIE 1931 2° colorimetry. {swatches}")
    props = {"thickness_nm": " ".join(f"{r['thickness_nm']:g}" for r in records), "swatches": swatches,
             "illuminant": header["illuminant"], "observer": header["observer"]}
    return xmp_packet(f"{header['name']} — sheet {number} of {of}", description, props)


def compose_sheet(spec: CatalogSpec, tile_job: TileRender, header: dict, records: list[dict], keys: list[str],
                  cache: Path, number: int, of: int, png_path: Path, exr_path: Path) -> None:
    """Compose one sheet from cached tile renders and write its PNG and EXR (with metadata).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    tile_job : swatch.catalog.tiles.TileRender
        What a tile missing from the cache is rendered with.
    header : dict
        ``catalog.json``'s ``catalog``.
    records : list of dict
        The sheet's swatches.
    keys : list of str
        Their :func:`swatch.catalog.tiles.tile_key`.
    cache : pathlib.Path
        The build cache holding the tile renders.
    number, of : int
        The sheet's number and the count.
    png_path, exr_path : pathlib.Path
        Where the sheet's display PNG (sRGB) and its linear EXR (sRGB primaries, half float) are written.

    Returns
    -------
    None
    """

    lay = Layout(spec)
    disp = _strip(lay.width, lay.height, PAGE)
    lin_patches: list[tuple[int, int, int, str]] = []  # (y, x, slot, render) pasted over the decoded page
    disp[lay.MARGIN // 2:lay.MARGIN // 2 + lay.HEADER - 14, lay.MARGIN:lay.width - lay.MARGIN] = \
        _header(spec, header, lay, number, of)
    fy = lay.height - lay.FOOTER - lay.MARGIN // 2 + 8
    disp[fy:fy + lay.FOOTER - 8, lay.MARGIN:lay.width - lay.MARGIN] = _footer(spec, header, lay)
    tiles = []
    bg = np.float32(BACKGROUND_LINEAR)
    for slot, (rec, key) in enumerate(zip(records, keys, strict=True)):
        arrays = load_tile(tile_job, cache, key, spec.thickness_nm[rec["index"] - 1])
        x0, y0 = lay.tile_origin(slot)
        draw_rect(disp, x0, y0, x0 + lay.tile_w, y0 + lay.tile_h, CARD, inplace=True)
        draw_rect(disp, x0, y0, x0 + lay.tile_w, y0 + lay.tile_h, RULE, fill=False, inplace=True)
        rx = x0 + lay.PAD + (lay.tile_w - 2 * lay.PAD - lay.renders_w) // 2
        ry = y0 + lay.PAD
        renders = []
        for i, shape in enumerate(spec.tile_renders):
            s = lay.size
            xx = rx + i * (s + lay.GAP)
            disp[ry:ry + s, xx:xx + s] = arrays[f"r{i}_display"]
            lin_patches.append((ry, xx, slot, f"r{i}"))  # pasted on the linear page below (tile read again)
            renders.append({"shape": shape, "rect_px": [xx, ry, s, s], "exposure": float(arrays[f"r{i}_exposure"]),
                            "lighting": tile_environment(spec) or f"light {LIGHT_DEG:g} deg",
                            **({"mesh": spec.mesh} if shape == "mesh" else {})})
        ly = ry + lay.size + lay.GAP
        labels = _tile_labels(rec, spec, lay)
        lx = x0 + lay.PAD
        disp[ly:ly + labels.shape[0], lx:lx + labels.shape[1]] = labels
        entry = {"id": rec["id"], "tile_rect_px": [x0, y0, lay.tile_w, lay.tile_h], "renders": renders}
        if lay.amap:
            ax = x0 + lay.tile_w - lay.PAD - lay.amap
            disp[ly:ly + lay.amap, ax:ax + lay.amap] = arrays["amap_display"]
            lin_patches.append((ly, ax, slot, "amap"))
            entry["angular_map"] = {"rect_px": [ax, ly, lay.amap, lay.amap], "light_deg": "0-85 bottom to top",
                                    "view_deg": "0-85 left to right", "model": "paper", "exposure": 1.0}
        tiles.append(entry)
    lin = _srgb_decode(disp)
    # the linear renders, one tile in memory at a time (holding them all took 0.6 GB at 512 px, 8 × 8)
    for slot, (rec, key) in enumerate(zip(records, keys, strict=True)):
        arrays = load_tile(tile_job, cache, key, spec.thickness_nm[rec["index"] - 1])
        for y, x, _slot, name in (p for p in lin_patches if p[2] == slot):
            if name == "amap":
                patch = arrays["amap_linear"].astype(np.float32)
            else:
                a = arrays[f"{name}_alpha"][..., None].astype(np.float32)
                patch = arrays[f"{name}_linear"].astype(np.float32) + (np.float32(1.0) - a) * bg
            lin[y:y + patch.shape[0], x:x + patch.shape[1]] = patch
    meta = {
        "catalog": header,
        "sheet": {"number": number, "of": of, "swatches": [r["id"] for r in records], "tiles": tiles,
                  "size_px": [lay.width, lay.height],
                  "exr_note": ("linear sRGB primaries; renders and maps with their display exposure applied "
                               "(divide by 'exposure' for scene-referred values, 1.0 = white diffuser); "
                               "elsewhere the decoded display page")},
    }
    for rec in records:
        meta[rec["id"]] = rec
    write_png(png_path, disp, meta, xmp=_sheet_xmp(header, records, number, of), dpi=SHEET_DPI)
    write_exr(exr_path, lin, meta, space="srgb", half=True)
