"""Catalog benchmark: the default titanium catalog built cold, then rebuilt with nothing changed.

Both are timed as the user runs them: ``swatch catalog build catalog/titanium.toml --out DIR`` in a
fresh process (start-up and imports included), DIR a new temporary folder; default ``--jobs``
(the machine's CPUs). Budgets (issue): cold <= 30 s, no-op <= 2 s. The cold figure is one run
(a cold build is the thing measured); the no-op figure is the median of 3.

``catalog_range_per_swatch_s``: what one more swatch of a 1 nm range costs, hero included (issue 50): the
default catalog's settings over a 1 nm range (its cover off: a fixed cost), built cold on a 2-worker Dask
``LocalCluster`` (worker processes, one thread each; local processes without the extra
``anodic-swatch[distributed]``) after one warm-up build, at two range lengths; the difference of the wall times
over the difference of the swatch counts, median of the repeats (``--tiny``: the tiny spec without heroes, local
processes, no warm-up). docs/performance.md extrapolates it to the 1,124-swatch range.
"""
from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.timing import DEFAULT_SPEC, ROOT, TINY_SPEC, bench_spec, pick

#: The range's two lengths (swatches) and the repeats of the pair (tiny: 1 and 2 swatches, once).
RANGE_SWATCHES = pick((4, 12), (1, 2))
RANGE_REPEATS = pick(3, 1)


def _build(spec: Path, out: Path) -> float:
    cmd = [sys.executable, "-m", "swatch.cli", "catalog", "build", str(spec), "--out", str(out), "--quiet"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"catalog build failed: {proc.stderr.strip()}")
    return wall


def _range_spec(folder: Path, count: int, tag: str) -> Path:
    """The default catalog's spec over ``count`` swatches 1 nm apart from 100 nm, without the page's cover (tiny:
    the tiny spec, no heroes)."""
    if pick(False, True):
        text = TINY_SPEC.replace("list_nm = [50.8, 120, 210]", f"start_nm = 100\nstop_nm = {99 + count}\nstep_nm = 1")
    else:
        text = DEFAULT_SPEC.read_text(encoding="utf-8")
        text = text.replace("start_nm = 20\nstop_nm = 300\nstep_nm = 5",
                            f"start_nm = 100\nstop_nm = {99 + count}\nstep_nm = 1")
        text = text.replace("hero_cover_px = 960", "hero_cover_px = 0")
        assert "hero_cover_px = 0" in text
    assert f"stop_nm = {99 + count}" in text
    path = folder / f"range-{tag}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def range_per_swatch() -> tuple[float, str]:
    """Seconds one more swatch of a range costs (hero included), and where it was measured."""
    from swatch.catalog.build import build_catalog

    with tempfile.TemporaryDirectory(prefix="swatch-bench-range-") as tmp:
        try:  # (tiny: local processes, no warm-up; the suite tests the cluster in tests/catalog/)
            from distributed import LocalCluster

            cluster = None if pick(False, True) else LocalCluster(
                n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0", silence_logs=40)
        except ImportError:
            cluster = None
        where = "local-processes" if cluster is None else "localcluster-2x1"
        scheduler = None if cluster is None else cluster.scheduler_address
        try:  # a warm-up build first: the workers' imports and Dr.Jit kernels (a deployment's are warm)
            if not pick(False, True):
                build_catalog(_range_spec(Path(tmp), 1, "warm"), Path(tmp) / "warm", scheduler=scheduler)
            costs = []
            for r in range(RANGE_REPEATS):
                walls = []
                for n in RANGE_SWATCHES:
                    spec = _range_spec(Path(tmp), n, f"{n}")
                    t0 = time.perf_counter()
                    build_catalog(spec, Path(tmp) / f"out-{r}-{n}", scheduler=scheduler)
                    walls.append(time.perf_counter() - t0)
                costs.append((walls[1] - walls[0]) / (RANGE_SWATCHES[1] - RANGE_SWATCHES[0]))
        finally:
            if cluster is not None:
                cluster.close()
    return statistics.median(costs), where


def run() -> list[str]:
    with tempfile.TemporaryDirectory(prefix="swatch-bench-catalog-") as tmp:
        out = Path(tmp) / "catalog"
        spec = bench_spec(tmp)
        cold = _build(spec, out)
        noop = statistics.median(_build(spec, out) for _ in range(pick(3, 1)))
    per, where = range_per_swatch()
    return [f"catalog_cold_s={cold:.2f} catalog_noop_s={noop:.2f}",
            f"catalog_range_per_swatch_s={per:.2f} catalog_range_on={where} "
            f"catalog_range_1124_h={per * 1124 / 3600:.2f}"]


if __name__ == "__main__":
    print("\n".join(run()))
