"""Calibration benchmarks: ``swatch calibrate`` on 16 coupons with the profile's tables (budget 2000 ms), and
the full search over the shipped tables on 30 coupons (issue 19, budget 10 s).

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
  the nested models with leave-one-out refits; one call, median of repeats (CSV parsed once);
* ``calibrate_tables_held_out_dE00=M/X calibrate_tables_pair=F/S calibrate_tables_knee_V=K
  calibrate_tables_spread=F`` — what it found.
"""
from __future__ import annotations

import numpy as np

from benchmarks.timing import median_cpu_seconds, median_seconds


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
    from swatch.fit.calibration_table import clear_tables

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
                    f"calibrate_tables_spread={d.get('spread_fraction')}"]
