"""Small timing helpers shared by the benchmark sections.

``SWATCH_BENCH_TINY=1`` (``python3 dev.py bench --tiny``) runs every section at a tiny size with one
repeat: what tests/test_bench.py does to keep each section running to its end. Its figures mean nothing.
"""
from __future__ import annotations

import os
import statistics
import time
from pathlib import Path

#: Every section at a tiny size, one repeat, no warm-up (the bench's smoke test).
TINY = os.environ.get("SWATCH_BENCH_TINY", "") == "1"

ROOT = Path(__file__).resolve().parents[1]

#: The default catalog's spec (the bundled ``titanium``).
DEFAULT_SPEC = ROOT / "catalog" / "titanium.toml"

#: The spec the catalog sections use in tiny mode: three swatches, small tiles, one sheet.
TINY_SPEC = """name = "Bench tiny"
[thickness]
list_nm = [50.8, 120, 210]
[render]
shapes = ["flat"]
size_px = 64
angular_map = false
[sheet]
columns = 2
rows = 2
[presets]
enabled = false
"""


def pick(full, tiny):
    """``full``, or ``tiny`` when the bench runs tiny (:data:`TINY`)."""
    return tiny if TINY else full


def bench_spec(folder) -> Path:
    """The catalog spec a section builds from: the default catalog, or in tiny mode :data:`TINY_SPEC`
    written into ``folder`` (a temporary folder of the caller's)."""
    if not TINY:
        return DEFAULT_SPEC
    path = Path(folder) / "bench-tiny.toml"
    path.write_text(TINY_SPEC, encoding="utf-8")
    return path


def median_seconds(fn, repeats: int = 5, warmup: int = 1) -> float:
    """Median wall time of ``fn()`` over ``repeats`` runs after ``warmup`` untimed runs (one run in tiny mode)."""
    if TINY:
        repeats, warmup = 1, 0
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def median_cpu_seconds(fn, repeats: int = 5, warmup: int = 1) -> float:
    """Median CPU time of this process for ``fn()`` (robust to other processes' load on a shared VM)."""
    if TINY:
        repeats, warmup = 1, 0
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times)
