"""Which parameters a line's coupons determine (``swatch calibrate``): outliers, then forward selection of the
nested models — growth law, + knee, + film index scale, + spread — each kept only when it lowers the
held-out (leave-one-out) mean ΔE2000 by :data:`GAIN_TO_KEEP` or more and the coupons determine it (standard
error under :data:`DETERMINED_BELOW`, enough coupons for its parameters and a held-out check).
"""
from __future__ import annotations

import numpy as np

from swatch.fit.calibration.leave_one_out import leave_one_out
from swatch.fit.calibration.model import (
    MODELS,
    NO_KNEE_V,
    ModelFit,
    Problem,
    covariance,
    fit_model,
    growth,
    knee_starts,
)
from swatch.fit.calibration.table import ComboTable

__all__ = ["outliers", "select_models", "OUTLIER_MIN_DE00", "GAIN_TO_KEEP", "DETERMINED_BELOW"]

#: A coupon is an outlier only if its ΔE2000 exceeds this, whatever the spread of the others.
OUTLIER_MIN_DE00 = 3.0
#: An added parameter must lower the held-out mean ΔE2000 by this fraction to be kept.
GAIN_TO_KEEP = 0.05
#: A fitted parameter is "determined" when its standard error is below this.
DETERMINED_BELOW = {"s": 0.02, "f": 0.02, "knee": 8.0}
_STEP_WORDS = {"+scale": "film index scale", "+spread": "thickness spread", "+knee": "knee (two-slope law)"}


def outliers(dE: np.ndarray) -> np.ndarray:
    """The coupons that fit no line: ΔE2000 over ``max(OUTLIER_MIN_DE00, 3 × 1.4826 × median)`` (none of fewer
    than four coupons).

    Parameters
    ----------
    dE : numpy.ndarray, shape (N,)
        The coupons' ΔE2000 under a robust fit.

    Returns
    -------
    numpy.ndarray of bool, shape (N,)
        True for the outliers.
    """
    if dE.size < 4:
        return np.zeros(dE.size, bool)
    return dE > max(OUTLIER_MIN_DE00, 3.0 * 1.4826 * float(np.median(dE)))


def _determined(table, prob, fit, keep, step: str) -> tuple[bool, str]:
    """Whether the parameters a step adds are determined by the coupons (and why not)."""
    cov = covariance(table, prob, fit, keep)
    if cov is None:
        return False, "the coupons leave it undetermined (singular fit)"
    se = dict(zip(fit.free, np.sqrt(np.maximum(np.diag(cov), 0.0)), strict=True))
    for name in {"+scale": ("s",), "+spread": ("f",), "+knee": ("knee",)}[step]:
        if se[name] > DETERMINED_BELOW[name]:
            return False, f"standard error {se[name]:.3g} is over {DETERMINED_BELOW[name]:g}"
    return True, ""


def select_models(table: ComboTable, prob: Problem, robust: ModelFit, outlier: np.ndarray, allow: dict,
                  scale0: float) -> tuple[ModelFit, list[dict]]:
    """Forward selection of the nested models by held-out ΔE2000 for one table pair (outliers set aside).

    Parameters
    ----------
    table, prob : ComboTable, Problem
        The pair's XYZ table (every scale) and the coupons.
    robust : ModelFit
        The pair's robust fit (its starting point).
    outlier : numpy.ndarray of bool, shape (N,)
        The coupons set aside.
    allow : dict
        ``"+knee"``, ``"+scale"``, ``"+spread"`` → whether that step may be tried.
    scale0 : float
        The base profile's film index scale (the growth law's).

    Returns
    -------
    (ModelFit, list of dict)
        The chosen model's fit (held-out ΔE2000 set) and the record of every step (held-out mean and max,
        kept or why not).
    """
    keep = ~outlier
    X = robust.X.copy()
    v_top = np.array([float(prob.V[keep].max())])
    X[1] = (growth(robust.X[None], v_top)[0, 0] - robust.X[0]) / v_top[0]  # the mean slope (of a knee fit)
    X[0] *= scale0 / robust.X[2]  # the same thickness at the base's scale
    X[1] *= scale0 / robust.X[2]
    X[2], X[3], X[4], X[5] = scale0, 0.0, NO_KNEE_V, X[1]
    chosen = fit_model(table, prob, MODELS["linear"], X[None], keep, robust=False, model="growth law")
    chosen.loo = leave_one_out(table, prob, chosen, keep)
    record = [{"model": "growth law", "parameters": 2, "held_out_mean_delta_E_00": round(chosen.loo_mean, 3),
               "held_out_max_delta_E_00": round(chosen.loo_max, 3), "kept": True}]
    n_keep = int(keep.sum())
    for step in ("+knee", "+scale", "+spread"):
        if not allow[step]:
            continue
        free = chosen.free + MODELS[step]
        if n_keep < len(free) + 3:
            record.append({"model": f"+ {_STEP_WORDS[step]}", "kept": False,
                           "why": f"{n_keep} coupons cannot hold {len(free)} parameters and a held-out check"})
            continue
        if step == "+spread":
            table.add_spread()
            X0 = np.repeat(chosen.X[None], 3, axis=0)
            X0[:, 3] = (0.01, 0.03, 0.06)
        elif step == "+knee":
            X0 = knee_starts(chosen, prob.V, keep, count=6 if "knee" in robust.free else 12)
            if "knee" in robust.free:
                rk = robust.X.copy()
                rk[[0, 1, 5]] *= chosen.X[2] / robust.X[2]
                rk[2], rk[3] = chosen.X[2], chosen.X[3]
                X0 = np.concatenate([X0, rk[None]])
            if X0.shape[0] == 0:
                record.append({"model": "+ knee (two-slope law)", "kept": False,
                               "why": "needs three voltages on each side of a knee"})
                continue
        else:
            X0 = chosen.X[None]
        cand = fit_model(table, prob, free, X0, keep, robust=False, model=step, iters=15)
        cand.loo = leave_one_out(table, prob, cand, keep)
        ok, why = _determined(table, prob, cand, keep, step)
        gain = 1.0 - cand.loo_mean / chosen.loo_mean if chosen.loo_mean > 0 else 0.0
        kept = ok and gain >= GAIN_TO_KEEP
        if ok and not kept:
            why = f"held-out mean ΔE2000 lowered by {100 * gain:.1f} % only (needs {100 * GAIN_TO_KEEP:g} %)"
        record.append({"model": f"+ {_STEP_WORDS[step]}", "parameters": len(free),
                       "held_out_mean_delta_E_00": round(cand.loo_mean, 3),
                       "held_out_max_delta_E_00": round(cand.loo_max, 3), "kept": kept, **({} if kept else {"why": why})})
        if kept:
            chosen = cand
    return chosen, record

