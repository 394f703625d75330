"""A generic global search for the minima of a multimodal 1-D function (thickness fits and matches).

The objectives of the fits are multimodal in thickness (interference orders). The search
evaluates the objective on a whole grid at once (a vectorised *curve*), takes its lowest local
minima (up to :data:`N_SCREEN`), re-scores them with the full objective at their grid points, and
refines the best ``n_refine`` by bounded Brent minimisation (scipy) within one grid step. Minima
closer than ``min_separation`` are the same minimum.
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.optimize import minimize_scalar

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_SEARCH_POINTS, MAX_THICKNESS_NM

__all__ = ["N_SCREEN", "N_REFINE", "MAX_SEARCH_POINTS", "check_search_range", "local_minima", "refine_minimum",
           "multimodal_search", "curvature_sigma"]

#: Local minima of the coarse search re-scored on the full data, and how many of those are refined.
N_SCREEN = 8
N_REFINE = 3
CURVATURE_STEP_NM = 0.05


def check_search_range(thickness_range, step_nm) -> tuple[float, float, float, int]:
    lo, hi = (float(x) for x in thickness_range)
    step = float(step_nm)
    if not (np.isfinite([lo, hi]).all() and 0 <= lo < hi <= MAX_THICKNESS_NM):
        raise SwatchError(f"thickness range must satisfy 0 <= A < B <= {MAX_THICKNESS_NM:g} nm (got {lo:g}:{hi:g})")
    if not (np.isfinite(step) and 0 < step <= (hi - lo) / 4):
        raise SwatchError(f"search step must be > 0 and at most a quarter of the range (got {step:g} nm)")
    span = (hi - lo) / step  # inf for a subnormal step: compared before any conversion
    if not span + 1 <= MAX_SEARCH_POINTS:
        n = f"{int(span) + 1}" if np.isfinite(span) else "too many"
        raise SwatchError(f"search grid has {n} thicknesses; use a larger step (at most {MAX_SEARCH_POINTS} points)")
    return lo, hi, step, int(np.floor(span + 1e-9)) + 1


def local_minima(f: np.ndarray) -> np.ndarray:
    """Indices of local minima of a sampled curve, lowest first.

    An end point of the range counts only when it is lower than every interior minimum (the
    best match lies at, or beyond, the end of the search range); otherwise a curve that merely
    falls towards the end of the range would add a minimum that is only an artefact of where
    the range stops.
    """
    n = f.size
    left = np.ones(n, dtype=bool)
    right = np.ones(n, dtype=bool)
    left[1:] = f[1:] < f[:-1]
    right[:-1] = f[:-1] <= f[1:]
    idx = np.flatnonzero(left & right)
    interior = idx[(idx > 0) & (idx < n - 1)]
    if interior.size:
        best_inside = f[interior].min()
        ends = idx[((idx == 0) | (idx == n - 1)) & (f[idx] < best_inside)]
        idx = np.concatenate([interior, ends])
    return idx[np.argsort(f[idx], kind="stable")]


def refine_minimum(fun: Callable[[float], float], grid_d: float, lo: float, hi: float, step: float) -> tuple[float, float]:
    a, b = max(lo, grid_d - step), min(hi, grid_d + step)
    res = minimize_scalar(fun, bounds=(a, b), method="bounded", options={"xatol": 1e-3})
    d, f = float(res.x), float(res.fun)
    f0 = float(fun(grid_d))
    if f0 < f:  # the grid point itself (e.g. a minimum on the bound of the search)
        d, f = float(grid_d), f0
    return d, f


def multimodal_search(curve_fun: Callable[[], np.ndarray], fine_fun: Callable[[float], float], lo: float,
                      hi: float, step: float, count: int, min_separation: float,
                      n_refine: int = N_REFINE) -> tuple[list[tuple[float, float]], np.ndarray, np.ndarray]:
    """Global search then local refinement.

    The coarse curve's lowest local minima (up to ``N_SCREEN``) are re-scored with the full
    objective at their grid points; the best ``n_refine`` are refined by bounded Brent
    minimisation within one grid step. Returns ``([(d, f), ...] lowest first and at least
    ``min_separation`` apart, thickness grid, coarse curve)``.
    """
    d_grid = lo + step * np.arange(count)
    f_coarse = curve_fun()
    cand = local_minima(f_coarse)[:N_SCREEN]
    screened = sorted(cand, key=lambda i: fine_fun(float(d_grid[i])))[:n_refine]
    minima = sorted((refine_minimum(fine_fun, float(d_grid[i]), lo, hi, step) for i in screened), key=lambda t: t[1])
    kept: list[tuple[float, float]] = []
    for d, f in minima:
        if all(abs(d - k) > min_separation for k, _ in kept):
            kept.append((d, f))
    return kept, d_grid, f_coarse


def curvature_sigma(fine_fun: Callable[[float], float], d: float, f_min: float, lo: float, hi: float, n: int, p: int) -> float | None:
    h = CURVATURE_STEP_NM
    if d - h < lo or d + h > hi or n <= p:
        return None
    curv = (fine_fun(d + h) - 2.0 * f_min + fine_fun(d - h)) / (h * h)
    if not np.isfinite(curv) or curv <= 0:
        return None
    s2 = f_min / (n - p)
    return float(np.sqrt(2.0 * s2 / curv))
