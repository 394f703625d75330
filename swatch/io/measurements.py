"""Measurements: spectral reflectance at G geometries (one spectrum or a multi-geometry sBRDF set) and
CIELAB at G geometries, as typed objects every reader returns (CSV: :mod:`swatch.io.measurement_csv`;
instrument files: :mod:`swatch.io.instrument_files`).

Geometry: polar angles from the normal and azimuths, degrees. Reflectance is stored as a fraction
(1 = 100 %); a file's values above :data:`PERCENT_THRESHOLD` mean percent unless the caller says which.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.grid import astm_e308_grid
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_MEASURED_WAVELENGTH_NM, MAX_WAVELENGTHS, MIN_MEASURED_WAVELENGTH_NM
from swatch.physics import geometry
from swatch.physics.materials import load_material

__all__ = ["PERCENT_THRESHOLD", "SpectralMeasurement", "LabMeasurement", "check_in_tables", "check_spectral_axis",
           "uniform_spectral_axis"]

#: Reflectance columns with a value above this are taken as percent.
PERCENT_THRESHOLD = 1.5


def _check_wavelengths(wl: np.ndarray, source: str, labels) -> None:
    """Finite, inside the measured range, strictly increasing: the first offender named by its label."""
    lo, hi = MIN_MEASURED_WAVELENGTH_NM, MAX_MEASURED_WAVELENGTH_NM
    bad = np.flatnonzero(~np.isfinite(wl))
    if bad.size:
        i = int(bad[0])
        raise SwatchError(f"{source}: {labels(i)}: {wl[i]!r} is not a finite number; a wavelength is a number of nm "
                          f"from {lo:g} to {hi:g}")
    bad = np.flatnonzero((wl < lo) | (wl > hi))
    if bad.size:
        i = int(bad[0])
        raise SwatchError(f"{source}: {labels(i)}: {wl[i]:g} nm is outside the measured range; a wavelength lies in "
                          f"{lo:g}–{hi:g} nm (colorimetry uses 360–830 nm of it)")
    bad = np.flatnonzero(np.diff(wl) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise SwatchError(f"{source}: {labels(i)}: {wl[i]:g} nm is not above {labels(i - 1)}'s {wl[i - 1]:g} nm; "
                          "the wavelengths must be strictly increasing")


def _labeller(labels, what: str):
    """Index -> the name of that wavelength in messages."""
    if callable(labels):
        return labels
    if labels is None:
        return lambda i: what
    return lambda i: str(labels[i])


def check_spectral_axis(wavelength_nm, source: str, labels=None, what: str = "wavelengths") -> np.ndarray:
    """A measured spectrum's wavelength axis, checked: the one rule of every reader (CSV, CGATS and
    ArgyllCMS ``.ti3``, CxF3, coupons).

    Two to :data:`swatch.core.limits.MAX_WAVELENGTHS` wavelengths, finite, strictly increasing, inside
    :data:`swatch.core.limits.MIN_MEASURED_WAVELENGTH_NM` – :data:`~swatch.core.limits.MAX_MEASURED_WAVELENGTH_NM`.
    An axis within :data:`swatch.colorimetry.grid.GRID_TOLERANCE_NM` of an ASTM E308 grid (an even 1, 5,
    10 or 20 nm step; instruments write 729.99999999 for 730) is returned as that grid exactly, which
    colour-science integrates as measured; any other axis is kept as it is, and the colorimetry interpolates
    its spectra onto a 5 nm grid and says so (:func:`swatch.fit.result.colour_grid`).

    Parameters
    ----------
    wavelength_nm : array_like, shape (W,)
        The wavelengths as the file gives them, nm.
    source : str
        Names the file (and sample) in messages.
    labels : sequence of str or callable, optional
        Names each wavelength in messages as the file does (a field name, ``line 12: wavelength_nm``), or
        a function of the wavelength's index that does; default ``what``.
    what : str
        Names the axis as a whole in messages.

    Returns
    -------
    numpy.ndarray, shape (W,)
        The wavelengths, nm, float64 (on an ASTM E308 grid: that grid's values).

    Raises
    ------
    swatch.core.errors.SwatchError
        One line naming the file, the wavelength (its label) and what is allowed.

    Examples
    --------
    >>> check_spectral_axis([380.0, 390.0, 399.99999999], "a.ti3").tolist()
    [380.0, 390.0, 400.0]
    >>> check_spectral_axis([400.0, float("nan")], "b.txt", ["SPEC_400", "SPEC_410"])
    Traceback (most recent call last):
    ...
    swatch.core.errors.SwatchError: b.txt: SPEC_410: nan is not a finite number; a wavelength is a number of nm from 200 to 2500
    """
    wl = np.array(wavelength_nm, dtype=np.float64).ravel()
    if not 2 <= wl.size <= MAX_WAVELENGTHS:
        raise SwatchError(f"{source}: {what}: {wl.size} wavelengths; a spectrum has 2 to {MAX_WAVELENGTHS}")
    _check_wavelengths(wl, source, _labeller(labels, what))
    exact = astm_e308_grid(wl)
    return exact if exact is not None else wl


def uniform_spectral_axis(start_nm: float, step_nm: float, count: int, source: str, start_label: str,
                          step_label: str) -> np.ndarray:
    """``start_nm + k * step_nm`` for ``k < count``, as a file states an axis by its start and increment
    (CxF3 ``StartWL`` and ``Increment``), checked by :func:`check_spectral_axis` before it is computed.

    Parameters
    ----------
    start_nm, step_nm : float
        The first wavelength and the increment, nm.
    count : int
        The number of values the spectrum holds.
    source : str
        Names the file in messages.
    start_label, step_label : str
        Name the start and the increment in messages as the file does.

    Returns
    -------
    numpy.ndarray, shape (count,)
        The wavelengths, nm (:func:`check_spectral_axis`'s).

    Raises
    ------
    swatch.core.errors.SwatchError
        A start or increment that is not a finite number, an increment not above 0, a count outside 2 to
        MAX_WAVELENGTHS, or an axis that leaves the measured range.

    Examples
    --------
    >>> uniform_spectral_axis(380.0, 10.0, 3, "c.cxf", "StartWL", "Increment").tolist()
    [380.0, 390.0, 400.0]
    """
    allowed = f"give the wavelengths in nm from {MIN_MEASURED_WAVELENGTH_NM:g} to {MAX_MEASURED_WAVELENGTH_NM:g}"
    values = []
    for label, v in ((start_label, start_nm), (step_label, step_nm)):
        try:
            x = float(v)
        except OverflowError:  # an integer of hundreds of digits
            raise SwatchError(f"{source}: {label}: a {len(str(v))}-digit number; {allowed}") from None
        if not math.isfinite(x):
            raise SwatchError(f"{source}: {label}: {x!r} is not a finite number; {allowed}")
        values.append(x)
    start, step = values
    if not step > 0:
        raise SwatchError(f"{source}: {step_label}: {step:g} nm; the increment must be above 0 nm (the wavelengths "
                          "strictly increasing)")
    if not 2 <= count <= MAX_WAVELENGTHS:
        raise SwatchError(f"{source}: {start_label}: a spectrum of {count} values; a spectrum has 2 to "
                          f"{MAX_WAVELENGTHS}")
    last = f"its last wavelength ({start_label} + {count - 1} × {step_label})"
    _check_wavelengths(np.array([start, start + step * (count - 1)]), source, lambda i: (start_label, last)[i])
    return check_spectral_axis(start + step * np.arange(count, dtype=np.float64), source, what=start_label)


@dataclass(frozen=True, eq=False)
class SpectralMeasurement:
    """Spectra at G geometries on one wavelength grid.

    Attributes
    ----------
    source : str
        The file (or ``<arrays>``).
    light_deg, view_deg : numpy.ndarray, shape (G,)
        Polar angles from the normal, degrees, in [0, 90).
    light_azimuth_deg, view_azimuth_deg : numpy.ndarray, shape (G,)
        Azimuths, degrees.
    wavelength_nm : numpy.ndarray, shape (W,)
        Strictly increasing, nm.
    reflectance : numpy.ndarray, shape (G, W)
        Reflectance factors, fraction.
    percent : bool
        The file was in percent.
    unit_detected : bool
        The unit was detected (not stated by the caller).
    geometry_line, wavelength_line : numpy.ndarray of int or None
        The first file line of each geometry / wavelength (1-based), for messages.
    """

    source: str
    light_deg: np.ndarray  # (G,) polar, [0, 90)
    view_deg: np.ndarray  # (G,) polar, [0, 90)
    light_azimuth_deg: np.ndarray  # (G,)
    view_azimuth_deg: np.ndarray  # (G,)
    wavelength_nm: np.ndarray  # (W,) strictly increasing
    reflectance: np.ndarray  # (G, W) fractions
    percent: bool = False  # the file was in percent
    unit_detected: bool = False  # the unit was detected (not stated by the caller)
    geometry_line: np.ndarray | None = None  # (G,) first line of each geometry (1-based)
    wavelength_line: np.ndarray | None = None  # (W,) first line of each wavelength

    @property
    def n_geometries(self) -> int:
        """G, the number of geometries.

        Returns
        -------
        int
            The number of geometry rows.
        """
        return int(self.light_deg.size)

    @classmethod
    def from_arrays(cls, light_deg, view_deg, wavelength_nm, reflectance, light_azimuth_deg=0.0,
                    view_azimuth_deg=None, source: str = "<arrays>") -> SpectralMeasurement:
        """Build a measurement from arrays.

        Parameters
        ----------
        light_deg, view_deg : array_like, shape (G,)
            Polar angles, degrees (broadcast together).
        wavelength_nm : array_like, shape (W,)
            nm.
        reflectance : array_like, shape (G, W)
            Fraction.
        light_azimuth_deg : array_like
            Degrees.
        view_azimuth_deg : array_like or None
            Degrees; None: the opposite side of the light.
        source : str
            Names it in messages.

        Returns
        -------
        SpectralMeasurement
            The arrays as float64, angles broadcast together, view azimuths resolved.

        Examples
        --------
        >>> m = SpectralMeasurement.from_arrays([45, 45], [0, 30], [500, 600], [[0.2, 0.3], [0.25, 0.35]])
        >>> m.n_geometries, m.view_azimuth_deg.tolist()
        (2, [180.0, 180.0])
        """
        l = np.atleast_1d(np.asarray(light_deg, dtype=np.float64))
        v = np.atleast_1d(np.asarray(view_deg, dtype=np.float64))
        l, v = np.broadcast_arrays(l, v)
        la = np.broadcast_to(np.asarray(light_azimuth_deg, dtype=np.float64), l.shape)
        va = np.broadcast_to(geometry.resolve_view_azimuth_deg(la, view_azimuth_deg), l.shape)
        wl = np.asarray(wavelength_nm, dtype=np.float64)
        R = np.asarray(reflectance, dtype=np.float64).reshape(l.size, wl.size)
        return cls(source, l.copy(), v.copy(), la.copy(), np.asarray(va, dtype=np.float64).copy(), wl, R)


@dataclass(frozen=True, eq=False)
class LabMeasurement:
    """CIELAB values at G geometries.

    Attributes
    ----------
    source : str
        The file.
    light_deg, view_deg : numpy.ndarray, shape (G,)
        Polar angles from the normal, degrees.
    light_azimuth_deg, view_azimuth_deg : numpy.ndarray, shape (G,)
        Azimuths, degrees.
    Lab : numpy.ndarray, shape (G, 3)
        CIELAB under the illuminant and observer the file was measured with.
    geometry_line : numpy.ndarray of int or None
        The file line of each geometry (1-based).
    """

    source: str
    light_deg: np.ndarray
    view_deg: np.ndarray
    light_azimuth_deg: np.ndarray
    view_azimuth_deg: np.ndarray
    Lab: np.ndarray
    geometry_line: np.ndarray | None = None

    @property
    def n_geometries(self) -> int:
        """G, the number of geometries.

        Returns
        -------
        int
            The number of geometry rows.
        """
        return int(self.light_deg.size)


def check_in_tables(measurement: SpectralMeasurement, film: str, substrate: str) -> None:
    """Refuse a spectral measurement with a wavelength outside the film's or the substrate's optical table.

    Parameters
    ----------
    measurement : SpectralMeasurement
        The spectra whose wavelengths are checked, nm.
    film, substrate : str
        Optical table names (:func:`swatch.physics.materials.load_material`).

    Returns
    -------
    None

    Raises
    ------
    swatch.core.errors.SwatchError
        Naming the file's line and the table's range, nm.
    """
    wl = measurement.wavelength_nm
    for name in (film, substrate):
        mat = load_material(name)
        lo, hi = mat.wavelength_range_nm
        bad = np.flatnonzero((wl < lo) | (wl > hi))
        if bad.size:
            i = int(bad[0])
            where = (f"line {int(measurement.wavelength_line[i])}: "
                     if measurement.wavelength_line is not None else "")
            raise SwatchError(
                f"{measurement.source}: {where}wavelength {wl[i]:g} nm is outside the table of {mat.name} "
                f"({lo:g}–{hi:g} nm); measure or crop to a range inside it"
            )
