"""Thickness from measurements, thickness from a target colour, and ΔE reports (the paper's §5).

Pure functions on arrays; the CLI (``swatch fit``, ``swatch match``) is in swatch/commands/fit.py.

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

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar

from swatch import geometry, optics
from swatch.colorimetry import ASTM_E308_STEPS_NM, Colorimeter, delta_E_00, delta_E_ab, get_colorimeter
from swatch.errors import SwatchError
from swatch.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, wavelength_grid
from swatch.measurements import LabMeasurement, SpectralMeasurement, check_in_tables
from swatch.model import DEFAULT_NM_PER_V, MAX_THICKNESS_NM, Coating, get_coating, thickness_to_voltage_V
from swatch.tolerance import DEFAULT_SCHEME, grade_bound, grade_for

__all__ = [
    "SCALE_MODES",
    "DEFAULT_EXCLUDE_MIRROR_DEG",
    "DEFAULT_THICKNESS_RANGE_NM",
    "FitResult",
    "MatchResult",
    "mirror_angle_deg",
    "colour_grid",
    "fit_spectra",
    "fit_lab",
    "match_colour",
    "delta_e_grid",
]

SCALE_MODES = ("energy", "lsq", "global", "none")
DEFAULT_EXCLUDE_MIRROR_DEG = 10.0
DEFAULT_THICKNESS_RANGE_NM = (0.0, 400.0)
DEFAULT_FIT_STEP_NM = 1.0
DEFAULT_MATCH_STEP_NM = 0.1
#: Wavelength spacing of the coarse search (the spectra are smooth on this scale).
COARSE_SPACING_NM = 10.0
#: Local minima of the coarse search re-scored on the full data, and how many of those are refined.
N_SCREEN = 8
N_REFINE = 3
#: Reported minima closer than this are the same minimum (nm).
MATCH_MIN_SEPARATION_NM = 5.0
_CURVATURE_STEP_NM = 0.05
_COLOUR_GRID_STEP_NM = 5.0
_CMF_RANGE_NM = (360.0, 830.0)


# -- geometry --------------------------------------------------------------------------------------
def mirror_angle_deg(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Angle (degrees) between the view vector and the mirror reflection of the light vector."""
    la = np.asarray(light_azimuth_deg, dtype=np.float64)
    va = la + 180.0 if view_azimuth_deg is None else np.asarray(view_azimuth_deg, dtype=np.float64)
    m = geometry.direction(light_deg, la) * np.array([-1.0, -1.0, 1.0])
    v = geometry.direction(view_deg, va)
    return np.degrees(np.arccos(np.clip(np.sum(m * v, axis=-1), -1.0, 1.0)))


def _check_range(thickness_range, step_nm) -> tuple[float, float, float, int]:
    lo, hi = (float(x) for x in thickness_range)
    step = float(step_nm)
    if not (np.isfinite([lo, hi]).all() and 0 <= lo < hi <= MAX_THICKNESS_NM):
        raise SwatchError(f"thickness range must satisfy 0 <= A < B <= {MAX_THICKNESS_NM:g} nm (got {lo:g}:{hi:g})")
    if not (np.isfinite(step) and 0 < step <= (hi - lo) / 4):
        raise SwatchError(f"search step must be > 0 and at most a quarter of the range (got {step:g} nm)")
    count = int(np.floor((hi - lo) / step + 1e-9)) + 1
    if count > 200_000:
        raise SwatchError(f"search grid has {count} thicknesses; use a larger step (at most 200000 points)")
    return lo, hi, step, count


def _check_scale(scale: str) -> str:
    if scale not in SCALE_MODES:
        raise SwatchError(f"unknown intensity scale {scale!r}; use one of {', '.join(SCALE_MODES)}")
    return scale


# -- model evaluation ------------------------------------------------------------------------------
def _unique_geometry(cos_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct facet incidence cosines and the index of each geometry into them.

    The half-vector model depends on the geometry only through ``theta_d``; measurement grids
    repeat it (in plane, theta_d = (light + view) / 2), so each distinct value is evaluated once.
    """
    cu, inv = np.unique(np.round(cos_d, 12), return_inverse=True)
    return cu, inv.reshape(-1)


def _film(coating: Coating, cos_u: np.ndarray, wl_index: np.ndarray | None = None) -> optics.FilmAtAngles:
    """The coating at fixed facet angles (Fresnel terms computed once), optionally on a sub-grid."""
    sel = slice(None) if wl_index is None else wl_index
    return optics.FilmAtAngles(cos_u, coating.wavelength_nm[sel], coating.n_film[sel], coating.n_substrate[sel])


def _sweep(coating: Coating, start: float, step: float, count: int, cos_u: np.ndarray,
           wl_index: np.ndarray | None = None) -> np.ndarray:
    """Unpolarised reflectance (count, U, W') for thicknesses ``start + step j`` in one sweep."""
    return _film(coating, cos_u, wl_index).sweep(start, step, count).R


class _FacetModel:
    """Half-vector reflectance at fixed facet angles for any thicknesses (refinement fast path):
    ``facets(d)`` has shape ``d.shape + (U, W)``."""

    def __init__(self, coating: Coating, cos_u: np.ndarray):
        self.film = _film(coating, cos_u)

    def __call__(self, thickness_nm) -> np.ndarray:
        d = np.asarray(thickness_nm, dtype=np.float64)
        if not np.all(np.isfinite(d)) or np.any(d < 0):
            raise SwatchError("film thickness must be finite and >= 0 nm")
        return self.film.reflectance(d[..., None]).R


def _model(coating: Coating, thickness_nm, cos_u: np.ndarray) -> np.ndarray:
    """Reflectance (..., U, W) at arbitrary thicknesses (shape ...) through the engine."""
    d = np.asarray(thickness_nm, dtype=np.float64)
    return coating.reflectance_cos(d[..., None], cos_u).R


# -- least squares with intensity correction --------------------------------------------------------
def _scales_and_ssr(S: np.ndarray, M: np.ndarray, scale: str) -> tuple[np.ndarray, np.ndarray]:
    """Intensity scales (..., G) and total squared error (...) of ``a S`` against ``M`` (G, W)."""
    S2 = np.einsum("...gw,...gw->...g", S, S)
    SM = np.einsum("...gw,gw->...g", S, M)
    M2 = np.einsum("gw,gw->g", M, M)
    if scale == "energy":
        S1 = S.sum(axis=-1)
        a = np.divide(M.sum(axis=-1), S1, out=np.zeros_like(S1), where=S1 > 0)
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


def _local_minima(f: np.ndarray) -> np.ndarray:
    """Indices of local minima of a sampled curve, lowest first.

    An end point of the range counts only when it is lower than every interior minimum (the
    best match lies at, or beyond, the end of the search range); otherwise a curve that merely
    falls towards the end of the range would add a minimum that is only an artefact of where
    the range stops.
    """
    n = f.size
    left = np.ones(n, dtype=bool)
    right = np.ones(n, dtype=bool)
    left[1:] = f[1:] < f[:-1]
    right[:-1] = f[:-1] <= f[1:]
    idx = np.flatnonzero(left & right)
    interior = idx[(idx > 0) & (idx < n - 1)]
    if interior.size:
        best_inside = f[interior].min()
        ends = idx[((idx == 0) | (idx == n - 1)) & (f[idx] < best_inside)]
        idx = np.concatenate([interior, ends])
    return idx[np.argsort(f[idx], kind="stable")]


def _refine(fun, grid_d: float, lo: float, hi: float, step: float) -> tuple[float, float]:
    a, b = max(lo, grid_d - step), min(hi, grid_d + step)
    res = minimize_scalar(fun, bounds=(a, b), method="bounded", options={"xatol": 1e-3})
    d, f = float(res.x), float(res.fun)
    f0 = float(fun(grid_d))
    if f0 < f:  # the grid point itself (e.g. a minimum on the bound of the search)
        d, f = float(grid_d), f0
    return d, f


def _search(curve_fun, fine_fun, lo, hi, step, count, min_separation, n_refine=N_REFINE):
    """Global search then local refinement.

    The coarse curve's lowest local minima (up to ``N_SCREEN``) are re-scored with the full
    objective at their grid points; the best ``n_refine`` are refined by bounded Brent
    minimisation within one grid step. Returns ``([(d, f), ...] lowest first and at least
    ``min_separation`` apart, thickness grid, coarse curve)``.
    """
    d_grid = lo + step * np.arange(count)
    f_coarse = curve_fun()
    cand = _local_minima(f_coarse)[:N_SCREEN]
    screened = sorted(cand, key=lambda i: fine_fun(float(d_grid[i])))[:n_refine]
    minima = sorted((_refine(fine_fun, float(d_grid[i]), lo, hi, step) for i in screened), key=lambda t: t[1])
    kept: list[tuple[float, float]] = []
    for d, f in minima:
        if all(abs(d - k) > min_separation for k, _ in kept):
            kept.append((d, f))
    return kept, d_grid, f_coarse


def _uncertainty(fine_fun, d: float, f_min: float, lo: float, hi: float, n: int, p: int) -> float | None:
    h = _CURVATURE_STEP_NM
    if d - h < lo or d + h > hi or n <= p:
        return None
    curv = (fine_fun(d + h) - 2.0 * f_min + fine_fun(d - h)) / (h * h)
    if not np.isfinite(curv) or curv <= 0:
        return None
    s2 = f_min / (n - p)
    return float(np.sqrt(2.0 * s2 / curv))


def _spectral_uncertainty(facets, inv, M, scale, d, lo, hi) -> float | None:
    """1-sigma of the thickness: Gauss–Newton with per-geometry noise (a sandwich estimate).

    ``J = d r / d d`` of the residual vector ``r = a S - M`` (scales profiled), by central
    differences; the noise variance of each geometry is its residual's mean square, so geometries
    of different intensity (and noise) are weighted correctly:
    ``sigma² = sum_g s_g² |J_g|² / (sum_g |J_g|²)²``.
    """
    h = _CURVATURE_STEP_NM
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
        if self.kind == "spectral":
            out["wavelength_nm"] = [float(self.wavelength_nm[0]), float(self.wavelength_nm[-1]),
                                    int(self.wavelength_nm.size)]
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


def _interp_rows(x_new: np.ndarray, x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Linear interpolation of each row of Y (G, W) from x onto x_new (inside x's range)."""
    i1 = np.clip(np.searchsorted(x, x_new, side="right"), 1, x.size - 1)
    i0 = i1 - 1
    t = (x_new - x[i0]) / (x[i1] - x[i0])
    return Y[:, i0] * (1.0 - t) + Y[:, i1] * t


def _geometry_arrays(m):
    l, v = m.light_deg, m.view_deg
    la, va = m.light_azimuth_deg, m.view_azimuth_deg
    geometry.check_polar_deg(l, "light")
    geometry.check_polar_deg(v, "view")
    cos_d = geometry.cos_theta_d(l, v, la, va)
    theta_d = geometry.theta_d_deg(l, v, la, va)
    mirror = mirror_angle_deg(l, v, la, va)
    return cos_d, theta_d, mirror


def _used(mirror: np.ndarray, exclude_mirror_deg: float) -> np.ndarray:
    x = float(exclude_mirror_deg)
    if not (np.isfinite(x) and 0 <= x < 180):
        raise SwatchError(f"mirror exclusion must be in [0, 180) degrees (got {x:g})")
    used = mirror > x if x > 0 else np.ones(mirror.shape, dtype=bool)
    if not used.any():
        raise SwatchError(
            f"all {mirror.size} geometries are within {x:g}° of the mirror direction; "
            "lower --exclude-mirror (0 keeps every geometry)"
        )
    return used


def _summary(Lab_m, Lab_s, used, scheme):
    dEab = np.atleast_1d(delta_E_ab(Lab_m, Lab_s))
    dE00 = np.atleast_1d(delta_E_00(Lab_m, Lab_s))
    mean_ab = float(dEab[used].mean())
    mean_00 = float(dE00[used].mean())
    return dEab, dE00, mean_ab, mean_00, grade_for(mean_ab, scheme)


def _search_fields(kept: list[tuple[float, float]], norm: float) -> dict:
    """FitResult fields from the search's minima (lowest first), residuals normalised by ``norm``."""
    d_best, f_best = kept[0]
    second = kept[1] if len(kept) > 1 else (None, None)
    return dict(
        residual=f_best * norm, second_best_thickness_nm=second[0],
        second_best_residual=None if second[1] is None else second[1] * norm,
        minima=[(d, f * norm) for d, f in kept],
    )


def _geometry_fields(measurement) -> dict:
    return dict(
        light_deg=measurement.light_deg, view_deg=measurement.view_deg,
        light_azimuth_deg=measurement.light_azimuth_deg, view_azimuth_deg=measurement.view_azimuth_deg,
    )


# -- spectral fit -----------------------------------------------------------------------------------
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
) -> FitResult:
    """Least-squares thickness of spectral measurements (see the module docstring)."""
    scale = _check_scale(scale)
    lo, hi, step, count = _check_range(thickness_range, step_nm)
    check_in_tables(measurement, film, substrate)
    wl = measurement.wavelength_nm
    coating = get_coating(film, substrate, wl)
    cos_d, theta_d, mirror = _geometry_arrays(measurement)
    used = _used(mirror, exclude_mirror_deg)
    M = measurement.reflectance[used]
    cu, inv = _unique_geometry(cos_d[used])
    stride = max(1, int(np.ceil(COARSE_SPACING_NM / max(float(np.median(np.diff(wl))), 1e-9) - 1e-9)))
    wl_idx = np.arange(0, wl.size, stride)
    if wl_idx.size < 3:
        wl_idx = np.arange(wl.size)
    Mc = M[:, wl_idx]

    def curve():
        S = _sweep(coating, lo, step, count, cu, wl_idx)[:, inv, :]
        return _scales_and_ssr(S, Mc, scale)[1]

    facets = _FacetModel(coating, cu)

    def fine(d):
        S = facets(d)[inv]
        return float(_scales_and_ssr(S, M, scale)[1])

    kept, d_grid, f_coarse = _search(curve, fine, lo, hi, step, count, min_separation=2.0 * step)
    d_best, f_best = kept[0]
    n = M.size
    sigma = _spectral_uncertainty(facets, inv, M, scale, d_best, lo, hi)

    # Scales for every geometry (excluded ones too) at the estimate.
    S_all = _model(coating, d_best, cos_d)
    a_used, _ = _scales_and_ssr(S_all[used], M, scale)
    if scale in ("energy", "lsq"):
        a_all, _ = _scales_and_ssr(S_all, measurement.reflectance, scale)
    else:
        a_all = np.full(cos_d.shape, float(a_used[0]))

    cwl, interpolated = colour_grid(wl)
    cm = get_colorimeter(cwl, illuminant, observer)
    if interpolated:
        M_col = _interp_rows(cwl, wl, measurement.reflectance)
        S_col = get_coating(film, substrate, cwl).reflectance_cos(d_best, cos_d).R
    else:
        M_col = measurement.reflectance
        S_col = S_all
    Lab_m = cm.spectrum_Lab(M_col)
    Lab_s = cm.spectrum_Lab(a_all[:, None] * S_col)
    dEab, dE00, mean_ab, mean_00, grade = _summary(Lab_m, Lab_s, used, scheme)
    norm = 1.0 / n
    return FitResult(
        kind="spectral", source=measurement.source, thickness_nm=d_best, uncertainty_nm=sigma,
        **_search_fields(kept, norm), scale_mode=scale, exclude_mirror_deg=float(exclude_mirror_deg),
        **_geometry_fields(measurement), theta_d_deg=theta_d, mirror_angle_deg=mirror, used=used, scale=a_all,
        Lab_measured=Lab_m, Lab_simulated=Lab_s, delta_E_ab=dEab, delta_E_00=dE00,
        mean_delta_E_ab=mean_ab, mean_delta_E_00=mean_00, grade=grade, scheme=scheme,
        film=coating.film, substrate=coating.substrate, illuminant=cm.illuminant, observer=cm.observer,
        colour_wavelength_nm=cwl, colour_grid_interpolated=interpolated, wavelength_nm=wl,
        reflectance_unit="percent" if measurement.percent else "fraction",
        reflectance_unit_detected=measurement.unit_detected,
        search_thickness_nm=d_grid, search_residual=f_coarse / (M.shape[0] * wl_idx.size),
    )


# -- Lab fit ----------------------------------------------------------------------------------------
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
    film: str = DEFAULT_FILM,
    substrate: str = DEFAULT_SUBSTRATE,
    *,
    scale: str = "energy",
    exclude_mirror_deg: float = DEFAULT_EXCLUDE_MIRROR_DEG,
    thickness_range=DEFAULT_THICKNESS_RANGE_NM,
    step_nm: float = DEFAULT_FIT_STEP_NM,
    wavelength_nm=None,
    illuminant: str = "D65",
    observer: str = "10",
    scheme: str = DEFAULT_SCHEME,
) -> FitResult:
    """Thickness from CIELAB measurements: least squares in ΔE2000 (see the module docstring)."""
    scale = _check_scale(scale)
    lo, hi, step, count = _check_range(thickness_range, step_nm)
    coating = get_coating(film, substrate, wavelength_nm)
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    cos_d, theta_d, mirror = _geometry_arrays(measurement)
    used = _used(mirror, exclude_mirror_deg)
    Lab_m_all = measurement.Lab
    Lab_m = Lab_m_all[used]
    Y_meas = cm.Lab_to_XYZ(Lab_m)[..., 1]
    cu, inv = _unique_geometry(cos_d[used])

    def objective(XYZ_u):
        Lab_s, _ = _scaled_Lab(XYZ_u[..., inv, :], Y_meas, scale, cm)
        dE = delta_E_00(Lab_s, np.broadcast_to(Lab_m, Lab_s.shape))
        return np.sum(dE * dE, axis=-1)

    def curve():
        return objective(cm.XYZ(_sweep(coating, lo, step, count, cu)))

    facets = _FacetModel(coating, cu)

    def fine(d):
        return float(objective(cm.XYZ(facets(d))))

    kept, d_grid, f_coarse = _search(curve, fine, lo, hi, step, count, min_separation=2.0 * step)
    d_best, f_best = kept[0]
    G = int(used.sum())
    p = 1 + {"energy": G, "lsq": G, "global": 1, "none": 0}[scale]
    sigma = _uncertainty(fine, d_best, f_best, lo, hi, 3 * G, p)

    XYZ_all = cm.XYZ(_model(coating, d_best, cos_d))
    Y_all = cm.Lab_to_XYZ(Lab_m_all)[..., 1]
    if scale in ("energy", "lsq", "none"):
        Lab_s, a_all = _scaled_Lab(XYZ_all, Y_all, scale, cm)
    else:
        _, a_used = _scaled_Lab(XYZ_all[used], Y_meas, scale, cm)
        a_all = np.full(cos_d.shape, float(a_used[0]))
        Lab_s = cm.Lab(XYZ_all * a_all[:, None])
    dEab, dE00, mean_ab, mean_00, grade = _summary(Lab_m_all, Lab_s, used, scheme)
    norm = 1.0 / G
    return FitResult(
        kind="lab", source=measurement.source, thickness_nm=d_best, uncertainty_nm=sigma,
        **_search_fields(kept, norm), scale_mode=scale, exclude_mirror_deg=float(exclude_mirror_deg),
        **_geometry_fields(measurement), theta_d_deg=theta_d, mirror_angle_deg=mirror, used=used, scale=np.asarray(a_all, dtype=np.float64),
        Lab_measured=Lab_m_all, Lab_simulated=Lab_s, delta_E_ab=dEab, delta_E_00=dE00,
        mean_delta_E_ab=mean_ab, mean_delta_E_00=mean_00, grade=grade, scheme=scheme,
        film=coating.film, substrate=coating.substrate, illuminant=cm.illuminant, observer=cm.observer,
        colour_wavelength_nm=coating.wavelength_nm, colour_grid_interpolated=False,
        search_thickness_nm=d_grid, search_residual=f_coarse * norm,
    )


# -- colour match -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class MatchResult:
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
        return any(c["within_grade"] for c in self.candidates)

    def to_dict(self) -> dict:
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
    nm_per_V: float = DEFAULT_NM_PER_V,
    grade: str = "C",
    scheme: str = DEFAULT_SCHEME,
    match_lightness: bool = False,
) -> MatchResult:
    """Thicknesses whose colour at one geometry is closest to ``target_Lab`` (ranked by ΔE2000).

    ``match_lightness`` scales the simulated colour so its Y equals the target's (compare hue
    and chroma only, for targets of unknown lightness such as photographs).
    """
    target = np.asarray(target_Lab, dtype=np.float64).reshape(3)
    if not np.all(np.isfinite(target)) or not 0 <= target[0] <= 100:
        raise SwatchError("target Lab must be finite with L in [0, 100]")
    if not (isinstance(top, int) and 1 <= top <= 100):
        raise SwatchError("--top must be an integer from 1 to 100")
    bound = grade_bound(grade, scheme)
    coating = coating or get_coating()
    cm = colorimeter or get_colorimeter(coating.wavelength_nm)
    if not np.array_equal(cm.wavelength_nm, coating.wavelength_nm):
        raise SwatchError("the colorimeter and the coating must use the same wavelength grid")
    lo, hi, step, count = _check_range(thickness_range, step_nm)
    geometry.check_polar_deg(light_deg, "light")
    geometry.check_polar_deg(view_deg, "view")
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
        Lab = Lab_of(_sweep(coating, lo, step, count, cos_d))
        return delta_E_00(Lab, np.broadcast_to(target, Lab.shape))

    facets = _FacetModel(coating, cos_d)

    def fine(d):
        return float(delta_E_00(Lab_of(facets(d)), target))

    kept, _, _ = _search(curve, fine, lo, hi, step, count, min_separation=MATCH_MIN_SEPARATION_NM,
                         n_refine=max(top, N_REFINE) + 2)
    kept = kept[:top]
    d = np.array([k[0] for k in kept])
    Lab = np.atleast_2d(Lab_of(_model(coating, d, cos_d)))
    dE00 = np.atleast_1d(delta_E_00(Lab, target))
    dEab = np.atleast_1d(delta_E_ab(Lab, target))
    volts = thickness_to_voltage_V(d, nm_per_V)
    cands = [
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


# -- ΔE map -----------------------------------------------------------------------------------------
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
