"""Thickness from spectral measurements: least squares with the paper's intensity correction
(see :mod:`swatch.fit.fitting` for the method)."""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.colorimetry.tolerance import DEFAULT_SCHEME, check_scheme
from swatch.core.choices import DEFAULT_EXCLUDE_MIRROR_DEG, DEFAULT_FIT_STEP_NM, DEFAULT_THICKNESS_RANGE_NM
from swatch.core.errors import SwatchError
from swatch.fit.fitting import (
    COARSE_SPACING_NM,
    FacetModel,
    check_scale,
    model_reflectance,
    sweep_curve,
    unique_geometry,
)
from swatch.fit.lab_fit import fit_lab
from swatch.fit.result import FitResult, colour_grid, fit_result, geometry_arrays, interp_rows, used_geometries
from swatch.fit.search import CURVATURE_STEP_NM, check_search_range, multimodal_search
from swatch.io.measurements import LabMeasurement, SpectralMeasurement, check_in_tables
from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE
from swatch.physics.model import get_coating, intensity_scale

__all__ = ["fit_spectra", "fit_measurement"]


# -- least squares with intensity correction --------------------------------------------------------
def _scales_and_ssr(S: np.ndarray, M: np.ndarray, scale: str) -> tuple[np.ndarray, np.ndarray]:
    """Intensity scales (..., G) and total squared error (...) of ``a S`` against ``M`` (G, W)."""
    S2 = np.einsum("...gw,...gw->...g", S, S)
    SM = np.einsum("...gw,gw->...g", S, M)
    M2 = np.einsum("gw,gw->g", M, M)
    if scale == "energy":
        a = intensity_scale(S, M)  # the paper's correction (swatch.physics.model)
    elif scale == "lsq":
        a = np.divide(SM, S2, out=np.zeros_like(S2), where=S2 > 0)
    elif scale == "global":
        num = SM.sum(axis=-1, keepdims=True)
        den = S2.sum(axis=-1, keepdims=True)
        a = np.broadcast_to(np.divide(num, den, out=np.zeros_like(den), where=den > 0), S2.shape)
    else:
        a = np.ones_like(S2)
    ssr = a * a * S2 - 2.0 * a * SM + M2
    return a, np.maximum(ssr, 0.0).sum(axis=-1)


def spectral_sigma(facets, inv, M, scale, d, lo, hi) -> float | None:
    """One-sigma thickness uncertainty of a spectral fit: Gauss–Newton with per-geometry noise (a sandwich estimate).

    ``J = ∂r/∂d`` of the residual vector ``r = a S − M`` (scales profiled), by central differences;
    the noise variance of each geometry is its residual's mean square, so geometries of different
    intensity (and noise) are weighted correctly: ``σ² = Σ_g s_g² |J_g|² / (Σ_g |J_g|²)²``.

    Parameters
    ----------
    facets : callable
        Thicknesses (nm, shape (3,)) → model reflectance factors at the unique facet angles, shape (3, U, W).
    inv : numpy.ndarray of int, shape (G,)
        Maps each geometry to its unique facet angle.
    M : numpy.ndarray, shape (G, W)
        Measured reflectance factors.
    scale : str
        The intensity correction (:func:`swatch.fit.fitting.check_scale`).
    d : float
        The fitted thickness, nm.
    lo, hi : float
        The search range, nm.

    Returns
    -------
    float or None
        σ, nm; None at the range's edge or where the Jacobian vanishes.
    """
    h = CURVATURE_STEP_NM
    if d - h < lo or d + h > hi:
        return None
    dd = np.array([d - h, d, d + h])
    S = facets(dd)[:, inv]  # (3, G, W)
    a, _ = _scales_and_ssr(S, M, scale)
    r = a[..., None] * S - M
    J = (r[2] - r[0]) / (2.0 * h)
    W = M.shape[1]
    dof = W - 1 if scale in ("energy", "lsq") else W
    s2 = np.sum(r[1] ** 2, axis=1) / max(dof, 1)
    J2 = np.sum(J * J, axis=1)
    den = J2.sum()
    if not np.isfinite(den) or den <= 0:
        return None
    return float(np.sqrt(np.sum(s2 * J2)) / den)


def fit_spectra(
    measurement: SpectralMeasurement,
    film: str = DEFAULT_FILM,
    substrate: str = DEFAULT_SUBSTRATE,
    *,
    scale: str = "energy",
    exclude_mirror_deg: float = DEFAULT_EXCLUDE_MIRROR_DEG,
    thickness_range=DEFAULT_THICKNESS_RANGE_NM,
    step_nm: float = DEFAULT_FIT_STEP_NM,
    illuminant: str = "D65",
    observer: str = "10",
    scheme: str = DEFAULT_SCHEME,
    film_index_scale: float = 1.0,
    spread=None,
) -> FitResult:
    """Least-squares thickness of spectral measurements with the paper's intensity correction.

    A global search over ``thickness_range`` (every ``step_nm``, the interference orders' minima
    screened and refined), geometries within ``exclude_mirror_deg`` of the mirror direction left out;
    the colour differences are then computed under ``illuminant`` and ``observer``.

    Parameters
    ----------
    measurement : swatch.io.measurements.SpectralMeasurement
        Reflectance factors (G, W) at G geometries.
    film, substrate : str
        Optical table names (they must cover the measured wavelengths).
    scale : str
        Intensity correction: ``energy`` (the paper's), ``lsq``, ``global`` or ``none``.
    exclude_mirror_deg : float
        Geometries whose view is within this of the mirror direction are left out, degrees.
    thickness_range : (float, float)
        The searched thicknesses, nm.
    step_nm : float
        The search grid's step, nm.
    illuminant, observer : str
        Colorimetry of the ΔE figures (CIE illuminant name; ``"2"`` or ``"10"``).
    scheme : str
        The tolerance scheme the grade is taken in.
    film_index_scale : float
        A process profile's scale of the film's real index (0.5–1.5).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread (the model's spectra are averaged over it).

    Returns
    -------
    swatch.fit.result.FitResult
        ``thickness_nm`` and its uncertainty, nm, the residual (mean squared error of reflectance fractions),
        the next minima, and the per-geometry Lab and ΔE under ``illuminant`` / ``observer`` with the grade.

    Raises
    ------
    swatch.core.errors.SwatchError
        A bad scale, range or step, or tables that do not cover the measured wavelengths.

    References
    ----------
    H. Fujii et al. (2019), doi:10.14923/transinfj.2018JDP7030, §4 (intensity correction) and Table 2.
    """
    scale = check_scale(scale)
    scheme = check_scheme(scheme)  # (any case; refused before the search)
    lo, hi, step, count = check_search_range(thickness_range, step_nm)
    check_in_tables(measurement, film, substrate)
    wl = measurement.wavelength_nm
    coating = get_coating(film, substrate, wl, film_index_scale, spread)
    cos_d, _theta_d, mirror = geometry_arrays(measurement)
    used = used_geometries(mirror, exclude_mirror_deg)
    M = measurement.reflectance[used]
    cu, inv = unique_geometry(cos_d[used])
    stride = max(1, int(np.ceil(COARSE_SPACING_NM / max(float(np.median(np.diff(wl))), 1e-9) - 1e-9)))
    wl_idx = np.arange(0, wl.size, stride)
    if wl_idx.size < 3:
        wl_idx = np.arange(wl.size)
    Mc = M[:, wl_idx]

    def curve():  # in chunks of thicknesses; the scaled residuals hold ~6 copies of (geometries, wavelengths)
        return sweep_curve(lambda R: _scales_and_ssr(R[:, inv, :], Mc, scale)[1], coating, lo, step, count, cu,
                           wl_idx, 6 * 8 * Mc.size)

    facets = FacetModel(coating, cu)

    def fine(d):
        S = facets(d)[inv]
        return float(_scales_and_ssr(S, M, scale)[1])

    kept, _grid, _curve = multimodal_search(curve, fine, lo, hi, step, count, min_separation=2.0 * step)
    d_best, _f_best = kept[0]
    n = M.size
    sigma = spectral_sigma(facets, inv, M, scale, d_best, lo, hi)

    # Scales for every geometry (excluded ones too) at the estimate.
    S_all = model_reflectance(coating, d_best, cos_d)
    a_used, _ = _scales_and_ssr(S_all[used], M, scale)
    if scale in ("energy", "lsq"):
        a_all, _ = _scales_and_ssr(S_all, measurement.reflectance, scale)
    else:
        a_all = np.full(cos_d.shape, float(a_used[0]))

    cwl, interpolated = colour_grid(wl)
    cm = get_colorimeter(cwl, illuminant, observer)
    if interpolated:
        M_col = interp_rows(cwl, wl, measurement.reflectance)
        S_col = get_coating(film, substrate, cwl, film_index_scale, spread).reflectance_cos(d_best, cos_d).R
    else:
        M_col = measurement.reflectance
        S_col = S_all
    Lab_m = cm.spectrum_Lab(M_col)
    Lab_s = cm.spectrum_Lab(a_all[:, None] * S_col)
    return fit_result("spectral", measurement, (kept, 1.0 / n, sigma), (scale, exclude_mirror_deg, scheme),
                      (a_all, Lab_m, Lab_s), (coating.film, coating.substrate), cm, interpolated, wavelength_nm=wl,
                      reflectance_unit="percent" if measurement.percent else "fraction",
                      reflectance_unit_detected=measurement.unit_detected)


def fit_measurement(measurement, film: str, substrate: str, wavelength_nm=None, grid_given: bool = False,
                    source: str | None = None, **options) -> FitResult:
    """The film thickness of a measurement: :func:`fit_spectra` of spectra, or
    :func:`swatch.fit.lab_fit.fit_lab` of CIELAB values.

    Least squares over every geometry outside the mirror region, with the paper's intensity
    correction (Table 2's estimate), a global search over the thickness range and a bounded
    refinement of the best minima.

    Parameters
    ----------
    measurement : SpectralMeasurement or LabMeasurement
        From :func:`swatch.io.measurement_csv.read_measurement` or an instrument file.
    film, substrate : str
        Optical table names.
    wavelength_nm : array_like or None
        The model's grid for CIELAB measurements, nm. Spectra are fitted on their own wavelengths:
        a grid the user gave (``grid_given``) is refused for them, naming ``source``.
    grid_given : bool
        Whether the user gave ``wavelength_nm`` (refused for spectra).
    source : str or None
        How to name the grid's origin in a refusal (the CLI passes its flag).
    **options
        Passed to the fit (scale mode, mirror exclusion in degrees, thickness range and step in nm,
        illuminant, observer, grading scheme, film index scale, spread).

    Returns
    -------
    FitResult
        ``thickness_nm``, ``uncertainty_nm`` (Gauss–Newton), residual, the second-best minimum,
        mean ΔE*ab and ΔE2000 over the geometries used, and the grade.

    References
    ----------
    H. Fujii et al. (2019), doi:10.14923/transinfj.2018JDP7030, §4 and Table 2.
    """

    if isinstance(measurement, LabMeasurement):
        coating = get_coating(film, substrate, wavelength_nm, options.pop("film_index_scale", 1.0),
                              options.pop("spread", None))
        return fit_lab(measurement, coating, **options)
    if grid_given:
        raise SwatchError(f"{source or measurement.source}: `wavelength_nm` applies to CIELAB files; a spectral fit "
                          "uses the measured wavelengths (crop the file to change them)")
    return fit_spectra(measurement, film, substrate, **options)
