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

Tile renders are cached per swatch (``.npz`` keyed by :func:`tile_key`) and computed in
parallel processes (``--jobs``); every job is a pure function of its inputs, so the result does
not depend on the number of jobs.
"""
from __future__ import annotations

import functools
import hashlib
import json
import multiprocessing as mp
import os
import zipfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swatch.catalog.exports import ase_name
from swatch.catalog.folder import remove_tree
from swatch.catalog.spec import CatalogSpec
from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES
from swatch.core.procguard import exit_with, ignore_interrupts, start_forkserver_ignoring_interrupts
from swatch.core.safepath import is_regular_file
from swatch.core.sources import package_dir, source_files
from swatch.io.imageio import draw_rect, draw_text, text_width, write_exr, write_png
from swatch.io.pngmeta import xmp_packet
from swatch.physics.finishes import get_finish
from swatch.physics.materials import wavelength_grid
from swatch.physics.model import get_coating
from swatch.render import render_swatch
from swatch.render.angular import angular_map
from swatch.render.display import BACKGROUND_LINEAR

if TYPE_CHECKING:
    from multiprocessing.context import BaseContext

__all__ = ["tile_key", "load_tile", "render_missing", "make_pool", "compose_sheet", "Layout", "AMAP_ANGLES_DEG", "label_lines",
           "chip_line", "label_width"]

TILE_VERSION = 1
#: Angular-map grid (light × view polar angles, degrees); 60 × 60 cells drawn at 2 px each.
AMAP_ANGLES_DEG = np.linspace(0.0, 85.0, 60)
AMAP_CELL_PX = 2
LIGHT_DEG = 45.0
#: Resolution written into sheet PNGs (pHYs): the page prints about 30 × 23 cm.
SHEET_DPI = 150

#: Lighting of the tile renders for the microfacet model (GGX): the studio, exposure 1
#: (swatch.render.env_render), so a render and its chip are on one scale; the paper model keeps the light.
ENVIRONMENT = "studio"


def tile_environment(spec: CatalogSpec) -> str | None:
    return ENVIRONMENT if spec.model == "microfacet" else None


def lighting_caption(spec: CatalogSpec) -> str:
    if tile_environment(spec):
        return "studio (soft boxes, dark walls, floor and horizon) at exposure 1 (white diffuser = white, as for the chip)"
    return f"one light at {LIGHT_DEG:g}°, display exposure per render"


# page colours (display sRGB)
PAGE = (238, 238, 240)
CARD = (255, 255, 255)
INK = (20, 20, 24)
MUTED = (88, 88, 96)
RULE = (200, 200, 206)


@functools.lru_cache(maxsize=1)
def _engine_code_hash() -> str:
    """Hash of the engine modules (every module outside catalog/, presets/ and commands/) and this
    file: a tile depends on all of them."""
    pkg = package_dir()
    h = hashlib.sha256()
    for f in [*source_files(exclude=("catalog", "presets", "commands")), Path(__file__).resolve()]:
        h.update(f.relative_to(pkg).as_posix().encode() + b"\0" + f.read_bytes())
    return h.hexdigest()


def tile_key(spec: CatalogSpec, thickness_nm: float, fp: dict) -> str:
    """Content hash of everything a swatch's renders depend on."""
    doc = {
        "v": TILE_VERSION, "code": _engine_code_hash(), "tables": fp["tables"], "versions": fp["versions"],
        "film": spec.film, "substrate": spec.substrate, "film_index_scale": spec.film_index_scale,
        "wl_step": spec.wavelength_step_nm,
        "illuminant": spec.illuminant, "observer": spec.observer, "d": float(thickness_nm),
        "shapes": list(spec.shapes), "size": spec.size_px, "model": spec.model, "roughness": spec.roughness,
        "amap": spec.angular_map, "amap_angles": AMAP_ANGLES_DEG.tolist(), "light": LIGHT_DEG,
        "environment": tile_environment(spec), **spec.spread.metadata(),
        **({"finish": spec.finish} if spec.finish else {}),
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:40]


# -- rendering (worker side) -----------------------------------------------------------------

def _render_job(args):
    """Render one swatch's tile images; a pure function of ``args`` (runs in a worker process)."""
    (d, film, substrate, scale, wl_step, illuminant, observer, shapes, size, model, roughness, amap, spread, finish) = args

    wl = wavelength_grid(380.0, 780.0, wl_step)
    coating = get_coating(film, substrate, wl, scale, spread)
    cm = get_colorimeter(wl, illuminant, observer)
    out: dict[str, Any] = {}
    for i, shape in enumerate(shapes):
        im = render_swatch(d, shape, size, light_deg=LIGHT_DEG, roughness_alpha=roughness, model=model,
                           coating=coating, colorimeter=cm, space="srgb", workers=1,
                           environment=ENVIRONMENT if model == "microfacet" else None,
                           finish=None if finish is None else get_finish(finish))
        # half floats: the sheet EXR is half anyway, and the cache stays small
        out[f"r{i}_linear"] = (np.asarray(im.linear_rgb, dtype=np.float32) * np.float32(im.exposure)).astype(np.float16)
        out[f"r{i}_alpha"] = np.asarray(im.coverage, dtype=np.float16)
        out[f"r{i}_display"] = np.asarray(im.display_rgb, dtype=np.uint8)
        out[f"r{i}_exposure"] = np.float64(im.exposure)
    if amap:
        am = angular_map(d, AMAP_ANGLES_DEG, AMAP_ANGLES_DEG, coating=coating, colorimeter=cm, model="paper")
        # rows = light angle: flip so light 0° is at the bottom (as swatch.report.figures.angular_figure)
        lin = np.asarray(am.linear_rgb, dtype=np.float32)[::-1] * np.float32(am.exposure)
        disp = np.asarray(am.display_rgb, dtype=np.uint8)[::-1]
        c = AMAP_CELL_PX
        out["amap_linear"] = np.repeat(np.repeat(lin, c, 0), c, 1).astype(np.float16)
        out["amap_display"] = np.repeat(np.repeat(disp, c, 0), c, 1)
    return out


def _job_args(spec: CatalogSpec, d: float):
    return (float(d), spec.film, spec.substrate, spec.film_index_scale, spec.wavelength_step_nm, spec.illuminant,
            spec.observer,
            tuple(spec.shapes), spec.size_px, spec.model, spec.roughness, spec.angular_map, spec.spread, spec.finish)


def _save_npz(path: Path, arrays: dict) -> None:
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.npz")
    try:
        np.savez(tmp, **arrays)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _tile_shapes(spec: CatalogSpec) -> dict:
    """Name -> (shape, dtype) of every array a tile of ``spec`` holds (see :func:`_render_job`)."""
    s = spec.size_px
    want = {}
    for i in range(len(spec.shapes)):
        want.update({f"r{i}_linear": ((s, s, 3), np.float16), f"r{i}_alpha": ((s, s), np.float16),
                     f"r{i}_display": ((s, s, 3), np.uint8), f"r{i}_exposure": ((), np.float64)})
    if spec.angular_map:
        m = AMAP_ANGLES_DEG.size * AMAP_CELL_PX
        want.update({"amap_linear": ((m, m, 3), np.float16), "amap_display": ((m, m, 3), np.uint8)})
    return want


def npz_fits(path: Path, want: dict) -> bool:
    """Whether the ``.npz`` at ``path`` holds exactly the arrays ``want`` (name -> (shape, dtype)), judged
    from its zip directory and each member's ``.npy`` header before any array is decompressed: a small
    file that would inflate to gigabytes is refused unread (zipfile stops at the declared size)."""

    try:
        with zipfile.ZipFile(path) as zf:
            infos = {i.filename: i for i in zf.infolist()}
            if sorted(infos) != sorted(f"{k}.npy" for k in want):
                return False
            for k, (shape, dtype) in want.items():
                info = infos[f"{k}.npy"]
                if info.file_size > int(np.prod(shape)) * np.dtype(dtype).itemsize + 4096:
                    return False
                with zf.open(info) as fh:
                    major, _minor = np.lib.format.read_magic(fh)
                    read = np.lib.format.read_array_header_1_0 if major == 1 else np.lib.format.read_array_header_2_0
                    got_shape, _fortran, got_dtype = read(fh)
                if tuple(got_shape) != tuple(shape) or got_dtype != np.dtype(dtype):
                    return False
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, RuntimeError):
        return False
    return True


def load_tile(spec: CatalogSpec, cache: Path, key: str, thickness_nm: float) -> dict:
    """A tile's arrays from the cache; an entry that does not read back intact is rendered again.

    The cache is the catalog folder's own but untrusted: only a regular file no larger than
    :data:`swatch.core.limits.MAX_CACHE_ENTRY_BYTES` holding exactly the expected arrays is used.
    """

    path = cache / f"{key}.npz"
    want = _tile_shapes(spec)
    if is_regular_file(path) and path.stat().st_size <= MAX_CACHE_ENTRY_BYTES and npz_fits(path, want):
        try:
            with np.load(path, allow_pickle=False) as z:
                if sorted(z.files) == sorted(want):
                    arrays = {k: z[k] for k in z.files}
                    if all(arrays[k].shape == sh and arrays[k].dtype == dt for k, (sh, dt) in want.items()):
                        return arrays
        except (OSError, ValueError, KeyError, EOFError, MemoryError, zipfile.BadZipFile):
            pass
    arrays = _render_job(_job_args(spec, thickness_nm))
    remove_tree(path)
    _save_npz(path, arrays)
    return arrays


def render_missing(spec: CatalogSpec, thickness_nm, missing: list[int], keys: list[str], cache: Path,
                   pool, progress_factory) -> int:
    """Render the swatches ``missing`` (indices) into ``cache`` (``<key>.npz``); returns how many.

    ``pool``: a process pool (see :func:`make_pool`) or None to render in this process.
    """
    if not missing:
        return 0
    args = [_job_args(spec, thickness_nm[i]) for i in missing]
    with progress_factory(len(missing)) as bar:
        results = map(_render_job, args) if pool is None else pool.map(_render_job, args, chunksize=1)
        for i, arrays in zip(missing, results, strict=True):
            _save_npz(cache / f"{keys[i]}.npz", arrays)
            bar.update(1)
    return len(missing)


def make_pool(spec: CatalogSpec, jobs: int):
    """A process pool of ``jobs`` workers (forked after the shared tables are loaded), or None."""
    if jobs <= 1:
        return None

    # Not "fork": a process that has used OpenImageIO (or any library with threads) may hold a
    # lock at the fork and the child would deadlock. The fork server is a fresh process that
    # imports the renderer once and forks the workers from there (cheap, and thread-free).
    ctx: BaseContext
    if "forkserver" in mp.get_all_start_methods():
        ctx = mp.get_context("forkserver")
        ctx.set_forkserver_preload(["swatch", "swatch.catalog.sheets", "swatch.render.dispatch", "swatch.colorimetry.colorimeter",
                                    "swatch.io.imageio", "OpenImageIO"])

        start_forkserver_ignoring_interrupts()  # workers ignore Ctrl-C from birth (one message, the build's)
    else:
        ctx = mp.get_context("spawn")
    return ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=_warm, initargs=(spec, os.getpid()))


def _warm(spec: CatalogSpec, parent_pid: int) -> None:
    exit_with(parent_pid)  # a killed build leaves no worker (nor fork server, nor resource tracker)
    ignore_interrupts()  # Ctrl-C: the build reports it once and shuts the pool down

    wl = wavelength_grid(380.0, 780.0, spec.wavelength_step_nm)
    spec.coating(wl)
    get_colorimeter(wl, spec.illuminant, spec.observer)


# -- layout ----------------------------------------------------------------------------------

class Layout:
    """Pixel geometry of a sheet for a spec."""

    PAD = 14
    GAP = 10
    GUTTER = 14
    MARGIN = 28
    HEADER = 112
    FOOTER = 44
    LINE = 20
    LABEL_LINES = 8  # title, 6 colour/window lines, the 3-D presets' errors
    TEXT_W = 250  # room for the longest label line (26 characters of 15 px DroidSansMono)

    def __init__(self, spec: CatalogSpec):
        s = spec.size_px
        n = len(spec.shapes)
        self.size = s
        self.amap = (AMAP_ANGLES_DEG.size * AMAP_CELL_PX) if spec.angular_map else 0
        self.renders_w = n * s + (n - 1) * self.GAP
        self.label_h = self.LABEL_LINES * self.LINE + 6
        text_and_map = self.TEXT_W + (self.amap + self.GAP if self.amap else 0)
        self.tile_w = max(self.renders_w, text_and_map) + 2 * self.PAD
        self.tile_h = self.PAD + s + self.GAP + max(self.label_h, self.amap) + self.PAD
        self.cols, self.rows = spec.columns, spec.rows
        self.width = 2 * self.MARGIN + self.cols * self.tile_w + (self.cols - 1) * self.GUTTER
        self.height = self.HEADER + self.rows * self.tile_h + (self.rows - 1) * self.GUTTER + self.FOOTER + self.MARGIN
        self.width = max(self.width, 900)

    def tile_origin(self, slot: int) -> tuple[int, int]:
        r, c = divmod(slot, self.cols)
        return (self.MARGIN + c * (self.tile_w + self.GUTTER), self.HEADER + r * (self.tile_h + self.GUTTER))


# -- text helpers ----------------------------------------------------------------------------

def _strip(w: int, h: int, color) -> np.ndarray:
    img = np.empty((h, w, 3), dtype=np.uint8)
    img[:] = color
    return img


def _fmt(x, nd: int) -> str:
    return "–" if x is None else f"{x:.{nd}f}".replace("-", "−")


def _fit(text: str, size: int, max_w: int, font: str) -> str:
    if text_width(text, size, font) <= max_w:
        return text
    while text and text_width(text + "…", size, font) > max_w:
        text = text[:-1]
    return text + "…"


def _num(x, width: int, nd: int) -> str:
    return ("–" if x is None else f"{x:.{nd}f}").replace("-", "−").rjust(width)


def label_lines(rec: dict) -> list[str | None]:
    """A tile's label text: the title (thickness to 0.1 nm, voltage), then the colour and window lines in
    DroidSansMono (None: the chip, hex and colour name line, :func:`chip_line`)."""
    L, a, b = rec["Lab"]
    _, C, hue = rec["LCh"]
    pw = rec["process_window"]
    n = rec["delta_E_00_to_neighbours"]
    volts = "" if rec["voltage_V"] is None else f"  ·  {rec['voltage_V']:.1f} V"
    lines: list[str | None] = [
        f"{rec['thickness_nm']:.1f} nm{volts}",
        f"L*a*b* {_num(L, 5, 1)}{_num(a, 7, 1)}{_num(b, 7, 1)}",
        f"L*C*h  {_num(L, 5, 1)}{_num(C, 7, 1)}{_num(hue, 6, 0)}°",
        None,  # chip + hex + colour name
        f"ΔE00 prev{_num(n['previous'], 5, 1)} next{_num(n['next'], 5, 1)}",
        # the tolerance the window is judged in is the header's (one a catalog): the line fits the label
        f"window{_num(-pw['thickness_minus_nm'], 5, 1)}/+{pw['thickness_plus_nm']:.1f} nm",
    ]
    if rec.get("presets"):  # max ΔE2000 (0–60°) of the glTF (as three.js shows it) / Blender / MaterialX presets
        p = rec["presets"]
        lines.append(f"glTF {_fmt(p['threejs_max_delta_E_00'], 1)} Bl {_fmt(p['blender_max_delta_E_00'], 1)}"
                     f" MtlX {_fmt(p['materialx_max_delta_E_00'], 1)}")
    return lines


def chip_line(rec: dict) -> str:
    """The text beside a tile's small chip: the hex code and the colour name."""
    return f"{rec['srgb_hex']}  {rec['colour_name']}"


def label_width(lay: Layout) -> int:
    """Width (px) of a tile's label block (beside the angular map when there is one)."""
    return lay.tile_w - 2 * lay.PAD - (lay.amap + lay.GAP if lay.amap else 0)


def _tile_labels(rec: dict, spec: CatalogSpec, lay: Layout) -> np.ndarray:
    """The label block of a tile (uint8): numbers in DroidSansMono (it has Δ and the minus sign)."""
    w = label_width(lay)
    h = max(lay.label_h, lay.amap)
    img = _strip(w, h, CARD)
    mono, size, step = "DroidSansMono", 15, lay.LINE
    y = 17
    title, *lines = label_lines(rec)
    img = draw_text(img, _fit(str(title), 18, w, "DroidSans-Bold"), 0, y, 18, INK, font="DroidSans-Bold")
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
    img = draw_text(img, _fit(spec.name, 28, w - 220, "DroidSans-Bold"), 0, 40, 28, INK, font="DroidSans-Bold")
    img = draw_text(img, f"sheet {number} of {of}", w, 40, 18, MUTED, align="right")
    line2 = (f"{spec.film} on {spec.substrate}  ·  illuminant {header['illuminant']}, CIE {header['observer_name']} "
             f"observer  ·  model: half-vector thin film (Fujii et al. 2019)  ·  process {spec.process}: "
             + (f"{spec.nm_per_V:g} nm/V + {spec.offset_nm:g} nm" if spec.nm_per_V is not None else "no growth rate")
             + (f" to {spec.knee_V:g} V, then {spec.nm_per_V_above_knee:g} nm/V" if spec.knee_V is not None else "")
             + (f", spread {spec.spread.text().strip(' ±')}" if not spec.spread.is_zero else "")
             + (f", film index ×{spec.film_index_scale:g}" if spec.film_index_scale != 1 else "")
             + (f"  ·  finish {spec.finish_spec.label()}" if spec.finish_spec is not None else ""))
    img = draw_text(img, _fit(line2, 16, w, "DroidSans"), 0, 66, 16, INK)
    line3 = (f"L*a*b* at {ref['name']} (light {ref['light_deg']:g}°, view {ref['view_deg']:g}° from the normal)  ·  "
             f"window: the thickness and voltage deviations that keep the colour difference to the nominal "
             f"colour within " + (f"{tol['scheme']} grade {tol['grade']}: " if tol["scheme"] else "")
             + f"{tol['metric']} <= {tol['max']:g}")
    img = draw_text(img, _fit(line3, 16, w, "DroidSans"), 0, 90, 16, INK)
    img = draw_rect(img, 0, img.shape[0] - 1, w, img.shape[0], RULE)
    return img


def _footer(spec: CatalogSpec, header: dict, lay: Layout) -> np.ndarray:
    w = lay.width - 2 * lay.MARGIN
    img = _strip(w, lay.FOOTER - 8, PAGE)
    shapes = " and ".join({"flat": "flat plate", "cylinder": "half cylinder", "sphere": "sphere"}[s] for s in spec.shapes)
    model = ("paper model" if spec.model != "microfacet" else f"microfacet GGX, {spec.finish_spec.label()}"
             if spec.finish_spec is not None else f"microfacet GGX, roughness {spec.roughness:g}")
    line1 = (f"Renders: {shapes}, {model}, {lighting_caption(spec)}."
             + ("  Map: colour over light angle (up) × view angle (right), 0–85°, paper model." if spec.angular_map else ""))
    line2 = ("prev / next: CIEDE2000 to the neighbouring swatches.  glTF / Bl / MtlX: the 3-D material presets'"
             " largest CIEDE2000 from the swatch (glTF as three.js shows it, Blender, MaterialX)."
              "  Hex, chips and pictures: sRGB from CIE 1931 2° colorimetry."
              f"  swatch {header['swatch_version']}")
    img = draw_text(img, _fit(line1, 13, w, "DroidSans"), 0, 15, 13, MUTED)
    return draw_text(img, _fit(line2, 13, w, "DroidSans"), 0, 33, 13, MUTED)


# -- composition -----------------------------------------------------------------------------

def _srgb_decode(u8: np.ndarray) -> np.ndarray:
    """Linear float32 of sRGB-encoded uint8, through a 256-entry table (one output array, no temporaries)."""
    x = np.arange(256, dtype=np.float32) / np.float32(255.0)
    lut = np.where(x <= 0.04045, x / np.float32(12.92), ((x + np.float32(0.055)) / np.float32(1.055)) ** np.float32(2.4))
    return lut.astype(np.float32)[u8]


#: Working bytes per sheet pixel while a sheet is composed and written (measured ~20: 1.03 GB for a
#: 8650 × 6010 px sheet, 512 px tiles 8 × 8): the display page (3), its
#: linear float copy (12), the EXR's half buffer (6) and the PNG writer's (3), with a margin.
SHEET_BYTES_PER_PX = 24
#: A worker process before its first sheet (interpreter, numpy, colour-science, OpenImageIO).
WORKER_BASE_BYTES = 250 * 1024 ** 2


def sheet_bytes(spec: CatalogSpec) -> int:
    """Planned peak bytes of one worker composing one sheet of ``spec``."""
    lay = Layout(spec)
    return lay.width * lay.height * SHEET_BYTES_PER_PX + WORKER_BASE_BYTES


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


def compose_sheet(spec: CatalogSpec, header: dict, records: list[dict], keys: list[str], cache: Path,
                  number: int, of: int, png_path: Path, exr_path: Path) -> None:
    """Compose one sheet from cached tile renders and write its PNG and EXR (with metadata)."""

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
        arrays = load_tile(spec, cache, key, spec.thickness_nm[rec["index"] - 1])
        x0, y0 = lay.tile_origin(slot)
        draw_rect(disp, x0, y0, x0 + lay.tile_w, y0 + lay.tile_h, CARD, inplace=True)
        draw_rect(disp, x0, y0, x0 + lay.tile_w, y0 + lay.tile_h, RULE, fill=False, inplace=True)
        rx = x0 + lay.PAD + (lay.tile_w - 2 * lay.PAD - lay.renders_w) // 2
        ry = y0 + lay.PAD
        renders = []
        for i, shape in enumerate(spec.shapes):
            s = lay.size
            xx = rx + i * (s + lay.GAP)
            disp[ry:ry + s, xx:xx + s] = arrays[f"r{i}_display"]
            lin_patches.append((ry, xx, slot, f"r{i}"))  # pasted on the linear page below (tile read again)
            renders.append({"shape": shape, "rect_px": [xx, ry, s, s], "exposure": float(arrays[f"r{i}_exposure"]),
                            "lighting": tile_environment(spec) or f"light {LIGHT_DEG:g} deg"})
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
        arrays = load_tile(spec, cache, key, spec.thickness_nm[rec["index"] - 1])
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
