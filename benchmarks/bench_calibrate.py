"""Calibration benchmarks: ``swatch calibrate`` on 16 coupons with the profile's tables (budget 2000 ms),
the full search over the shipped tables on 30 coupons (issue 19, budget 10 s), and at the cap of 1000
coupons (issue 50, budget 60 s and 2 GB on 2 cores).

Data: 16 CIELAB coupons at 10–85 V (5 V steps) of a line growing 2.45 nm/V from 6 nm of
TiO2-Franta on Ti-Johnson (evaluated by the model on the half-vector facet at 45°:0°, D65, 10°),
0.25 ΔE*ab noise and one mislabelled coupon, calibrated from the titanium-fujii2019 profile
(TiO2-Siefke: the film index scale is fitted). Times the compute of one ``calibrate`` call
(global search over the interference order, robust refinements, outlier refit, uncertainties;
no CSV parsing), median of repeats. Lines:

* ``calibrate_ms=T`` — the 16-coupon calibration, tables fixed (``search_tables=False``), the
  table cache emptied before each call (what one ``swatch calibrate`` run computes);
  ``calibrate_cpu_ms`` the same in CPU time (robust to a loaded VM), ``calibrate_cached_ms`` a
  repeated call on the same coupons (its tables cached);
* ``calibrate_rate_nm_per_V=R calibrate_scale=S calibrate_outliers=N`` — what it found;
* ``calibrate_tables_ms=T`` — the full search of issue 19 on the simulated line of
  tests/data/simulated-line-coupons.csv (30 coupons from tmm: TiO2-Franta on Ti-Palm, a knee at
  45 V, 3.5 % spread, one mislabelled): 25 film × substrate pairs screened, the best three through
  the nested models by leave-one-out; one call, median of repeats (CSV parsed once);
* ``calibrate_tables_held_out_dE00=M/X calibrate_tables_pair=F/S calibrate_tables_knee_V=K
  calibrate_tables_spread=F`` — what it found;
* ``calibrate_1000_s=T calibrate_1000_cpu_s=C calibrate_1000_peak_mb=M`` — ``calibrate`` at the cap (``MAX_COUPONS``, 1000):
  a synthetic line generated from the model (TiO2-Siefke on Ti-Johnson, 3 nm + 2.1 nm/V, 1000 coupons
  evenly over 0.5–300 V, CIELAB at 45°:0°, D65, 10°, seeded noise 0.3 per coordinate), the full table
  search from titanium-fujii2019 (leave-one-out by Newton steps, a bounded number of folds refitted). Each
  run is a fresh process (``python -m benchmarks.bench_calibrate 1000``: cold tables); ``T`` is the median
  wall time of the ``calibrate`` call over three runs (``calibrate_1000_cpu_s`` its CPU time, all threads: what a
  loaded machine measures fairly), ``M`` the largest peak resident memory of those processes, MB
  (interpreter and imports included). ``--tiny``: 40 coupons, one run.
"""
from __future__ import annotations

import os
import statistics
import subprocess
import sys

import numpy as np

from benchmarks.timing import ROOT, median_cpu_seconds, median_seconds, pick


def run() -> list[str]:
    import swatch  # noqa: F401  (silences colour-science's plotting notice)
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.fit.calibration import calibrate
    from swatch.io.coupons import Coupons
    from swatch.physics.model import get_coating
    from swatch.physics.process import load_process

    rng = np.random.default_rng(8)
    volts = np.arange(10.0, 86.0, 5.0)
    grown = 6.0 + 2.45 * volts
    grown[7] = 6.0 + 2.45 * 20.0  # mislabelled
    coating = get_coating("TiO2-Franta", "Ti-Johnson")
    cm = get_colorimeter(coating.wavelength_nm)
    Lab = cm.Lab(cm.XYZ(coating.half_vector(grown, 45.0, 0.0)[0].R)) + rng.normal(0.0, 0.25, (volts.size, 3))
    coupons = Coupons("bench.csv", volts, np.full(volts.size, np.nan), tuple(f"c{i}" for i in range(volts.size)),
                      Lab=Lab)
    base = load_process("titanium-fujii2019")
    from swatch.fit.calibration import clear_tables

    def cold():
        clear_tables()
        return calibrate(coupons, base, search_tables=False)

    cal = cold()
    t = median_seconds(cold, repeats=5)
    cpu = median_cpu_seconds(cold, repeats=5)
    cached = median_seconds(lambda: calibrate(coupons, base, search_tables=False), repeats=5)
    lines = [f"calibrate_ms={1000 * t:.0f} calibrate_cpu_ms={1000 * cpu:.0f} calibrate_cached_ms={1000 * cached:.0f}",
             f"calibrate_rate_nm_per_V={cal.process.nm_per_V:.4f} calibrate_scale={cal.process.film_index_scale:.4f} "
             f"calibrate_outliers={int(cal.outlier.sum())}"]
    from pathlib import Path

    from swatch.io.coupons import read_coupons

    line = read_coupons(Path(__file__).resolve().parents[1] / "tests" / "data" / "simulated-line-coupons.csv")
    runs: list = []  # the timed calls' results: the figures below are the last one's (no extra untimed call)
    t = median_seconds(lambda: runs.append(calibrate(line, base)), repeats=3)
    d = runs[-1].to_dict()
    return [*lines, f"calibrate_tables_ms={1000 * t:.0f}",
                    f"calibrate_tables_held_out_dE00={d['held_out_mean_delta_E_00']:.2f}/{d['held_out_max_delta_E_00']:.2f} "
                    f"calibrate_tables_pair={d['film']}/{d['substrate']} calibrate_tables_knee_V={d.get('knee_V')} "
                    f"calibrate_tables_spread={d.get('spread_fraction')}", cap_line()]


def synthetic_line(n: int):
    """``n`` coupons of a line generated from the model (see the module docstring), seeded noise."""
    from swatch.colorimetry.appearance import thickness_colours
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.io.coupons import Coupons
    from swatch.physics.model import get_coating

    V = np.linspace(0.5, 300.0, n)
    coating = get_coating()
    Lab = thickness_colours(np.minimum(3.0 + 2.1 * V, 999.0), 45.0, 0.0, coating,
                            get_colorimeter(coating.wavelength_nm)).Lab
    Lab = Lab + np.random.default_rng(38).normal(0.0, 0.3, Lab.shape)
    return Coupons("synthetic.csv", V, np.full(n, np.nan), tuple(f"c{i:04d}" for i in range(n)), Lab=Lab)


def cap_line() -> str:
    """``calibrate_1000_s`` and ``calibrate_1000_peak_mb``: fresh processes at the cap (see the module docstring)."""
    n, runs = pick(1000, 40), pick(3, 1)
    seconds, cpu, peaks = [], [], []
    for _ in range(runs):
        proc = subprocess.run([sys.executable, "-m", "benchmarks.bench_calibrate", str(n)], cwd=ROOT, check=True,
                              capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)))
        s, c, mb = proc.stdout.split()[-3:]
        seconds.append(float(s))
        cpu.append(float(c))
        peaks.append(float(mb))
    return (f"calibrate_{n}_s={statistics.median(seconds):.1f} calibrate_{n}_cpu_s={statistics.median(cpu):.1f} "
            f"calibrate_{n}_peak_mb={max(peaks):.0f}")


def _child(n: int) -> None:
    """One cold calibration of the synthetic line: prints its wall and CPU seconds (all threads) and this
    process's peak resident memory, MB."""
    import resource
    import time

    import swatch  # noqa: F401  (silences colour-science's plotting notice)
    from swatch.fit.calibration import calibrate
    from swatch.physics.process import load_process

    coupons = synthetic_line(n)
    base = load_process("titanium-fujii2019")
    t0, c0 = time.perf_counter(), time.process_time()
    calibrate(coupons, base)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"{seconds:.3f} {cpu:.3f} {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.1f}")  # Linux: KiB


if __name__ == "__main__":
    _child(int(sys.argv[1]))
