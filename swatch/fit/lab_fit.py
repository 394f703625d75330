"""Thickness from CIELAB measurements: least squares in ΔE2000 (see :mod:`swatch.fit.fitting`)."""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, delta_E_00, get_colorimeter
from swatch.colorimetry.tolerance import DEFAULT_SCHEME, check_scheme
from swatch.core.choices import DEFAULT_EXCLUDE_MIRROR_DEG, DEFAULT_FIT_STEP_NM, DEFAULT_THICKNESS_RANGE_NM
from swatch.fit.fitting import FacetModel, check_scale, model_reflectance, sweep_curve, unique_geometry
from swatch.fit.result import FitResult, fit_result, geometry_arrays, used_geometries
from swatch.fit.search import check_search_range, curvature_sigma, multimodal_search
from swatch.io.measurements import LabMeasurement
from swatch.physics.model import Coating, get_coating

__all__ = ["fit_lab"]


def _scaled_Lab(XYZ: np.ndarray, Y_meas: np.ndarray, scale: str, cm: Colorimeter) -> tuple[np.ndarray, np.ndarray]:
    """Lab of simulated XYZ (..., G, 3) after the intensity correction, and the scales (..., G)."""
    Y = XYZ[..., 1]
    if scale in ("energy", "lsq"):
        a = np.divide(Y_meas, Y, out=np.zeros_like(Y), where=Y > 0)
    elif scale == "global":
        s = Y.sum(axis=-1, keepdims=True)
        a = np.broadcast_to(np.divide(Y_meas.sum(), s, out=np.zeros_like(s), where=s > 0), Y.shape)
    else:
        a = np.ones_like(Y)
    return cm.Lab(XYZ * a[..., None]), a


def fit_lab(
    measurement: LabMeasurement,
    coating: Coating | None = None,
    *,
    scale: str = "energy",
    exclude_mirror_deg: float = DEFAULT_EXCLUDE_MIRROR_DEG,
    thickness_range=DEFAULT_THICKNESS_RANGE_NM,
    step_nm: float = DEFAULT_FIT_STEP_NM,
    illuminant: str = "D65",
    observer: str = "10",
    scheme: str = DEFAULT_SCHEME,
) -> FitResult:
    """Thickness from CIELAB measurements: least squares in ΔE2000 (see the module docstring).

    Parameters
    ----------
    measurement : LabMeasurement
        CIELAB per geometry, with the illuminant and observer they were measured under.
    coating : swatch.physics.model.Coating, optional
        The film model: film and substrate tables, the film's index scale, its thickness spread (the model's
        colours are averaged over it) and the wavelength grid of the colours, nm (default: TiO2 on Ti, 5 nm).
    scale : {"energy", "lsq", "global", "none"}
        The intensity correction applied to the model's spectra before their colour is compared.
    exclude_mirror_deg : float
        Geometries within this many degrees of the mirror direction are left out, degrees.
    thickness_range : (float, float)
        Search range, nm.
    step_nm : float
        Step of the global search, nm.
    illuminant, observer : str
        The conditions of the Lab values (e.g. ``D65``, ``10``).
    scheme : str
        Grading scheme of the fit's grade (judged in its own metric).

    Returns
    -------
    FitResult
        ``thickness_nm`` and its uncertainty, nm, the residual (mean squared ΔE2000), the next minima, and
        the per-geometry Lab and ΔE under ``illuminant`` / ``observer`` with the grade.

    References
    ----------
    G. Sharma, W. Wu and E. N. Dalal (2005), doi:10.1002/col.20070 (CIEDE2000).
    """
    scale = check_scale(scale)
    scheme = check_scheme(scheme)  # (any case; refused before the search)
    lo, hi, step, count = check_search_range(thickness_range, step_nm)
    coating = get_coating() if coating is None else coating
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    cos_d, _theta_d, mirror = geometry_arrays(measurement)
    used = used_geometries(mirror, exclude_mirror_deg)
    Lab_m_all = measurement.Lab
    Lab_m = Lab_m_all[used]
    Y_meas = cm.Lab_to_XYZ(Lab_m)[..., 1]
    cu, inv = unique_geometry(cos_d[used])

    def objective(XYZ_u):
        Lab_s, _ = _scaled_Lab(XYZ_u[..., inv, :], Y_meas, scale, cm)
        dE = delta_E_00(Lab_s, np.broadcast_to(Lab_m, Lab_s.shape))
        return np.sum(dE * dE, axis=-1)

    def curve():  # in chunks of thicknesses; ΔE2000 holds ~40 temporaries a geometry
        return sweep_curve(lambda R: objective(cm.XYZ(R)), coating, lo, step, count, cu, None, 40 * 8 * Lab_m.shape[0])

    facets = FacetModel(coating, cu)

    def fine(d):
        return float(objective(cm.XYZ(facets(d))))

    kept, _grid, _curve = multimodal_search(curve, fine, lo, hi, step, count, min_separation=2.0 * step)
    d_best, f_best = kept[0]
    G = int(used.sum())
    p = 1 + {"energy": G, "lsq": G, "global": 1, "none": 0}[scale]
    sigma = curvature_sigma(fine, d_best, f_best, lo, hi, 3 * G, p)

    cu_all, inv_all = unique_geometry(cos_d)  # (each distinct facet angle once, not a spectrum per geometry)
    XYZ_all = cm.XYZ(model_reflectance(coating, d_best, cu_all))[inv_all]
    Y_all = cm.Lab_to_XYZ(Lab_m_all)[..., 1]
    if scale in ("energy", "lsq", "none"):
        Lab_s, a_all = _scaled_Lab(XYZ_all, Y_all, scale, cm)
    else:
        _, a_used = _scaled_Lab(XYZ_all[used], Y_meas, scale, cm)
        a_all = np.full(cos_d.shape, float(a_used[0]))
        Lab_s = cm.Lab(XYZ_all * a_all[:, None])
    return fit_result("lab", measurement, (kept, 1.0 / G, sigma), (scale, exclude_mirror_deg, scheme),
                      (np.asarray(a_all, dtype=np.float64), Lab_m_all, Lab_s), (coating.film, coating.substrate), cm)
