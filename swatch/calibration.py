"""Calibrate a line's process profile from its test coupons (``swatch calibrate``).

Model: a coupon anodised at ``voltage_V`` carries ``thickness_nm = offset_nm + nm_per_V ×
voltage_V`` of the profile's film, whose index's real part is scaled by ``film_index_scale``;
its colour is the half-vector model's at the measuring geometry (default 45°:0°, D65, 10°).

Fit: colours recur with thickness (interference orders), so a local fit from a guess can land
on the wrong order. The rate and offset are first searched globally on a grid (every coupon's
colour looked up in a precomputed thickness → CIELAB table), scoring each grid point by a
robust sum of per-coupon ΔE2000; the best distinct minima are then refined with
``scipy.optimize.least_squares`` (soft-L1 loss, so one mislabelled coupon cannot pull the
line), the film index scale joining the refinement when the coupons determine it. Coupons
whose ΔE2000 stays far above the others' (over ``max(OUTLIER_MIN_DE00, 3 × 1.4826 × median)``)
are flagged as outliers and the line refitted without them; parameter uncertainties are the
standard errors of that final least-squares fit (Gauss–Newton covariance scaled by the
residual variance). Measured thicknesses (``thickness_nm`` column) join the fit as residuals of
``THICKNESS_SIGMA_NM``.

Data that cannot determine a parameter are refused in one line: fewer than two coupons, all
coupons at one voltage; the film index scale is fitted only when it is determined (otherwise
kept at the base profile's value and reported without an uncertainty).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from swatch import geometry, optics
from swatch.colorimetry import delta_E_00
from swatch.coupons import Coupons
from swatch.errors import SwatchError
from swatch.limits import MAX_VOLTAGE_V
from swatch.process import OFFSET_RANGE, RATE_RANGE, SCALE_RANGE, Process

__all__ = ["Calibration", "calibrate", "OUTLIER_MIN_DE00", "THICKNESS_SIGMA_NM"]

#: A coupon is an outlier only if its ΔE2000 exceeds this, whatever the spread of the others.
OUTLIER_MIN_DE00 = 3.0
#: Weight of a measured thickness: its residual counts as (model − measured) / this, in ΔE units.
THICKNESS_SIGMA_NM = 2.0
#: soft-L1 scale: residuals (ΔE2000) beyond it count about linearly.
LOSS_SCALE_DE00 = 1.0
#: The scale is "determined" when its standard error is below this.
SCALE_MAX_UNCERTAINTY = 0.02
_TABLE_STEP_NM = 0.5
_SEARCH_OFFSET_NM = (-10.0, 40.0, 1.0)  # start, stop, step of the global search
_SEARCH_RATE = (0.5, 5.0)
_N_STARTS = 4


@dataclass
class Calibration:
    """The fitted profile and the per-coupon report."""

    process: Process
    uncertainty: dict  # nm_per_V, offset_nm, film_index_scale: standard errors (None: not determined / fixed)
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
    runner_up: dict | None  # the best other interference order: nm_per_V, offset_nm, median ΔE2000
    model: _Model | None = dataclasses.field(default=None, repr=False)
    #: per coupon: for an outlier, the voltage on the fitted line whose colour is closest to its colour
    #: (a mislabelled coupon shows up here) and that ΔE2000; None for the others
    outlier_match: tuple = ()
    measured_R: np.ndarray | None = dataclasses.field(default=None, repr=False)

    def figure(self) -> np.ndarray:
        """The report figure (swatch.calibration_report): chips per coupon and the voltage → colour strip."""
        from swatch.calibration_report import calibration_figure

        m, p = self.model, self.process
        assert m is not None and p.nm_per_V is not None, "calibrate() gives a model and a growth rate"
        strip_V = np.linspace(0.0, 1.1 * float(self.voltage_V.max()), 400)
        strip_d = np.clip(p.offset_nm + p.nm_per_V * strip_V, 0.0, 1000.0)
        return calibration_figure(self, m.R(self.thickness_nm, p.film_index_scale), self.measured_R, strip_V,
                                  m.R(strip_d, p.film_index_scale), m.cm)

    def to_dict(self) -> dict:
        inl = ~self.outlier
        p = self.process
        return {
            "nm_per_V": p.nm_per_V, "offset_nm": p.offset_nm, "film_index_scale": p.film_index_scale,
            "uncertainty": self.uncertainty,
            "samples": [{"coupon": lab, "voltage_V": float(v), "thickness_nm": round(float(d), 3),
                         "delta_E_00": round(float(e), 3), "outlier": bool(o),
                         "matches_voltage_V": None if m is None else m[0],
                         "matches_delta_E_00": None if m is None else m[1]}
                        for lab, v, d, e, o, m in zip(self.labels, self.voltage_V, self.thickness_nm, self.delta_E_00,
                                                      self.outlier, self.outlier_match or (None,) * len(self.labels),
                                                      strict=True)],
            "mean_delta_E_00": round(float(self.delta_E_00[inl].mean()), 3),
            "max_delta_E_00": round(float(self.delta_E_00[inl].max()), 3),
            "outliers": int(self.outlier.sum()),
            "runner_up": self.runner_up,
            "geometry": self.geometry, "illuminant": self.illuminant, "observer": self.observer,
            "process": p.metadata(),
        }


class _Model:
    """Lab of the profile's film at thicknesses, for a film index scale, at one geometry."""

    def __init__(self, base: Process, wavelength_nm, cm, cos_d):
        coating = base.coating(wavelength_nm)
        self.wl = coating.wavelength_nm
        self.n_film = coating.n_film  # already scaled by the base profile's film_index_scale
        self.n_sub = coating.n_substrate
        self.base_scale = base.film_index_scale
        self.cm = cm
        self.cos_d = np.asarray(cos_d, dtype=np.float64)

    def R(self, thickness_nm, scale: float) -> np.ndarray:
        n = self.n_film.real * (scale / self.base_scale) + 1j * self.n_film.imag
        d = np.clip(np.asarray(thickness_nm, dtype=np.float64), 0.0, 1000.0)
        return optics.film_reflectance_cos(d, self.cos_d, self.wl, n, self.n_sub).R

    def Lab(self, thickness_nm, scale: float) -> np.ndarray:
        return self.cm.Lab(self.cm.XYZ(self.R(thickness_nm, scale)))


def _check(coupons: Coupons) -> None:
    n = len(coupons)
    if n < 2:
        raise SwatchError(f"{coupons.source}: one coupon cannot determine a growth rate and an offset; "
                          "anodise coupons at two or more voltages (four or more to catch a mislabelled one)")
    if np.unique(coupons.voltage_V).size < 2:
        raise SwatchError(f"{coupons.source}: all {n} coupons were anodised at {coupons.voltage_V[0]:g} V, which "
                          "cannot separate the growth rate from the offset; add coupons at other voltages")


def _robust(dE: np.ndarray) -> np.ndarray:
    z = (dE / LOSS_SCALE_DE00) ** 2
    return 2.0 * (np.sqrt(1.0 + z) - 1.0)


def _global_search(model: _Model, V: np.ndarray, Lab_m: np.ndarray, d_meas: np.ndarray, scale: float):
    """Grid (rate, offset) candidates, best first, one per distinct line."""
    from swatch.colorimetry import delta_E_00

    d_table = np.arange(0.0, 1000.0 + _TABLE_STEP_NM, _TABLE_STEP_NM)
    Lab_table = model.Lab(d_table, scale)
    v_max = float(V.max())
    rate_step = min(0.02, 1.0 / v_max)  # ≤ 1 nm of thickness at the top voltage per step
    rates = np.arange(_SEARCH_RATE[0], _SEARCH_RATE[1] + 1e-9, rate_step)
    offsets = np.arange(*_SEARCH_OFFSET_NM[:2], _SEARCH_OFFSET_NM[2]) + 0.0
    offsets = np.append(offsets, _SEARCH_OFFSET_NM[1])
    d = offsets[None, :, None] + rates[:, None, None] * V[None, None, :]  # (R, O, N)
    inside = (d >= 0.0) & (d <= 1000.0)
    idx = np.clip(np.rint(d / _TABLE_STEP_NM).astype(np.int64), 0, d_table.size - 1)
    dE = delta_E_00(Lab_table[idx], np.broadcast_to(Lab_m, (*idx.shape, 3)))
    cost = _robust(dE)
    have = np.isfinite(d_meas)
    if have.any():
        cost = cost + np.where(have, ((d - np.nan_to_num(d_meas)) / THICKNESS_SIGMA_NM) ** 2, 0.0)
    total = np.where(inside.all(axis=2), cost.sum(axis=2), np.inf)
    order = np.argsort(total, axis=None)
    best = float(total.flat[order[0]])
    picks: list[tuple[float, float]] = []
    for flat in order[:5000]:
        if not np.isfinite(total.flat[flat]) or total.flat[flat] > best + max(0.5 * best, 4.0):
            break  # other orders this much worse do not survive refinement: not worth refining
        i, j = np.unravel_index(flat, total.shape)
        line = offsets[j] + rates[i] * V
        if all(np.max(np.abs(line - (o + r * V))) > 8.0 for r, o in picks):
            picks.append((float(rates[i]), float(offsets[j])))
            if len(picks) == _N_STARTS:
                break
    return picks


_STEPS = np.array([1e-5, 1e-3, 1e-5])  # forward-difference steps: nm/V, nm, scale


def _fit(model, V, Lab_m, d_meas, x0, fit_scale: bool, scale0: float, loss: str, tol: float = 1e-8):
    """Least squares on per-coupon ΔE2000 (and thickness) residuals; the Jacobian's rate and
    offset columns come from one model call on stacked thicknesses."""
    from scipy.optimize import least_squares

    from swatch.colorimetry import delta_E_00

    have = np.isfinite(d_meas)
    p = 3 if fit_scale else 2

    # With the scale free, the parameters are the optical growth (rate and offset times
    # scale / scale0) and the scale: colours follow the optical thickness n·d closely, so this
    # turns the long rate–scale valley into one along an axis (fast convergence).
    def unpack(x):
        return (x[0] * scale0 / x[2], x[1] * scale0 / x[2], x[2]) if fit_scale else (x[0], x[1], scale0)

    def stack(d, dE):  # d (..., N), dE (..., N) -> residual rows
        if have.any():
            return np.concatenate([dE, (d[..., have] - d_meas[have]) / THICKNESS_SIGMA_NM], axis=-1)
        return dE

    def residuals(x):
        rate, offset, scale = unpack(x)
        d = offset + rate * V
        return stack(d, delta_E_00(model.Lab(d, scale), Lab_m))

    def jacobian(x):
        rate, offset, scale = unpack(x)
        k = scale0 / x[2] if fit_scale else 1.0  # d(thickness)/d(optical growth)
        d = np.stack([offset + rate * V, offset + (rate + k * _STEPS[0]) * V, offset + k * _STEPS[1] + rate * V])
        r = stack(d, delta_E_00(model.Lab(d, scale), Lab_m))
        cols = [(r[1] - r[0]) / _STEPS[0], (r[2] - r[0]) / _STEPS[1]]
        if fit_scale:
            r_s = residuals(x + np.array([0.0, 0.0, _STEPS[2]]))
            cols.append((r_s - r[0]) / _STEPS[2])
        return np.stack(cols, axis=1)

    lo = np.array([RATE_RANGE[0], OFFSET_RANGE[0], SCALE_RANGE[0]])[:p]
    hi = np.array([RATE_RANGE[1], OFFSET_RANGE[1], SCALE_RANGE[1]])[:p] - _STEPS[:p]
    s0 = x0[2] if len(x0) > 2 else scale0
    packed = [x0[0] * s0 / scale0, x0[1] * s0 / scale0, s0] if fit_scale else [x0[0], x0[1]]
    start = np.clip(np.array(packed), lo + 1e-9, hi - 1e-9)
    res = least_squares(residuals, start, jac=jacobian, bounds=(lo, hi), loss=loss, f_scale=LOSS_SCALE_DE00,
                        x_scale=np.array([0.01, 1.0, 0.01])[:p], ftol=tol, xtol=tol, max_nfev=200)
    return res, unpack(res.x)


def _errors(res, n_params: int):
    """Standard errors from the Gauss–Newton covariance (None when the data leave it undetermined)."""
    J = res.jac
    dof = J.shape[0] - n_params
    if dof <= 0:
        return [None] * n_params
    s2 = float(np.sum(res.fun ** 2)) / dof
    JtJ = J.T @ J
    if np.linalg.cond(JtJ) > 1e12:
        return [None] * n_params
    cov = np.linalg.inv(JtJ) * max(s2, 1e-12)
    return [float(np.sqrt(max(c, 0.0))) for c in np.diag(cov)]


def calibrate(coupons: Coupons, base: Process, light_deg: float = 45.0, view_deg: float = 0.0,
              illuminant: str = "D65", observer: str = "10", fit_scale: bool | None = None,
              name: str | None = None) -> Calibration:
    """Fit ``base``'s growth law (and film index scale) to ``coupons`` (see the module docstring).

    ``fit_scale``: True fits the film index scale (refused if the coupons cannot determine it),
    False keeps the base's, None fits it when determined.
    """
    from swatch.colorimetry import delta_E_00, get_colorimeter
    from swatch.materials import DEFAULT_WAVELENGTHS_NM

    _check(coupons)
    geometry.check_polar_deg(light_deg, "light")
    geometry.check_polar_deg(view_deg, "view")
    wl = DEFAULT_WAVELENGTHS_NM if coupons.Lab is not None else coupons.wavelength_nm
    cm = get_colorimeter(wl, illuminant, observer)
    Lab_m = coupons.Lab if coupons.Lab is not None else cm.Lab(cm.XYZ(coupons.reflectance))
    model = _Model(base, wl, cm, geometry.cos_theta_d(light_deg, view_deg))
    V, d_meas = coupons.voltage_V, coupons.thickness_nm
    scale0 = base.film_index_scale

    starts = _global_search(model, V, Lab_m, d_meas, scale0)
    if not starts:
        raise SwatchError(f"{coupons.source}: no growth law from {_SEARCH_RATE[0]:g} to {_SEARCH_RATE[1]:g} nm/V "
                          "keeps every coupon between 0 and 1000 nm; check the voltages")
    can_scale = np.unique(V).size >= 3 and len(coupons) >= 4
    if fit_scale and not can_scale:
        raise SwatchError(f"{coupons.source}: the film index scale needs coupons at three or more voltages "
                          "(four or more coupons); fit without it (--fixed-scale)")
    try_scale = can_scale if fit_scale is None else bool(fit_scale)
    runs = []
    for rate, offset in starts:  # each interference order, the scale held: cheap
        res, params = _fit(model, V, Lab_m, d_meas, (rate, offset), False, scale0, "soft_l1", 1e-5)
        runs.append((res.cost, params))
    runs.sort(key=lambda r: r[0])
    rate, offset, scale = runs[0][1]
    if try_scale:
        res, (rate, offset, scale) = _fit(model, V, Lab_m, d_meas, (rate, offset, scale), True, scale0, "soft_l1")
    runner_up = None
    r1, o1, _ = runs[0][1]
    for _cost, (r2, o2, _) in runs[1:]:  # another interference order than the best (scale held)
        if np.max(np.abs((o2 + r2 * V) - (o1 + r1 * V))) > 8.0:
            dE2 = delta_E_00(model.Lab(o2 + r2 * V, scale0), Lab_m)
            runner_up = {"nm_per_V": round(r2, 4), "offset_nm": round(o2, 2),
                         "mean_delta_E_00": round(float(np.median(dE2)), 2)}
            break

    dE = delta_E_00(model.Lab(offset + rate * V, scale), Lab_m)
    spread = 3.0 * 1.4826 * float(np.median(dE))
    outlier = dE > max(OUTLIER_MIN_DE00, spread) if len(coupons) >= 4 else np.zeros(len(coupons), bool)
    keep = ~outlier
    if np.unique(V[keep]).size < 2:
        raise SwatchError(f"{coupons.source}: after setting aside {int(outlier.sum())} coupon(s) that fit no line, "
                          "the rest are at one voltage; add coupons at other voltages")

    def final(with_scale: bool):
        res, params = _fit(model, V[keep], Lab_m[keep], d_meas[keep], (rate, offset, scale), with_scale,
                           scale0, "linear")
        return res, params, _errors(res, 3 if with_scale else 2)

    res, params, errs = final(try_scale)
    if try_scale and (errs[2] is None or errs[2] > SCALE_MAX_UNCERTAINTY):
        if fit_scale:
            raise SwatchError(f"{coupons.source}: these coupons do not determine the film index scale "
                              f"(standard error {'unbounded' if errs[2] is None else f'{errs[2]:.3f}'}); "
                              "fit without it (--fixed-scale) or add coupons over a wider voltage range")
        res, params, errs = final(False)
        try_scale = False
    rate, offset, scale = params
    if errs[0] is None:
        raise SwatchError(f"{coupons.source}: these coupons do not determine the growth rate and offset "
                          "(too few coupons for the parameters); add coupons at other voltages")
    d_fit = offset + rate * V
    Lab_p = model.Lab(d_fit, scale)
    dE = delta_E_00(Lab_p, Lab_m)
    uncertainty = {"nm_per_V": _round(errs[0], 5), "offset_nm": _round(errs[1], 3),
                   "film_index_scale": _round(errs[2], 5) if try_scale else None}
    from pathlib import Path

    src = Path(coupons.source).name
    how = (f"calibrated from {src}, {len(coupons)} coupons ({int(outlier.sum())} set aside as outliers), "
           "date-free")
    kept = dict(base.sources)
    sources = {"nm_per_V": how, "offset_nm": how,
               "film_index_scale": how if try_scale else f"not determined by the coupons; kept from {base.name}: "
               + kept.get("film_index_scale", "")}
    sources.update({k: kept[k] for k in ("film", "substrate", "roughness") if k in kept})
    inl = ~outlier
    calibration = (("source", src), ("measured", coupons.kind), ("coupons", len(coupons)),
                   ("outliers", int(outlier.sum())),
                   ("geometry", f"light {light_deg:g} deg, view {view_deg:g} deg (half-vector model)"),
                   ("illuminant", cm.illuminant), ("observer", f"CIE {cm.observer} deg"),
                   ("mean_delta_E_00", round(float(dE[inl].mean()), 3)),
                   ("max_delta_E_00", round(float(dE[inl].max()), 3)),
                   *((f"{k}_uncertainty", v) for k, v in uncertainty.items() if v is not None))
    proc = dataclasses.replace(
        base, name=name or f"{base.name}-calibrated", nm_per_V=round(float(rate), 5),
        offset_nm=round(float(offset), 3), film_index_scale=round(float(scale), 5), origin="calibrated",
        description=(f"{base.film} on {base.substrate}, calibrated from {len(coupons)} coupons of {src}"),
        sources=tuple(sources.items()), calibration=calibration,
    )
    match = _outlier_matches(model, Lab_m, outlier, rate, offset, scale, float(V.max()))
    return Calibration(
        outlier_match=match, process=proc, uncertainty=uncertainty, voltage_V=V, thickness_nm=d_fit, Lab_measured=Lab_m,
        Lab_predicted=Lab_p, delta_E_00=dE, outlier=outlier, labels=coupons.labels,
        geometry={"light_deg": light_deg, "view_deg": view_deg}, illuminant=cm.illuminant,
        observer=cm.observer, runner_up=runner_up, model=model, measured_R=coupons.reflectance,
    )


#: Voltage step of the search for the voltage an outlier's colour matches.
MATCH_STEP_V = 0.1


def _outlier_matches(model, Lab_m, outlier, rate, offset, scale, v_max) -> tuple:
    """For each outlier, (voltage_V, ΔE2000) of the closest colour on the fitted line over
    0 … 1.5 × the largest coupon voltage (at most MAX_VOLTAGE_V); None for the other coupons."""
    if not outlier.any():
        return (None,) * outlier.size
    grid = np.arange(0.0, min(1.5 * v_max, MAX_VOLTAGE_V) + MATCH_STEP_V / 2, MATCH_STEP_V)
    d = np.clip(offset + rate * grid, 0.0, 1000.0)
    table = model.Lab(d, scale)  # (K, 3)
    out: list[tuple[float, float] | None] = []
    for i in range(outlier.size):
        if not outlier[i]:
            out.append(None)
            continue
        dE = delta_E_00(table, np.broadcast_to(Lab_m[i], table.shape))
        k = int(np.argmin(dE))
        out.append((round(float(grid[k]), 1), round(float(dE[k]), 2)))
    return tuple(out)


def _round(x, nd):
    return None if x is None else round(float(x), nd)
