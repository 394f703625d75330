"""``swatch catalog build``: content-hashed, incremental, atomic catalog builds.

Layout of an output folder ``DIR``::

    DIR/index.html, catalog.json, catalog.csv, <slug>.cxf, <slug>.ase, <slug>-srgb.ase   page, data, exports
    DIR/sheets/, chips/, presets/, heroes/   sheet_NN.png/.exr, chip_S001.png/.tif, preset_S001.*, hero_S001.png
    DIR/.swatch-catalog/manifest.json   what the last build wrote (file hashes, input fingerprint)
    DIR/.swatch-catalog/cache/*.npz     tile renders, keyed by the hash of what they depend on
    DIR/.swatch-catalog/lock            one build at a time (flock)

Incremental: the build's *fingerprint* hashes the validated spec, the spec file's name, the
source of the modules that compute the outputs, the material and tolerance tables and the
library versions. If it equals the manifest's and every file listed there is intact, the build
is a no-op (nothing heavier than numpy is imported). Otherwise the numbers are recomputed (a
vectorised pass, ~1 s), each swatch's renders are taken from the cache when their key (film,
substrate, thickness, colorimetry, render options, code) is unchanged, and each sheet is
recomposed only when its own key (its tiles, labels and metadata) changed.

Atomic: every output is first written into ``DIR/.swatch-catalog/staging-*``. The commit writes
a journal (the list of files and the new manifest) and then moves the staged files into place
with ``os.replace`` (SIGINT/SIGTERM held off for those few milliseconds), removes the previous
build's files that are no longer produced, writes the manifest and deletes the journal. A
build that fails or is interrupted before the commit leaves the previous catalog untouched (its
staging folder is removed on the next run); one killed during the commit is completed from the
journal by the next run, and one whose commit fails is rolled back (``swatch.catalog.journal``).
Nothing is written or deleted outside ``DIR``; its metadata is untrusted input. An older flat folder
is migrated by the next commit (its files retired as any the build no longer writes; swatch.catalog.layout). A non-empty ``DIR`` that has no
manifest is not a swatch catalog and is refused.

Distributed: given a Dask scheduler (``scheduler``, ``[build] scheduler``), the units of work (tiles, sheets,
chips, heroes) run on its workers (:mod:`swatch.catalog.cluster`, imported only then); their bytes come back and
are staged and committed here as above.
"""
from __future__ import annotations

import json
import os
import tempfile
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from swatch.catalog.fingerprint import FORMAT_VERSION, code_fingerprint, hash_json
from swatch.catalog.folder import (
    JOURNAL,
    MANIFEST,
    META_DIR,
    cache_folder,
    check_targets,
    file_matches,
    intact,
    load_manifest,
    locked,
    meta_folder,
    remove_tree,
    signals_held,
)
from swatch.catalog.journal import commit, is_catalog, prepare_commit, recover, rollback
from swatch.catalog.layout import SHEETS, make_subfolders, output_files, sheet_count
from swatch.catalog.spec import load_spec, resolve_spec_path
from swatch.core.errors import SwatchError
from swatch.core.fileio import check_writable_dir
from swatch.core.procguard import raise_if_signalled
from swatch.core.safepath import make_real_folder
from swatch.core.sources import sha256_file

__all__ = ["build_catalog", "BuildResult", "ProgressBarFactory", "FORMAT_VERSION", "META_DIR"]

#: A progress-bar factory: ``factory(label, total)`` returns a context manager whose value has ``update(n)``
#: (``click.progressbar``'s shape; the CLI passes one, the library draws nothing itself).
ProgressBarFactory = Callable[[str, int], AbstractContextManager[Any]]


@dataclass
class BuildResult:
    """What a catalog build did.

    Attributes
    ----------
    out_dir : pathlib.Path
        The catalog folder.
    noop : bool
        The catalog was up to date (nothing written).
    swatches, sheets : int
        How many swatches and sheets the catalog has.
    rendered : int
        Tiles rendered (not from the cache).
    composed : int
        Sheets written (not reused).
    seconds : float
        Wall time.
    files : list of str
        The catalog's output names.
    """
    out_dir: Path
    noop: bool
    swatches: int
    sheets: int
    rendered: int = 0  # tiles rendered (not from the cache)
    composed: int = 0  # sheets written (not reused)
    seconds: float = 0.0
    files: list[str] = field(default_factory=list)


# -- output folder ---------------------------------------------------------------------------

def _prepare_out_dir(out: Path) -> Path:
    if out.exists() and not out.is_dir():
        raise SwatchError(f"output folder {out} is a file; give a folder")
    meta = meta_folder(out)
    if out.exists() and not is_catalog(out, meta):  # before any journal is acted on
        raise SwatchError(
            f"output folder {out} is not empty and is not a swatch catalog (no {META_DIR}/{MANIFEST}); "
            "give an empty or new folder, or a folder a previous catalog build wrote")
    check_writable_dir(out)
    return make_real_folder(meta, "catalog metadata folder")


def _read_only(out: Path, meta: Path) -> str | None:
    """Why an existing catalog folder cannot be written (a no-op rebuild is still answered), or None."""
    if os.access(out, os.W_OK | os.X_OK) and (not os.path.isdir(meta) or os.access(meta, os.W_OK | os.X_OK)):
        return None
    if not (os.path.isdir(meta) and os.path.lexists(meta / MANIFEST)):
        return None  # (no catalog there: the writability check refuses it as for any folder)
    return f"output folder {out} is not writable"


def _remove_first_build(out: Path, meta: Path) -> None:
    """A first build that failed leaves nothing: its metadata folder, and the folder if now empty."""
    remove_tree(meta)
    with suppress(OSError):
        out.rmdir()


# -- the build -------------------------------------------------------------------------------

class _NoBar:
    """The bar of a build without progress reporting."""

    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc) -> None:
        return None

    def update(self, n: int) -> None:
        return None


def _progress(label: str, total: int, bar_factory: ProgressBarFactory | None):
    """``bar_factory(label, total)``, or a bar that draws nothing (no factory, or nothing to do)."""
    if bar_factory is None or total == 0:
        return _NoBar()
    return bar_factory(label, total)


def build_catalog(spec_path, out_dir, jobs: int | None = None, progress: ProgressBarFactory | None = None,
                  log=None, scheduler: str | None = None) -> BuildResult:
    """Build (or bring up to date) the catalog of ``spec_path`` in ``out_dir``.

    Only what changed is rebuilt (tiles are cached under ``.swatch-catalog/``); the folder is
    updated by an atomic commit, so a build that fails or is killed leaves the previous catalog.

    Parameters
    ----------
    spec_path : str or path-like
        The catalog spec (TOML; see docs/catalog.md): a file, or the name of a bundled spec
        (:func:`swatch.catalog.spec.resolve_spec_path`, e.g. ``"titanium"``).
    out_dir : str or path-like
        The catalog folder (the build's own: it writes and deletes only inside it).
    jobs : int or None
        Worker processes for the sheets (None: one per core, at most 8).
    progress : callable(label, total) or None
        Progress reporting: called with a step's label (``str``) and its number of items (``int``), it
        returns a context manager whose value's ``update(n)`` is called as items finish (the signature of
        ``click.progressbar(length=total, label=label)``, which the CLI passes). None: no reporting.
    log : callable or None
        Receives one line per step.
    scheduler : str or None
        The address of a Dask scheduler (``tcp://host:8786``) to send the build's units of work to (tiles,
        sheets, chips, heroes; :mod:`swatch.catalog.cluster`, the extra ``anodic-swatch[distributed]``); None:
        the spec's ``[build] scheduler``, else local processes. The files are the same bytes either way; only
        this process writes the folder. Connected only when something must be built.

    Returns
    -------
    BuildResult
        What the build did: no-op or not, counts of tiles rendered and sheets written, wall time (s), files.
    """
    t0 = time.perf_counter()
    say = log or (lambda msg: None)
    if not str(out_dir).strip():  # (Path('') is the current folder)
        raise SwatchError("`out_dir` is an empty string; give a folder path")
    spec_path = resolve_spec_path(spec_path)
    spec, _raw = load_spec(spec_path)
    spec_name = spec_path.name
    out = Path(out_dir)
    jobs = _check_jobs(jobs)
    created = not out.exists()
    read_only = _read_only(out, out / META_DIR) if not created else None
    if read_only is not None:  # a read-only catalog: up to date is an answer; anything else is refused
        meta = meta_folder(out)
        with locked(meta, read_only=True):
            return _check_up_to_date(spec, spec_name, out, meta, read_only, t0)
    meta = _prepare_out_dir(out)
    with locked(meta):  # only the lock holder creates, changes or removes anything
        try:
            return _locked_build(spec, spec_name, out, meta, jobs, progress, say, t0,
                                 spec.scheduler if scheduler is None else scheduler)
        except BaseException:
            with signals_held():  # (a second Ctrl-C or a hang-up's SIGHUP + SIGTERM must not cut the cleanup short)
                if created and not os.path.lexists(meta / MANIFEST) and not os.path.lexists(meta / JOURNAL):
                    _remove_first_build(out, meta)  # a first build that failed leaves nothing behind
            raise


def _check_up_to_date(spec, spec_name, out, meta, why: str, t0) -> BuildResult:
    """The no-op answer for a catalog folder that cannot be written; SwatchError if it is not up to date."""
    if os.path.lexists(meta / JOURNAL):
        raise SwatchError(f"{why}, and an interrupted build left a journal to finish; make it writable and build again")
    fingerprint = hash_json({"spec": spec.canonical(), "spec_file": spec_name, "env": code_fingerprint()})
    old = load_manifest(meta)
    if old.get("fingerprint") == fingerprint and intact(out, old):
        return BuildResult(out, True, len(spec.thickness_nm), sheet_count(old), seconds=time.perf_counter() - t0,
                           files=sorted(old["files"]))
    raise SwatchError(f"{why}, and the catalog there is not up to date with {spec_name}; make it writable, or "
                      "build into another folder")


def _locked_build(spec, spec_name, out, meta, jobs, progress, say, t0, scheduler) -> BuildResult:
    recover(out, meta, say)
    fp = code_fingerprint()
    fingerprint = hash_json({"spec": spec.canonical(), "spec_file": spec_name, "env": fp})
    old = load_manifest(meta)
    if old.get("fingerprint") == fingerprint and intact(out, old):
        return BuildResult(out, True, len(spec.thickness_nm), sheet_count(old), seconds=time.perf_counter() - t0,
                           files=sorted(old["files"]))
    return _full_build(spec, spec_name, out, meta, fp, fingerprint, old, jobs, progress, say, t0, scheduler)


def _check_jobs(jobs) -> int:
    if jobs is None:
        return max(1, min(os.cpu_count() or 1, 8))
    if not isinstance(jobs, int) or not 1 <= jobs <= 64:
        raise SwatchError(f"`jobs` must be a whole number from 1 to 64 (got {jobs!r})")
    return jobs


def _connect(scheduler: str):
    """The build's Dask cluster (:func:`swatch.catalog.cluster.connect`), or one line saying what to install."""
    try:
        with signals_held():  # (as the stages' import below)
            from swatch.catalog import cluster
    except ImportError as exc:
        if (exc.name or "").split(".")[0] not in ("dask", "distributed"):
            raise
        raise SwatchError("`scheduler` needs Dask's distributed scheduler, which is not installed: "
                          "pip install 'anodic-swatch[distributed]'") from None
    return cluster.connect(scheduler)


def _full_build(spec, spec_name, out, meta, fp, fingerprint, old, jobs, progress, say, t0, scheduler) -> BuildResult:
    # The one seam between the plan (this module: fingerprint, up-to-date check) and the stages, which load
    # colour-science and OpenImageIO: imported here, after the no-op check (tests/test_layers.py); with the
    # stop signals held (a KeyboardInterrupt raised inside a nanobind module's initialisation, OpenImageIO's,
    # aborts the interpreter: exit -6 and a C++ traceback); a stop meanwhile is raised when the import is done
    with signals_held():
        from swatch.catalog import execute

    sheetmod, tilemod = execute.sheetmod, execute.tilemod
    ctx = execute.check_buildable(spec)
    data = execute.compute(ctx)
    header = execute.catalog_header(spec, data, spec_name)
    n = len(data.swatches)
    per = spec.per_sheet
    n_sheets = (n + per - 1) // per

    staging = Path(tempfile.mkdtemp(prefix="staging-", dir=meta))
    pool = cluster = None
    try:
        if scheduler:  # a Dask cluster does the work (an unreachable one: one line, the staging folder removed)
            cluster = _connect(scheduler)
        make_subfolders(staging)
        cache = cache_folder(meta)
        # 1. tiles (renders), from the cache or rendered in parallel: the pool starts on them (its workers
        # save them into the cache) before the presets are fitted and the heroes path-traced here, so both
        # overlap the renders
        tile_keys = [tilemod.tile_key(spec, d, fp) for d in data.thickness_nm]
        missing = [i for i, k in enumerate(tile_keys) if not (cache / f"{k}.npz").is_file()]
        tiles = tilemod.tile_render(data.context)  # the context's coating and colorimeter, sent to the workers
        if cluster is not None:  # the cluster's workers render, this process saves into the cache
            renders = cluster.start_renders(tiles, data.thickness_nm, missing, tile_keys, cache)
        else:
            pool = tilemod.make_pool(sheetmod.plan_jobs(spec, min(jobs, max(len(missing), n_sheets))))
            renders = tilemod.start_renders(tiles, data.thickness_nm, missing, tile_keys, cache, pool)
        preset_files: dict[str, bytes] = {}
        preset_entries: Sequence[dict | None] = [None] * n  # `[presets] enabled = false`: no fits, files, entries
        if spec.presets:
            preset_files, preset_entries = execute.catalog_presets(spec, data.records, cache,  # fits cached
                                                                   data.context.mesh)
        heroes = execute.catalog_heroes(spec, data.records, cache, say, data.context.mesh,  # when spec.hero; cached
                                        None if cluster is None else cluster.render_heroes)
        hero_out, hero_used = heroes[0], heroes[1]
        records = execute.final_records(spec, data, preset_entries, *heroes[2:])  # the one serialisation
        rendered = tilemod.finish_renders(renders, len(missing),
                                          lambda total: _progress("rendering swatches", total, progress))
        # 2. sheets: unchanged ones stay in place; the others are composed (in the pool)
        sheet_list = []
        old_sheet_keys = old.get("sheet_keys", {})
        old_files = old.get("files", {})
        files: dict[str, dict] = {}
        todo: list[Any] = []
        for s in range(n_sheets):
            recs = records[s * per:(s + 1) * per]
            png, exr = f"{SHEETS}/sheet_{s + 1:02d}.png", f"{SHEETS}/sheet_{s + 1:02d}.exr"
            key = hash_json({"tiles": tile_keys[s * per:(s + 1) * per], "records": recs, "header": header,
                              "number": s + 1, "of": n_sheets, "env": fp})
            sheet_list.append({"number": s + 1, "png": png, "exr": exr, "swatches": [r["id"] for r in recs],
                               "key": key})
            reuse = (old_sheet_keys.get(png) == key and old_sheet_keys.get(exr) == key
                     and all(file_matches(out / f, old_files.get(f)) for f in (png, exr)))
            if reuse:  # unchanged and intact: left in place, not staged
                for f in (png, exr):
                    files[f] = old_files[f]
            else:
                args = (spec, tiles, header, recs, [tile_keys[r["index"] - 1] for r in recs], cache, s + 1,
                        n_sheets, staging / png, staging / exr)
                todo.append(cluster.compose_sheet(*args) if cluster is not None
                            else pool.submit(sheetmod.compose_sheet, *args) if pool is not None else args)
        # print chips, in the pool beside the sheets
        chip_jobs: list[Any] = []
        if spec.chips:
            for args in execute.chipmod.chip_batches(staging, header, data, records, execute.metal_symbol(spec),
                                                     spec.chip_size_mm, spec.chip_dpi,
                                                     jobs if cluster is None else cluster.threads):
                chip_jobs.append(cluster.write_chips(*args) if cluster is not None
                                 else pool.submit(execute.chipmod.write_chips, *args) if pool is not None else args)
        # 3. data files, page and exports (meanwhile the pool composes the sheets)
        catalog_doc = {"format": "swatch-catalog", "format_version": FORMAT_VERSION, "catalog": header,
                       "sheets": [{k: v for k, v in sh.items() if k != "key"} for sh in sheet_list],
                       "swatches": records}
        outputs = {
            "catalog.json": (json.dumps(catalog_doc, indent=1, ensure_ascii=False, allow_nan=False) + "\n").encode(),
            "catalog.csv": execute.csv_bytes(spec, records, data.illuminant, data.observer),
            header["exports"]["cxf"]: execute.cxf_bytes(spec, data),
            header["exports"]["ase"]: execute.ase_bytes(spec, records, "lab"),
            header["exports"]["ase_srgb"]: execute.ase_bytes(spec, records, "srgb"),
        }
        outputs.update(preset_files | hero_out)
        outputs["index.html"] = execute.page(spec, data, catalog_doc, cache).encode("utf-8")
        for name, blob in outputs.items():
            (staging / name).write_bytes(blob)
        with _progress("composing sheets", len(todo), progress) as bar:
            for job in todo:
                if isinstance(job, tuple):
                    sheetmod.compose_sheet(*job)
                else:  # the pool's future, or the cluster's pending sheet (written here)
                    job.result()
                bar.update(1)
        composed = len(todo)
        chip_files = [f for job in chip_jobs
                      for f in (execute.chipmod.write_chips(*job) if isinstance(job, tuple) else job.result())]
        for name in list(outputs) + chip_files + [f for sh in sheet_list for f in (sh["png"], sh["exr"])
                                                  if f not in files]:
            p = staging / name
            files[name] = {"sha256": sha256_file(p), "size": p.stat().st_size}
        staged = output_files(staging)
        for name in staged:
            os.chmod(staging / name, 0o644)
        # 4. commit
        manifest = {"format": "swatch-catalog-manifest", "format_version": FORMAT_VERSION,
                    "fingerprint": fingerprint, "spec_file": spec_name, "name": spec.name,
                    "files": files, "sheet_keys": {f: sh["key"] for sh in sheet_list for f in (sh["png"], sh["exr"])}}
        # retired: the previous build's files no longer produced, if still as it wrote them (a user's edit stays)
        removed = sorted(f for f in set(old_files) - set(files) if file_matches(out / f, old_files[f]))
        check_targets(out, staged)
        journal = {"phase": "commit", "staging": staging.name, "files": staged, "remove": removed,
                   "manifest": manifest}
        raise_if_signalled()  # (a stop a finaliser dropped, or one the pool's threads met: no commit after it)
        with signals_held():
            prepare_commit(meta, staging, journal)
            try:
                commit(out, meta, journal)
            except (OSError, SwatchError) as exc:
                rollback(out, meta, journal)  # the previous catalog comes back as it was
                why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
                where = f" ({exc.filename})" if isinstance(exc, OSError) and exc.filename else ""
                raise SwatchError(f"could not move the new catalog into {out}: {why}{where}; "
                                  "the previous catalog was restored") from None
        # 5. prune the cache to the tiles in use
        keep = {f"{k}.npz" for k in tile_keys}
        for p in cache.glob("*.npz"):
            if p.name not in keep:
                remove_tree(p)
        execute.prune_heroes(cache, hero_used)
    except BaseException:
        with signals_held():  # the workers finish their piece, the staging folder goes: a second signal waits
            if pool is not None:
                pool.shutdown(wait=True, cancel_futures=True)
                pool = None
            if cluster is not None:  # its futures cancelled, the client closed
                cluster.close()
                cluster = None
            if not (meta / JOURNAL).exists():  # (else the commit started: the next run completes it from the journal)
                remove_tree(staging)
        raise
    finally:
        if pool is not None:
            pool.shutdown(wait=True)
        if cluster is not None:
            cluster.close()
    return BuildResult(out, False, n, n_sheets, rendered=rendered, composed=composed,
                       seconds=time.perf_counter() - t0, files=sorted(files))
