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
    """Check a thickness search range and step and give its grid.

    Parameters
    ----------
    thickness_range : (float, float)
        ``(A, B)``, nm: 0 ≤ A < B ≤ :data:`swatch.core.limits.MAX_THICKNESS_NM`.
    step_nm : float
        Grid step, nm: > 0 and at most a quarter of the range.

    Returns
    -------
    (float, float, float, int)
        ``lo``, ``hi``, ``step`` (nm) and the number of grid points (at most :data:`MAX_SEARCH_POINTS`).

    Raises
    ------
    swatch.core.errors.SwatchError
        The range or step is outside those bounds (checked before any grid is allocated).

    Examples
    --------
    >>> check_search_range((0, 400), 0.5)
    (0.0, 400.0, 0.5, 801)
    """
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
    """Indices of the local minima of a sampled curve, lowest first.

    An end point of the range counts only when it is lower than every interior minimum (the best
    match lies at, or beyond, the end of the search range); otherwise a curve that merely falls
    towards the end of the range would add a minimum that is only an artefact of where the range stops.

    Parameters
    ----------
    f : numpy.ndarray, shape (K,)
        The curve on its grid.

    Returns
    -------
    numpy.ndarray of int
        Indices into ``f``, by increasing ``f``.

    Examples
    --------
    >>> local_minima(np.array([3.0, 1.0, 2.0, 0.5, 0.7, 4.0])).tolist()
    [3, 1]
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
    """Refine a grid minimum by bounded Brent minimisation (scipy) within one grid step.

    Parameters
    ----------
    fun : callable
        The full objective, thickness (nm) → float.
    grid_d : float
        The grid point of the minimum, nm.
    lo, hi : float
        The search range, nm (the refinement stays inside it).
    step : float
        The grid step, nm.

    Returns
    -------
    (float, float)
        The thickness, nm (to 0.001 nm), and the objective there; the grid point itself when it is lower.
    """
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
    """Global search on a grid, then local refinement of the best minima.

    The coarse curve's lowest local minima (up to :data:`N_SCREEN`) are re-scored with the full
    objective at their grid points; the best ``n_refine`` are refined by bounded Brent minimisation
    within one grid step.

    Parameters
    ----------
    curve_fun : callable
        () → the coarse objective on the whole grid, shape (count,) (vectorised).
    fine_fun : callable
        Thickness (nm) → the full objective.
    lo, hi, step : float
        The grid, nm (:func:`check_search_range`).
    count : int
        Number of grid points.
    min_separation : float
        Minima closer than this (nm) are the same minimum.
    n_refine : int
        How many screened minima are refined.

    Returns
    -------
    minima : list of (float, float)
        (thickness nm, objective), lowest first, at least ``min_separation`` apart.
    d_grid : numpy.ndarray, shape (count,)
        The grid, nm.
    f_coarse : numpy.ndarray, shape (count,)
        The coarse curve.
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
    """One-sigma thickness uncertainty from the objective's curvature at its minimum.

    ``σ = sqrt(2 s² / f'')`` with ``s² = f_min / (n − p)`` and ``f''`` by central differences
    (step 0.05 nm): the least-squares estimate for a sum of squares ``f``.

    Parameters
    ----------
    fine_fun : callable
        Thickness (nm) → the objective (a sum of squared residuals).
    d : float
        The minimum, nm.
    f_min : float
        The objective there.
    lo, hi : float
        The search range, nm.
    n, p : int
        Number of residuals and of fitted parameters.

    Returns
    -------
    float or None
        σ, nm; None at the range's edge, with too few residuals, or where the curvature is not positive.
    """
    h = CURVATURE_STEP_NM
    if d - h < lo or d + h > hi or n <= p:
        return None
    curv = (fine_fun(d + h) - 2.0 * f_min + fine_fun(d - h)) / (h * h)
    if not np.isfinite(curv) or curv <= 0:
        return None
    s2 = f_min / (n - p)
    return float(np.sqrt(2.0 * s2 / curv))
