"""Catalog benchmark: the default titanium catalog built cold, then rebuilt with nothing changed.

Both are timed as the user runs them: ``swatch catalog build catalog/titanium.toml --out DIR`` in a
fresh process (start-up and imports included), DIR a new temporary folder; default ``--jobs``
(the machine's CPUs). Budgets (issue): cold <= 30 s, no-op <= 2 s. The cold figure is one run
(a cold build is the thing measured); the no-op figure is the median of 3.
"""
from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.timing import ROOT, bench_spec, pick


def _build(spec: Path, out: Path) -> float:
    cmd = [sys.executable, "-m", "swatch.cli", "catalog", "build", str(spec), "--out", str(out), "--quiet"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"catalog build failed: {proc.stderr.strip()}")
    return wall


def run() -> list[str]:
    with tempfile.TemporaryDirectory(prefix="swatch-bench-catalog-") as tmp:
        out = Path(tmp) / "catalog"
        spec = bench_spec(tmp)
        cold = _build(spec, out)
        noop = statistics.median(_build(spec, out) for _ in range(pick(3, 1)))
    return [f"catalog_cold_s={cold:.2f} catalog_noop_s={noop:.2f}"]


if __name__ == "__main__":
    print("\n".join(run()))
