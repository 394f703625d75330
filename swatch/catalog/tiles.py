"""A swatch's tile: its renders and angular map, keyed by content, cached and rendered in parallel.

A tile holds the swatch rendered flat and curved (``swatch.render.render_swatch``, the spec's
shapes, model and roughness, light 45° or the studio), and a small angular map
(``swatch.render.angular.angular_map``, paper model: the colour over light × view angle, 0–85°).
Tile renders are cached per swatch (``.npz`` keyed by :func:`tile_key`) and computed in
parallel processes (``--jobs``); every job is a pure function of its inputs, so the result does
not depend on the number of jobs. The sheets (``swatch.catalog.sheets``) paste them.
"""
from __future__ import annotations

import functools
import hashlib
import json
import multiprocessing as mp
import os
import zipfile
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swatch.catalog.context import CatalogContext
from swatch.catalog.folder import remove_tree
from swatch.catalog.spec import CatalogSpec
from swatch.colorimetry.colorimeter import Colorimeter
from swatch.core.choices import POINT_LIGHT
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES
from swatch.core.procguard import (
    exit_with,
    ignore_interrupts,
    raise_if_signalled,
    signals_held,
    start_forkserver_ignoring_interrupts,
)
from swatch.core.safepath import is_regular_file
from swatch.core.sources import code_hash
from swatch.physics.finishes import get_finish
from swatch.physics.model import Coating
from swatch.render import render_swatch
from swatch.render.angular import angular_map
from swatch.render.mesh import MeshShape, load_mesh

if TYPE_CHECKING:
    from multiprocessing.context import BaseContext

__all__ = ["TileRender", "tile_render", "render_tile", "tile_key", "tile_shapes", "npz_fits", "load_tile",
           "render_into", "start_renders", "finish_renders",
           "make_pool", "tile_environment", "lighting_caption", "AMAP_ANGLES_DEG", "AMAP_CELL_PX", "LIGHT_DEG", "ENVIRONMENT"]

TILE_VERSION = 1
#: Angular-map grid (light × view polar angles, degrees); 60 × 60 cells drawn at 2 px each.
AMAP_ANGLES_DEG = np.linspace(0.0, 85.0, 60)
AMAP_CELL_PX = 2
LIGHT_DEG = 45.0

#: Lighting of the tile renders for the microfacet model (GGX): the studio, exposure 1
#: (swatch.render.builtin.env_render), so a render and its chip are on one scale; the paper model keeps the light.
ENVIRONMENT = "studio"


def tile_environment(spec: CatalogSpec) -> str | None:
    """The tiles' lighting: the studio for the microfacet model, None (the point light) for the paper model.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    str or None
        The built-in lighting's name (:data:`ENVIRONMENT`, the studio), or None for the point light.
    """
    return ENVIRONMENT if spec.model == "microfacet" else None


def lighting_caption(spec: CatalogSpec) -> str:
    """The sheets' footer text for the tiles' lighting.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    str
        One line: the lighting and the exposure the tiles are shown at.
    """
    if tile_environment(spec):
        return "studio (soft boxes, dark walls, floor and horizon) at exposure 1 (white diffuser = white, as for the chip)"
    return f"one light at {LIGHT_DEG:g}°, display exposure per render"



@functools.lru_cache(maxsize=1)
def _engine_code_hash() -> str:
    """Hash of the code a tile's renders run: this module and every module it imports (the engines)."""
    return code_hash(__name__)


def tile_key(spec: CatalogSpec, thickness_nm: float, fp: dict) -> str:
    """Content hash of everything a swatch's tile renders depend on (the cache entry's name).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    thickness_nm : float
        The swatch's film thickness, nm.
    fp : dict
        The build's code fingerprint (its ``tables`` and ``versions``).

    Returns
    -------
    str
        40 hex digits.
    """
    doc = {
        "v": TILE_VERSION, "code": _engine_code_hash(), "tables": fp["tables"], "versions": fp["versions"],
        "film": spec.film, "substrate": spec.substrate, "film_index_scale": spec.film_index_scale,
        "wl_step": spec.wavelength_step_nm,
        "illuminant": spec.illuminant, "observer": spec.observer, "d": float(thickness_nm),
        "shapes": list(spec.shapes), "size": spec.size_px, "model": spec.model, "roughness": spec.roughness,
        "amap": spec.angular_map, "amap_angles": AMAP_ANGLES_DEG.tolist(), "light": LIGHT_DEG,
        "environment": tile_environment(spec), **spec.spread.metadata(),
        **({"finish": spec.finish} if spec.finish else {}),
        **({"mesh": spec.mesh_sha256} if spec.mesh else {}),  # the part, by its bytes
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:40]


# -- rendering (worker side) -----------------------------------------------------------------

@dataclass(frozen=True)
class TileRender:
    """What every tile of a catalog is rendered with: the build's coating and colorimeter (from its
    :class:`~swatch.catalog.context.CatalogContext`, not rebuilt from the spec) and the spec's render
    options. Picklable: it goes to the pool's workers as it is.

    Attributes
    ----------
    coating : swatch.physics.model.Coating
        The catalog's film on its substrate (the context's).
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        The catalog's illuminant and observer (the context's); display RGB from its 2° twin.
    shapes : tuple of str
        The shapes rendered, in order (``r0``, ``r1``, ... in the tile); ``mesh`` is the spec's part.
    size_px : int
        Pixels per side of each render.
    model : str
        The intensity model (``microfacet``: under the studio; ``paper``: the point light).
    roughness_alpha : float
        GGX α (a finish's replaces it).
    angular_map : bool
        Whether the tile holds the angular map.
    finish : str or None
        A named finish (:func:`swatch.physics.finishes.get_finish`).
    mesh_path, mesh_key : str or None
        The part's file and its :attr:`swatch.render.mesh.MeshShape.key` (``mesh:<sha256>``; a worker reads the
        file once and refuses other bytes); None without a part.
    """

    coating: Coating
    colorimeter: Colorimeter
    shapes: tuple[str, ...]
    size_px: int
    model: str
    roughness_alpha: float
    angular_map: bool
    finish: str | None
    mesh_path: str | None = None
    mesh_key: str | None = None

    @property
    def tile_renders(self) -> tuple[str, ...]:
        """The renders of a tile, in order (as :attr:`swatch.catalog.spec.CatalogSpec.tile_renders`).

        Returns
        -------
        tuple of str
            :attr:`shapes`.
        """
        return self.shapes


@functools.lru_cache(maxsize=2)
def _part(path: str, key: str) -> MeshShape:
    """The catalog's part, read once per process (a worker's tiles share it and its prepared scene)."""
    mesh = load_mesh(path)
    if mesh.key != key:
        raise SwatchError(f"{Path(path).name} changed while the catalog was being built; build again")
    return mesh


def tile_render(ctx: CatalogContext) -> TileRender:
    """The :class:`TileRender` of a build, from its context (built once, in the build).

    Parameters
    ----------
    ctx : swatch.catalog.context.CatalogContext
        The build's grid, coating and colorimeter (the records' own).

    Returns
    -------
    TileRender
        The coating, colorimeter and render options of every tile (picklable).
    """
    spec = ctx.spec
    return TileRender(ctx.coating, ctx.colorimeter, spec.tile_renders, spec.size_px, spec.model, spec.roughness,
                      spec.angular_map, spec.finish, spec.mesh_path if ctx.mesh is not None else None,
                      ctx.mesh.key if ctx.mesh is not None else None)


def render_tile(job: TileRender, thickness_nm: float) -> dict:
    """Render one swatch's tile images: a pure function of its inputs (runs in a worker process).

    Parameters
    ----------
    job : TileRender
        The build's coating, colorimeter and render options.
    thickness_nm : float
        The swatch's film thickness, nm.

    Returns
    -------
    dict
        Name → array (:func:`tile_shapes`): per shape (and the part) the exposed linear render (half), its
        coverage, its display sRGB and exposure; the angular map (linear and display) when the job asks for it.
    """
    d = float(thickness_nm)
    coating, cm = job.coating, job.colorimeter
    out: dict[str, Any] = {}
    for i, shape in enumerate(job.shapes):
        part = _part(job.mesh_path, job.mesh_key) if shape == "mesh" and job.mesh_path and job.mesh_key else None
        opts: dict[str, Any] = {"mesh": part, "model": job.model, "coating": coating, "colorimeter": cm, "space": "srgb",
                                "workers": 1, "environment": ENVIRONMENT if job.model == "microfacet" else POINT_LIGHT}
        if job.model != "microfacet":  # the light's angle, the roughness: only where they change the picture
            opts["light_deg"] = LIGHT_DEG
        opts.update({"roughness_alpha": job.roughness_alpha} if job.finish is None else {"finish": get_finish(job.finish)})
        im = render_swatch(d, "sphere" if part is not None else shape, job.size_px, **opts)
        # half floats: the sheet EXR is half anyway, and the cache stays small
        out[f"r{i}_linear"] = (np.asarray(im.linear_rgb, dtype=np.float32) * np.float32(im.exposure)).astype(np.float16)
        out[f"r{i}_alpha"] = np.asarray(im.coverage, dtype=np.float16)
        out[f"r{i}_display"] = np.asarray(im.display_rgb, dtype=np.uint8)
        out[f"r{i}_exposure"] = np.float64(im.exposure)
    if job.angular_map:
        am = angular_map(d, AMAP_ANGLES_DEG, AMAP_ANGLES_DEG, coating=coating, colorimeter=cm, model="paper")
        # rows = light angle: flip so light 0° is at the bottom (as swatch.report.figures.angular_figure)
        lin = np.asarray(am.linear_rgb, dtype=np.float32)[::-1] * np.float32(am.exposure)
        disp = np.asarray(am.display_rgb, dtype=np.uint8)[::-1]
        c = AMAP_CELL_PX
        out["amap_linear"] = np.repeat(np.repeat(lin, c, 0), c, 1).astype(np.float16)
        out["amap_display"] = np.repeat(np.repeat(disp, c, 0), c, 1)
    return out


def _save_npz(path: Path, arrays: dict) -> None:
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.npz")
    try:
        np.savez(tmp, **arrays)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def tile_shapes(spec: CatalogSpec | TileRender) -> dict:
    """Name → (shape, dtype) of every array a tile of ``spec`` holds (renders, coverage, display, exposure,
    angular map).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec or TileRender
        Its ``tile_renders`` (the shapes and the part), ``size_px`` and ``angular_map`` decide.

    Returns
    -------
    dict
        Array name → (shape tuple, numpy dtype).
    """
    s = spec.size_px
    want = {}
    for i in range(len(spec.tile_renders)):
        want.update({f"r{i}_linear": ((s, s, 3), np.float16), f"r{i}_alpha": ((s, s), np.float16),
                     f"r{i}_display": ((s, s, 3), np.uint8), f"r{i}_exposure": ((), np.float64)})
    if spec.angular_map:
        m = AMAP_ANGLES_DEG.size * AMAP_CELL_PX
        want.update({"amap_linear": ((m, m, 3), np.float16), "amap_display": ((m, m, 3), np.uint8)})
    return want


def npz_fits(path: Path, want: dict) -> bool:
    """Whether a ``.npz`` holds exactly the arrays ``want``, judged from its zip directory and each member's
    ``.npy`` header before any array is decompressed (a small file that would inflate to gigabytes is
    refused unread).

    Parameters
    ----------
    path : pathlib.Path
        The cache entry (untrusted).
    want : dict
        Name → (shape, dtype) (:func:`tile_shapes`).

    Returns
    -------
    bool
        True when the members' names, shapes and dtypes are exactly ``want``'s.
    """

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


def load_tile(job: TileRender, cache: Path, key: str, thickness_nm: float) -> dict:
    """A tile's arrays from the cache; an entry that does not read back intact is rendered again.

    The cache is the catalog folder's own but untrusted: only a regular file no larger than
    :data:`swatch.core.limits.MAX_CACHE_ENTRY_BYTES` holding exactly the expected arrays is used.

    Parameters
    ----------
    job : TileRender
        What the tile is rendered with (on a miss).
    cache : pathlib.Path
        The cache folder.
    key : str
        :func:`tile_key`.
    thickness_nm : float
        The swatch's film thickness, nm (rendered on a miss).

    Returns
    -------
    dict
        Name → array (:func:`tile_shapes`).
    """

    path = cache / f"{key}.npz"
    want = tile_shapes(job)
    if is_regular_file(path) and path.stat().st_size <= MAX_CACHE_ENTRY_BYTES and npz_fits(path, want):
        try:
            with np.load(path, allow_pickle=False) as z:
                if sorted(z.files) == sorted(want):
                    arrays = {k: z[k] for k in z.files}
                    if all(arrays[k].shape == sh and arrays[k].dtype == dt for k, (sh, dt) in want.items()):
                        return arrays
        except (OSError, ValueError, KeyError, EOFError, MemoryError, zipfile.BadZipFile):
            pass
    arrays = render_tile(job, thickness_nm)
    remove_tree(path)
    _save_npz(path, arrays)
    return arrays


def render_into(job: TileRender, thickness_nm: float, path: Path) -> None:
    """Render one swatch's tile (:func:`render_tile`) and save it as ``path`` (``<key>.npz``, atomic): in a
    worker, so the arrays are not sent back to the building process to be written there one by one.

    Parameters
    ----------
    job : TileRender
        What the tile is rendered with.
    thickness_nm : float
        The swatch's film thickness, nm.
    path : pathlib.Path
        The cache entry.

    Returns
    -------
    None
    """
    _save_npz(path, render_tile(job, thickness_nm))


def start_renders(job: TileRender, thickness_nm, missing: list[int], keys: list[str], cache: Path,
                  pool) -> Iterator[None]:
    """The renders of the swatches ``missing`` into the cache (``<key>.npz``), submitted to the pool at once
    (the workers save them; the building process fits the presets meanwhile), or, without a pool, rendered
    here one by one as they are collected.

    Parameters
    ----------
    job : TileRender
        What the tiles are rendered with (sent to the workers as it is).
    thickness_nm : sequence of float
        Every swatch's thickness, nm.
    missing : list of int
        Indices to render.
    keys : list of str
        Every swatch's :func:`tile_key`.
    cache : pathlib.Path
        The cache folder the workers write into.
    pool : concurrent.futures.ProcessPoolExecutor or None
        :func:`make_pool`; None renders here.

    Returns
    -------
    iterator of None
        One item per swatch rendered and saved, in the order of ``missing`` (:func:`finish_renders`).
    """
    ds = [float(thickness_nm[i]) for i in missing]
    jobs = [job] * len(ds)
    paths = [cache / f"{keys[i]}.npz" for i in missing]
    return map(render_into, jobs, ds, paths) if pool is None else pool.map(render_into, jobs, ds, paths, chunksize=1)


def finish_renders(renders: Iterator[None], count: int, progress_factory) -> int:
    """Wait for :func:`start_renders`' tiles (a worker's error is raised here).

    Parameters
    ----------
    renders : iterator of None
        :func:`start_renders`.
    count : int
        How many it renders.
    progress_factory : callable
        ``total`` → a context manager with ``update(n)``.

    Returns
    -------
    int
        How many were rendered.
    """
    if not count:
        return 0
    with progress_factory(count) as bar:
        for _ in renders:
            raise_if_signalled()  # (a stop whose exception a finaliser dropped: the build goes no further)
            bar.update(1)
    return count


def make_pool(jobs: int):
    """A process pool of ``jobs`` workers, or None for one job.

    The fork server (not ``fork``: a process that used OpenImageIO may hold a lock at the fork)
    imports the renderer once; the workers ignore Ctrl-C and exit with the build.

    Parameters
    ----------
    jobs : int
        Worker processes.

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor or None
        The pool (the caller shuts it down), or None when ``jobs`` is 1 or less.
    """
    if jobs <= 1:
        return None

    # Not "fork": a process that has used OpenImageIO (or any library with threads) may hold a
    # lock at the fork and the child would deadlock. The fork server is a fresh process that
    # imports the renderer once and forks the workers from there (cheap, and thread-free).
    ctx: BaseContext
    if "forkserver" in mp.get_all_start_methods():
        ctx = mp.get_context("forkserver")
        # (swatch.core.forkchild first: a worker forked once the build has gone dies without a traceback)
        ctx.set_forkserver_preload(["swatch.core.forkchild", "swatch", "swatch.catalog.sheets", "swatch.render.dispatch",
                                    "swatch.colorimetry.colorimeter", "swatch.io.imageio", "OpenImageIO"])

        start_forkserver_ignoring_interrupts()  # workers ignore Ctrl-C from birth (one message, the build's)
    else:
        ctx = mp.get_context("spawn")
    return _Pool(max_workers=jobs, mp_context=ctx, initializer=_warm, initargs=(os.getpid(),))


class _Pool(ProcessPoolExecutor):
    """A pool whose ``submit`` (which may start a worker) is not cut in two by a signal: a Ctrl-C there left a
    worker the pool did not know of, starting while the build exited, and printed its traceback (its start-up
    data named the build's semaphores, gone by then)."""

    def submit(self, fn, /, *args, **kwargs):
        with signals_held():
            return super().submit(fn, *args, **kwargs)


def _warm(parent_pid: int) -> None:
    exit_with(parent_pid)  # a killed build leaves no worker (nor fork server, nor resource tracker)
    ignore_interrupts()  # Ctrl-C: the build reports it once and shuts the pool down
