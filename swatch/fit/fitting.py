"""Thickness from measurements and from a target colour (the paper's §5): the method, and the parts
the fits share (geometry, the facet model, the result).

Pure functions on arrays, in four modules: :mod:`swatch.fit.spectral_fit` (:func:`fit_spectra`),
:mod:`swatch.fit.lab_fit` (:func:`fit_lab`), :mod:`swatch.fit.matching` (:func:`match_colour`) and the
generic multimodal 1-D search they all use, :mod:`swatch.fit.search`. The CLI (``swatch fit``,
``swatch match``) is in swatch/commands/fit.py; the result and its colour comparison in
:mod:`swatch.fit.result`; the reports in :mod:`swatch.report.text`.

Spectral fit (:func:`fit_spectra`) — the paper estimates each sample's thickness by the least mean
squared error between simulated and measured spectra (Table 2):

* model: the half-vector Airy reflectance (eq. 2–5) at each measured geometry, on the measured
  wavelengths (which must be inside the material tables);
* intensity (``scale``): ``"energy"`` (default, the paper's correction: per geometry, the simulated
  spectrum is scaled so its spectral mean equals the measured one), ``"lsq"`` (per geometry, the
  least-squares optimal scale), ``"global"`` (one least-squares scale for all geometries) or
  ``"none"`` (absolute reflectance);
* mirror region: geometries whose view is within ``exclude_mirror_deg`` (default 10°) of the mirror
  direction of the light (angle between the view vector and the mirrored light vector ``<= N``) are
  left out of the fit and of the mean ΔE, as the paper leaves out the specular region (Table 3);
  ``exclude_mirror_deg = 0`` keeps every geometry. They are still reported, flagged ``excluded``;
* residual: the mean squared spectral error over the used geometries and wavelengths (fraction²);
* search: the error is multimodal in thickness (interference orders). Every thickness on a coarse
  grid (default 0–400 nm, 1 nm) × every geometry × wavelengths (subsampled to >= 10 nm spacing for
  this stage) is evaluated in one vectorised sweep; the lowest local minima are refined with bounded
  scalar minimisation (scipy) on the full data. The best is the estimate, the next distinct local
  minimum (more than two grid steps away; a bound of the range only when it beats every interior
  minimum) is ``second_best``.
  The model depends on the geometry only through theta_d, so repeated facet angles (in-plane grids)
  are evaluated once; up to 8 coarse minima are re-scored on the full data and the best 3 refined;
* uncertainty: one standard deviation of the thickness by Gauss–Newton linearisation at the
  minimum, ``sigma² = sum_g s_g² |J_g|² / (sum_g |J_g|²)²``, with ``J = dr/dd`` of the residual
  vector ``r = a S - M`` (intensity scales profiled, central differences) and ``s_g²`` each
  geometry's residual mean square (a sandwich estimate: geometries differ in intensity and noise,
  so one pooled variance — ``2 s² / f''`` — would understate it). It reflects the noise seen in the
  residual; systematic model error counts as noise. Checked for calibration in the tests (the
  spread of error / sigma over noise seeds is about 1). ``None`` at a bound of the search range.

Colour (ΔE) report: Lab of the measured and of the intensity-corrected simulated spectra under the
chosen illuminant/observer, ΔE*ab (the paper's eq. 6) and ΔE2000 per geometry, their means over the
used geometries and the tolerance grade of the mean ΔE*ab. Colorimetry needs an even 1/5/10/20 nm
grid (ASTM E308): a measurement on such a grid is used as is; otherwise it is interpolated (linearly)
onto the 5 nm grid inside its range (and inside the observer's 360–830 nm), and the model is
evaluated on that grid directly.

Lab fit (:func:`fit_lab`): minimises the sum of squared ΔE2000 over the used geometries. Intensity:
``"energy"``/``"lsq"`` scale the simulated XYZ per geometry so Y equals the measured Y (the colour
counterpart of the energy match; ΔE then measures chromaticity differences), ``"global"`` uses one
scale (ratio of the sums of Y), ``"none"`` compares absolute colours. The uncertainty is from the
curvature of the sum of squared ΔE2000, ``sigma² = 2 s² / f''`` with ``s² = f_min / (3 G - p)``; it is approximate.

Colour match (:func:`match_colour`): the model's Lab at one geometry over 0–400 nm in 0.1 nm steps,
the local minima of ΔE2000 to the target (one per interference order), each refined and ranked.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from swatch.core.choices import SCALE_MODES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_FIT_GEOMETRIES, MAX_WAVELENGTHS, plan_rows
from swatch.physics import geometry, optics
from swatch.physics.model import Coating

__all__ = ["FacetModel", "sweep_curve", "sweep_reflectance", "film_at_angles", "model_reflectance", "unique_geometry",
           "mirror_angle_deg", "check_scale", "COARSE_SPACING_NM"]

#: Wavelength spacing of the coarse search (the spectra are smooth on this scale).
COARSE_SPACING_NM = 10.0


# -- geometry --------------------------------------------------------------------------------------
def mirror_angle_deg(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Angle between the view vector and the mirror reflection of the light vector.

    Parameters
    ----------
    light_deg, view_deg : array_like
        Polar angles from the normal, degrees (broadcast together).
    light_azimuth_deg : array_like
        The light's azimuth, degrees.
    view_azimuth_deg : array_like or None
        The view's azimuth, degrees (None: the opposite side, light + 180°).

    Returns
    -------
    numpy.ndarray
        Degrees, 0 in the mirror direction; the broadcast shape.

    Examples
    --------
    >>> float(mirror_angle_deg(45.0, 45.0)), float(mirror_angle_deg(45.0, 0.0))
    (0.0, 45.0)
    """
    la = np.asarray(light_azimuth_deg, dtype=np.float64)
    va = geometry.resolve_view_azimuth_deg(la, view_azimuth_deg)
    m = geometry.direction(light_deg, la) * np.array([-1.0, -1.0, 1.0])
    v = geometry.direction(view_deg, va)
    return np.degrees(np.arccos(np.clip(np.sum(m * v, axis=-1), -1.0, 1.0)))


def check_scale(scale: str) -> str:
    """Check an intensity correction's name.

    Parameters
    ----------
    scale : str
        One of :data:`swatch.core.choices.SCALE_MODES` (``energy``, ``lsq``, ``global``, ``none``).

    Returns
    -------
    str
        ``scale``.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other name.
    """
    if scale not in SCALE_MODES:
        raise SwatchError(f"unknown intensity scale {scale!r}; use one of {', '.join(SCALE_MODES)}")
    return scale


# -- model evaluation ------------------------------------------------------------------------------
def unique_geometry(cos_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct facet incidence cosines and the index of each geometry into them.

    The half-vector model depends on the geometry only through ``theta_d``; measurement grids repeat
    it (in plane, theta_d = (light + view) / 2), so each distinct value is evaluated once.

    Parameters
    ----------
    cos_d : numpy.ndarray, shape (G,)
        cos(theta_d) of each geometry.

    Returns
    -------
    cos_u : numpy.ndarray, shape (U,)
        The distinct cosines (to 1e-12), sorted.
    inv : numpy.ndarray of int, shape (G,)
        ``cos_u[inv]`` is ``cos_d``.

    Examples
    --------
    >>> cu, inv = unique_geometry(np.array([0.5, 1.0, 0.5]))
    >>> cu.tolist(), inv.tolist()
    ([0.5, 1.0], [0, 1, 0])
    """
    cu, inv = np.unique(np.round(cos_d, 12), return_inverse=True)
    return cu, inv.reshape(-1)


def film_at_angles(coating: Coating, cos_u: np.ndarray, wl_index: np.ndarray | None = None) -> optics.FilmAtAngles:
    """The coating at fixed facet angles (Fresnel terms computed once), optionally on a sub-grid.

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        Film, substrate and wavelength grid.
    cos_u : numpy.ndarray, shape (U,)
        Facet incidence cosines.
    wl_index : numpy.ndarray of int, optional
        Wavelength indices of a sub-grid (the coarse search's).

    Returns
    -------
    swatch.physics.optics.FilmAtAngles
        The film at the U facet angles on the (sub-)grid, ready to evaluate any number of thicknesses.
    """
    sel = slice(None) if wl_index is None else wl_index
    return optics.FilmAtAngles(cos_u, coating.wavelength_nm[sel], coating.n_film[sel], coating.n_substrate[sel])


def sweep_reflectance(coating: Coating, start: float, step: float, count: int, cos_u: np.ndarray,
                      wl_index: np.ndarray | None = None) -> np.ndarray:
    """Unpolarised reflectance for the thicknesses ``start + step j`` (``j < count``) in one sweep (a film
    with a thickness spread: averaged over it, through the coating).

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        Film, substrate, grid and spread.
    start, step : float
        First thickness and step, nm.
    count : int
        Number of thicknesses.
    cos_u : numpy.ndarray, shape (U,)
        Facet incidence cosines.
    wl_index : numpy.ndarray of int, optional
        Wavelength indices of a sub-grid (W' of them; default all W).

    Returns
    -------
    numpy.ndarray, shape (count, U, W')
        Reflectance factors, 0–1.
    """
    if not coating.spread.is_zero:
        sub = coating if wl_index is None else dataclasses.replace(
            coating, wavelength_nm=coating.wavelength_nm[wl_index], n_film=coating.n_film[wl_index],
            n_substrate=coating.n_substrate[wl_index])
        d = float(start) + float(step) * np.arange(int(count))
        return sub.reflectance_cos(d[:, None], cos_u).R
    return film_at_angles(coating, cos_u, wl_index).sweep(start, step, count).R


#: Working bytes per (thickness, facet angle, wavelength) sample of a sweep (complex Airy terms, the
#: spread's accumulator), with a margin; the memory table of docs/cli.md has the measured peaks.
SWEEP_BYTES_PER_SAMPLE = 320


def sweep_curve(objective, coating: Coating, start: float, step: float, count: int, cos_u: np.ndarray,
                wl_index: np.ndarray | None, objective_bytes_per_thickness: int) -> np.ndarray:
    """An objective over a thickness sweep, in chunks planned against the run's memory budget.

    A fine ``--step`` or many geometries would otherwise build the whole (count, U, W') sweep at once;
    the chunk size comes from :func:`swatch.core.limits.plan_rows` (:data:`swatch.core.limits.MAX_RUN_BYTES`).

    Parameters
    ----------
    objective : callable
        Reflectance of n thicknesses, shape (n, U, W') → objective values, shape (n,).
    coating, start, step, count, cos_u, wl_index
        As :func:`sweep_reflectance`.
    objective_bytes_per_thickness : int
        The objective's own working bytes per thickness.

    Returns
    -------
    numpy.ndarray, shape (count,)
        The objective at thicknesses ``start + i * step`` nm, i = 0 … count − 1.

    Raises
    ------
    swatch.core.errors.SwatchError
        Not even one thickness fits in the budget.
    """
    n_wl = coating.wavelength_nm.size if wl_index is None else len(wl_index)
    per_thickness = cos_u.size * n_wl * SWEEP_BYTES_PER_SAMPLE + int(objective_bytes_per_thickness)
    rows = plan_rows(per_thickness, "the thickness search",
                     f"at most {MAX_FIT_GEOMETRIES} geometries and {MAX_WAVELENGTHS} wavelengths")
    out = [objective(sweep_reflectance(coating, start + step * j0, step, min(rows, count - j0), cos_u, wl_index))
           for j0 in range(0, int(count), rows)]
    return np.concatenate(out)


class FacetModel:
    """Half-vector reflectance at fixed facet angles for any thicknesses (the refinement's fast path).

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        Film, substrate, grid and spread.
    cos_u : numpy.ndarray, shape (U,)
        Facet incidence cosines.

    Notes
    -----
    ``model(d)`` gives reflectance factors of shape ``d.shape + (U, W)``, d in nm (finite, ≥ 0,
    else :class:`swatch.core.errors.SwatchError`).
    """

    def __init__(self, coating: Coating, cos_u: np.ndarray):
        self.film = film_at_angles(coating, cos_u)
        self.coating = coating
        self.cos_u = cos_u

    def __call__(self, thickness_nm) -> np.ndarray:
        d = np.asarray(thickness_nm, dtype=np.float64)
        if not np.all(np.isfinite(d)) or np.any(d < 0):
            raise SwatchError("film thickness must be finite and >= 0 nm")
        if not self.coating.spread.is_zero:  # averaged over the thickness spread
            return self.coating.reflectance_cos(d[..., None], self.cos_u).R
        return self.film.reflectance(d[..., None]).R


def model_reflectance(coating: Coating, thickness_nm, cos_u: np.ndarray) -> np.ndarray:
    """Reflectance at arbitrary thicknesses through the coating (any spread included).

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        Film, substrate, grid and spread.
    thickness_nm : array_like, shape S
        Thicknesses, nm.
    cos_u : numpy.ndarray, shape (U,)
        Facet incidence cosines.

    Returns
    -------
    numpy.ndarray, shape S + (U, W)
        Reflectance factors, 0–1.
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    return coating.reflectance_cos(d[..., None], cos_u).R
