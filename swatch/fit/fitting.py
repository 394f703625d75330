"""Thickness from measurements and from a target colour (the paper's §5): the method, and the parts
the fits share (geometry, the facet model, the result).

Pure functions on arrays, in four modules: :mod:`swatch.fit.spectral_fit` (:func:`fit_spectra`),
:mod:`swatch.fit.lab_fit` (:func:`fit_lab`), :mod:`swatch.fit.matching` (:func:`match_colour`) and the
generic multimodal 1-D search they all use, :mod:`swatch.fit.search`. The CLI (``swatch fit``,
``swatch match``) is in swatch/commands/fit.py; the reports in :mod:`swatch.report.text`.

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
from dataclasses import dataclass, field

import numpy as np

from swatch.colorimetry.colorimeter import ASTM_E308_STEPS_NM, delta_E_00, delta_E_ab
from swatch.colorimetry.tolerance import grade_for, grade_metric
from swatch.core.choices import SCALE_MODES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_FIT_GEOMETRIES, MAX_WAVELENGTHS, plan_rows
from swatch.physics import geometry, optics
from swatch.physics.materials import wavelength_grid
from swatch.physics.model import DEFAULT_NM_PER_V, Coating, thickness_to_voltage_V

__all__ = ["FitResult", "FacetModel", "sweep_curve", "mirror_angle_deg", "colour_grid", "check_scale", "delta_e_grid"]

#: Wavelength spacing of the coarse search (the spectra are smooth on this scale).
COARSE_SPACING_NM = 10.0
_COLOUR_GRID_STEP_NM = 5.0
_CMF_RANGE_NM = (360.0, 830.0)


# -- geometry --------------------------------------------------------------------------------------
def mirror_angle_deg(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Angle (degrees) between the view vector and the mirror reflection of the light vector."""
    la = np.asarray(light_azimuth_deg, dtype=np.float64)
    va = geometry.resolve_view_azimuth_deg(la, view_azimuth_deg)
    m = geometry.direction(light_deg, la) * np.array([-1.0, -1.0, 1.0])
    v = geometry.direction(view_deg, va)
    return np.degrees(np.arccos(np.clip(np.sum(m * v, axis=-1), -1.0, 1.0)))


def check_scale(scale: str) -> str:
    """The intensity correction's name (one of :data:`swatch.core.choices.SCALE_MODES`), or SwatchError."""
    if scale not in SCALE_MODES:
        raise SwatchError(f"unknown intensity scale {scale!r}; use one of {', '.join(SCALE_MODES)}")
    return scale


# -- model evaluation ------------------------------------------------------------------------------
def unique_geometry(cos_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct facet incidence cosines and the index of each geometry into them.

    The half-vector model depends on the geometry only through ``theta_d``; measurement grids
    repeat it (in plane, theta_d = (light + view) / 2), so each distinct value is evaluated once.
    """
    cu, inv = np.unique(np.round(cos_d, 12), return_inverse=True)
    return cu, inv.reshape(-1)


def film_at_angles(coating: Coating, cos_u: np.ndarray, wl_index: np.ndarray | None = None) -> optics.FilmAtAngles:
    """The coating at fixed facet angles (Fresnel terms computed once), optionally on a sub-grid."""
    sel = slice(None) if wl_index is None else wl_index
    return optics.FilmAtAngles(cos_u, coating.wavelength_nm[sel], coating.n_film[sel], coating.n_substrate[sel])


def sweep_reflectance(coating: Coating, start: float, step: float, count: int, cos_u: np.ndarray,
                      wl_index: np.ndarray | None = None) -> np.ndarray:
    """Unpolarised reflectance (count, U, W') for thicknesses ``start + step j`` in one sweep
    (a film with a thickness spread: averaged over it, through the coating)."""
    if not coating.spread.is_zero:
        sub = coating if wl_index is None else dataclasses.replace(
            coating, wavelength_nm=coating.wavelength_nm[wl_index], n_film=coating.n_film[wl_index],
            n_substrate=coating.n_substrate[wl_index])
        d = float(start) + float(step) * np.arange(int(count))
        return sub.reflectance_cos(d[:, None], cos_u).R
    return film_at_angles(coating, cos_u, wl_index).sweep(start, step, count).R


#: Working bytes per (thickness, facet angle, wavelength) sample of a sweep (complex Airy terms, the
#: spread's accumulator), with a margin; the README's memory table has the measured peaks.
SWEEP_BYTES_PER_SAMPLE = 320


def sweep_curve(objective, coating: Coating, start: float, step: float, count: int, cos_u: np.ndarray,
                wl_index: np.ndarray | None, objective_bytes_per_thickness: int) -> np.ndarray:
    """``objective(R)`` (R: (n, U, W') reflectance of n thicknesses → (n,)) over ``start + step j``, ``j < count``,
    in chunks of thicknesses planned against :data:`swatch.core.limits.MAX_RUN_BYTES` (a fine ``--step`` or many
    geometries would otherwise build the whole (count, U, W') sweep at once)."""
    n_wl = coating.wavelength_nm.size if wl_index is None else len(wl_index)
    per_thickness = cos_u.size * n_wl * SWEEP_BYTES_PER_SAMPLE + int(objective_bytes_per_thickness)
    rows = plan_rows(per_thickness, "the thickness search",
                     f"at most {MAX_FIT_GEOMETRIES} geometries and {MAX_WAVELENGTHS} wavelengths")
    out = [objective(sweep_reflectance(coating, start + step * j0, step, min(rows, count - j0), cos_u, wl_index))
           for j0 in range(0, int(count), rows)]
    return np.concatenate(out)


class FacetModel:
    """Half-vector reflectance at fixed facet angles for any thicknesses (refinement fast path):
    ``facets(d)`` has shape ``d.shape + (U, W)``."""

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
    """Reflectance (..., U, W) at arbitrary thicknesses (shape ...) through the engine."""
    d = np.asarray(thickness_nm, dtype=np.float64)
    return coating.reflectance_cos(d[..., None], cos_u).R


# -- results ----------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class FitResult:
    """Estimated thickness and the per-geometry colour comparison at it."""

    kind: str  # "spectral" or "lab"
    source: str
    thickness_nm: float
    uncertainty_nm: float | None
    residual: float  # spectral: mean squared error (fraction²); lab: mean squared ΔE00
    second_best_thickness_nm: float | None
    second_best_residual: float | None
    minima: list  # [(thickness_nm, residual), ...] lowest first
    scale_mode: str
    exclude_mirror_deg: float
    light_deg: np.ndarray
    view_deg: np.ndarray
    light_azimuth_deg: np.ndarray
    view_azimuth_deg: np.ndarray
    theta_d_deg: np.ndarray
    mirror_angle_deg: np.ndarray
    used: np.ndarray  # (G,) bool: in the fit and the means
    scale: np.ndarray  # (G,) intensity scale applied to the simulation
    Lab_measured: np.ndarray
    Lab_simulated: np.ndarray
    delta_E_ab: np.ndarray
    delta_E_00: np.ndarray
    mean_delta_E_ab: float
    mean_delta_E_00: float
    grade: str
    scheme: str
    film: str
    substrate: str
    illuminant: str
    observer: str
    colour_wavelength_nm: np.ndarray
    colour_grid_interpolated: bool
    wavelength_nm: np.ndarray | None = None
    reflectance_unit: str | None = None
    reflectance_unit_detected: bool | None = None
    search_thickness_nm: np.ndarray | None = field(default=None, repr=False)
    search_residual: np.ndarray | None = field(default=None, repr=False)

    def to_dict(self, nm_per_V: float = DEFAULT_NM_PER_V) -> dict:
        """JSON-ready dictionary (the contract of ``swatch fit --json``)."""
        def opt(x):
            return None if x is None else float(x)

        geoms = []
        for i in range(self.light_deg.size):
            geoms.append({
                "light_deg": float(self.light_deg[i]),
                "view_deg": float(self.view_deg[i]),
                "light_azimuth_deg": float(self.light_azimuth_deg[i]),
                "view_azimuth_deg": float(self.view_azimuth_deg[i]),
                "theta_d_deg": float(self.theta_d_deg[i]),
                "mirror_angle_deg": float(self.mirror_angle_deg[i]),
                "excluded": bool(not self.used[i]),
                "scale": float(self.scale[i]),
                "Lab_measured": [float(v) for v in self.Lab_measured[i]],
                "Lab_simulated": [float(v) for v in self.Lab_simulated[i]],
                "delta_E_ab": float(self.delta_E_ab[i]),
                "delta_E_00": float(self.delta_E_00[i]),
            })
        out = {
            "source": self.source,
            "kind": self.kind,
            "thickness_nm": float(self.thickness_nm),
            "uncertainty_nm": opt(self.uncertainty_nm),
            "voltage_V": float(thickness_to_voltage_V(self.thickness_nm, nm_per_V)),
            "nm_per_V": float(nm_per_V),
            "residual": float(self.residual),
            "second_best_thickness_nm": opt(self.second_best_thickness_nm),
            "second_best_residual": opt(self.second_best_residual),
            "minima": [{"thickness_nm": float(d), "residual": float(f)} for d, f in self.minima],
            "mean_delta_E_ab": float(self.mean_delta_E_ab),
            "mean_delta_E_00": float(self.mean_delta_E_00),
            "max_delta_E_ab": float(np.max(self.delta_E_ab[self.used])),
            "grade": self.grade,
            "scheme": self.scheme,
            "scale_mode": self.scale_mode,
            "exclude_mirror_deg": float(self.exclude_mirror_deg),
            "n_geometries": int(self.used.size),
            "n_used": int(self.used.sum()),
            "film": self.film,
            "substrate": self.substrate,
            "illuminant": self.illuminant,
            "observer": self.observer,
            "colour_wavelength_nm": [float(self.colour_wavelength_nm[0]), float(self.colour_wavelength_nm[-1]),
                                     float(self.colour_wavelength_nm[1] - self.colour_wavelength_nm[0])],
            "colour_grid_interpolated": bool(self.colour_grid_interpolated),
        }
        if self.kind == "spectral" and self.wavelength_nm is not None:
            wl = self.wavelength_nm
            out["wavelength_nm"] = [float(wl[0]), float(wl[-1]), int(wl.size)]
            out["reflectance_unit"] = self.reflectance_unit
            out["reflectance_unit_detected"] = bool(self.reflectance_unit_detected)
        out["geometries"] = geoms
        return out


#: colour-science's spectral interpolation (used by ASTM E308) needs six samples.
MIN_COLOUR_SAMPLES = 6


def colour_grid(wavelength_nm) -> tuple[np.ndarray, bool]:
    """The grid used for colorimetry and whether the measurement must be interpolated onto it."""
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    lo_cmf, hi_cmf = _CMF_RANGE_NM
    if wl.size >= MIN_COLOUR_SAMPLES:
        steps = np.diff(wl)
        step = float(steps[0])
        even = np.allclose(steps, step, rtol=0, atol=1e-6)
        astm = any(np.isclose(step, s) for s in ASTM_E308_STEPS_NM)
        aligned = np.isclose(wl[0] / step, np.round(wl[0] / step), rtol=0, atol=1e-6)
        if even and astm and aligned and wl[0] >= lo_cmf and wl[-1] <= hi_cmf:
            return wl, False
    s = _COLOUR_GRID_STEP_NM
    a = np.ceil(max(wl[0], lo_cmf) / s - 1e-9) * s
    b = np.floor(min(wl[-1], hi_cmf) / s + 1e-9) * s
    if b - a < (MIN_COLOUR_SAMPLES - 1) * s:
        raise SwatchError(
            f"the measured range {wl[0]:g}–{wl[-1]:g} nm is too narrow for colorimetry; "
            f"it needs at least {(MIN_COLOUR_SAMPLES - 1) * s:g} nm inside {lo_cmf:g}–{hi_cmf:g} nm"
        )
    return wavelength_grid(a, b, s), True


def interp_rows(x_new: np.ndarray, x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Linear interpolation of each row of Y (G, W) from x onto x_new (inside x's range)."""
    i1 = np.clip(np.searchsorted(x, x_new, side="right"), 1, x.size - 1)
    i0 = i1 - 1
    t = (x_new - x[i0]) / (x[i1] - x[i0])
    return Y[:, i0] * (1.0 - t) + Y[:, i1] * t


def geometry_arrays(m):
    l, v = m.light_deg, m.view_deg
    la, va = m.light_azimuth_deg, m.view_azimuth_deg
    geometry.check_light_view_deg(l, v)
    cos_d = geometry.cos_theta_d(l, v, la, va)
    theta_d = geometry.theta_d_deg(l, v, la, va)
    mirror = mirror_angle_deg(l, v, la, va)
    return cos_d, theta_d, mirror


def used_geometries(mirror: np.ndarray, exclude_mirror_deg: float) -> np.ndarray:
    x = float(exclude_mirror_deg)
    if not (np.isfinite(x) and 0 <= x < 180):
        raise SwatchError(f"mirror exclusion must be in [0, 180) degrees (got {x:g})")
    used = mirror > x if x > 0 else np.ones(mirror.shape, dtype=bool)
    if not used.any():
        raise SwatchError(
            f"all {mirror.size} geometries are within {x:g}° of the mirror direction; "
            "lower `exclude_mirror_deg` (0 keeps every geometry)"
        )
    return used


def colour_summary(Lab_m, Lab_s, used, scheme):
    dEab = np.atleast_1d(delta_E_ab(Lab_m, Lab_s))
    dE00 = np.atleast_1d(delta_E_00(Lab_m, Lab_s))
    mean_ab = float(dEab[used].mean())
    mean_00 = float(dE00[used].mean())
    # the grade in the metric the scheme bounds (CSAJ and NBS: ΔE*ab)
    return dEab, dE00, mean_ab, mean_00, grade_for(mean_ab if grade_metric(scheme) == "dEab" else mean_00, scheme)


def search_fields(kept: list[tuple[float, float]], norm: float) -> dict:
    """FitResult fields from the search's minima (lowest first), residuals normalised by ``norm``."""
    _d_best, f_best = kept[0]
    second = kept[1] if len(kept) > 1 else (None, None)
    return dict(
        residual=f_best * norm, second_best_thickness_nm=second[0],
        second_best_residual=None if second[1] is None else second[1] * norm,
        minima=[(d, f * norm) for d, f in kept],
    )


def geometry_fields(measurement) -> dict:
    return dict(
        light_deg=measurement.light_deg, view_deg=measurement.view_deg,
        light_azimuth_deg=measurement.light_azimuth_deg, view_azimuth_deg=measurement.view_azimuth_deg,
    )


def delta_e_grid(result: FitResult, which: str = "delta_E_ab"):
    """ΔE over a light × view grid of the measured geometries (the paper's Fig. 12).

    Returns ``(light_values, view_values, grid, excluded, signed)``: ``grid`` (nL, nV) holds the
    mean ΔE of the geometries in each cell (NaN where none was measured), ``excluded`` marks cells
    whose geometries are all in the mirror region. When every geometry is in the plane of incidence
    the view axis is signed (negative: on the light's side); otherwise it is the view's polar angle
    and geometries differing only in azimuth share a cell.
    """
    values = getattr(result, which)
    dphi = np.mod(result.view_azimuth_deg - result.light_azimuth_deg, 360.0)
    far = np.isclose(dphi, 180.0, atol=1e-6)
    near = np.isclose(dphi, 0.0, atol=1e-6) | np.isclose(dphi, 360.0, atol=1e-6) | (result.view_deg == 0)
    signed = bool(np.all(far | near))
    view = np.where(far | (result.view_deg == 0), result.view_deg, -result.view_deg) if signed else result.view_deg
    lv = np.unique(np.round(result.light_deg, 6))
    vv = np.unique(np.round(view, 6))
    li = np.searchsorted(lv, np.round(result.light_deg, 6))
    vi = np.searchsorted(vv, np.round(view, 6))
    total = np.zeros((lv.size, vv.size))
    n = np.zeros((lv.size, vv.size))
    n_used = np.zeros((lv.size, vv.size))
    np.add.at(total, (li, vi), values)
    np.add.at(n, (li, vi), 1.0)
    np.add.at(n_used, (li, vi), result.used.astype(np.float64))
    grid = np.divide(total, n, out=np.full(total.shape, np.nan), where=n > 0)
    excluded = (n > 0) & (n_used == 0)
    return lv, vv, grid, excluded, signed
