"""Thickness from a target seen at several geometries (``swatch match --angles`` or a multi-angle
measurement): candidates ranked by the worst or the mean ΔE2000 over the geometries.

A target colour given once (``--hex``/``--lab``) is compared with the model's colour at every
geometry ("reads gold at 45:0 and still at 45:60"); a multi-angle measurement gives one target per
geometry. As in :func:`swatch.fit.matching.match_colour`, the whole thickness range is swept (all
interference orders), the local minima of the objective refined, and each candidate judged
within the tolerance when its *worst* geometry is within it, in the tolerance's own metric.
"""
from __future__ import annotations

import re
from typing import Any

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.choices import DEFAULT_MATCH_STEP_NM, DEFAULT_THICKNESS_RANGE_NM
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_INSTRUMENT_GEOMETRIES
from swatch.fit.fitting import FacetModel, model_reflectance, sweep_reflectance, unique_geometry
from swatch.fit.matching import MATCH_MIN_SEPARATION_NM
from swatch.fit.search import N_REFINE, check_search_range, multimodal_search
from swatch.physics import geometry

__all__ = ["RANKS", "parse_angles", "match_angles"]

#: How candidates are ranked over the geometries.
RANKS = ("worst", "mean")
_ASPEC = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*as\s*(-?\d+(?:\.\d+)?)\s*$", re.IGNORECASE)
_PAIR = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*:\s*(-?\d+(?:\.\d+)?)\s*$")


def parse_angles(text: str) -> list[tuple[str, float, float]]:
    """Parse a list of measuring geometries.

    Parameters
    ----------
    text : str
        ``45:0,45:60`` (light:view polar angles in degrees, a negative view on the light's side) or
        ``45as15,45as110`` (light and ASTM E2194 aspecular angle), comma-separated.

    Returns
    -------
    list of (str, float, float)
        (name as given, light_deg, signed view_deg).

    Raises
    ------
    swatch.core.errors.SwatchError
        An item of neither form, an angle 90° or more from the normal, a repeated geometry, or more
        than :data:`swatch.core.limits.MAX_INSTRUMENT_GEOMETRIES` of them.

    Examples
    --------
    >>> parse_angles("45:0, 45as110")
    [('45:0', 45.0, 0.0), ('45as110', 45.0, -65.0)]
    """
    out = []
    for item in str(text).split(","):
        m, a = _PAIR.match(item), _ASPEC.match(item)
        if m:
            light, view = float(m.group(1)), float(m.group(2))
        elif a:
            light = float(a.group(1))
            view = float(geometry.aspecular_view_deg(light, float(a.group(2))))
        else:
            raise SwatchError(f"`angles` item {item.strip()!r} must be LIGHT:VIEW (e.g. 45:0, 45:-15 on the "
                              "light's side) or LIGHTasASPECULAR (e.g. 45as15)")
        if not (0 <= light < 90 and abs(view) < 90):
            raise SwatchError(f"`angles` item {item.strip()!r}: light and view must lie within 90° of the normal")
        out.append((item.strip(), light, view))
    if not 1 <= len(out) <= MAX_INSTRUMENT_GEOMETRIES:
        raise SwatchError(f"`angles` takes 1 to {MAX_INSTRUMENT_GEOMETRIES} geometries")
    if len({(l, v) for _, l, v in out}) != len(out):
        raise SwatchError("`angles` repeats a geometry")
    return out


def match_angles(targets_Lab, angles, coating, cm, tolerance, *, rank: str = "worst",
                 thickness_range=DEFAULT_THICKNESS_RANGE_NM, step_nm: float = DEFAULT_MATCH_STEP_NM, top: int = 5,
                 voltage_of=None) -> dict:
    """Candidates ranked by the ``rank`` ("worst" or "mean") ΔE2000 over ``angles``.

    Parameters
    ----------
    targets_Lab : array_like, shape (3,) or (G, 3)
        One target for every geometry, or one per geometry (CIELAB under ``cm``).
    angles : list of (name, light_deg, signed view_deg)
        In-plane geometries (:func:`parse_angles`).
    tolerance : swatch.colorimetry.tolerance.Tolerance
        A candidate is within it when every geometry is, in the tolerance's metric.

    Returns
    -------
    dict
        ``rank``, ``geometries``, ``candidates`` (``thickness_nm``, ``voltage_V``, ``worst_delta_E_00``,
        ``mean_delta_E_00``, per geometry ``delta_E_00`` / ``delta_E`` (tolerance metric) / ``Lab``,
        ``within_tolerance``), best first.
    """
    if rank not in RANKS:
        raise SwatchError(f"`rank` must be one of {', '.join(RANKS)}")
    if not (isinstance(top, int) and 1 <= top <= 100):
        raise SwatchError("`top` must be an integer from 1 to 100")
    G = len(angles)
    target = np.broadcast_to(np.asarray(targets_Lab, dtype=np.float64), (G, 3))
    if not np.all(np.isfinite(target)) or np.any((target[:, 0] < 0) | (target[:, 0] > 100)):
        raise SwatchError("target Lab must be finite with L in [0, 100]")
    lo, hi, step, count = check_search_range(thickness_range, step_nm)
    light = np.array([a[1] for a in angles])
    view = np.array([a[2] for a in angles])
    cos_d = np.atleast_1d(geometry.cos_theta_d(light, np.abs(view), 0.0, np.where(view < 0, 0.0, 180.0)))
    cu, inv = unique_geometry(cos_d)
    reduce = np.max if rank == "worst" else np.mean

    def objective(R):  # R (..., U, W) -> (...)
        Lab = cm.Lab(cm.XYZ(R[..., inv, :]))
        return reduce(delta_E_00(Lab, np.broadcast_to(target, Lab.shape)), axis=-1)

    facets = FacetModel(coating, cu)
    kept, _, _ = multimodal_search(lambda: objective(sweep_reflectance(coating, lo, step, count, cu)),
                                   lambda d: float(objective(facets(d))), lo, hi, step, count,
                                   min_separation=MATCH_MIN_SEPARATION_NM, n_refine=max(top, N_REFINE) + 2)
    cands: list[dict[str, Any]] = []
    for d, _f in kept[:top]:
        Lab = cm.Lab(cm.XYZ(model_reflectance(coating, np.array([d]), cu)[0][inv]))
        d00 = np.atleast_1d(delta_E_00(Lab, target))
        dtol = np.atleast_1d(tolerance.delta_E(Lab, target))
        v = None if voltage_of is None else voltage_of(d)
        cands.append({
            "thickness_nm": round(float(d), 3), "voltage_V": None if v is None else round(float(v), 3),
            "worst_delta_E_00": round(float(d00.max()), 3), "mean_delta_E_00": round(float(d00.mean()), 3),
            "within_tolerance": bool(np.all(dtol <= tolerance.max)),
            "geometries": {a[0]: {"Lab": [round(float(x), 3) for x in Lab[g]], "delta_E_00": round(float(d00[g]), 3),
                                  "delta_E": round(float(dtol[g]), 3)} for g, a in enumerate(angles)},
        })
    cands.sort(key=lambda c: c[f"{rank}_delta_E_00"])
    return {"rank": rank, "metric": tolerance.metric,
            "geometries": [{"name": n, "light_deg": lt, "view_deg": v} for n, lt, v in angles],
            "target_Lab": [[round(float(x), 3) for x in t] for t in target], "candidates": cands}
