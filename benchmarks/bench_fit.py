"""Fit benchmark: thickness estimation from 100-geometry sBRDF sets (the issue's validation).

Data: tests/synthetic.py (tmm.coh_tmm reflectance on the half-vector facet × GGX intensity ×
an unknown scale + 1 % noise) at the paper's ten thicknesses (Table 2), on a 10 × 10 in-plane
light × view grid (0–72°, 8° steps), 380–780 nm every 5 nm. Times are the compute of one
``fit_spectra`` call (search, refinement, uncertainty and the ΔE report; no CSV parsing), median
of repeats. Lines:

* ``fit_100_geometries_ms=T`` — the in-plane grid (the issue's figure, budget 50 ms);
* ``fit_100_offplane_ms=T`` — 100 geometries at random azimuths (no repeated facet angles);
* ``match_ms=T`` — ``match_colour`` over 0–400 nm in 0.1 nm steps;
* ``fit_recovery_max_err_nm=E fit_recovery_errors_nm=e1,...,e10`` — |estimate − truth| per thickness.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from benchmarks.timing import median_seconds

_TESTS = Path(__file__).resolve().parents[1] / "tests"


def run() -> list[str]:
    if str(_TESTS) not in sys.path:
        sys.path.insert(0, str(_TESTS))
    from synthetic import PAPER_THICKNESSES_NM, WAVELENGTHS_NM, make_measurement, paper_dataset

    import swatch  # noqa: F401  (silences colour-science's plotting notice)
    from swatch.fit.matching import match_colour
    from swatch.fit.spectral_fit import fit_spectra
    from swatch.io.measurements import SpectralMeasurement

    errors = []
    measurements = []
    for i, d in enumerate(PAPER_THICKNESSES_NM):
        _, light, view, wl, R, _ = paper_dataset(i)
        m = SpectralMeasurement.from_arrays(light, view, wl, R)
        measurements.append(m)
        errors.append(abs(fit_spectra(m).thickness_nm - d))

    m = measurements[4]
    t_fit = median_seconds(lambda: fit_spectra(m), repeats=15, warmup=2)

    rng = np.random.default_rng(1)
    light = rng.uniform(0, 75, 100)
    view = rng.uniform(0, 75, 100)
    la = np.zeros(100)
    va = rng.uniform(0, 360, 100)
    R, _ = make_measurement(138.4, light, view, WAVELENGTHS_NM, la, va, seed=1)
    m_off = SpectralMeasurement.from_arrays(light, view, WAVELENGTHS_NM, R, la, va)
    t_off = median_seconds(lambda: fit_spectra(m_off), repeats=9, warmup=1)

    t_match = median_seconds(lambda: match_colour([50.0, 0.0, -40.0]), repeats=9, warmup=1)
    return [
        f"fit_100_geometries_ms={t_fit * 1e3:.1f}",
        f"fit_100_offplane_ms={t_off * 1e3:.1f} match_ms={t_match * 1e3:.1f}",
        f"fit_recovery_max_err_nm={max(errors):.3f} fit_recovery_errors_nm=" + ",".join(f"{e:.3f}" for e in errors),
    ]


if __name__ == "__main__":
    print("\n".join(run()))
