"""The held-out (leave-one-out) ΔE2000 of a calibration model: each kept coupon predicted by the model fitted
without it.

Every fold starts from the full fit:

1. **one Newton step** (closed-form influence of the coupon; Cook & Weisberg 1982, §3.4; Pregibon 1981). A
   fold's objective is the full problem's less its coupon's squared residual, so its gradient at the full
   fit is the full problem's gradient less its coupon's (forward differences with the fit's own steps,
   :data:`swatch.fit.calibration.model.STEPS`: the exact derivatives of the tables), and its Hessian the full
   problem's less its coupon's — central differences over a stencil of ``1 + 2P²`` parameter rows
   (:func:`newton_steps`: a few table nodes wide, the curvature the piecewise-linear tables have on that
   scale). Time linear in the coupons.
2. **refits where the step leaves that scale**: a fold whose step differs from the full problem's own
   Newton step (a full fit short of its minimum moves every fold alike) by more than :data:`NEWTON_TRUST`
   of the stencil step in some parameter — the coupon moves the fit further than the quadratic model
   holds — is refitted from the step's point by Levenberg–Marquardt, the :data:`REFIT_FOLDS_MAX` farthest
   at most, so the work stays linear in the coupons. Measured: 11–28 of the 29 folds of the shipped line
   (examples/coupons.csv) per model; 0–32 of the 1000 of ``python3 dev.py bench calibrate``'s line (none
   in 8 of its 12 leave-one-outs, the cap in 2).

The same rule holds for every number of coupons. Checked against scipy's ``least_squares`` refitting every
fold to convergence (tests/fit/test_calibration_leave_one_out.py).

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

__all__ = ["leave_one_out", "newton_steps", "NEWTON_U_STEP_NM", "NEWTON_SCALE_STEP", "NEWTON_SPREAD_STEP",
           "NEWTON_TRUST", "REFIT_FOLDS_MAX", "REFIT_ITERS"]

#: The Newton stencil's central differences displace each parameter by this much optical growth (nm) at the
#: largest kept voltage: the tables are linear between 0.5 nm nodes, so the stencil spans a few of them.
NEWTON_U_STEP_NM = 0.5
#: The Newton stencil's steps of the film index scale and the spread fraction (their tables' nodes are
#: 0.05 and 0.01 apart).
NEWTON_SCALE_STEP = 0.005
NEWTON_SPREAD_STEP = 0.003
#: A fold whose Newton step moves a parameter by more than this fraction of its stencil step is refitted.
NEWTON_TRUST = 0.1
#: At most this many folds per model are refitted (the largest steps first).
REFIT_FOLDS_MAX = 32
#: Levenberg–Marquardt iterations of a refitted fold (it stops earlier once no fold's step is taken).
REFIT_ITERS = 40


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


def leave_one_out(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> np.ndarray:
    """Held-out ΔE2000 of each kept coupon under ``fit.model`` fitted without it (see the module docstring).

    Parameters
    ----------
    table, prob, fit : ComboTable, Problem, ModelFit
        The pair's XYZ table, the coupons and the full fit.
    keep : numpy.ndarray of bool, shape (N,)
        The inliers (each one held out in turn).

    Returns
    -------
    numpy.ndarray, shape (N,)
        ΔE2000; NaN for the coupons not kept.
    """
    idx = np.flatnonzero(keep)
    free = free_index(fit.free)
    spread = "f" in fit.free
    X, reach = _newton_folds(table, prob, fit, keep)
    far = np.argsort(-reach, kind="stable")[:REFIT_FOLDS_MAX]
    far = far[reach[far] > NEWTON_TRUST]
    if far.size:
        W = np.repeat(keep[None].astype(np.float64), far.size, axis=0)
        W[np.arange(far.size), idx[far]] = 0.0

        def resid(Xr, rows):
            return residuals(table, prob, Xr, W[rows], spread, False)

        X[far], _ = batch_lm(resid, X[far], free, LO, HI, STEPS, iters=REFIT_ITERS)
    u = growth_law_nm(prob.V[idx], X[:, 1], X[:, 0], X[:, 4], X[:, 5])  # each fold at its own coupon only
    Lab = prob.cm.Lab(table.XYZ_at(X[:, 2], u, X[:, 3] if spread else None))
    out = np.full(prob.n, np.nan)
    out[idx] = delta_E_00(Lab, prob.Lab[idx])
    return out


def _stencil(P: int, h: np.ndarray) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """The central-difference stencil (1 + 2P², P): centre, ±each step, the four corners of each pair."""
    E = np.eye(P) * h
    pairs = [(a, b) for a in range(P) for b in range(a + 1, P)]
    D = np.concatenate([np.zeros((1, P)), *([E[a], -E[a]] for a in range(P)),
                        *([E[a] + E[b], E[a] - E[b], -E[a] + E[b], -E[a] - E[b]] for a, b in pairs)])
    return D, pairs


def _newton_folds(table: ComboTable, prob: Problem, fit: ModelFit, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each kept coupon's fold after one Newton step from the full fit: parameter rows (K, 6) and how far the
    step reaches (K,), its largest |step| over the stencil step."""
    idx = np.flatnonzero(keep)
    free = free_index(fit.free)
    P = len(free)
    spread = "f" in fit.free
    x = np.clip(fit.X, LO, HI)
    have = np.flatnonzero(np.isfinite(prob.d_meas))
    rows = np.concatenate([np.arange(prob.n), have])  # each residual row's coupon
    # gradients: forward differences at the fit (its own steps), every coupon's at once
    Xg = np.repeat(x[None], P + 1, axis=0)
    Xg[1 + np.arange(P), free] += STEPS[free]
    R = residuals(table, prob, Xg, np.repeat(keep[None].astype(np.float64), P + 1, axis=0), spread, False)
    J = (R[1:] - R[:1]) / STEPS[free][:, None]  # (P, M)
    grad = np.zeros((prob.n, P))
    np.add.at(grad, rows, (2.0 * J * R[0]).T)
    # Hessians: central differences of each coupon's squared residual over the stencil
    h = newton_steps(free, float(prob.V[keep].max()))
    c = np.clip(x[free], LO[free] + h, HI[free] - h)  # the stencil's centre: inside the bounds
    D, pairs = _stencil(P, h)
    Xs = np.repeat(x[None], D.shape[0], axis=0)
    Xs[:, free] = c + D
    R = residuals(table, prob, Xs, np.repeat(keep[None].astype(np.float64), D.shape[0], axis=0), spread, False)
    q = np.zeros((D.shape[0], prob.n))  # (1 + 2P², N): each coupon's squared residual at every stencil row
    np.add.at(q.T, rows, (R ** 2).T)
    hess = np.empty((prob.n, P, P))
    for a in range(P):
        hess[:, a, a] = (q[1 + 2 * a] - 2.0 * q[0] + q[2 + 2 * a]) / h[a] ** 2
    for k, (a, b) in enumerate(pairs):
        row = 1 + 2 * P + 4 * k
        hess[:, a, b] = hess[:, b, a] = (q[row] - q[row + 1] - q[row + 2] + q[row + 3]) / (4.0 * h[a] * h[b])
    g_fold = grad.sum(axis=0)[None] - grad[idx]  # (K, P): each fold's gradient and Hessian, its coupon's taken out
    H_fold = hess.sum(axis=0)[None] - hess[idx]
    low = np.minimum(np.linalg.eigvalsh(H_fold)[:, 0], 0.0)  # a fold with negative curvature: shifted positive
    H_fold += (1e-9 * np.abs(np.einsum("kpp->k", H_fold)) - 1.1 * low)[:, None, None] * np.eye(P)
    step = -np.linalg.solve(H_fold, g_fold[..., None])[..., 0]
    X = np.repeat(x[None], idx.size, axis=0)
    X[:, free] = np.clip(x[free] + step, LO[free], HI[free])
    H = hess.sum(axis=0)
    H += (1e-9 * abs(np.trace(H)) - 1.1 * min(float(np.linalg.eigvalsh(H)[0]), 0.0)) * np.eye(P)
    own = -np.linalg.solve(H, grad.sum(axis=0))  # the full problem's own step (a fit short of its minimum)
    return X, np.max(np.abs(step - own) / h, axis=1)
