"""The model search behind ``swatch calibrate``: optical tables, growth law, film index scale and spread.

Every candidate model predicts a coupon's colour from its voltage through

* the **optical growth** ``u(V) = o + r1 × min(V, knee) + r2 × max(V − knee, 0)`` (nm; the film's
  thickness times the film index scale ``s``: colours fix ``n × d``, so the fit runs in it and the
  rate–scale valley of a physical parametrisation is an axis here); the thickness is ``u / s``; a
  linear law has no knee;
* the film table's index with its real part times ``s``, on one substrate table;
* a proportional thickness spread ``σ = f × d`` (:mod:`swatch.physics.spread`; ``f u`` in optical units);
* the half-vector model at the measuring geometry, colour under the calibration's illuminant and
  observer.

Speed (every table pair with leave-one-out refits in seconds): colours are lookups in tables made
once per pair (:mod:`swatch.fit.calibration_table`); fits are Levenberg–Marquardt iterations
vectorised over a batch of problems (starts, knees or leave-one-out folds).

The leave-one-out (held-out) error of a model is the ΔE2000 of each inlier coupon predicted by the
model refitted without it. Models are nested (law → + scale → + spread → + knee); a parameter
joins only when it lowers the held-out mean ΔE2000 by at least ``GAIN_TO_KEEP`` (relative) and the
coupons leave enough degrees of freedom.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00
from swatch.core.limits import MAX_COUPONS, plan_rows
from swatch.fit.batch_lm import batch_lm
from swatch.fit.calibration_table import TABLE_SCALES, TABLE_SPREADS, U_MAX_NM, U_STEP_NM, ComboTable
from swatch.physics.growth import growth_law_nm

__all__ = ["Problem", "ModelFit", "PARAMS", "MODELS", "fit_model",
           "leave_one_out", "initial_lines", "GAIN_TO_KEEP", "predict_Lab", "covariance", "u_max_nm",
           "screen"]

#: Parameter vector: optical offset and rate, film index scale, spread fraction, knee (V), optical rate above it.
PARAMS = ("o", "r1", "s", "f", "knee", "r2")
NO_KNEE_V = 1e6
LO = np.array([-60.0, 0.2, float(TABLE_SCALES[0]), 0.0, 0.0, 0.05])
HI = np.array([120.0, 7.5, float(TABLE_SCALES[-1]), float(TABLE_SPREADS[-1]), 300.0, 7.5])
_STEPS = np.array([1e-3, 1e-5, 1e-5, 1e-5, 1e-3, 1e-5])
#: The parameter groups the nested models add, in order.
MODELS = {"linear": ("o", "r1"), "+knee": ("knee", "r2"), "+scale": ("s",), "+spread": ("f",)}
#: An added parameter must lower the held-out mean ΔE2000 by this fraction to be kept.
GAIN_TO_KEEP = 0.05
#: soft-L1 scale of the robust fits (ΔE2000).
LOSS_SCALE_DE00 = 1.0
#: Weight of a measured thickness: its residual counts as (model − measured) / this, in ΔE units.
THICKNESS_SIGMA_NM = 2.0


@dataclass
class Problem:
    """The coupons one search fits.

    Attributes
    ----------
    V : numpy.ndarray, shape (N,)
        Voltages, V.
    Lab : numpy.ndarray, shape (N, 3)
        Measured CIELAB under ``cm``'s illuminant and observer.
    d_meas : numpy.ndarray, shape (N,)
        Measured thicknesses, nm (NaN where none).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The illuminant and observer of ``Lab``, on the tables' wavelengths.
    """

    V: np.ndarray
    Lab: np.ndarray
    d_meas: np.ndarray
    cm: Colorimeter

    @property
    def n(self) -> int:
        """N, the number of coupons.

        Returns
        -------
        int
            The number of coupons.
        """
        return int(self.V.size)


def growth(X: np.ndarray, V: np.ndarray) -> np.ndarray:
    """The optical growth ``u = o + r1 min(V, knee) + r2 max(V − knee, 0)`` of parameter rows.

    Parameters
    ----------
    X : numpy.ndarray, shape (B, 6)
        Rows of :data:`PARAMS` (offset nm, rate nm/V, scale, spread, knee V, rate above nm/V).
    V : numpy.ndarray, shape (N,)
        V.

    Returns
    -------
    numpy.ndarray, shape (B, N)
        nm.
    """
    return growth_law_nm(V, X[:, 1:2], X[:, 0:1], X[:, 4:5], X[:, 5:6])


def predict_Lab(table: ComboTable, prob: Problem, X: np.ndarray, spread: bool, row=None) -> np.ndarray:
    """CIELAB of the coupons under parameter rows.

    Parameters
    ----------
    table, prob : ComboTable, Problem
        The pair's XYZ table and the coupons.
    X : numpy.ndarray, shape (B, 6)
        Parameter rows of :data:`PARAMS` (offset nm, rate nm/V, scale, spread, knee V, rate above nm/V).
    spread : bool
        Use the spread fraction (the table needs ``XYZ_spread``).
    row : numpy.ndarray of int, shape (B,), optional
        Rows of a stack of screening tables.

    Returns
    -------
    numpy.ndarray, shape (B, N, 3)
        CIELAB per row and coupon, under ``prob.cm``'s illuminant and observer.
    """
    u = growth(X, prob.V)
    XYZ = table.XYZ_at(X[:, 2:3], u, X[:, 3:4] if spread else None, None if row is None else row[:, None])
    return prob.cm.Lab(XYZ)


def _residuals(table, prob, X, weights, spread: bool, robust: bool, row=None) -> np.ndarray:
    """Residual rows (B, M): per-coupon ΔE2000 (soft-L1 transformed when robust) and thickness rows."""
    dE = delta_E_00(predict_Lab(table, prob, X, spread, row), prob.Lab[None])
    if robust:
        dE = np.sqrt(2.0 * (np.sqrt(1.0 + (dE / LOSS_SCALE_DE00) ** 2) - 1.0)) * LOSS_SCALE_DE00
    rows = [np.sqrt(weights) * dE]
    have = np.isfinite(prob.d_meas)
    if have.any():
        d = growth(X, prob.V[have]) / X[:, 2:3]
        rows.append(np.sqrt(weights[:, have]) * (d - prob.d_meas[have]) / THICKNESS_SIGMA_NM)
    return np.concatenate(rows, axis=1)


@dataclass
class ModelFit:
    """One model fitted to one table pair.

    Attributes
    ----------
    model : str
        Its name (:data:`MODELS` keys joined); ``free`` its free parameters.
    free : tuple of str
        Its free parameters, names of :data:`PARAMS`.
    X, dE : numpy.ndarray, shapes (6,) and (N,)
        The parameters and the in-sample ΔE2000.
    loo : numpy.ndarray, shape (N,), or None
        Held-out ΔE2000 (NaN for outliers).
    """

    model: str
    free: tuple[str, ...]
    X: np.ndarray  # (6,)
    dE: np.ndarray  # (N,) in-sample
    loo: np.ndarray | None = None  # (N,) held-out, NaN for outliers

    @property
    def loo_mean(self) -> float:
        """The mean held-out ΔE2000 (inf before :func:`leave_one_out`).

        Returns
        -------
        float
            Mean over the kept coupons, ΔE2000.
        """
        return float(np.nanmean(self.loo)) if self.loo is not None else float("inf")

    @property
    def loo_max(self) -> float:
        """The largest held-out ΔE2000 (inf before :func:`leave_one_out`).

        Returns
        -------
        float
            Largest over the kept coupons, ΔE2000.
        """
        return float(np.nanmax(self.loo)) if self.loo is not None else float("inf")


def _free_index(names) -> list[int]:
    return [PARAMS.index(p) for p in names]


def fit_model(table: ComboTable, prob: Problem, names: tuple[str, ...], starts: np.ndarray, keep: np.ndarray,
              robust: bool, model: str = "", iters: int = 20) -> ModelFit:
    """Fit the free parameters ``names`` from several starting rows on the coupons ``keep``; the best start wins.

    Parameters
    ----------
    table, prob : ComboTable, Problem
        The pair's XYZ table and the coupons.
    names : tuple of str
        Free parameters of :data:`PARAMS`.
    starts : numpy.ndarray, shape (B, 6)
        Starting parameter rows of :data:`PARAMS` (the fixed ones are kept).
    keep : numpy.ndarray of bool, shape (N,)
        The inliers.
    robust : bool
        Soft-L1 loss (scale :data:`LOSS_SCALE_DE00`).
    model, iters : str, int
        The model's name (recorded) and the Levenberg–Marquardt iterations.

    Returns
    -------
    ModelFit
        The best start's parameters and in-sample ΔE2000 (``loo`` not yet set).
    """
    free = _free_index(names)
    spread = "f" in names
    weights = np.broadcast_to(keep.astype(np.float64), (starts.shape[0], prob.n))

    def resid(X, rows):
        return _residuals(table, prob, X, weights[rows], spread, robust)

    X, cost = batch_lm(resid, starts, free, LO, HI, _STEPS, iters=iters)
    best = X[int(np.argmin(cost))]
    dE = delta_E_00(predict_Lab(table, prob, best[None], spread)[0], prob.Lab)
    return ModelFit(model, tuple(names), best, dE)


def knee_starts(fit: ModelFit, V: np.ndarray, keep: np.ndarray, count: int = 12) -> np.ndarray:
    """Starting rows for a knee model: ``count`` knees from the 3rd to the 3rd-last kept voltage.

    Parameters
    ----------
    fit : ModelFit
        The linear fit they start from.
    V, keep : numpy.ndarray, shape (N,)
        Voltages (V) and the inliers (bool).
    count : int
        The largest number of knee positions.

    Returns
    -------
    numpy.ndarray, shape (count, 6) or (0, 6)
        Parameter rows, the same growth at each knee; none with fewer than 6 distinct kept voltages.
    """
    v = np.sort(np.unique(V[keep]))
    if v.size < 6:
        return np.empty((0, 6))
    knees = np.linspace(v[2], v[-3], min(count, v.size - 4))
    X = np.repeat(fit.X[None], knees.size, axis=0)
    u_knee = X[:, 0] + X[:, 1] * knees
    X[:, 4] = knees
    X[:, 5] = X[:, 1]
    X[:, 0] = u_knee - X[:, 1] * knees
    return X


def leave_one_out(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> np.ndarray:
    """Held-out ΔE2000 of each kept coupon under ``fit.model`` refitted without it (all folds in one batch).

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the fit to refit fold by fold.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (each one held out in turn).

    Returns
    -------
    numpy.ndarray, shape (N,)
        NaN for the coupons not kept.
    """
    idx = np.flatnonzero(keep)
    free = _free_index(fit.free)
    spread = "f" in fit.free
    W = np.repeat(keep[None].astype(np.float64), idx.size, axis=0)
    W[np.arange(idx.size), idx] = 0.0

    def resid(X, rows):
        return _residuals(table, prob, X, W[rows], spread, False)

    # every fold starts at the full fit, where its residuals and Jacobian are the full problem's less its
    # coupon's rows: evaluated once (P + 1 rows), not once per fold
    x = np.clip(fit.X, LO, HI)
    Xs = np.repeat(x[None], len(free) + 1, axis=0)
    Xs[1 + np.arange(len(free)), free] += _STEPS[free]
    R = _residuals(table, prob, Xs, np.repeat(keep[None].astype(np.float64), len(free) + 1, axis=0), spread, False)
    have = np.flatnonzero(np.isfinite(prob.d_meas))
    out_rows = np.concatenate([np.arange(prob.n), have])[None, :] == idx[:, None]  # (K, M): each fold's coupon
    r0 = np.where(out_rows, 0.0, R[0][None])
    J0 = np.where(out_rows[:, None, :], 0.0, ((R[1:] - R[:1]) / _STEPS[free][:, None])[None])
    X, _ = batch_lm(resid, np.repeat(fit.X[None], idx.size, axis=0), free, LO, HI, _STEPS, iters=6, start=(r0, J0))
    u = growth_law_nm(prob.V[idx], X[:, 1], X[:, 0], X[:, 4], X[:, 5])  # each fold at its own coupon only
    Lab = prob.cm.Lab(table.XYZ_at(X[:, 2], u, X[:, 3] if spread else None))
    out = np.full(prob.n, np.nan)
    out[idx] = delta_E_00(Lab, prob.Lab[idx])
    return out


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


def covariance(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> np.ndarray | None:
    """Gauss–Newton covariance of the physical parameters (offset_nm, nm_per_V, s, f, knee_V,
    nm_per_V_above_knee) at ``fit`` (residual variance scaled), restricted to the free ones.

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the fitted model.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (the residuals counted).

    Returns
    -------
    numpy.ndarray or None
        (P, P) for the P free parameters; None when undetermined (too few degrees of freedom, singular).
    """
    free = _free_index(fit.free)
    spread = "f" in fit.free
    x = fit.X
    s = x[2]
    theta = np.array([x[0] / s, x[1] / s, s, x[3], x[4], x[5] / s])

    def to_x(th):
        out = th.copy()
        out[:, 0], out[:, 1], out[:, 5] = th[:, 0] * th[:, 2], th[:, 1] * th[:, 2], th[:, 5] * th[:, 2]
        return out

    w = keep.astype(np.float64)[None]
    base = _residuals(table, prob, to_x(theta[None]), w, spread, False)[0]
    h = _STEPS[free] * 10.0
    T = np.repeat(theta[None], len(free), axis=0)
    T[np.arange(len(free)), free] += h
    R = _residuals(table, prob, to_x(T), np.repeat(w, len(free), axis=0), spread, False)
    J = ((R - base[None]) / h[:, None]).T  # (M, P)
    J = J[np.concatenate([keep, np.ones(J.shape[0] - prob.n, bool)])] if J.shape[0] > prob.n else J[keep]
    dof = J.shape[0] - len(free)
    if dof <= 0:
        return None
    JtJ = J.T @ J
    if not np.all(np.isfinite(JtJ)) or np.linalg.cond(JtJ) > 1e12:
        return None
    s2 = float(np.sum(base[np.concatenate([keep, np.ones(base.size - prob.n, bool)])] ** 2)) / dof
    return np.linalg.inv(JtJ) * max(s2, 1e-12)


def u_max_nm(V) -> float:
    """The largest optical growth the search can reach at these voltages (the tables' extent).

    Parameters
    ----------
    V : array_like
        V.

    Returns
    -------
    float
        nm, at most :data:`swatch.fit.calibration_table.U_MAX_NM`.
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
            return _residuals(stack, prob, X, np.broadcast_to(ones, (rows.size, prob.n)), False, True, of[rows])

        X, cost = batch_lm(resid, X0, _free_index(names), LO, HI, _STEPS, iters=iters)
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
