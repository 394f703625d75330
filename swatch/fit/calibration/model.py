"""The model behind ``swatch calibrate``: a coupon's colour from its voltage, and its least-squares fit.

Every candidate model predicts a coupon's colour from its voltage through

* the **optical growth** ``u(V) = o + r1 × min(V, knee) + r2 × max(V − knee, 0)`` (nm; the film's
  thickness times the film index scale ``s``: colours fix ``n × d``, so the fit runs in it and the
  rate–scale valley of a physical parametrisation is an axis here); the thickness is ``u / s``; a
  linear law has no knee;
* the film table's index with its real part times ``s``, on one substrate table;
* a proportional thickness spread ``σ = f × d`` (:mod:`swatch.physics.spread`; ``f u`` in optical units);
* the half-vector model at the measuring geometry, colour under the calibration's illuminant and
  observer.

Colours are lookups in tables made once per pair (:mod:`swatch.fit.calibration.table`); fits are
Levenberg–Marquardt iterations vectorised over a batch of problems (starts, knees or leave-one-out
folds, :mod:`swatch.fit.batch_lm`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00
from swatch.fit.batch_lm import batch_lm
from swatch.fit.calibration.table import TABLE_SCALES, TABLE_SPREADS, ComboTable
from swatch.physics.growth import growth_law_nm

__all__ = ["Problem", "ModelFit", "PARAMS", "MODELS", "LO", "HI", "STEPS", "NO_KNEE_V", "LOSS_SCALE_DE00",
           "THICKNESS_SIGMA_NM", "growth", "predict_Lab", "residuals", "free_index", "fit_model", "knee_starts",
           "covariance"]

#: Parameter vector: optical offset and rate, film index scale, spread fraction, knee (V), optical rate above it.
PARAMS = ("o", "r1", "s", "f", "knee", "r2")
NO_KNEE_V = 1e6
LO = np.array([-60.0, 0.2, float(TABLE_SCALES[0]), 0.0, 0.0, 0.05])
HI = np.array([120.0, 7.5, float(TABLE_SCALES[-1]), float(TABLE_SPREADS[-1]), 300.0, 7.5])
STEPS = np.array([1e-3, 1e-5, 1e-5, 1e-5, 1e-3, 1e-5])
#: The parameter groups the nested models add, in order.
MODELS = {"linear": ("o", "r1"), "+knee": ("knee", "r2"), "+scale": ("s",), "+spread": ("f",)}
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


def residuals(table, prob, X, weights, spread: bool, robust: bool, row=None) -> np.ndarray:
    """The residuals of parameter rows: per-coupon ΔE2000 (soft-L1 transformed when robust), then the measured
    thicknesses' rows.

    Parameters
    ----------
    table, prob : ComboTable, Problem
        The pair's XYZ table and the coupons.
    X : numpy.ndarray, shape (B, 6)
        Parameter rows of :data:`PARAMS`.
    weights : numpy.ndarray, shape (B, N)
        Per row and coupon: 1 counted, 0 left out.
    spread, robust : bool
        Use the spread fraction; soft-L1 loss (scale :data:`LOSS_SCALE_DE00`).
    row : numpy.ndarray of int, shape (B,), optional
        Rows of a stack of screening tables.

    Returns
    -------
    numpy.ndarray, shape (B, M)
        M = N ΔE2000 rows, then one row per coupon with a measured thickness ((model − measured) /
        :data:`THICKNESS_SIGMA_NM`).
    """
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
        """The mean held-out ΔE2000 (inf before :func:`swatch.fit.calibration.leave_one_out.leave_one_out`).

        Returns
        -------
        float
            Mean over the kept coupons, ΔE2000.
        """
        return float(np.nanmean(self.loo)) if self.loo is not None else float("inf")

    @property
    def loo_max(self) -> float:
        """The largest held-out ΔE2000 (inf before :func:`swatch.fit.calibration.leave_one_out.leave_one_out`).

        Returns
        -------
        float
            Largest over the kept coupons, ΔE2000.
        """
        return float(np.nanmax(self.loo)) if self.loo is not None else float("inf")


def free_index(names) -> list[int]:
    """The columns of :data:`PARAMS` named ``names``.

    Parameters
    ----------
    names : iterable of str
        Names of :data:`PARAMS`.

    Returns
    -------
    list of int
        Their indices.
    """
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
    free = free_index(names)
    spread = "f" in names
    weights = np.broadcast_to(keep.astype(np.float64), (starts.shape[0], prob.n))

    def resid(X, rows):
        return residuals(table, prob, X, weights[rows], spread, robust)

    X, cost = batch_lm(resid, starts, free, LO, HI, STEPS, iters=iters)
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
    free = free_index(fit.free)
    spread = "f" in fit.free
    x = fit.X
    s = x[2]
    theta = np.array([x[0] / s, x[1] / s, s, x[3], x[4], x[5] / s])

    def to_x(th):
        out = th.copy()
        out[:, 0], out[:, 1], out[:, 5] = th[:, 0] * th[:, 2], th[:, 1] * th[:, 2], th[:, 5] * th[:, 2]
        return out

    w = keep.astype(np.float64)[None]
    base = residuals(table, prob, to_x(theta[None]), w, spread, False)[0]
    h = STEPS[free] * 10.0
    T = np.repeat(theta[None], len(free), axis=0)
    T[np.arange(len(free)), free] += h
    R = residuals(table, prob, to_x(T), np.repeat(w, len(free), axis=0), spread, False)
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


