"""The held-out (leave-one-out) ΔE2000 of a calibration model: each kept coupon predicted by the model fitted
without it.

Two routes to the folds' fits, both from the full fit:

* **refits** (:func:`refit_folds`, up to :data:`REFIT_MAX_COUPONS` kept coupons): each fold's own
  Levenberg–Marquardt iterations, all folds in one batch. Every fold evaluates every coupon, so the time
  grows as the square of the coupons.
* **one Newton step** (:func:`newton_folds`, beyond): each coupon's squared residual is modelled as a
  quadratic in the free parameters around the full fit (central differences over a stencil of
  ``1 + 2P²`` parameter rows: every coupon's gradient and Hessian at once); a fold's objective is the
  sum over the others, i.e. the full problem's gradient and Hessian less its coupon's, and its fit is
  one Newton step from the full fit — the closed-form influence of the coupon (Cook & Weisberg 1982,
  §3.4; Pregibon 1981). The time is linear in the coupons.

References
----------
R. D. Cook and S. Weisberg, *Residuals and Influence in Regression* (Chapman & Hall, 1982), §3.4.
D. Pregibon, "Logistic Regression Diagnostics", Ann. Statist. 9(4), 705–724 (1981), doi:10.1214/aos/1176345513.
"""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.fit.batch_lm import batch_lm
from swatch.fit.calibration.model import HI, LO, STEPS, ModelFit, Problem, free_index, residuals
from swatch.fit.calibration.table import ComboTable
from swatch.physics.growth import growth_law_nm

__all__ = ["leave_one_out", "refit_folds", "newton_folds", "REFIT_MAX_COUPONS", "NEWTON_U_STEP_NM"]

#: Up to this many kept coupons the folds are refitted (:func:`refit_folds`); beyond, one Newton step each
#: (:func:`newton_folds`).
REFIT_MAX_COUPONS = 300
#: The Newton step's central differences displace each parameter by this much optical growth (nm) at the
#: largest kept voltage: the tables are linear between 0.5 nm nodes, so the stencil spans a few of them.
NEWTON_U_STEP_NM = 0.5
#: The Newton stencil's steps of the film index scale and the spread fraction (their tables' nodes are
#: 0.05 and 0.01 apart).
NEWTON_SCALE_STEP = 0.005
NEWTON_SPREAD_STEP = 0.003


def leave_one_out(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> np.ndarray:
    """Held-out ΔE2000 of each kept coupon under ``fit.model`` fitted without it.

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the full fit.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (each one held out in turn).

    Returns
    -------
    numpy.ndarray, shape (N,)
        NaN for the coupons not kept: :func:`refit_folds` up to :data:`REFIT_MAX_COUPONS` kept coupons,
        :func:`newton_folds` beyond.
    """
    if int(np.count_nonzero(keep)) <= REFIT_MAX_COUPONS:
        return refit_folds(table, prob, fit, keep)
    return newton_folds(table, prob, fit, keep)


def _held_out(table: ComboTable, prob: Problem, X: np.ndarray, idx: np.ndarray, spread: bool) -> np.ndarray:
    """ΔE2000 (N,) of each fold's coupon ``idx`` under its parameter row ``X`` (NaN elsewhere)."""
    u = growth_law_nm(prob.V[idx], X[:, 1], X[:, 0], X[:, 4], X[:, 5])  # each fold at its own coupon only
    Lab = prob.cm.Lab(table.XYZ_at(X[:, 2], u, X[:, 3] if spread else None))
    out = np.full(prob.n, np.nan)
    out[idx] = delta_E_00(Lab, prob.Lab[idx])
    return out


def refit_folds(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray, iters: int = 6) -> np.ndarray:
    """Held-out ΔE2000 of each kept coupon under ``fit.model`` refitted without it (all folds in one batch,
    ``iters`` Levenberg–Marquardt iterations each from the full fit).

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the fit to refit fold by fold.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (each one held out in turn).
    iters : int
        Levenberg–Marquardt iterations per fold (six in the calibration).

    Returns
    -------
    numpy.ndarray, shape (N,)
        NaN for the coupons not kept.
    """
    idx = np.flatnonzero(keep)
    free = free_index(fit.free)
    spread = "f" in fit.free
    W = np.repeat(keep[None].astype(np.float64), idx.size, axis=0)
    W[np.arange(idx.size), idx] = 0.0

    def resid(X, rows):
        return residuals(table, prob, X, W[rows], spread, False)

    # every fold starts at the full fit, where its residuals and Jacobian are the full problem's less its
    # coupon's rows: evaluated once (P + 1 rows), not once per fold
    x = np.clip(fit.X, LO, HI)
    Xs = np.repeat(x[None], len(free) + 1, axis=0)
    Xs[1 + np.arange(len(free)), free] += STEPS[free]
    R = residuals(table, prob, Xs, np.repeat(keep[None].astype(np.float64), len(free) + 1, axis=0), spread, False)
    have = np.flatnonzero(np.isfinite(prob.d_meas))
    out_rows = np.concatenate([np.arange(prob.n), have])[None, :] == idx[:, None]  # (K, M): each fold's coupon
    r0 = np.where(out_rows, 0.0, R[0][None])
    J0 = np.where(out_rows[:, None, :], 0.0, ((R[1:] - R[:1]) / STEPS[free][:, None])[None])
    X, _ = batch_lm(resid, np.repeat(fit.X[None], idx.size, axis=0), free, LO, HI, STEPS, iters=iters, start=(r0, J0))
    return _held_out(table, prob, X, idx, spread)


def newton_steps(free: list[int], v_max: float) -> np.ndarray:
    """The Newton stencil's step of each free parameter.

    Parameters
    ----------
    free : list of int
        Columns of :data:`swatch.fit.calibration.model.PARAMS`.
    v_max : float
        The largest kept voltage, V.

    Returns
    -------
    numpy.ndarray, shape (P,)
        In the parameters' units (nm, nm/V, 1, 1, V, nm/V).
    """
    per = np.array([NEWTON_U_STEP_NM, NEWTON_U_STEP_NM / v_max, NEWTON_SCALE_STEP, NEWTON_SPREAD_STEP,
                    NEWTON_U_STEP_NM, NEWTON_U_STEP_NM / v_max])
    return per[free]


def newton_folds(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> np.ndarray:
    """Held-out ΔE2000 of each kept coupon under ``fit.model`` fitted without it by one Newton step from the full
    fit (the closed-form influence of the coupon; see the module docstring). Time and memory linear in N.

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the full fit.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (each one held out in turn).

    Returns
    -------
    numpy.ndarray, shape (N,)
        NaN for the coupons not kept.
    """
    idx = np.flatnonzero(keep)
    free = free_index(fit.free)
    P = len(free)
    spread = "f" in fit.free
    x = np.clip(fit.X, LO, HI)
    h = newton_steps(free, float(prob.V[keep].max()))
    c = np.clip(x[free], LO[free] + h, HI[free] - h)  # the stencil's centre: inside the bounds
    E = np.eye(P) * h
    pairs = [(a, b) for a in range(P) for b in range(a + 1, P)]
    D = np.concatenate([np.zeros((1, P)), *([E[a], -E[a]] for a in range(P)),
                        *([E[a] + E[b], E[a] - E[b], -E[a] + E[b], -E[a] - E[b]] for a, b in pairs)])
    Xs = np.repeat(x[None], D.shape[0], axis=0)
    Xs[:, free] = c + D
    R = residuals(table, prob, Xs, np.ones((D.shape[0], prob.n)), spread, False)  # (1 + 2P², M)
    q = R[:, :prob.n] ** 2  # each coupon's squared residual at every stencil row
    have = np.flatnonzero(np.isfinite(prob.d_meas))
    q[:, have] += R[:, prob.n:] ** 2
    q *= keep
    grad = np.empty((prob.n, P))
    hess = np.empty((prob.n, P, P))
    for a in range(P):
        plus, minus = q[1 + 2 * a], q[2 + 2 * a]
        grad[:, a] = (plus - minus) / (2.0 * h[a])
        hess[:, a, a] = (plus - 2.0 * q[0] + minus) / h[a] ** 2
    for k, (a, b) in enumerate(pairs):
        row = 1 + 2 * P + 4 * k
        hess[:, a, b] = hess[:, b, a] = (q[row] - q[row + 1] - q[row + 2] + q[row + 3]) / (4.0 * h[a] * h[b])
    grad += hess @ (x[free] - c)  # at the full fit (the stencil's centre may sit off a bound)
    g_fold = grad.sum(axis=0)[None] - grad[idx]  # (K, P): each fold's gradient and Hessian, its coupon's taken out
    H_fold = hess.sum(axis=0)[None] - hess[idx]
    low = np.minimum(np.linalg.eigvalsh(H_fold)[:, 0], 0.0)  # a fold with negative curvature: shifted positive
    H_fold += (1e-9 * np.abs(np.einsum("kpp->k", H_fold)) - 1.1 * low)[:, None, None] * np.eye(P)
    step = -np.linalg.solve(H_fold, g_fold[..., None])[..., 0]
    X = np.repeat(x[None], idx.size, axis=0)
    X[:, free] = np.clip(x[free] + step, LO[free], HI[free])
    return _held_out(table, prob, X, idx, spread)
