"""Bounded Levenberg–Marquardt on a batch of small least-squares problems, vectorised over the batch.

Each iteration evaluates every problem's residuals and forward-difference Jacobian in one call of the
residual function (the calibration's colour-science call has a fixed overhead of a few ms, so one call
per iteration instead of one per problem and parameter is what makes the table search fast), solves
the damped normal equations of all problems at once, and keeps a step only where it lowers the cost.
Used by :mod:`swatch.fit.calibration`.

References
----------
D. W. Marquardt, "An Algorithm for Least-Squares Estimation of Nonlinear Parameters", J. Soc. Indust.
Appl. Math. 11(2), 431–441 (1963), doi:10.1137/0111030.
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["batch_lm", "SPLIT_VALUES"]

#: A batch whose residuals and Jacobian come to this many values or more evaluates each iteration's trial
#: points first, then the Jacobians of the steps taken only (a leave-one-out batch of 300 folds refuses
#: most of its steps); a smaller one evaluates both in one call.
SPLIT_VALUES = 1 << 18


def batch_lm(resid: Callable[[np.ndarray, np.ndarray], np.ndarray], X0: np.ndarray, free: list[int],
             lo: np.ndarray, hi: np.ndarray, steps: np.ndarray, iters: int = 30,
             start: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Levenberg–Marquardt on a batch of problems (each iteration vectorised over the batch; forward-difference Jacobians).

    Parameters
    ----------
    resid : callable
        ``resid(X, rows)`` → residuals (len(rows), M) of parameter rows X for the batch's problems ``rows``.
    X0 : numpy.ndarray, shape (B, K)
        Starting rows (clipped to the parameters' bounds).
    free : list of int
        The free parameters' indices (columns of ``X0``; the others stay as given).
    lo, hi : numpy.ndarray, shape (K,)
        The parameters' bounds (every step is clipped to them).
    steps : numpy.ndarray, shape (K,)
        Forward-difference steps per parameter.
    iters : int, optional
        At most this many iterations of the whole batch.
    start : (numpy.ndarray, numpy.ndarray), optional
        The residuals (B, M) at the starting rows and their forward-difference Jacobians (B, P, M), when the
        caller has them (the leave-one-out folds: the full problem's, less each fold's rows); else evaluated.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The parameters (B, K) and costs (B,) (sums of squared residuals).
    """
    X = np.clip(X0.astype(np.float64), lo, hi)
    B, P = X.shape[0], len(free)
    batch = np.arange(B)
    h = steps[free]

    def at(Xc, rows, base=None):
        """Residuals at rows Xc (len(rows), K) of the problems ``rows`` and their forward-difference Jacobian,
        in ONE call of ``resid`` (each call costs colour-science's fixed overhead, ~4 ms); with ``base``, the
        residuals at Xc already known, only the P displaced rows are evaluated."""
        first = 0 if base is None else 1
        Xs = np.repeat(Xc[:, None, :], P + 1 - first, axis=1)
        Xs[:, 1 - first + np.arange(P), free] += h
        Rs = resid(Xs.reshape(-1, Xc.shape[1]), np.repeat(rows, P + 1 - first)).reshape(rows.size, P + 1 - first, -1)
        r0 = Rs[:, 0] if base is None else base
        return r0, (Rs[:, 1 - first:] - r0[:, None]) / h[None, :, None]  # (B, M), (B, P, M)

    r, J = at(X, batch) if start is None else (start[0].copy(), start[1].copy())
    cost = np.sum(r * r, axis=1)
    lam = np.full(B, 1e-3)
    # a large batch evaluates the trial points first and the Jacobians of the taken ones only (a refused step
    # keeps J; near a solution most steps are refused); a small one both in one call (colour-science's overhead)
    split = B * (P + 1) * r.shape[1] >= SPLIT_VALUES
    for _ in range(iters):  # iterations of the whole batch (each one vectorised)
        A = J @ np.swapaxes(J, 1, 2)
        g = np.einsum("bpm,bm->bp", J, r)
        diag = np.einsum("bpp->bp", A)
        Areg = A + (lam[:, None] * (diag + 1e-12))[..., None] * np.eye(P)
        step = -np.linalg.solve(Areg, g[..., None])[..., 0]
        Xn = X.copy()
        Xn[:, free] = np.clip(X[:, free] + step, lo[free], hi[free])
        if split:
            rn = resid(Xn, batch)
            cn = np.sum(rn * rn, axis=1)
            better = cn < cost
            if better.any():
                rn, Jn = at(Xn[better], batch[better], rn[better])
                X[better], r[better], cost[better], J[better] = Xn[better], rn, cn[better], Jn
        else:
            rn, Jn = at(Xn, batch)  # the trial point and, should it be taken, its Jacobian
            cn = np.sum(rn * rn, axis=1)
            better = cn < cost
            X[better], r[better], cost[better], J[better] = Xn[better], rn[better], cn[better], Jn[better]
        lam = np.where(better, lam * 0.3, lam * 10.0)
        if np.all(lam > 1e8) or np.all(np.abs(step) < 1e-9):
            break
    return X, cost
