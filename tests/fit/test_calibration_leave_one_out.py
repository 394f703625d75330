"""Issue #50: the calibration's leave-one-out past 300 coupons is one Newton step per fold from the full fit
(swatch.fit.calibration.leave_one_out.newton_folds), linear in the coupons. Checked against refits: on the
shipped line (examples/coupons.csv) the Newton folds keep the same parameters, the same winning tables and
the same profile as the folds' refits; per fold, against scipy.optimize.least_squares refitting each fold
to convergence (an optimiser we did not write)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import least_squares

from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
from swatch.fit.calibration import calibrate
from swatch.fit.calibration import leave_one_out as loo
from swatch.fit.calibration.model import (
    HI,
    LO,
    MODELS,
    NO_KNEE_V,
    Problem,
    fit_model,
    free_index,
    predict_Lab,
    residuals,
)
from swatch.fit.calibration.table import build_table
from swatch.io.coupons import read_coupons
from swatch.physics.materials import DEFAULT_WAVELENGTHS_NM
from swatch.physics.model import get_coating
from swatch.physics.process import load_process

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "examples" / "coupons.csv"


@pytest.fixture(scope="module")
def shipped_both():
    """The shipped line calibrated with the folds refitted (its 29 kept coupons: the default) and with Newton
    folds (what past REFIT_MAX_COUPONS coupons get)."""
    coupons, base = read_coupons(SHIPPED), load_process("titanium-fujii2019")
    refits = calibrate(coupons, base).to_dict()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(loo, "REFIT_MAX_COUPONS", 0)
        newton = calibrate(coupons, base).to_dict()
    return refits, newton


def test_newton_folds_keep_the_shipped_lines_parameters_tables_and_profile(shipped_both):
    """Same parameters kept, same winning tables and ranking of the finalists, the same profile (the fits do
    not depend on the folds); each step's held-out mean within 0.05 ΔE2000. The held-out figures are not the
    same at the printed precision: the winner's mean is 0.316 refitted, 0.330 by Newton steps and 0.327 by
    scipy's converged refits (the six-iteration refits stop short of the folds' minima on 29 coupons). The
    shipped line is refitted (up to REFIT_MAX_COUPONS kept coupons); the Newton steps are for more."""
    refits, newton = shipped_both
    assert [s["kept"] for s in newton["steps"]] == [s["kept"] for s in refits["steps"]]
    assert [s["model"] for s in newton["steps"]] == [s["model"] for s in refits["steps"]]
    assert [(r["film"], r["substrate"], r["model"]) for r in newton["ranking"]] == \
           [(r["film"], r["substrate"], r["model"]) for r in refits["ranking"]]
    for key in ("film", "substrate", "nm_per_V", "offset_nm", "film_index_scale", "knee_V", "nm_per_V_above_knee",
                "spread_fraction", "uncertainty", "outliers", "mean_delta_E_00"):
        assert newton[key] == refits[key], key
    for a, b in zip(newton["steps"], refits["steps"], strict=True):
        if "held_out_mean_delta_E_00" in b:
            assert a["held_out_mean_delta_E_00"] == pytest.approx(b["held_out_mean_delta_E_00"], abs=0.05), a
    assert newton["held_out_mean_delta_E_00"] == pytest.approx(refits["held_out_mean_delta_E_00"], abs=0.02)


def _scipy_fold_refits(table, prob, fit, keep, folds):
    """Held-out ΔE2000 of coupons ``folds``, each fold refitted to convergence by scipy's bounded trust-region
    least squares from the full fit."""
    free = free_index(fit.free)
    spread = "f" in fit.free
    out = []
    for i in folds:
        w = keep.astype(np.float64)
        w[i] = 0.0

        def fun(theta, w=w):
            X = fit.X.copy()
            X[free] = theta
            return residuals(table, prob, X[None], w[None], spread, False)[0]

        x0 = np.clip(fit.X[free], LO[free] + 1e-9, HI[free] - 1e-9)
        sol = least_squares(fun, x0, bounds=(LO[free], HI[free]), x_scale="jac", xtol=1e-12, ftol=1e-12,
                            gtol=1e-12, max_nfev=400)
        X = fit.X.copy()
        X[free] = sol.x
        out.append(float(delta_E_00(predict_Lab(table, prob, X[None], spread)[0, i], prob.Lab[i])))
    return np.array(out)


@pytest.mark.parametrize("model", ["linear", "+scale"])
def test_newton_folds_match_converged_refits(model):
    """120 coupons over 0.5–300 V of a line generated from the model (seeded noise 0.3 per Lab coordinate):
    each Newton fold's held-out ΔE2000 agrees with scipy's converged refit of that fold within 0.005 (measured
    0.0007; the six-iteration refits 0.0012), and their mean with the six-iteration refits' within 0.002."""
    n = 120
    coating = get_coating("TiO2-Siefke", "Ti-Johnson")
    cm = get_colorimeter(DEFAULT_WAVELENGTHS_NM)
    cos_d = float(np.cos(np.radians(22.5)))
    V = np.linspace(0.5, 300.0, n)
    Lab = cm.Lab(cm.XYZ(coating.reflectance_cos(np.minimum(3.0 + 2.1 * V, 999.0), cos_d).R))
    Lab = Lab + np.random.default_rng(38).normal(0.0, 0.3, Lab.shape)
    prob = Problem(V, Lab, np.full(n, np.nan), cm)
    table = build_table("TiO2-Siefke", "Ti-Johnson", DEFAULT_WAVELENGTHS_NM, cm, cos_d, 700.0)
    keep = np.ones(n, bool)
    names = MODELS["linear"] + (MODELS["+scale"] if model == "+scale" else ())
    start = np.array([[3.0, 2.1, 1.0, 0.0, NO_KNEE_V, 2.1]])
    fit = fit_model(table, prob, names, start, keep, robust=False, iters=30)
    newton = loo.newton_folds(table, prob, fit, keep)
    assert np.isfinite(newton).all()
    folds = np.arange(0, n, 12)
    reference = _scipy_fold_refits(table, prob, fit, keep, folds)
    np.testing.assert_allclose(newton[folds], reference, rtol=0, atol=0.005)
    assert float(np.mean(newton)) == pytest.approx(float(np.mean(loo.refit_folds(table, prob, fit, keep))), abs=0.002)


def test_leave_one_out_refits_up_to_the_threshold_and_steps_beyond(monkeypatch):
    """The route: refits up to REFIT_MAX_COUPONS kept coupons, Newton steps beyond."""
    calls = []
    monkeypatch.setattr(loo, "refit_folds", lambda *a: calls.append("refit") or np.zeros(3))
    monkeypatch.setattr(loo, "newton_folds", lambda *a: calls.append("newton") or np.zeros(3))
    monkeypatch.setattr(loo, "REFIT_MAX_COUPONS", 2)
    loo.leave_one_out(None, None, None, np.array([True, True, False]))
    loo.leave_one_out(None, None, None, np.array([True, True, True]))
    assert calls == ["refit", "newton"]
