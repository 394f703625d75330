"""A fit's result and the colour comparison at it: :class:`FitResult`, the colorimetry grid of a
measurement (:func:`colour_grid`), the per-geometry ΔE*ab / ΔE2000 and their light × view grid
(:func:`delta_e_grid`, the paper's Fig. 12). The method is described in :mod:`swatch.fit.fitting`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00, delta_E_ab
from swatch.colorimetry.grid import astm_e308_grid
from swatch.colorimetry.tolerance import grade_for, grade_metric
from swatch.core.errors import SwatchError
from swatch.fit.fitting import mirror_angle_deg
from swatch.physics import geometry
from swatch.physics.growth import DEFAULT_NM_PER_V, thickness_to_voltage_V
from swatch.physics.materials import wavelength_grid

__all__ = ["FitResult", "colour_grid", "resampled_words", "interp_rows",
           "geometry_arrays", "used_geometries", "colour_summary", "search_fields", "geometry_fields", "fit_result",
           "delta_e_grid", "MIN_COLOUR_SAMPLES"]

_COLOUR_GRID_STEP_NM = 5.0
_CMF_RANGE_NM = (360.0, 830.0)


@dataclass(frozen=True, eq=False)
class FitResult:
    """Estimated thickness and the per-geometry colour comparison at it.

    Attributes
    ----------
    kind : str
        ``"spectral"`` or ``"lab"``.
    source : str
        The measurement file.
    thickness_nm, uncertainty_nm : float, float or None
        The estimate and its one-sigma uncertainty, nm (None at a bound of the range).
    residual : float
        Spectral: mean squared error (reflectance fraction²); Lab: mean squared ΔE2000.
    second_best_thickness_nm, second_best_residual : float or None
        The next distinct local minimum.
    minima : list of (float, float)
        (thickness nm, residual), lowest first.
    scale_mode : str
        The intensity correction.
    exclude_mirror_deg : float
        Geometries this close to the mirror direction are left out, degrees.
    light_deg, view_deg, light_azimuth_deg, view_azimuth_deg, theta_d_deg, mirror_angle_deg : numpy.ndarray, shape (G,)
        The geometries, degrees.
    used : numpy.ndarray of bool, shape (G,)
        In the fit and the means.
    scale : numpy.ndarray, shape (G,)
        Intensity scale applied to the simulation.
    Lab_measured, Lab_simulated : numpy.ndarray, shape (G, 3)
        CIELAB under ``illuminant`` / ``observer``.
    delta_E_ab, delta_E_00 : numpy.ndarray, shape (G,)
        ΔE*ab (CIE 1976) and ΔE2000 per geometry.
    mean_delta_E_ab, mean_delta_E_00 : float
        Their means over the used geometries.
    grade, scheme : str
        The grade of the mean in the scheme's metric.
    film, substrate, illuminant, observer : str
        Materials and colorimetry.
    colour_wavelength_nm : numpy.ndarray
        The colorimetry grid, nm; ``colour_grid_interpolated`` whether the data were interpolated onto it.
    wavelength_nm, reflectance_unit, reflectance_unit_detected
        Spectral fits: the measured grid (nm) and how the reflectance unit was read.
    """

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

    def to_dict(self, nm_per_V: float = DEFAULT_NM_PER_V) -> dict:
        """JSON-ready dictionary (the contract of ``swatch fit --json``).

        Parameters
        ----------
        nm_per_V : float
            Growth rate for the ``voltage_V`` entry, nm/V (the CLI then applies the process's own law).

        Returns
        -------
        dict
            The scalars, ``minima``, ``max_delta_E_ab``, counts, and ``geometries`` (one dict per geometry).
        """
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
    """The wavelength grid used for colorimetry, and whether the measurement must be interpolated onto it.

    A grid of ASTM E308 step (1, 5, 10, 20 nm), aligned and inside the observer's 360–830 nm, is used
    as is; otherwise the 5 nm grid inside the measured range.

    Parameters
    ----------
    wavelength_nm : array_like, shape (W,)
        The measured wavelengths, nm, increasing.

    Returns
    -------
    (numpy.ndarray, bool)
        The grid, nm, and True when the data must be interpolated.

    Raises
    ------
    swatch.core.errors.SwatchError
        Less than 25 nm (six 5 nm samples) of the range lies inside 360–830 nm.

    Examples
    --------
    >>> wl, interp = colour_grid(np.arange(402.0, 701.0, 4.0))
    >>> float(wl[0]), float(wl[-1]), interp
    (405.0, 695.0, True)
    """
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    lo_cmf, hi_cmf = _CMF_RANGE_NM
    exact = astm_e308_grid(wl) if wl.size >= MIN_COLOUR_SAMPLES else None
    if exact is not None and exact[0] >= lo_cmf and exact[-1] <= hi_cmf:
        return exact, False  # (within GRID_TOLERANCE_NM of wl: the measured values are used as they are)
    s = _COLOUR_GRID_STEP_NM
    a = np.ceil(max(wl[0], lo_cmf) / s - 1e-9) * s
    b = np.floor(min(wl[-1], hi_cmf) / s + 1e-9) * s
    if b - a < (MIN_COLOUR_SAMPLES - 1) * s:
        raise SwatchError(
            f"the measured range {wl[0]:g}–{wl[-1]:g} nm is too narrow for colorimetry; "
            f"it needs at least {(MIN_COLOUR_SAMPLES - 1) * s:g} nm inside {lo_cmf:g}–{hi_cmf:g} nm"
        )
    return wavelength_grid(a, b, s), True


def resampled_words(colour_wavelength_nm) -> str:
    """Why and onto what :func:`colour_grid` interpolated a measurement, in the words every report uses.

    Parameters
    ----------
    colour_wavelength_nm : sequence of float
        The colorimetry grid's first and last wavelength and its step, nm (``FitResult.to_dict``'s
        ``colour_wavelength_nm``).

    Returns
    -------
    str
        ``not an even … grid …; colour from the spectra interpolated linearly onto A–B nm at S nm``.
    """
    a, b, step = (float(x) for x in colour_wavelength_nm)
    lo, hi = _CMF_RANGE_NM
    return (f"not an even 1, 5, 10 or 20 nm grid inside {lo:g}–{hi:g} nm (ASTM E308); colour from the spectra "
            f"interpolated linearly onto {a:g}–{b:g} nm at {step:g} nm")


def interp_rows(x_new: np.ndarray, x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Linear interpolation of each row of ``Y`` from ``x`` onto ``x_new`` (inside ``x``'s range).

    Parameters
    ----------
    x_new : numpy.ndarray, shape (W',)
        New abscissae (e.g. wavelengths, nm).
    x : numpy.ndarray, shape (W,)
        Increasing abscissae of ``Y``.
    Y : numpy.ndarray, shape (G, W)
        Rows to interpolate.

    Returns
    -------
    numpy.ndarray, shape (G, W')
        Each row of ``Y`` at ``x_new``.
    """
    i1 = np.clip(np.searchsorted(x, x_new, side="right"), 1, x.size - 1)
    i0 = i1 - 1
    t = (x_new - x[i0]) / (x[i1] - x[i0])
    return Y[:, i0] * (1.0 - t) + Y[:, i1] * t


def geometry_arrays(m):
    """The facet cosines, facet angles and mirror angles of a measurement's geometries (checked).

    Parameters
    ----------
    m : swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        Its ``light_deg``, ``view_deg`` and azimuths, degrees, shape (G,).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        cos(theta_d), theta_d (degrees) and the mirror angle (degrees), each shape (G,).

    Raises
    ------
    swatch.core.errors.SwatchError
        A light or view angle outside [0, 90) degrees.
    """
    l, v = m.light_deg, m.view_deg
    la, va = m.light_azimuth_deg, m.view_azimuth_deg
    geometry.check_light_view_deg(l, v)
    cos_d = geometry.cos_theta_d(l, v, la, va)
    theta_d = geometry.theta_d_deg(l, v, la, va)
    mirror = mirror_angle_deg(l, v, la, va)
    return cos_d, theta_d, mirror


def used_geometries(mirror: np.ndarray, exclude_mirror_deg: float) -> np.ndarray:
    """The geometries the fit uses: those farther than ``exclude_mirror_deg`` from the mirror direction.

    Parameters
    ----------
    mirror : numpy.ndarray, shape (G,)
        Mirror angles, degrees (:func:`swatch.fit.fitting.mirror_angle_deg`).
    exclude_mirror_deg : float
        In [0, 180) degrees; 0 keeps every geometry.

    Returns
    -------
    numpy.ndarray of bool, shape (G,)
        True for a geometry the fit uses.

    Raises
    ------
    swatch.core.errors.SwatchError
        The exclusion is out of range or leaves no geometry.
    """
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
    """ΔE*ab and ΔE2000 per geometry, their means over the used ones and the grade of the mean.

    Parameters
    ----------
    Lab_m, Lab_s : numpy.ndarray, shape (G, 3)
        Measured and simulated CIELAB.
    used : numpy.ndarray of bool, shape (G,)
        The geometries the means are taken over.
    scheme : str
        The tolerance scheme (its grade is taken in the metric it bounds: ΔE*ab for CSAJ and NBS).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, float, float, str)
        ΔE*ab (G,), ΔE2000 (G,), their means and the grade.
    """
    dEab = np.atleast_1d(delta_E_ab(Lab_m, Lab_s))
    dE00 = np.atleast_1d(delta_E_00(Lab_m, Lab_s))
    mean_ab = float(dEab[used].mean())
    mean_00 = float(dE00[used].mean())
    # the grade in the metric the scheme bounds (CSAJ and NBS: ΔE*ab)
    return dEab, dE00, mean_ab, mean_00, grade_for(mean_ab if grade_metric(scheme) == "dEab" else mean_00, scheme)


def search_fields(kept: list[tuple[float, float]], norm: float) -> dict:
    """:class:`FitResult` fields from the search's minima.

    Parameters
    ----------
    kept : list of (float, float)
        (thickness nm, objective), lowest first (:func:`swatch.fit.search.multimodal_search`).
    norm : float
        Multiplies the objective into the reported residual.

    Returns
    -------
    dict
        ``residual``, ``second_best_thickness_nm``, ``second_best_residual`` and ``minima``.
    """
    _d_best, f_best = kept[0]
    second = kept[1] if len(kept) > 1 else (None, None)
    return dict(
        residual=f_best * norm, second_best_thickness_nm=second[0],
        second_best_residual=None if second[1] is None else second[1] * norm,
        minima=[(d, f * norm) for d, f in kept],
    )


def geometry_fields(measurement) -> dict:
    """:class:`FitResult` fields of a measurement's geometries.

    Parameters
    ----------
    measurement : swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        The measurement.

    Returns
    -------
    dict
        ``light_deg``, ``view_deg``, ``light_azimuth_deg``, ``view_azimuth_deg`` (degrees, shape (G,)).
    """
    return dict(
        light_deg=measurement.light_deg, view_deg=measurement.view_deg,
        light_azimuth_deg=measurement.light_azimuth_deg, view_azimuth_deg=measurement.view_azimuth_deg,
    )


def fit_result(kind: str, measurement, minima: tuple, options: tuple, colours: tuple, tables: tuple, cm,
               interpolated: bool = False, **extra) -> FitResult:
    """The :class:`FitResult` of a spectral or CIELAB fit (the colour comparison and grade computed here).

    Parameters
    ----------
    kind : {"spectral", "lab"}
        The fit.
    measurement : swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        What was fitted (its source and geometries).
    minima : (list of (float, float), float, float or None)
        The search's minima (thickness nm, objective), lowest first; the factor turning an objective into
        the reported residual; the thickness's uncertainty, nm.
    options : (str, float, str)
        The intensity correction's mode, the mirror exclusion (degrees) and the grading scheme.
    colours : (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        The intensity scale per geometry (G,) and the measured and simulated CIELAB (G, 3) under ``cm``.
    tables : (str, str)
        The film and substrate tables.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The illuminant, observer and wavelength grid (nm) of the colours.
    interpolated : bool
        Whether the data were interpolated onto ``cm``'s grid.
    **extra
        Further :class:`FitResult` fields (the spectral fit's grid and reflectance unit).

    Returns
    -------
    FitResult
        The thickness at the lowest minimum with its uncertainty, residuals, and per-geometry ΔE and grade.
    """
    kept, norm, uncertainty_nm = minima
    scale_mode, exclude_mirror_deg, scheme = options
    scale, Lab_m, Lab_s = colours
    _cos_d, theta_d, mirror = geometry_arrays(measurement)
    used = used_geometries(mirror, exclude_mirror_deg)
    dEab, dE00, mean_ab, mean_00, grade = colour_summary(Lab_m, Lab_s, used, scheme)
    return FitResult(
        kind=kind, source=measurement.source, thickness_nm=kept[0][0], uncertainty_nm=uncertainty_nm,
        **search_fields(kept, norm), scale_mode=scale_mode, exclude_mirror_deg=float(exclude_mirror_deg),
        **geometry_fields(measurement), theta_d_deg=theta_d, mirror_angle_deg=mirror, used=used, scale=scale,
        Lab_measured=Lab_m, Lab_simulated=Lab_s, delta_E_ab=dEab, delta_E_00=dE00,
        mean_delta_E_ab=mean_ab, mean_delta_E_00=mean_00, grade=grade, scheme=scheme,
        film=tables[0], substrate=tables[1], illuminant=cm.illuminant, observer=cm.observer,
        colour_wavelength_nm=cm.wavelength_nm, colour_grid_interpolated=interpolated, **extra,
    )


def delta_e_grid(result: FitResult, which: str = "delta_E_ab"):
    """ΔE over a light × view grid of the measured geometries (the paper's Fig. 12).

    When every geometry is in the plane of incidence the view axis is signed (negative: on the light's
    side); otherwise it is the view's polar angle and geometries differing only in azimuth share a cell.

    Parameters
    ----------
    result : FitResult
        The fit.
    which : str
        ``"delta_E_ab"`` or ``"delta_E_00"``.

    Returns
    -------
    light_values : numpy.ndarray, shape (nL,)
        Light polar angles, degrees.
    view_values : numpy.ndarray, shape (nV,)
        View angles, degrees (signed when in plane).
    grid : numpy.ndarray, shape (nL, nV)
        Mean ΔE of the geometries in each cell, NaN where none was measured.
    excluded : numpy.ndarray of bool, shape (nL, nV)
        Cells whose geometries are all in the mirror region.
    signed : bool
        Whether the view axis is signed.

    References
    ----------
    H. Fujii et al. (2019), doi:10.14923/transinfj.2018JDP7030, Fig. 12.
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
