"""Calibrate a line's process profile from its test coupons (``swatch calibrate``).

Model (:mod:`swatch.fit.calibration_search`): a coupon anodised at ``voltage_V`` carries a film grown
by the line's growth law (linear, ``offset_nm + nm_per_V × voltage_V``, or two slopes with a knee
voltage, continuous at the knee), of a film table whose index's real part is scaled by
``film_index_scale``, on a substrate table, with a proportional thickness spread
(``spread_fraction``); its colour is the half-vector model's at the measuring geometry (default
45°:0°, D65, 10°).

Search: for every film × substrate table pair of the base profile's materials (or only the base's
pair when ``--film``/``--substrate`` fix them, or when fewer than ``COUPONS_FOR_TABLES`` coupons
are left to choose among them), the interference order is found by a global grid over the growth
law (each coupon's colour looked up in a thickness → CIELAB table), refined robustly (soft-L1, so a
mislabelled coupon cannot pull the line); coupons whose ΔE2000 stays far above the others' (over
``max(OUTLIER_MIN_DE00, 3 × 1.4826 × median)``) are outliers. Then, on the other coupons, the nested
models are fitted one parameter group at a time — growth law, + film index scale, + spread,
+ knee — each kept only when it lowers the leave-one-out (held-out) mean ΔE2000 by 5 % or more and
the coupons determine it (standard error small, enough coupons on each side of a knee). The table
pairs are ranked by that held-out mean: the first is the winner, written with its evidence
(``[calibration]``). Uncertainties are the standard errors of the final least-squares fit
(Gauss–Newton covariance scaled by the residual variance), in the profile's own parameters.
Measured thicknesses (``thickness_nm`` column) join the fit as residuals of ``THICKNESS_SIGMA_NM``.

Data that cannot determine a parameter are refused in one line: fewer than two coupons, all
coupons at one voltage.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00, get_colorimeter
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_PROFILE_NAME_CHARS, MAX_VOLTAGE_V
from swatch.fit import calibration_search as cs
from swatch.fit import calibration_table as ctab
from swatch.io.coupons import Coupons
from swatch.physics import geometry
from swatch.physics.materials import DEFAULT_WAVELENGTHS_NM, same_formula
from swatch.physics.process import Process
from swatch.physics.spread import ThicknessSpread

__all__ = ["Calibration", "calibrate", "OUTLIER_MIN_DE00", "THICKNESS_SIGMA_NM", "COUPONS_FOR_TABLES"]

#: A coupon is an outlier only if its ΔE2000 exceeds this, whatever the spread of the others.
OUTLIER_MIN_DE00 = 3.0
THICKNESS_SIGMA_NM = cs.THICKNESS_SIGMA_NM
#: Fewest inlier coupons with which the tables are chosen (fewer: the base profile's are kept).
COUPONS_FOR_TABLES = 8
#: A fitted parameter is "determined" when its standard error is below this.
DETERMINED_BELOW = {"s": 0.02, "f": 0.02, "knee": 8.0}
#: Table pairs refitted with every model (spread included); the others are ranked without a spread.
FULL_SEARCH_PAIRS = 3
_PHYSICAL = ("offset_nm", "nm_per_V", "film_index_scale", "spread_fraction", "knee_V", "nm_per_V_above_knee")
_STEP_WORDS = {"+scale": "film index scale", "+spread": "thickness spread", "+knee": "knee (two-slope law)"}


@dataclass
class Calibration:
    """The fitted process profile and the per-coupon report of ``swatch calibrate``.

    Attributes
    ----------
    process : swatch.physics.process.Process
        The calibrated profile (growth law, index scale, spread).
    uncertainty : dict
        The fitted parameters' standard errors (None: fixed or not determined).
    voltage_V, thickness_nm : numpy.ndarray, shape (N,)
        The coupons' voltages (V) and thicknesses by the fitted law (nm).
    Lab_measured, Lab_predicted : numpy.ndarray, shape (N, 3)
        Under ``illuminant`` / ``observer`` at ``geometry``.
    delta_E_00 : numpy.ndarray, shape (N,)
        CIEDE2000 between them.
    outlier : numpy.ndarray of bool, shape (N,)
        True for the coupons set aside as fitting no line (left out of the fit).
    labels : tuple of str
        The coupons' labels, in the order of the arrays.
    geometry : dict
        ``light_deg`` and ``view_deg``: the measuring geometry, degrees.
    illuminant, observer : str
        The CIELAB conditions: illuminant name and observer (``2`` or ``10`` degrees).
    runner_up : dict or None
        The best other interference order (nm_per_V, offset_nm, mean ΔE2000).
    held_out : numpy.ndarray or None
        Leave-one-out ΔE2000 per coupon (NaN for outliers).
    steps : tuple of dict
        What each parameter group bought (held-out ΔE2000 before and after).
    ranking : tuple of dict
        The optical-table pairs, best first.
    fixed : tuple of (str, str)
        Parameter → why it was fixed.
    cm : swatch.colorimetry.colorimeter.Colorimeter or None
        The illuminant and observer on the fit's wavelengths (None: not attached).
    cos_d : float
        cos θ_d of the measuring geometry.
    outlier_match : tuple
        Per coupon: for an outlier, the voltage on the fitted law whose colour is closest (a mislabelled
        coupon shows up here) and that ΔE2000; None for the others.
    measured_R : numpy.ndarray or None
        Measured spectra of spectral coupons.
    """

    process: Process
    uncertainty: dict  # the profile's fitted parameters: standard errors (None: fixed / not determined)
    voltage_V: np.ndarray
    thickness_nm: np.ndarray  # by the fitted growth law
    Lab_measured: np.ndarray
    Lab_predicted: np.ndarray
    delta_E_00: np.ndarray
    outlier: np.ndarray
    labels: tuple[str, ...]
    geometry: dict
    illuminant: str
    observer: str
    runner_up: dict | None  # the best other interference order: nm_per_V, offset_nm, mean ΔE2000
    held_out: np.ndarray | None = None  # leave-one-out ΔE2000 per coupon (NaN for outliers)
    steps: tuple[dict, ...] = ()  # what each parameter group bought (held-out ΔE2000 before and after)
    ranking: tuple[dict, ...] = ()  # table pairs, best first
    fixed: tuple[tuple[str, str], ...] = ()  # parameter -> why it was fixed
    cm: Colorimeter | None = dataclasses.field(default=None, repr=False)
    cos_d: float = 1.0
    #: per coupon: for an outlier, the voltage on the fitted law whose colour is closest to its colour
    #: (a mislabelled coupon shows up here) and that ΔE2000; None for the others
    outlier_match: tuple = ()
    measured_R: np.ndarray | None = dataclasses.field(default=None, repr=False)

    def to_dict(self) -> dict:
        """JSON-ready dictionary (``swatch calibrate --json`` and the report figure's metadata).

        Returns
        -------
        dict
            The profile's values and uncertainty, one entry per coupon, the mean and max ΔE2000 over the
            inliers, the runner-up, the steps, the ranking and what was fixed.
        """
        inl = ~self.outlier
        p = self.process
        out = {
            "film": p.film, "substrate": p.substrate,
            "nm_per_V": p.nm_per_V, "offset_nm": p.offset_nm, "film_index_scale": p.film_index_scale,
            **p.knee_metadata(), **p.spread.metadata(),
            "uncertainty": self.uncertainty,
            "samples": [{"coupon": lab, "voltage_V": float(v), "thickness_nm": round(float(d), 3),
                         "delta_E_00": round(float(e), 3), "outlier": bool(o),
                         "held_out_delta_E_00": None if self.held_out is None or not np.isfinite(h)
                         else round(float(h), 3),
                         "matches_voltage_V": None if m is None else m[0],
                         "matches_delta_E_00": None if m is None else m[1]}
                        for lab, v, d, e, o, h, m in zip(self.labels, self.voltage_V, self.thickness_nm, self.delta_E_00,
                                                         self.outlier, self._held(),
                                                         self.outlier_match or (None,) * len(self.labels), strict=True)],
            "mean_delta_E_00": round(float(self.delta_E_00[inl].mean()), 3),
            "max_delta_E_00": round(float(self.delta_E_00[inl].max()), 3),
            "outliers": int(self.outlier.sum()),
            "runner_up": self.runner_up,
            "geometry": self.geometry, "illuminant": self.illuminant, "observer": self.observer,
            "process": p.metadata(),
            "steps": list(self.steps), "ranking": list(self.ranking), "fixed": dict(self.fixed),
        }
        if self.held_out is not None:
            out["held_out_mean_delta_E_00"] = round(float(np.nanmean(self.held_out)), 3)
            out["held_out_max_delta_E_00"] = round(float(np.nanmax(self.held_out)), 3)
        return out

    def _held(self) -> np.ndarray:
        return self.held_out if self.held_out is not None else np.full(self.voltage_V.size, np.nan)


def _check(coupons: Coupons) -> None:
    n = len(coupons)
    if n < 2:
        raise SwatchError(f"{coupons.source}: one coupon cannot determine a growth rate and an offset; "
                          "anodise coupons at two or more voltages (four or more to catch a mislabelled one)")
    if np.unique(coupons.voltage_V).size < 2:
        raise SwatchError(f"{coupons.source}: all {n} coupons were anodised at {coupons.voltage_V[0]:g} V, which "
                          "cannot separate the growth rate from the offset; add coupons at other voltages")


def _pairs(base: Process, film: str | None, substrate: str | None) -> list[tuple[str, str]]:
    """The table pairs to search: the base's materials' films × substrates (a given one fixed)."""
    films = [film] if film else same_formula("film", base.film)
    subs = [substrate] if substrate else same_formula("substrate", base.substrate)
    return [(f, s) for f in films for s in subs]


def _outliers(dE: np.ndarray) -> np.ndarray:
    if dE.size < 4:
        return np.zeros(dE.size, bool)
    return dE > max(OUTLIER_MIN_DE00, 3.0 * 1.4826 * float(np.median(dE)))


def _determined(table, prob, fit, keep, step: str) -> tuple[bool, str]:
    """Whether the parameters a step adds are determined by the coupons (and why not)."""
    cov = cs.covariance(table, prob, fit, keep)
    if cov is None:
        return False, "the coupons leave it undetermined (singular fit)"
    se = dict(zip(fit.free, np.sqrt(np.maximum(np.diag(cov), 0.0)), strict=True))
    for name in {"+scale": ("s",), "+spread": ("f",), "+knee": ("knee",)}[step]:
        if se[name] > DETERMINED_BELOW[name]:
            return False, f"standard error {se[name]:.3g} is over {DETERMINED_BELOW[name]:g}"
    return True, ""


def _soft(dE) -> float:
    return float(np.sum(2.0 * (np.sqrt(1.0 + (np.asarray(dE) / cs.LOSS_SCALE_DE00) ** 2) - 1.0)))


def _select(table, prob, robust, outlier, allow: dict, scale0: float):
    """Forward selection of the nested models by held-out ΔE2000 for one table pair (outliers set aside)."""
    keep = ~outlier
    X = robust.X.copy()
    v_top = np.array([float(prob.V[keep].max())])
    X[1] = (cs.growth(robust.X[None], v_top)[0, 0] - robust.X[0]) / v_top[0]  # the mean slope (of a knee fit)
    X[0] *= scale0 / robust.X[2]  # the same thickness at the base's scale
    X[1] *= scale0 / robust.X[2]
    X[2], X[3], X[4], X[5] = scale0, 0.0, cs.NO_KNEE_V, X[1]
    chosen = cs.fit_model(table, prob, cs.MODELS["linear"], X[None], keep, robust=False, model="growth law")
    chosen.loo = cs.leave_one_out(table, prob, chosen, keep)
    record = [{"model": "growth law", "parameters": 2, "held_out_mean_delta_E_00": round(chosen.loo_mean, 3),
               "held_out_max_delta_E_00": round(chosen.loo_max, 3), "kept": True}]
    n_keep = int(keep.sum())
    for step in ("+knee", "+scale", "+spread"):
        if not allow[step]:
            continue
        free = chosen.free + cs.MODELS[step]
        if n_keep < len(free) + 3:
            record.append({"model": f"+ {_STEP_WORDS[step]}", "kept": False,
                           "why": f"{n_keep} coupons cannot hold {len(free)} parameters and a held-out check"})
            continue
        if step == "+spread":
            table.add_spread()
            X0 = np.repeat(chosen.X[None], 3, axis=0)
            X0[:, 3] = (0.01, 0.03, 0.06)
        elif step == "+knee":
            X0 = cs.knee_starts(chosen, prob.V, keep, count=6 if "knee" in robust.free else 12)
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
        cand = cs.fit_model(table, prob, free, X0, keep, robust=False, model=step, iters=15)
        cand.loo = cs.leave_one_out(table, prob, cand, keep)
        ok, why = _determined(table, prob, cand, keep, step)
        gain = 1.0 - cand.loo_mean / chosen.loo_mean if chosen.loo_mean > 0 else 0.0
        kept = ok and gain >= cs.GAIN_TO_KEEP
        if ok and not kept:
            why = f"held-out mean ΔE2000 lowered by {100 * gain:.1f} % only (needs {100 * cs.GAIN_TO_KEEP:g} %)"
        record.append({"model": f"+ {_STEP_WORDS[step]}", "parameters": len(free),
                       "held_out_mean_delta_E_00": round(cand.loo_mean, 3),
                       "held_out_max_delta_E_00": round(cand.loo_max, 3), "kept": kept, **({} if kept else {"why": why})})
        if kept:
            chosen = cand
    return chosen, record


def calibrate(coupons: Coupons, base: Process, light_deg: float = 45.0, view_deg: float = 0.0,
              illuminant: str = "D65", observer: str = "10", fit_scale: bool | None = None,
              name: str | None = None, search_tables: bool = True, film: str | None = None,
              substrate: str | None = None) -> Calibration:
    """Fit a line's process profile to its test coupons (see the module docstring).

    Parameters
    ----------
    coupons : Coupons
        Voltages (V) with measured CIELAB or spectra (:func:`swatch.io.coupons.read_coupons`).
    base : Process
        The profile to start from (its tables, scale and spread where they are not fitted).
    light_deg, view_deg : float
        The measuring geometry, degrees.
    illuminant, observer : str
        The conditions of the coupons' CIELAB.
    fit_scale : bool or None
        True fits the film index scale (refused if the coupons cannot determine it), False keeps
        the base's, None fits it when determined.
    name : str or None
        The new profile's name.
    search_tables : bool
        Choose the film and substrate tables too, by leave-one-out ΔE2000 (``film``/``substrate``
        fix one of them); False keeps the base's.
    film, substrate : str or None
        Optical table names that fix that side of the search (None: searched).

    Returns
    -------
    Calibration
        The fitted profile (offset nm, rate nm/V, scale, growth law), standard errors, per-coupon
        ΔE2000 and outlier flags, and the ranking of the tables tried.
    """
    _check(coupons)
    geometry.check_polar_deg(light_deg, "light_deg")
    geometry.check_polar_deg(view_deg, "view_deg")
    wl = DEFAULT_WAVELENGTHS_NM if coupons.Lab is not None else coupons.wavelength_nm
    cm = get_colorimeter(wl, illuminant, observer)
    Lab_m = coupons.Lab if coupons.Lab is not None else cm.Lab(cm.XYZ(coupons.reflectance))
    cos_d = float(geometry.cos_theta_d(light_deg, view_deg))
    V, n = coupons.voltage_V, len(coupons)
    can_scale = np.unique(V).size >= 3 and n >= 4
    if fit_scale and not can_scale:
        raise SwatchError(f"{coupons.source}: the film index scale needs coupons at three or more voltages "
                          "(four or more coupons); fit without it (`fit_scale=False`)")
    fixed: dict[str, str] = {}
    allow = {"+scale": fit_scale is not False and can_scale, "+spread": n >= 6, "+knee": n >= 8}
    if fit_scale is False:
        fixed["film_index_scale"] = f"kept from {base.name} (--fixed-scale)"
    elif not can_scale:
        fixed["film_index_scale"] = "kept: it needs coupons at three or more voltages (four or more coupons)"
    if n < 6:
        fixed["spread_fraction"] = "kept: a spread needs six or more coupons"
    if n < 8:
        fixed["knee_V"] = "none: a knee needs eight or more coupons"
    fixed["spread_nm"] = ("kept at 0: the search fits a spread proportional to thickness only (an absolute "
                          "part is not separable from it over one line's range)")
    pairs = _pairs(base, film, substrate) if search_tables else [(base.film, base.substrate)]
    if len(pairs) > 1 and n < COUPONS_FOR_TABLES:
        pairs = [(film or base.film, substrate or base.substrate)]
        fixed["tables"] = f"kept from {base.name}: choosing tables needs {COUPONS_FOR_TABLES} or more coupons"
    elif not search_tables:
        fixed["tables"] = f"kept from {base.name} (--fixed-tables)"
    elif film or substrate:
        fixed["tables"] = "given: " + ", ".join(x for x in (film and f"film {film}", substrate and
                                                             f"substrate {substrate}") if x)
    u_max = cs.u_max_nm(V)
    scale0 = float(np.clip(base.film_index_scale, ctab.TABLE_SCALES[0], ctab.TABLE_SCALES[-1]))
    tables = [ctab.build_table(f, s, wl, cm, cos_d, u_max, scale0) for f, s in pairs]  # screening: one scale
    prob = cs.Problem(np.asarray(V, dtype=np.float64), np.asarray(Lab_m, dtype=np.float64),
                      np.asarray(coupons.thickness_nm, dtype=np.float64), cm)

    # every pair: its interference order, robust fit and outliers; the best FULL_SEARCH_PAIRS by that
    # in-sample fit then go through the held-out model selection (spread included)
    robust: list[tuple[cs.ModelFit, np.ndarray, np.ndarray] | None] = []
    for r in cs.screen(tables, prob, scale0, allow["+knee"]):
        if r is None:
            robust.append(None)
            continue
        x, dE, starts = r
        free = cs.MODELS["linear"] + (cs.MODELS["+knee"] if x[4] < cs.NO_KNEE_V else ())
        robust.append((cs.ModelFit("robust", free, x, dE), _outliers(dE), starts))
    screen = [np.inf if r is None else float(np.mean(r[0].dE[~r[1]])) for r in robust]
    order = [int(k) for k in np.argsort(screen, kind="stable") if np.isfinite(screen[k])]
    if not order:
        raise SwatchError(f"{coupons.source}: no growth law from 0.2 to 7.5 nm/V (optical) keeps every coupon "
                          "between 0 and 1000 nm; check the voltages")
    fitted = {k: r for k, r in enumerate(robust) if r is not None}  # the pairs with a growth law
    full = {}
    for k in order[:FULL_SEARCH_PAIRS]:
        if allow["+scale"]:  # every scale, for the fits that free it
            tables[k] = ctab.build_table(tables[k].film, tables[k].substrate, wl, cm, cos_d, u_max)
        full[k] = _select(tables[k], prob, fitted[k][0], fitted[k][1], allow, scale0)
    ranked = sorted(full, key=lambda k: full[k][0].loo_mean) + order[FULL_SEARCH_PAIRS:]
    win = ranked[0]
    (fit, record), (_, outlier, starts) = full[win], fitted[win]
    table = tables[win]
    ranking = tuple(
        {"film": tables[k].film, "substrate": tables[k].substrate,
         **({"model": ", ".join(r["model"] for r in full[k][1] if r.get("kept")),
             "held_out_mean_delta_E_00": round(full[k][0].loo_mean, 3),
             "held_out_max_delta_E_00": round(full[k][0].loo_max, 3)} if k in full else
            {"model": "screened out", "in_sample_mean_delta_E_00": round(screen[k], 3)}),
         "outliers": int(fitted[k][1].sum())} for k in ranked)
    if np.unique(V[~outlier]).size < 2:
        raise SwatchError(f"{coupons.source}: after setting aside {int(outlier.sum())} coupon(s) that fit no line, "
                          "the rest are at one voltage; add coupons at other voltages")
    if fit_scale and "s" not in fit.free:
        raise SwatchError(f"{coupons.source}: these coupons do not determine the film index scale; fit without "
                          "it (`fit_scale=False`) or add coupons over a wider voltage range")
    keep = ~outlier
    cov = cs.covariance(table, prob, fit, keep)
    if cov is None:
        raise SwatchError(f"{coupons.source}: these coupons do not determine the growth rate and offset "
                          "(too few coupons for the parameters); add coupons at other voltages")
    se = dict(zip(fit.free, np.sqrt(np.maximum(np.diag(cov), 0.0)), strict=True))
    return _result(coupons, base, name, (fit, se, outlier, record, ranking, table, starts), fixed, cm, cos_d, Lab_m,
                   (light_deg, view_deg))


def _result(coupons, base, name, winner: tuple, fixed, cm, cos_d, Lab_m, geometry_deg: tuple) -> Calibration:
    """The calibration of the winning pair: ``winner`` is (model fit, standard errors, outliers, the selection's
    record, the pairs' ranking, the pair's table, the search's starts); ``geometry_deg`` (light, view)."""
    fit, se, outlier, record, ranking, table, starts = winner
    light_deg, view_deg = geometry_deg
    x = fit.X
    s = float(x[2])
    knee = "knee" in fit.free
    theta = dict(zip(_PHYSICAL, (x[0] / s, x[1] / s, s, x[3], x[4], x[5] / s), strict=True))
    key = dict(zip(cs.PARAMS, _PHYSICAL, strict=True))
    unc = {key[p]: round(float(v), 5) for p, v in se.items()}
    uncertainty = {"nm_per_V": unc.get("nm_per_V"), "offset_nm": unc.get("offset_nm"),
                   "film_index_scale": unc.get("film_index_scale")}
    if "f" in fit.free:
        uncertainty["spread_fraction"] = unc.get("spread_fraction")
    if knee:
        uncertainty["knee_V"] = unc.get("knee_V")
        uncertainty["nm_per_V_above_knee"] = unc.get("nm_per_V_above_knee")
    src = Path(coupons.source).name
    how = f"calibrated from {src}, {len(coupons)} coupons ({int(outlier.sum())} set aside as outliers), date-free"
    kept = dict(base.sources)
    sources = {"nm_per_V": how, "offset_nm": how,
               "film_index_scale": how if "s" in fit.free else f"not fitted; kept from {base.name}: "
               + kept.get("film_index_scale", ""),
               "film": f"{table.film}: ranked first of {len(ranking)} film x substrate pairs by held-out ΔE2000"
               if len(ranking) > 1 else kept.get("film", table.film),
               "substrate": f"{table.substrate}: ranked first of {len(ranking)} pairs by held-out ΔE2000"
               if len(ranking) > 1 else kept.get("substrate", table.substrate)}
    if "f" in fit.free:
        sources["spread_fraction"] = how
    if knee:
        sources["knee_V"] = sources["nm_per_V_above_knee"] = how
    if "roughness" in kept:
        sources["roughness"] = kept["roughness"]
    spread = ThicknessSpread(0.0, round(float(theta["spread_fraction"]), 5)) if "f" in fit.free else base.spread
    proc = dataclasses.replace(
        base, name=name if name is not None else f"{base.name[:MAX_PROFILE_NAME_CHARS - 11]}-calibrated", film=table.film, substrate=table.substrate,
        nm_per_V=round(float(theta["nm_per_V"]), 5), offset_nm=round(float(theta["offset_nm"]), 3),
        film_index_scale=round(s, 5) if "s" in fit.free else base.film_index_scale, origin="calibrated",
        knee_V=round(float(theta["knee_V"]), 3) if knee else None,
        nm_per_V_above_knee=round(float(theta["nm_per_V_above_knee"]), 5) if knee else None,
        spread=spread,
        description=f"{table.film} on {table.substrate}, calibrated from {len(coupons)} coupons of {src}",
        sources=tuple(sources.items()),
    )
    V = coupons.voltage_V
    d_fit = np.clip(cs.growth(fit.X[None], V)[0] / s, 0.0, 1000.0)
    coating = proc.coating(cm.wavelength_nm)
    Lab_p = cm.Lab(cm.XYZ(coating.reflectance_cos(d_fit, cos_d).R))
    dE = delta_E_00(Lab_p, Lab_m)
    inl = ~outlier
    runner_up = None
    if starts.shape[0] > 1:
        o2, r2 = starts[1, 0] / s, starts[1, 1] / s
        runner_up = {"nm_per_V": round(float(r2), 4), "offset_nm": round(float(o2), 2),
                     "mean_delta_E_00": round(float(np.median(delta_E_00(
                         cs.predict_Lab(table, cs.Problem(V, Lab_m, coupons.thickness_nm, cm), starts[1:2],
                                        False)[0], Lab_m))), 2)}
    bought = "; ".join(f"{r['model']}: " + (f"held-out {r['held_out_mean_delta_E_00']:.2f}" if "held_out_mean_delta_E_00"
                                             in r else "") + ("" if r["kept"] else f" (not kept: {r.get('why', '')})")
                       for r in record)
    calibration = (("source", src), ("measured", coupons.kind), ("coupons", len(coupons)),
                   ("outliers", int(outlier.sum())),
                   ("geometry", f"light {light_deg:g} deg, view {view_deg:g} deg (half-vector model)"),
                   ("illuminant", cm.illuminant), ("observer", f"CIE {cm.observer} deg"),
                   ("model", ", ".join(r["model"] for r in record if r["kept"])),
                   ("parameters", bought[:1990]),
                   ("fixed", "; ".join(f"{k}: {v}" for k, v in fixed.items())[:1990]),
                   ("ranking", "; ".join(f"{r['film']}/{r['substrate']} " + (
                       f"held-out {r['held_out_mean_delta_E_00']:.2f}" if "held_out_mean_delta_E_00" in r
                       else f"screened out, in-sample {r['in_sample_mean_delta_E_00']:.2f}")
                       for r in ranking)[:1990]),
                   ("mean_delta_E_00", round(float(dE[inl].mean()), 3)),
                   ("max_delta_E_00", round(float(dE[inl].max()), 3)),
                   ("held_out_mean_delta_E_00", round(fit.loo_mean, 3)),
                   ("held_out_max_delta_E_00", round(fit.loo_max, 3)),
                   *((f"{k}_uncertainty", v) for k, v in uncertainty.items() if v is not None))
    proc = dataclasses.replace(proc, calibration=calibration)
    match = _outlier_matches(proc, coating, cm, cos_d, Lab_m, outlier, float(V.max()))
    return Calibration(
        outlier_match=match, process=proc, uncertainty=uncertainty, voltage_V=V, thickness_nm=d_fit, Lab_measured=Lab_m,
        Lab_predicted=Lab_p, delta_E_00=dE, outlier=outlier, labels=coupons.labels,
        geometry={"light_deg": light_deg, "view_deg": view_deg}, illuminant=cm.illuminant,
        observer=cm.observer, runner_up=runner_up, held_out=fit.loo, steps=tuple(record), ranking=ranking,
        fixed=tuple(fixed.items()), cm=cm, cos_d=cos_d, measured_R=coupons.reflectance,
    )


#: Voltage step of the search for the voltage an outlier's colour matches.
MATCH_STEP_V = 0.1


def _outlier_matches(proc, coating, cm, cos_d, Lab_m, outlier, v_max) -> tuple:
    """For each outlier, (voltage_V, ΔE2000) of the closest colour on the fitted growth law over
    0 … 1.5 × the largest coupon voltage (at most MAX_VOLTAGE_V); None for the other coupons."""
    if not outlier.any():
        return (None,) * outlier.size
    grid = np.arange(0.0, min(1.5 * v_max, MAX_VOLTAGE_V) + MATCH_STEP_V / 2, MATCH_STEP_V)
    d = np.clip(proc.thickness_nm(grid), 0.0, 1000.0)
    table = cm.Lab(cm.XYZ(coating.reflectance_cos(d, cos_d).R))  # (K, 3)
    out: list[tuple[float, float] | None] = []
    for i in range(outlier.size):  # the outliers only (a few)
        if not outlier[i]:
            out.append(None)
            continue
        dE = delta_E_00(table, np.broadcast_to(Lab_m[i], table.shape))
        k = int(np.argmin(dE))
        out.append((round(float(grid[k]), 1), round(float(dE[k]), 2)))
    return tuple(out)
