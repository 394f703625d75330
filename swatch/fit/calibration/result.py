"""The result of ``swatch calibrate``: the fitted profile with its evidence, per coupon and per step."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00
from swatch.core.limits import MAX_PROFILE_NAME_CHARS, MAX_VOLTAGE_V
from swatch.fit.calibration.model import PARAMS, Problem, growth, predict_Lab
from swatch.io.coupons import Coupons
from swatch.physics.process import Process
from swatch.physics.spread import ThicknessSpread

__all__ = ["Calibration", "calibration_result", "MATCH_STEP_V"]

_PHYSICAL = ("offset_nm", "nm_per_V", "film_index_scale", "spread_fraction", "knee_V", "nm_per_V_above_knee")


@dataclass
class Calibration:
    """The fitted process profile and the per-coupon report of ``swatch calibrate``.

    Attributes
    ----------
    process : swatch.physiprocess.Process
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

def calibration_result(coupons: Coupons, base: Process, name: str | None, winner: tuple, fixed: dict,
                       cm: Colorimeter, cos_d: float, Lab_m: np.ndarray, geometry_deg: tuple) -> Calibration:
    """The calibration of the winning table pair.

    Parameters
    ----------
    coupons, base : Coupons, Process
        The coupons and the profile calibrated from.
    name : str or None
        The new profile's name (None: ``<base>-calibrated``).
    winner : tuple
        (model fit, standard errors, outliers, the selection's record, the pairs' ranking, the pair's table,
        the search's starting lines).
    fixed : dict
        Parameter → why it was fixed.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The coupons' illuminant and observer on the fit's wavelengths.
    cos_d : float
        cos θ_d of the measuring geometry.
    Lab_m : numpy.ndarray, shape (N, 3)
        The coupons' measured CIELAB under ``cm``.
    geometry_deg : (float, float)
        The measuring geometry (light, view), degrees.

    Returns
    -------
    Calibration
        The profile (rounded values, sources, the ``[calibration]`` evidence) and the per-coupon report.
    """
    fit, se, outlier, record, ranking, table, starts = winner
    light_deg, view_deg = geometry_deg
    x = fit.X
    s = float(x[2])
    knee = "knee" in fit.free
    theta = dict(zip(_PHYSICAL, (x[0] / s, x[1] / s, s, x[3], x[4], x[5] / s), strict=True))
    key = dict(zip(PARAMS, _PHYSICAL, strict=True))
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
    d_fit = np.clip(growth(fit.X[None], V)[0] / s, 0.0, 1000.0)
    coating = proc.coating(cm.wavelength_nm)
    Lab_p = cm.Lab(cm.XYZ(coating.reflectance_cos(d_fit, cos_d).R))
    dE = delta_E_00(Lab_p, Lab_m)
    inl = ~outlier
    runner_up = None
    if starts.shape[0] > 1:
        o2, r2 = starts[1, 0] / s, starts[1, 1] / s
        runner_up = {"nm_per_V": round(float(r2), 4), "offset_nm": round(float(o2), 2),
                     "mean_delta_E_00": round(float(np.median(delta_E_00(
                         predict_Lab(table, Problem(V, Lab_m, coupons.thickness_nm, cm), starts[1:2],
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
