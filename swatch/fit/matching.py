"""Thickness from a target colour: the model's colour at one geometry over the thickness range,
the local minima of ΔE2000 to the target (one per interference order), each refined and ranked."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00, delta_E_ab, get_colorimeter
from swatch.colorimetry.tolerance import DEFAULT_SCHEME, grade_bound
from swatch.core.choices import DEFAULT_MATCH_STEP_NM, DEFAULT_THICKNESS_RANGE_NM
from swatch.core.errors import SwatchError
from swatch.fit.fitting import FacetModel, model_reflectance, sweep_reflectance
from swatch.fit.search import N_REFINE, check_search_range, multimodal_search
from swatch.physics import geometry
from swatch.physics.growth import DEFAULT_NM_PER_V, thickness_to_voltage_V
from swatch.physics.model import Coating, get_coating

__all__ = ["MatchResult", "match_colour", "judge_candidates", "MATCH_MIN_SEPARATION_NM"]

#: Reported minima closer than this are the same minimum (nm).
MATCH_MIN_SEPARATION_NM = 5.0


@dataclass(frozen=True)
class MatchResult:
    """The thicknesses whose colour at one geometry is closest to a target (:func:`match_colour`).

    Attributes
    ----------
    target_Lab : numpy.ndarray, shape (3,)
        The target's CIELAB under the colorimeter's illuminant and observer.
    light_deg, view_deg : float
        Polar angles of light and view from the normal, degrees.
    light_azimuth_deg : float
        The light's azimuth, degrees.
    view_azimuth_deg : float or None
        The view's azimuth, degrees (None: the opposite side, light + 180°).
    theta_d_deg : float
        Incidence angle on the half-vector facet, degrees (Fujii et al. eq. 5).
    grade, scheme : str
        The tolerance grade judged and its scheme.
    grade_max_delta_E_ab : float
        The grade's bound (ΔE*ab for CSAJ).
    match_lightness : bool
        Whether L* counted (otherwise chromaticity only).
    candidates : list of dict
        Best first: ``thickness_nm`` (nm), ``voltage_V`` (V or None), ``Lab``, ``delta_E_00``,
        ``delta_E_ab``, ``within_grade``, ``at_range_bound``.
    """
    target_Lab: np.ndarray
    light_deg: float
    view_deg: float
    light_azimuth_deg: float
    view_azimuth_deg: float | None
    theta_d_deg: float
    grade: str
    scheme: str
    grade_max_delta_E_ab: float
    match_lightness: bool
    candidates: list  # dicts, best first

    @property
    def any_within_grade(self) -> bool:
        """Whether any candidate is within the grade.

        Returns
        -------
        bool
            True when at least one candidate's colour difference is within the grade's bound.
        """
        return any(c["within_grade"] for c in self.candidates)

    def to_dict(self) -> dict:
        """The result as JSON-ready Python (``swatch match --json``).

        Returns
        -------
        dict
            The attributes (``target_Lab`` as a list) and ``any_within_grade``.
        """
        return {
            "target_Lab": [float(v) for v in self.target_Lab],
            "light_deg": self.light_deg,
            "view_deg": self.view_deg,
            "light_azimuth_deg": self.light_azimuth_deg,
            "view_azimuth_deg": self.view_azimuth_deg,
            "theta_d_deg": self.theta_d_deg,
            "grade": self.grade,
            "scheme": self.scheme,
            "grade_max_delta_E_ab": self.grade_max_delta_E_ab,
            "match_lightness": self.match_lightness,
            "any_within_grade": self.any_within_grade,
            "candidates": self.candidates,
        }


def match_colour(
    target_Lab,
    coating: Coating | None = None,
    colorimeter: Colorimeter | None = None,
    light_deg: float = 45.0,
    view_deg: float = 0.0,
    light_azimuth_deg: float = 0.0,
    view_azimuth_deg: float | None = None,
    *,
    thickness_range=DEFAULT_THICKNESS_RANGE_NM,
    step_nm: float = DEFAULT_MATCH_STEP_NM,
    top: int = 5,
    grade: str = "C",
    match_lightness: bool = False,
) -> MatchResult:
    """Thicknesses whose colour at one geometry is closest to ``target_Lab`` (ranked by ΔE2000).

    Colours recur with interference order, so one candidate per local minimum (order) is kept.

    Parameters
    ----------
    target_Lab : array_like, shape (3,)
        The target colour, CIELAB under the colorimeter's illuminant and observer.
    coating, colorimeter : Coating, Colorimeter or None
        Defaults: the default process, D65, CIE 1964 10°.
    light_deg, view_deg, light_azimuth_deg, view_azimuth_deg : float
        The geometry, degrees (default 45°:0°).
    thickness_range : (float, float)
        Search range, nm.
    step_nm : float
        Search step, nm.
    top : int
        How many candidates to return.
    grade : str
        The tolerance grade the candidates are judged against: a grade of the default scheme (``C``), or
        ``scheme:grade`` (``csaj:B``, ``nbs:trace``). Voltages are by the paper's titanium growth law
        (:data:`swatch.physics.growth.DEFAULT_NM_PER_V`); :func:`judge_candidates` sets them, and the
        verdicts, by a process and a tolerance in its own metric.
    match_lightness : bool
        Scale the simulated colour so its Y equals the target's (compare hue and chroma only, for
        targets of unknown lightness such as photographs).

    Returns
    -------
    MatchResult
        Candidates with ``thickness_nm``, ``voltage_V``, ``Lab``, ``delta_E_00`` and ``within_grade``.
    """
    target = np.asarray(target_Lab, dtype=np.float64).reshape(3)
    if not np.all(np.isfinite(target)) or not 0 <= target[0] <= 100:
        raise SwatchError("target Lab must be finite with L in [0, 100]")
    if not (isinstance(top, int) and 1 <= top <= 100):
        raise SwatchError("`top` must be an integer from 1 to 100")
    scheme, grade = grade.split(":", 1) if ":" in str(grade) else (DEFAULT_SCHEME, grade)
    bound = grade_bound(grade, scheme)
    coating = coating or get_coating()
    cm = colorimeter or get_colorimeter(coating.wavelength_nm)
    if not np.array_equal(cm.wavelength_nm, coating.wavelength_nm):
        raise SwatchError("the colorimeter and the coating must use the same wavelength grid")
    lo, hi, step, count = check_search_range(thickness_range, step_nm)
    geometry.check_light_view_deg(light_deg, view_deg)
    cos_d = np.atleast_1d(geometry.cos_theta_d(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg))
    theta_d = float(geometry.theta_d_deg(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg))
    Y_target = cm.Lab_to_XYZ(target)[1]

    def Lab_of(R):
        XYZ = cm.XYZ(R[..., 0, :])
        if match_lightness:
            Y = XYZ[..., 1:2]
            XYZ = XYZ * np.divide(Y_target, Y, out=np.zeros_like(Y), where=Y > 0)
        return cm.Lab(XYZ)

    def curve():
        Lab = Lab_of(sweep_reflectance(coating, lo, step, count, cos_d))
        return delta_E_00(Lab, np.broadcast_to(target, Lab.shape))

    facets = FacetModel(coating, cos_d)

    def fine(d):
        return float(delta_E_00(Lab_of(facets(d)), target))

    kept, _, _ = multimodal_search(curve, fine, lo, hi, step, count, min_separation=MATCH_MIN_SEPARATION_NM,
                         n_refine=max(top, N_REFINE) + 2)
    kept = kept[:top]
    d = np.array([k[0] for k in kept])
    Lab = np.atleast_2d(Lab_of(model_reflectance(coating, d, cos_d)))
    dE00 = np.atleast_1d(delta_E_00(Lab, target))
    dEab = np.atleast_1d(delta_E_ab(Lab, target))
    volts = thickness_to_voltage_V(d, DEFAULT_NM_PER_V)
    cands: list[dict[str, Any]] = [
        {
            "thickness_nm": float(d[i]),
            "voltage_V": float(volts[i]),
            "Lab": [float(v) for v in Lab[i]],
            "delta_E_00": float(dE00[i]),
            "delta_E_ab": float(dEab[i]),
            "within_grade": bool(dEab[i] <= bound),
            # a minimum on the end of the search range is one only because the range stops there
            "at_range_bound": bool(min(d[i] - lo, hi - d[i]) < 1e-6),
        }
        for i in range(d.size)
    ]
    cands.sort(key=lambda c: c["delta_E_00"])
    return MatchResult(
        target_Lab=target, light_deg=float(light_deg), view_deg=float(view_deg),
        light_azimuth_deg=float(light_azimuth_deg),
        view_azimuth_deg=None if view_azimuth_deg is None else float(view_azimuth_deg),
        theta_d_deg=theta_d, grade=str(grade), scheme=scheme, grade_max_delta_E_ab=float(bound),
        match_lightness=bool(match_lightness), candidates=cands,
    )


def judge_candidates(res: MatchResult, voltage_of, tolerance) -> None:
    """Set each candidate's voltage by a process's growth law and its within-tolerance flag (in place).

    Parameters
    ----------
    res : MatchResult
        The match; its candidates' ``voltage_V`` and ``within_grade`` are set.
    voltage_of : callable
        Thickness (nm) → voltage (V), or None without a growth rate
        (:meth:`swatch.physics.process.Process.voltage_V`).
    tolerance : swatch.colorimetry.tolerance.Tolerance
        Judged in its own metric (ΔE*ab or ΔE2000).

    Returns
    -------
    None
    """
    for c in res.candidates:
        v = voltage_of(c["thickness_nm"])
        c["voltage_V"] = None if v is None else float(v)
        c["within_grade"] = bool(c["delta_E_ab" if tolerance.metric == "dEab" else "delta_E_00"] <= tolerance.max)
