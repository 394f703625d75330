"""Measurements: spectral reflectance at G geometries (one spectrum or a multi-geometry sBRDF set) and
CIELAB at G geometries, as typed objects every reader returns (CSV: :mod:`swatch.io.measurement_csv`;
instrument files: :mod:`swatch.io.instrument_files`).

Geometry: polar angles from the normal and azimuths, degrees. Reflectance is stored as a fraction
(1 = 100 %); a file's values above :data:`PERCENT_THRESHOLD` mean percent unless the caller says which.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swatch.core.errors import SwatchError
from swatch.physics import geometry
from swatch.physics.materials import load_material

__all__ = ["PERCENT_THRESHOLD", "SpectralMeasurement", "LabMeasurement", "check_in_tables"]

#: Reflectance columns with a value above this are taken as percent.
PERCENT_THRESHOLD = 1.5


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
