"""A catalog build's work on a Dask cluster (issue 50): ``swatch catalog build SPEC --scheduler ADDRESS``.

The build (:mod:`swatch.catalog.build`) sends its units of work to an existing ``dask.distributed`` scheduler:
each tile's renders (:func:`tile_npz`), each sheet (:func:`sheet_files`), each batch of print chips
(:func:`chip_files`) and each hero render (:func:`hero_png`). A worker computes in a folder of its own and returns
the bytes; only the building process (the client) writes the catalog folder and its cache, with the build's
journal and atomic commit, so a worker needs no access to it. The files are the same bytes as a local build's: the
same functions write them, with the same seeds; nothing of where they ran reaches a file or the fingerprint.

A worker that dies loses nothing: the scheduler gives its tasks to the others (Dask's
``distributed.scheduler.allowed-failures``); a task that raises is run again up to
:data:`swatch.core.limits.CLUSTER_TASK_RETRIES` times. Past that the build stops with one line and leaves the
catalog as it was; building again completes it. A stop (Ctrl-C) cancels the build's futures and closes the client.

Mitsuba on a worker: Dr.Jit renders with as many threads as the worker has (its ``nthreads``), one hero at a time
per worker process; its kernel cache (``DRJIT_CACHE_DIR``) is a folder in the worker's ``local_directory``
unless the worker's environment names one (:class:`DrJitCache`).

This module imports ``distributed`` at its top; the build imports it only when a scheduler is given (the optional
extra ``anodic-swatch[distributed]``).
"""
from __future__ import annotations

import asyncio
import concurrent.futures
import importlib.metadata
import os
import tempfile
import threading
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import suppress
from pathlib import Path
from typing import Any

import distributed
from distributed.comm import connect as comm_connect
from distributed.security import Security

from swatch.catalog.chips import write_chips
from swatch.catalog.fingerprint import code_fingerprint, hash_json
from swatch.catalog.hero import render_hero
from swatch.catalog.layout import make_subfolders
from swatch.catalog.sheets import compose_sheet
from swatch.catalog.tiles import render_into
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_bytes
from swatch.core.limits import CLUSTER_TASK_RETRIES, MAX_CACHE_ENTRY_BYTES, SCHEDULER_TIMEOUT_S
from swatch.core.procguard import raise_if_signalled, signals_held
from swatch.core.safepath import is_regular_file
from swatch.render.dispatch import set_engine_threads

__all__ = ["Cluster", "DrJitCache", "connect", "code_identity", "tile_npz", "sheet_files", "chip_files", "hero_png"]

#: The renderers' distributions whose versions reach the files beside those of the catalog's fingerprint.
RENDERER_DISTRIBUTIONS = ("mitsuba", "drjit", "mitsuba-oidn", "trimesh", "embreex")

#: One Mitsuba render at a time in a worker process: it takes all the worker's threads (Dr.Jit's pool is the
#: process's), and the other tasks (tiles, sheets, chips: NumPy) run beside it.
_MITSUBA = threading.Lock()


# -- the units of work (run on a worker: a folder of their own, bytes back) -------------------------------------

def tile_npz(job, thickness_nm: float) -> bytes:
    """One swatch's tile renders (:func:`swatch.catalog.tiles.render_into`), as the cache entry's bytes.

    Parameters
    ----------
    job : swatch.catalog.tiles.TileRender
        What the tiles are rendered with.
    thickness_nm : float
        The swatch's film thickness, nm.

    Returns
    -------
    bytes
        The ``.npz`` the client saves as ``<key>.npz`` in its cache.
    """
    with tempfile.TemporaryDirectory(prefix="swatch-tile-") as tmp:
        path = Path(tmp) / "tile.npz"
        render_into(job, thickness_nm, path)
        return path.read_bytes()


def sheet_files(args: tuple, tiles: dict[str, bytes]) -> tuple[bytes, bytes]:
    """One sheet (:func:`swatch.catalog.sheets.compose_sheet`) from the client's cached tiles.

    Parameters
    ----------
    args : tuple
        ``compose_sheet``'s arguments as the build makes them (its cache and output paths are the client's:
        replaced here by the worker's own folder).
    tiles : dict of str to bytes
        The sheet's tile cache entries by key (one the client could not send is rendered here).

    Returns
    -------
    tuple of bytes
        The sheet's PNG and EXR.
    """
    spec, job, header, recs, keys, _cache, number, of, _png, _exr = args
    with tempfile.TemporaryDirectory(prefix="swatch-sheet-") as tmp:
        cache = Path(tmp) / "cache"
        cache.mkdir()
        for key, blob in tiles.items():
            (cache / f"{key}.npz").write_bytes(blob)
        png, exr = Path(tmp) / "sheet.png", Path(tmp) / "sheet.exr"
        compose_sheet(spec, job, header, recs, keys, cache, number, of, png, exr)
        return png.read_bytes(), exr.read_bytes()


def chip_files(args: tuple) -> dict[str, bytes]:
    """A batch of print chips (:func:`swatch.catalog.chips.write_chips`).

    Parameters
    ----------
    args : tuple
        ``write_chips``' arguments as :func:`swatch.catalog.chips.chip_batches` makes them (its folder is the
        client's staging folder: replaced here by the worker's own).

    Returns
    -------
    dict of str to bytes
        Catalog-relative name to the file's bytes.
    """
    with tempfile.TemporaryDirectory(prefix="swatch-chips-") as tmp:
        make_subfolders(Path(tmp))
        names = write_chips(tmp, *args[1:])
        return {name: (Path(tmp) / name).read_bytes() for name in names}


def hero_png(request, finish: str | None, rec: dict) -> bytes:
    """One hero render (:func:`swatch.catalog.hero.render_hero`) with the worker's threads.

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        The hero's checked request, at the swatch's thickness.
    finish : str or None
        The finish rendered.
    rec : dict
        The swatch's record.

    Returns
    -------
    bytes
        The PNG.
    """
    with _MITSUBA, tempfile.TemporaryDirectory(prefix="swatch-hero-") as tmp:
        with suppress(ValueError):  # (not on a worker: Dr.Jit's own default, one thread per core)
            set_engine_threads("mitsuba", distributed.get_worker().state.nthreads)
        path = Path(tmp) / "hero.png"
        render_hero(request, finish, rec, path)
        return path.read_bytes()


class DrJitCache(distributed.WorkerPlugin):
    """Each worker's Dr.Jit kernel cache in its own folder: ``DRJIT_CACHE_DIR`` (which Dr.Jit reads when it
    starts, before any kernel) set to ``<local_directory>/drjit``, unless the worker's environment names one
    (a deployment's shared or persistent cache)."""

    name = "swatch-drjit-cache"

    def setup(self, worker) -> None:
        """Point ``DRJIT_CACHE_DIR`` at the worker's folder.

        Parameters
        ----------
        worker : distributed.Worker
            The worker starting (or running when the plugin is registered).
        """
        if "DRJIT_CACHE_DIR" not in os.environ:
            folder = os.path.join(worker.local_directory, "drjit")
            os.makedirs(folder, exist_ok=True)
            os.environ["DRJIT_CACHE_DIR"] = folder


def code_identity() -> str:
    """What a process's outputs depend on besides their inputs: the catalog's code fingerprint
    (:func:`swatch.catalog.fingerprint.code_fingerprint`) and the renderers' versions, hashed. A worker must
    answer the building process's own (the files and the fingerprint would disagree otherwise).

    Returns
    -------
    str
        Hex digest.
    """
    versions: dict[str, str | None] = {}
    for dist in RENDERER_DISTRIBUTIONS:
        try:
            versions[dist] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            versions[dist] = None
    return hash_json({"code": code_fingerprint(), "renderers": versions})


# -- the client side ---------------------------------------------------------------------------------------------

async def _probe(address: str, timeout_s: float) -> None:
    comm = await comm_connect(address, timeout=timeout_s, **Security().get_connection_args("client"))
    await comm.close()


def connect(address: str, timeout_s: float | None = None) -> Cluster:
    """A client of the Dask scheduler at ``address``, with at least one worker, or one line why not.

    Parameters
    ----------
    address : str
        The scheduler's address (``tcp://host:8786``, ``host:8786``; what ``dask scheduler`` prints).
    timeout_s : float, optional
        How long to wait for it to answer, and for a worker, seconds (None:
        :data:`swatch.core.limits.SCHEDULER_TIMEOUT_S`).

    Returns
    -------
    Cluster
        Connected (the build closes it).

    Raises
    ------
    swatch.core.errors.SwatchError
        No Dask scheduler answered at ``address`` within ``timeout_s``, it has no worker, or a worker runs other
        code or renderer versions than this process (:func:`code_identity`).
    """
    timeout_s = SCHEDULER_TIMEOUT_S if timeout_s is None else timeout_s
    try:
        # (a Client that fails to connect hangs its interpreter's exit). On a thread of its own: the calling
        # thread may already run an event loop (a notebook, Playwright's sync API), where asyncio.run refuses.
        with concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="swatch-probe") as pool:
            pool.submit(asyncio.run, _probe(address, timeout_s)).result()
    except Exception as exc:  # an address Dask cannot parse, no answer, or no Dask scheduler answering
        raise SwatchError(f"`scheduler` {address!r}: no Dask scheduler answered within {timeout_s:g} s "
                          f"({_one_line(exc)}); give the address `dask scheduler` prints "
                          "(tcp://HOST:8786)") from None
    client = distributed.Client(address, timeout=timeout_s, set_as_default=False)
    try:  # (a refusal or a stop: the client closed, nothing left running)
        _check_workers(client, address, timeout_s)
        client.register_plugin(DrJitCache())
    except BaseException:
        client.close()
        raise
    return Cluster(client)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def _check_workers(client, address: str, timeout_s: float) -> None:
    """At least one worker, each running this process's code (:func:`code_identity`); else one line."""
    try:
        client.wait_for_workers(1, timeout=timeout_s)
    except (TimeoutError, OSError):
        raise SwatchError(f"`scheduler` {address!r} has no worker (waited {timeout_s:g} s); start some with "
                          f"`dask worker {address}`") from None
    try:
        answers = client.run(code_identity)
    except Exception as exc:  # (a worker without swatch cannot even read the question)
        raise SwatchError(f"`scheduler` {address!r}: a worker cannot run swatch ({_one_line(exc)}); install "
                          "anodic-swatch[distributed] there, the same version as here") from None
    mine = code_identity()
    other = sorted(w for w, theirs in answers.items() if theirs != mine)
    if other:
        raise SwatchError(f"`scheduler` {address!r}: {len(other)} worker(s) ({other[0]}, …) run other swatch code or "
                          "libraries than this build (their files would differ); install the same version there")


class _Pending:
    """A unit of work sent to the cluster: ``result()`` waits for it and writes what it returned."""

    def __init__(self, cluster: Cluster, future, write: Callable[[Any], Any]):
        self.cluster, self.future, self.write = cluster, future, write

    def result(self):
        return self.write(self.cluster.result(self.future))


class Cluster:
    """The build's connection to a Dask cluster: sends the units of work, writes what comes back.

    Parameters
    ----------
    client : distributed.Client
        Connected (:func:`connect`); closed by :meth:`close`.
    """

    def __init__(self, client):
        self.client = client
        self.futures: dict[str, Any] = {}  # sent and not yet collected, by task key (cancelled by close)
        self.tiles: dict[str, Any] = {}  # tile key -> the future of its render, until its sheet is composed

    @property
    def threads(self) -> int:
        """The cluster's worker threads in all.

        Returns
        -------
        int
            Threads of all its workers (at least 1): how many batches the chips are split into.
        """
        return max(1, sum(self.client.nthreads().values()))

    def submit(self, fn, *args):
        """``fn(*args)`` on a worker (run again on another if its worker dies, or up to
        :data:`swatch.core.limits.CLUSTER_TASK_RETRIES` times after it raised).

        Parameters
        ----------
        fn : callable
            One of this module's units of work.
        *args
            Its arguments (pickled to the worker).

        Returns
        -------
        distributed.Future
            Its future, kept to be cancelled by :meth:`close`.
        """
        with signals_held(), warnings.catch_warnings():  # (a stop meanwhile: raised once the future is kept)
            # a unit carries its inputs (a sheet's cached tiles, a hero's part), which Dask finds large: no warning
            warnings.filterwarnings("ignore", "Sending large graph", UserWarning)
            future = self.client.submit(fn, *args, pure=False, retries=CLUSTER_TASK_RETRIES)
            self.futures[future.key] = future
        return future

    def result(self, future):
        """The future's value; a unit of work the cluster gave up on is one line.

        Parameters
        ----------
        future : distributed.Future
            From :meth:`submit`.

        Returns
        -------
        object
            What the unit of work returned (its exception is raised here).

        Raises
        ------
        swatch.core.errors.SwatchError
            Its workers died running it more often than the scheduler allows.
        """
        try:
            value = future.result()
            self.futures.pop(future.key, None)  # (collected: what it holds on the cluster goes when it is dropped)
        except distributed.KilledWorker as exc:
            raise SwatchError(f"the cluster gave up on a unit of the build ({exc.task}): its workers died running "
                              "it; the catalog is as it was, build again") from None
        raise_if_signalled()
        return value

    def start_renders(self, job, thickness_nm, missing: Sequence[int], keys: Sequence[str],
                      cache: Path) -> Iterator[None]:
        """:func:`swatch.catalog.tiles.start_renders` on the cluster: every missing tile sent now, each saved
        into the cache (atomic) as it is collected, in order.

        Parameters
        ----------
        job : swatch.catalog.tiles.TileRender
            What the tiles are rendered with.
        thickness_nm : sequence of float
            Every swatch's thickness, nm.
        missing : sequence of int
            The swatches to render.
        keys : sequence of str
            Every swatch's tile key.
        cache : pathlib.Path
            The build's cache.

        Returns
        -------
        iterator of None
            One item per tile saved (:func:`swatch.catalog.tiles.finish_renders`).
        """
        futures = [self.submit(tile_npz, job, float(thickness_nm[i])) for i in missing]
        self.tiles.update((keys[i], f) for i, f in zip(missing, futures, strict=True))

        def collect() -> Iterator[None]:
            for i, future in zip(missing, futures, strict=True):
                atomic_write_bytes(cache / f"{keys[i]}.npz", self.result(future))
                yield None

        return collect()

    def compose_sheet(self, *args) -> _Pending:
        """:func:`swatch.catalog.sheets.compose_sheet` on the cluster (its tiles rendered on the cluster go from
        worker to worker; those from the cache are sent from here).

        Parameters
        ----------
        *args
            ``compose_sheet``'s arguments (its cache and the staged PNG and EXR paths are this process's).

        Returns
        -------
        object
            The pending sheet: its ``result()`` waits for it and writes the PNG and EXR where the arguments say.
        """
        keys, cache, png, exr = args[4], args[5], args[8], args[9]
        tiles: dict[str, Any] = {}
        for key in keys:  # (the cache is untrusted: an entry out of bounds is not sent, the worker renders it)
            path = cache / f"{key}.npz"
            if key in self.tiles:
                tiles[key] = self.tiles[key]
            elif is_regular_file(path) and path.stat().st_size <= MAX_CACHE_ENTRY_BYTES:
                tiles[key] = path.read_bytes()

        def write(blobs: tuple[bytes, bytes]) -> None:
            png.write_bytes(blobs[0])
            exr.write_bytes(blobs[1])
            for key in keys:  # its tiles' bytes leave the workers' memory (a tile is on one sheet)
                self.tiles.pop(key, None)

        return _Pending(self, self.submit(sheet_files, args, tiles), write)

    def write_chips(self, *args) -> _Pending:
        """:func:`swatch.catalog.chips.write_chips` on the cluster.

        Parameters
        ----------
        *args
            ``write_chips``' arguments (its folder is this process's staging folder).

        Returns
        -------
        object
            The pending batch: its ``result()`` writes the chips into that folder and returns their names.
        """
        folder = Path(args[0])

        def write(files: dict[str, bytes]) -> list[str]:
            for name, blob in files.items():
                (folder / name).write_bytes(blob)
            return list(files)

        return _Pending(self, self.submit(chip_files, args), write)

    def render_heroes(self, jobs: list[tuple]) -> list[bytes]:
        """Hero renders on the cluster (:func:`hero_png`), all sent at once (``render_many`` of
        :func:`swatch.catalog.hero.hero_files`).

        Parameters
        ----------
        jobs : list of tuple
            ``(request, finish, record)`` each.

        Returns
        -------
        list of bytes
            Each one's PNG, in order.
        """
        futures = [self.submit(hero_png, *job) for job in jobs]
        return [self.result(f) for f in futures]

    def close(self) -> None:
        """Cancel what the build sent and has not collected, and close the client.

        Returns
        -------
        None
            Returns when closed.
        """
        try:
            pending = [f for f in self.futures.values() if not f.done()]
            if pending:
                self.client.cancel(pending, force=True)
        finally:
            self.futures, self.tiles = {}, {}
            self.client.close()
