"""``swatch calibrate``'s procedure: check the coupons, screen every table pair, select the models of the
best ones by held-out ΔE2000, and report the winner (see :mod:`swatch.fit.calibration`)."""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.core.errors import SwatchError
from swatch.fit.calibration.model import MODELS, NO_KNEE_V, ModelFit, Problem, covariance
from swatch.fit.calibration.result import Calibration, calibration_result
from swatch.fit.calibration.search import screen, u_max_nm
from swatch.fit.calibration.selection import outliers, select_models
from swatch.fit.calibration.table import TABLE_SCALES, build_table
from swatch.io.coupons import Coupons
from swatch.physics import geometry
from swatch.physics.materials import DEFAULT_WAVELENGTHS_NM, same_formula
from swatch.physics.process import Process

__all__ = ["calibrate", "COUPONS_FOR_TABLES", "FULL_SEARCH_PAIRS"]

#: Fewest inlier coupons with which the tables are chosen (fewer: the base profile's are kept).
COUPONS_FOR_TABLES = 8
#: Table pairs refitted with every model (spread included); the others are ranked without a spread.
FULL_SEARCH_PAIRS = 3


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
    u_max = u_max_nm(V)
    scale0 = float(np.clip(base.film_index_scale, TABLE_SCALES[0], TABLE_SCALES[-1]))
    tables = [build_table(f, s, wl, cm, cos_d, u_max, scale0) for f, s in pairs]  # screening: one scale
    prob = Problem(np.asarray(V, dtype=np.float64), np.asarray(Lab_m, dtype=np.float64),
                      np.asarray(coupons.thickness_nm, dtype=np.float64), cm)

    # every pair: its interference order, robust fit and outliers; the best FULL_SEARCH_PAIRS by that
    # in-sample fit then go through the held-out model selection (spread included)
    robust: list[tuple[ModelFit, np.ndarray, np.ndarray] | None] = []
    for r in screen(tables, prob, scale0, allow["+knee"]):
        if r is None:
            robust.append(None)
            continue
        x, dE, starts = r
        free = MODELS["linear"] + (MODELS["+knee"] if x[4] < NO_KNEE_V else ())
        robust.append((ModelFit("robust", free, x, dE), outliers(dE), starts))
    in_sample = [np.inf if r is None else float(np.mean(r[0].dE[~r[1]])) for r in robust]
    order = [int(k) for k in np.argsort(in_sample, kind="stable") if np.isfinite(in_sample[k])]
    if not order:
        raise SwatchError(f"{coupons.source}: no growth law from 0.2 to 7.5 nm/V (optical) keeps every coupon "
                          "between 0 and 1000 nm; check the voltages")
    fitted = {k: r for k, r in enumerate(robust) if r is not None}  # the pairs with a growth law
    full = {}
    for k in order[:FULL_SEARCH_PAIRS]:
        if allow["+scale"]:  # every scale, for the fits that free it
            tables[k] = build_table(tables[k].film, tables[k].substrate, wl, cm, cos_d, u_max)
        full[k] = select_models(tables[k], prob, fitted[k][0], fitted[k][1], allow, scale0)
    ranked = sorted(full, key=lambda k: full[k][0].loo_mean) + order[FULL_SEARCH_PAIRS:]
    win = ranked[0]
    (fit, record), (_, outlier, starts) = full[win], fitted[win]
    table = tables[win]
    ranking = tuple(
        {"film": tables[k].film, "substrate": tables[k].substrate,
         **({"model": ", ".join(r["model"] for r in full[k][1] if r.get("kept")),
             "held_out_mean_delta_E_00": round(full[k][0].loo_mean, 3),
             "held_out_max_delta_E_00": round(full[k][0].loo_max, 3)} if k in full else
            {"model": "screened out", "in_sample_mean_delta_E_00": round(in_sample[k], 3)}),
         "outliers": int(fitted[k][1].sum())} for k in ranked)
    if np.unique(V[~outlier]).size < 2:
        raise SwatchError(f"{coupons.source}: after setting aside {int(outlier.sum())} coupon(s) that fit no line, "
                          "the rest are at one voltage; add coupons at other voltages")
    if fit_scale and "s" not in fit.free:
        raise SwatchError(f"{coupons.source}: these coupons do not determine the film index scale; fit without "
                          "it (`fit_scale=False`) or add coupons over a wider voltage range")
    keep = ~outlier
    cov = covariance(table, prob, fit, keep)
    if cov is None:
        raise SwatchError(f"{coupons.source}: these coupons do not determine the growth rate and offset "
                          "(too few coupons for the parameters); add coupons at other voltages")
    se = dict(zip(fit.free, np.sqrt(np.maximum(np.diag(cov), 0.0)), strict=True))
    return calibration_result(coupons, base, name, (fit, se, outlier, record, ranking, table, starts), fixed, cm, cos_d, Lab_m,
                   (light_deg, view_deg))

