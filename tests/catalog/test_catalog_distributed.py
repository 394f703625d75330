"""``swatch catalog build --scheduler``: a catalog's work on a Dask cluster (issue 50), on one 2-worker
``LocalCluster`` (worker processes) for the module: the same bytes as a local build with a worker killed
mid-build, nothing written on an unreachable scheduler or a missing install, a stop cancels the cluster's work."""
from __future__ import annotations

import os
import shutil
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")  # the extra anodic-swatch[distributed] (in the test extra too)

import distributed
from distributed import Client, LocalCluster, WorkerPlugin

import swatch  # noqa: F401  (first: silences colour-science's plotting notice)
from swatch.catalog import cluster as clustermod
from swatch.catalog.build import META_DIR, build_catalog
from swatch.catalog.spec import parse_spec
from swatch.core.errors import SwatchError
from tests.catalog.folder_helpers import digest
from tests.cli_helpers import run_swatch

pytestmark = pytest.mark.slow  # builds catalogs on a cluster

# Two swatches with tiny heroes (Mitsuba) on one sheet: every kind of unit of work (tiles, a sheet, chips, heroes)
SPEC = """
name = "Distributed test"
[thickness]
list_nm = [60, 150]
[render]
size_px = 64
hero = true
hero_size_px = 32
hero_spp = 4
[sheet]
columns = 2
rows = 1
"""


class KillFirstTile(WorkerPlugin):
    """Kills its worker's process (no cleanup, as a lost machine) when the first tile render starts on it, once in
    the cluster's life (a marker file): the scheduler must give the task to a worker that lives."""

    name = "kill-first-tile"

    def __init__(self, marker: str):
        self.marker = marker

    def transition(self, key, start, finish, **kwargs):
        if finish == "executing" and str(key).startswith("tile_npz"):
            try:
                fd = os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                return
            os.close(fd)
            os._exit(1)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """One LocalCluster of 2 worker processes for the module. Its workers share this machine's Dr.Jit kernel
    cache (DRJIT_CACHE_DIR named, as a deployment may: DrJitCache then leaves it), so the heroes' kernels the
    local build compiled are not compiled again per worker (tests' time); the per-worker folder is tested below."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DRJIT_CACHE_DIR", os.environ.get("DRJIT_CACHE_DIR", str(Path.home() / ".drjit")))
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                      silence_logs=40) as lc:
            yield lc


@pytest.fixture(scope="module")
def spec_path(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("dspec") / "dist.toml"
    path.write_text(SPEC, encoding="utf-8")
    return path


def test_same_bytes_on_the_cluster_with_a_worker_killed_mid_build(cluster, spec_path, tmp_path):
    local = build_catalog(spec_path, tmp_path / "local", jobs=1)
    # the stages the building process runs either way (presets' fits, the page's lighting and studio set) taken
    # from the local build's cache (tests' time); the cluster's units (tiles, sheets, chips, heroes) are not
    cache = tmp_path / "dist" / META_DIR / "cache"
    cache.mkdir(parents=True)
    for p in (tmp_path / "local" / META_DIR / "cache").iterdir():
        if p.name.startswith(("presets-", "explorer-env-", "studio-set-")):
            shutil.copyfile(p, cache / p.name)
    marker = tmp_path / "killed"
    with Client(cluster.scheduler_address) as client:
        client.register_plugin(KillFirstTile(str(marker)))
        try:
            res = build_catalog(spec_path, tmp_path / "dist", scheduler=cluster.scheduler_address)
        finally:
            client.unregister_worker_plugin(KillFirstTile.name)
    assert marker.exists(), "no worker was killed: the test did not test the loss of one"
    assert not res.noop and res.rendered == local.rendered == 2
    assert len(list(cache.glob("hero-*.png"))) == 2  # the heroes made on the cluster, cached here
    a, b = digest(tmp_path / "local"), digest(tmp_path / "dist")
    assert sorted(a) == sorted(b) and any(n.startswith("heroes/hero_") for n in a) and any(
        n.startswith("chips/") for n in a) and any(n.startswith("sheets/") for n in a)
    assert [n for n in a if a[n] != b[n]] == []
    # the manifests (hashes of every file, fingerprint) too: where the work ran is in no file
    assert ((tmp_path / "local" / META_DIR / "manifest.json").read_bytes()
            == (tmp_path / "dist" / META_DIR / "manifest.json").read_bytes())
    # and the folder is up to date for a local rebuild (the scheduler is not in the fingerprint)
    assert build_catalog(spec_path, tmp_path / "dist", jobs=1).noop


def test_the_spec_names_a_scheduler_outside_the_fingerprint():
    base = {"name": "x", "thickness": {"list_nm": [60]}}
    spec = parse_spec(base | {"build": {"scheduler": "tcp://10.0.0.1:8786"}})
    assert spec.scheduler == "tcp://10.0.0.1:8786" and spec.canonical() == parse_spec(base).canonical()
    with pytest.raises(SwatchError, match=r"build\.scheduler"):
        parse_spec(base | {"build": {"scheduler": 8786}})


def test_a_stop_cancels_the_clusters_work_and_leaves_the_folder(cluster, spec_path, tmp_path, monkeypatch):
    out = tmp_path / "c"

    def stop(*args, **kwargs):  # Ctrl-C while the tiles are on the cluster
        raise KeyboardInterrupt

    from swatch.catalog import execute

    monkeypatch.setattr(execute, "catalog_presets", stop)
    with pytest.raises(KeyboardInterrupt):
        build_catalog(spec_path, out, scheduler=cluster.scheduler_address)
    assert not out.exists()  # a first build stopped leaves nothing
    with Client(cluster.scheduler_address) as client:
        deadline = time.monotonic() + 10
        while client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)) == 0


def test_unreachable_scheduler_is_one_line_within_the_timeout(tmp_path, spec_path, monkeypatch):
    monkeypatch.setattr(clustermod, "SCHEDULER_TIMEOUT_S", 2.0)
    import socket

    with socket.socket() as s:  # a port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    t0 = time.monotonic()
    r = run_swatch("catalog", "build", spec_path, "--out", tmp_path / "x", "--scheduler", f"tcp://127.0.0.1:{port}")
    assert time.monotonic() - t0 < 2.0 + 5.0  # the timeout, and the build's own start
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.startswith("error: --scheduler") and r.stderr.count("\n") == 1 and "2 s" in r.stderr, r.stderr
    assert not (tmp_path / "x").exists()
    r = run_swatch("catalog", "build", spec_path, "--out", tmp_path / "x", "--scheduler", "no port here")
    assert r.returncode == 2 and r.stderr.startswith("error: ") and r.stderr.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_scheduler_from_the_environment_without_dask_installed(tmp_path, spec_path, monkeypatch):
    import swatch.catalog

    monkeypatch.delattr(swatch.catalog, "cluster")  # (imported by this module: forgotten for the test)
    monkeypatch.delitem(sys.modules, "swatch.catalog.cluster")
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails, as without the extra
    monkeypatch.setenv("SWATCH_SCHEDULER", "tcp://127.0.0.1:8786")
    r = run_swatch("catalog", "build", spec_path, "--out", tmp_path / "x")
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert r.stderr.startswith("error: --scheduler") and "pip install 'anodic-swatch[distributed]'" in r.stderr
    assert not (tmp_path / "x").exists()


def test_each_worker_has_its_own_kernel_cache_unless_one_is_named(tmp_path, monkeypatch):
    class Worker:  # what DrJitCache reads of a distributed.Worker
        local_directory = str(tmp_path / "w1")

    monkeypatch.delenv("DRJIT_CACHE_DIR", raising=False)
    clustermod.DrJitCache().setup(Worker())
    assert os.environ["DRJIT_CACHE_DIR"] == str(tmp_path / "w1" / "drjit") and (tmp_path / "w1" / "drjit").is_dir()
    Worker.local_directory = str(tmp_path / "w2")
    clustermod.DrJitCache().setup(Worker())  # a deployment's (or an earlier setup's) setting stays
    assert os.environ["DRJIT_CACHE_DIR"] == str(tmp_path / "w1" / "drjit")


def test_workers_running_other_code_are_refused(cluster, spec_path, tmp_path, monkeypatch):
    # this process's identity changed (as another library's version would change it); the workers answer theirs
    monkeypatch.setattr(clustermod, "RENDERER_DISTRIBUTIONS", (*clustermod.RENDERER_DISTRIBUTIONS, "numpy"))
    r = run_swatch("catalog", "build", spec_path, "--out", tmp_path / "x", "--scheduler", cluster.scheduler_address)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "run other swatch code" in r.stderr, r.stderr
    assert not (tmp_path / "x").exists()


def test_a_unit_the_cluster_gave_up_on_is_one_line():
    class Lost:  # a future whose workers all died running it (past distributed.scheduler.allowed-failures)
        key = "tile_npz-1"

        def result(self):
            raise distributed.KilledWorker("tile_npz-1", None, 3)  # type: ignore[arg-type]

    with pytest.raises(SwatchError, match=r"gave up on a unit of the build \(tile_npz-1\).*build again") as exc:
        clustermod.Cluster(client=None).result(Lost())
    assert "\n" not in str(exc.value)
