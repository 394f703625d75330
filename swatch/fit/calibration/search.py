"""The global search behind ``swatch calibrate``: every table pair's interference order and robust fit.

The interference order is found by a global grid over the growth law (each coupon's colour looked up in
a thickness → CIELAB table, :func:`initial_lines`), then refined robustly (soft-L1, so a mislabelled
coupon cannot pull the line) for every table pair at once (:func:`screen`).
"""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.limits import MAX_COUPONS, plan_rows
from swatch.fit.batch_lm import batch_lm
from swatch.fit.calibration.model import (
    HI,
    LO,
    LOSS_SCALE_DE00,
    MODELS,
    NO_KNEE_V,
    STEPS,
    THICKNESS_SIGMA_NM,
    ModelFit,
    Problem,
    free_index,
    knee_starts,
    predict_Lab,
    residuals,
)
from swatch.fit.calibration.table import U_MAX_NM, U_STEP_NM, ComboTable

__all__ = ["initial_lines", "screen", "u_max_nm"]


_GRID_BYTES_PER_CELL = 96  # working bytes per (rate, offset, coupon) cell of the grid (u, mask, index, cost)


def initial_lines(tables: list[ComboTable], prob: Problem, scale: float, count: int = 3) -> list[np.ndarray]:
    """Distinct linear laws per table pair, best by a global grid over optical rate and offset (robust ΔE2000
    sum), one per interference order: every coupon's ΔE2000 to every tabulated u is computed once per pair,
    and the grid's lookup positions once for all pairs.

    Parameters
    ----------
    tables : list of ComboTable
        The pairs' XYZ tables (one u grid: the same extent).
    prob : Problem
        The coupons.
    scale : float
        The film index scale of the lines.
    count : int
        The largest number of laws (interference orders) returned per pair.

    Returns
    -------
    list of numpy.ndarray, shape (count, 6) each
        Per pair, parameter rows (offset nm, rate nm/V, ``scale``, no spread, no knee), best first; fewer if
        fewer orders fit.
    """
    stride = 2  # a 1 nm lookup is enough to find the order (the fits refine)
    u = np.arange(0, tables[0].XYZ.shape[1], stride) * U_STEP_NM
    cost_tables = []
    for table in tables:
        Lab_u = prob.cm.Lab(table.XYZ_at(np.full(u.shape, scale), u))  # (U', 3)
        dE_table = delta_E_00(Lab_u[:, None, :], prob.Lab[None, :, :])  # (U, N)
        cost_tables.append((2.0 * (np.sqrt(1.0 + (dE_table / LOSS_SCALE_DE00) ** 2) - 1.0)).ravel())
    have = np.isfinite(prob.d_meas)
    V = prob.V
    v_max = float(V.max())
    rates = np.arange(0.4, 7.0 + 1e-9, min(0.03, 2.0 / v_max))  # ≤ 2 nm at the top voltage: the fit refines
    offsets = np.arange(-10.0, 40.0 + 1e-9, 2.0)

    def totals(r: np.ndarray) -> list[np.ndarray]:  # per pair (len(r), O): the robust cost of each line
        grid_u = offsets[None, :, None] + r[:, None, None] * V[None, None, :]  # (R, O, N)
        inside = (grid_u >= 0.0) & (grid_u <= U_MAX_NM)
        at = np.clip(np.rint(grid_u / (U_STEP_NM * stride)).astype(np.int64), 0, u.size - 1) * prob.n
        at += np.arange(prob.n)  # the flat (u, coupon) cell of each line's coupon
        thick = (np.where(have, ((grid_u / scale - np.nan_to_num(prob.d_meas)) / THICKNESS_SIGMA_NM) ** 2, 0.0)
                 if have.any() else None)
        lines = inside.all(axis=2)
        out = []
        for flat in cost_tables:
            cost = np.take(flat, at)
            if thick is not None:
                cost = cost + thick
            out.append(np.where(lines, cost.sum(axis=2), np.inf))
        return out

    # the rate × offset × coupon grid in chunks of rates planned against the run's budget (issue 22)
    rows = plan_rows(offsets.size * V.size * _GRID_BYTES_PER_CELL, "the calibration's grid search",
                     f"at most {MAX_COUPONS} coupons")
    chunks = [totals(rates[i:i + rows]) for i in range(0, rates.size, rows)]
    return [_distinct_lines(np.concatenate([c[k] for c in chunks]), rates, offsets, V, scale, count)
            for k in range(len(tables))]


def _distinct_lines(total: np.ndarray, rates, offsets, V, scale: float, count: int) -> np.ndarray:
    """The best ``count`` lines of the grid's costs ``total`` (rates × offsets) more than 8 nm apart somewhere."""
    order = np.argsort(total, axis=None)
    picks: list[tuple[float, float]] = []
    for flat in order[:5000]:
        if not np.isfinite(total.flat[flat]):
            break
        i, j = np.unravel_index(flat, total.shape)
        line = offsets[j] + rates[i] * V
        if all(np.max(np.abs(line - (o + r * V))) > 8.0 for r, o in picks):
            picks.append((float(rates[i]), float(offsets[j])))
            if len(picks) == count:
                break
    X = np.zeros((len(picks), 6))
    for k, (r, o) in enumerate(picks):
        X[k] = (o, r, scale, 0.0, NO_KNEE_V, r)
    return X


def u_max_nm(V) -> float:
    """The largest optical growth the search can reach at these voltages (the tables' extent).

    Parameters
    ----------
    V : array_like
        V.

    Returns
    -------
    float
        nm, at most :data:`swatch.fit.calibration.table.U_MAX_NM`.
    """
    return float(min(U_MAX_NM, HI[1] * float(np.max(V)) + HI[0] + 20.0))


def screen(tables: list[ComboTable], prob: Problem, scale0: float, knee: bool, iters: int = 12):
    """Robust (soft-L1) fits of every table pair at once, at a fixed scale (one-row tables): the straight law
    from each pair's interference orders, then (``knee``) a knee from six positions.

    Parameters
    ----------
    tables : list of ComboTable
        One-scale tables, one per pair.
    prob : Problem
        The coupons.
    scale0 : float
        The fixed film index scale.
    knee : bool
        Also try a knee (two-slope law) after the straight one.
    iters : int
        Levenberg–Marquardt iterations per fit.

    Returns
    -------
    list
        Per pair: (best parameter row (6,), its ΔE2000 (N,), the pair's starting lines), or None.
    """
    stack = ComboTable("*", "*", np.stack([t.XYZ[0] for t in tables]), 0.0, 0.0, np.array([scale0]))
    starts = initial_lines(tables, prob, scale0)
    out: list = [None] * len(tables)
    pair = np.concatenate([np.full(st.shape[0], k) for k, st in enumerate(starts)]).astype(np.int64)
    if pair.size == 0:
        return out
    ones = np.ones((1, prob.n))

    def run(X0, of, names):
        def resid(X, rows):
            return residuals(stack, prob, X, np.broadcast_to(ones, (rows.size, prob.n)), False, True, of[rows])

        X, cost = batch_lm(resid, X0, free_index(names), LO, HI, STEPS, iters=iters)
        best = {}
        for k in np.unique(of):
            i = np.flatnonzero(of == k)
            best[int(k)] = (X[i[np.argmin(cost[i])]], float(np.min(cost[i])))
        return best

    lines = run(np.concatenate(starts), pair, MODELS["linear"])
    result = dict(lines)
    if knee:
        X0, of = [], []
        for k, (x, _) in lines.items():
            ks = knee_starts(ModelFit("", MODELS["linear"], x, np.zeros(prob.n)), prob.V, np.ones(prob.n, bool), 6)
            X0.append(ks)
            of.append(np.full(ks.shape[0], k))
        if sum(x.shape[0] for x in X0):
            knees = run(np.concatenate(X0), np.concatenate(of).astype(np.int64), MODELS["linear"] + MODELS["+knee"])
            result.update({k: v for k, v in knees.items() if v[1] < result[k][1]})
    rows = np.array(sorted(result), dtype=np.int64)
    Xb = np.stack([result[k][0] for k in rows])
    dE = delta_E_00(predict_Lab(stack, prob, Xb, False, rows), prob.Lab[None])
    for i, k in enumerate(rows):
        out[k] = (Xb[i], dE[i], starts[k])
    return out
