"""The half-vector thin-film model (Fujii et al., eqs. 2–5) and the thickness ↔ voltage relation.

A :class:`Coating` fixes the film and substrate materials and the wavelength grid; its methods
give the spectral reflectance of the facets that mirror the light into the view (incidence angle
``theta_d`` on the half-vector facet, eq. 5) for arrays of thicknesses and geometries.

References
----------
.. [1] :cite:`Fujii2019`: eqs. 2–5, the half-vector model; Table 2.
.. [2] :cite:`Born1999`: §1.6.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_FILM_INDEX_SCALE, MAX_THICKNESS_NM, MIN_FILM_INDEX_SCALE
from swatch.physics import geometry, optics
from swatch.physics.materials import (
    DEFAULT_FILM,
    DEFAULT_SUBSTRATE,
    DEFAULT_WAVELENGTHS_NM,
    list_materials,
    load_material,
)
from swatch.physics.spread import NO_SPREAD, ThicknessSpread, spread_average

__all__ = [
    "Coating",
    "HalfVector",
    "averaged_over_spread",
    "check_no_amplitudes",
    "get_coating",
    "check_thickness_nm",
    "intensity_correction",
    "intensity_scale",
]

def check_thickness_nm(thickness_nm) -> np.ndarray:
    """Film thicknesses, checked: the one check of a thickness the library is given (issue 17).

    Parameters
    ----------
    thickness_nm : array_like
        Film thickness(es), nm: finite, from 0 to :data:`swatch.core.limits.MAX_THICKNESS_NM`.

    Returns
    -------
    numpy.ndarray
        ``thickness_nm`` as float64, same shape.

    Raises
    ------
    SwatchError
        Naming the parameter (```thickness_nm```; the CLI says ``--thickness``) and the first value
        out of range, when any is.

    Examples
    --------
    >>> check_thickness_nm([50, 120.5]).tolist()
    [50.0, 120.5]
    >>> check_thickness_nm([50, 2000])
    Traceback (most recent call last):
    ...
    swatch.core.errors.SwatchError: `thickness_nm` must be a number from 0 to 1000 nm (got 2000)
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    if d.size == 0:
        raise SwatchError("no thickness given (`thickness_nm` is empty)")
    bad = ~(np.isfinite(d) & (d >= 0) & (d <= MAX_THICKNESS_NM))
    if bad.any():
        raise SwatchError(f"`thickness_nm` must be a number from 0 to {MAX_THICKNESS_NM:g} nm "
                          f"(got {float(d.reshape(-1)[bad.reshape(-1)][0]):g})")
    return d


def intensity_scale(simulated, measured) -> np.ndarray:
    """The paper's intensity correction as a factor: ``mean(measured) / mean(simulated)`` per spectrum.

    Parameters
    ----------
    simulated, measured : array_like, shapes (..., W) broadcasting together
        Spectra on one wavelength grid (last axis).

    Returns
    -------
    numpy.ndarray, the broadcast shape without the last axis
        The scale (dimensionless); 0 where the simulated spectrum has no energy. Computed as the
        ratio of the spectral sums (equal to the ratio of the means on a common grid).
    """
    sim_sum = np.asarray(simulated, dtype=np.float64).sum(axis=-1)
    mea_sum = np.asarray(measured, dtype=np.float64).sum(axis=-1)
    sim_sum, mea_sum = np.broadcast_arrays(sim_sum, mea_sum)
    return np.divide(mea_sum, sim_sum, out=np.zeros_like(sim_sum), where=sim_sum > 0)


def intensity_correction(simulated, measured) -> np.ndarray:
    """The paper's intensity correction: scale ``simulated`` so its spectral mean equals ``measured``'s.

    Works on the last axis (wavelength) of broadcastable arrays; returns the scaled spectra
    (``simulated × intensity_scale(simulated, measured)``).

    Parameters
    ----------
    simulated, measured : array_like, shapes (..., W) broadcasting together
        Spectra on one wavelength grid (last axis).

    Returns
    -------
    numpy.ndarray
        The scaled simulated spectra, the broadcast shape (..., W).

    Examples
    --------
    >>> intensity_correction([0.1, 0.3], [0.2, 0.6]).tolist()
    [0.2, 0.6]
    """
    return np.asarray(simulated, dtype=np.float64) * intensity_scale(simulated, measured)[..., None]


class HalfVector:
    """The half-vector model (Fujii et al., eq. 5) on top of a ``reflectance_cos`` method: the base of
    :class:`Coating` and :class:`swatch.physics.overcoat.OvercoatedCoating`."""

    def reflectance_cos(self, thickness_nm, cos_incidence, amplitudes: bool = False) -> optics.Reflectance:
        """Reflectance at incidence cosines on the facet (implemented by the coating).

        Parameters
        ----------
        thickness_nm : array_like
            Film thickness, nm.
        cos_incidence : array_like
            Cosine of the incidence angle on the facet, broadcast with ``thickness_nm`` to S.
        amplitudes : bool, optional
            Also the complex amplitudes ``r_s``, ``r_p``.

        Returns
        -------
        swatch.physics.optics.Reflectance
            Shapes S + (W,).
        """
        raise NotImplementedError

    def half_vector(
        self, thickness_nm, light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None,
        amplitudes: bool = False,
    ) -> tuple[optics.Reflectance, np.ndarray]:
        """The half-vector model: reflectance at ``theta_d`` (eq. 5) and ``theta_d`` in degrees.

        Parameters
        ----------
        thickness_nm : array_like
            Film thickness, nm (0 to ``MAX_THICKNESS_NM``).
        light_deg, view_deg : array_like
            Polar angles of light and view from the surface normal, degrees in [0, 90).
        light_azimuth_deg : array_like, optional
            The light's azimuth, degrees.
        view_azimuth_deg : array_like or None, optional
            The view's azimuth, degrees; None: opposite the light (the plane of incidence).
        amplitudes : bool, optional
            Also the complex amplitudes.

        Returns
        -------
        reflectance : swatch.physics.optics.Reflectance
            At θ_d, shapes S + (W,) (S: all inputs broadcast).
        theta_d_deg : numpy.ndarray
            θ_d = ½ arccos(l·v), degrees, shape S.

        Raises
        ------
        SwatchError
            For a thickness or an angle out of range (naming the parameter).

        References
        ----------
        :cite:`Fujii2019`, eq. 5.
        """
        geometry.check_light_view_deg(light_deg, view_deg)
        cos_d = geometry.cos_theta_d(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
        theta_d = geometry.theta_d_deg(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
        return self.reflectance_cos(thickness_nm, cos_d, amplitudes), theta_d


@dataclass(frozen=True)
class Coating(HalfVector):
    """Ambient (air) / film / substrate with tabulated complex indices on a wavelength grid.

    The half-vector model of Fujii et al.: :meth:`half_vector` evaluates Airy's reflectance
    (eq. 2–4) at the incidence angle θ_d on the facet whose normal is the half vector of light and
    view (eq. 5); :meth:`reflectance` and :meth:`reflectance_cos` take the facet's incidence
    directly. Thicknesses and angles broadcast together to a shape S; results are S + (W,).

    Attributes
    ----------
    film, substrate : str
        Table names (:func:`swatch.physics.materials.load_material`).
    wavelength_nm : numpy.ndarray, float64, shape (W,)
        Vacuum wavelengths, nm.
    n_film, n_substrate : numpy.ndarray, complex128, shape (W,)
        Complex indices ``n + i k`` on the grid (the film's real part times a process profile's
        film index scale).
    spread : ThicknessSpread
        The film's thickness non-uniformity (:mod:`swatch.physics.spread`): with one, every
        reflectance is the incoherent average over the local thicknesses around the given (mean)
        thickness; without (the default) the uniform film's code path runs unchanged.
    film_index_scale : float
        The factor already applied to the film's real index (kept for engines that build the
        indices from the tables themselves, such as the Mitsuba plugin).

    References
    ----------
    :cite:`Fujii2019`; :cite:`Born1999`, §1.6 (Airy's formula for one film).

    Examples
    --------
    >>> c = get_coating()
    >>> R, theta_d = c.half_vector(50.8, 45.0, 0.0)
    >>> R.R.shape, float(theta_d)
    ((81,), 22.5)
    """

    film: str
    substrate: str
    wavelength_nm: np.ndarray
    n_film: np.ndarray
    n_substrate: np.ndarray
    spread: ThicknessSpread = NO_SPREAD
    film_index_scale: float = 1.0

    def reflectance_cos(self, thickness_nm, cos_incidence, amplitudes: bool = False) -> optics.Reflectance:
        """Reflectance for thicknesses and incidence cosines on the facet, broadcast together.

        Parameters
        ----------
        thickness_nm : array_like
            Film thickness, nm (0 to ``MAX_THICKNESS_NM``); the mean one with a spread.
        cos_incidence : array_like
            Cosine of the incidence angle on the facet (0, 1], broadcast with ``thickness_nm`` to S.
        amplitudes : bool, optional
            Also the complex amplitudes ``r_s``, ``r_p`` (not with a thickness spread).

        Returns
        -------
        swatch.physics.optics.Reflectance
            ``R_s``, ``R_p`` (and ``R``), shapes S + (W,).

        Raises
        ------
        SwatchError
            For a thickness out of range (```thickness_nm```), or amplitudes of a spread film.
        """
        d = check_thickness_nm(thickness_nm)
        if self.spread.is_zero:
            return optics.film_reflectance_cos(d, cos_incidence, self.wavelength_nm,
                                               self.n_film, self.n_substrate, amplitudes=amplitudes)
        check_no_amplitudes(amplitudes)
        film = optics.FilmAtAngles(cos_incidence, self.wavelength_nm, self.n_film, self.n_substrate)

        def reflect(t):
            r = film.reflectance(t)
            return r.R_s, r.R_p

        return averaged_over_spread(reflect, d, self)

    def reflectance(self, thickness_nm, incidence_deg, amplitudes: bool = False) -> optics.Reflectance:
        """Reflectance at incidence angles on the facet, in degrees.

        Parameters
        ----------
        thickness_nm : array_like
            Film thickness, nm (0 to ``MAX_THICKNESS_NM``).
        incidence_deg : array_like
            Incidence angle on the facet, degrees in [0, 90), broadcast with ``thickness_nm`` to S.
        amplitudes : bool, optional
            Also the complex amplitudes (not with a thickness spread).

        Returns
        -------
        swatch.physics.optics.Reflectance
            Shapes S + (W,).

        Raises
        ------
        SwatchError
            For a thickness or angle out of range, or amplitudes of a spread film.

        Examples
        --------
        >>> R = get_coating().reflectance([0.0, 50.8], 0.0)
        >>> R.R.shape, bool((R.R > 0).all() and (R.R < 1).all())
        ((2, 81), True)
        """
        if self.spread.is_zero:
            return optics.film_reflectance(
                check_thickness_nm(thickness_nm), incidence_deg, self.wavelength_nm,
                self.n_film, self.n_substrate, amplitudes=amplitudes,
            )
        theta = np.asarray(incidence_deg, dtype=np.float64)
        geometry.check_polar_deg(theta, "incidence_deg")
        return self.reflectance_cos(thickness_nm, np.cos(np.radians(theta)), amplitudes)


def check_no_amplitudes(amplitudes: bool) -> None:
    """Refuse complex amplitudes of a film with a thickness spread (its local reflectances add incoherently).

    Parameters
    ----------
    amplitudes : bool
        Whether amplitudes were asked for.

    Raises
    ------
    SwatchError
        When they were.
    """
    if amplitudes:
        raise SwatchError("a film with a thickness spread has no single complex amplitude (its local "
                          "reflectances add incoherently); ask for reflectances, or set the spread to 0")


def averaged_over_spread(reflect, d: np.ndarray, base: Coating) -> optics.Reflectance:
    """Reflectance averaged incoherently over a coating's thickness spread (Gauss–Hermite nodes).

    Parameters
    ----------
    reflect : callable
        Local thickness array (nm) -> ``(R_s, R_p)`` arrays of shape ``t.shape + (W,)``.
    d : numpy.ndarray
        The mean thicknesses, nm (checked).
    base : Coating
        Its ``spread``, the film's largest real index and the shortest wavelength set the node count.

    Returns
    -------
    swatch.physics.optics.Reflectance
        ``R_s``, ``R_p`` (no amplitudes), shapes ``d.shape``-broadcast + (W,).
    """
    R_s, R_p = spread_average(reflect, d, base.spread, float(np.max(base.n_film.real)),
                              float(np.min(base.wavelength_nm)))
    return optics.Reflectance(R_s=R_s, R_p=R_p)


@functools.lru_cache(maxsize=64)
def _coating(film: str, substrate: str, grid: tuple, film_index_scale: float = 1.0,
             spread: ThicknessSpread = NO_SPREAD) -> Coating:
    wl = np.array(grid, dtype=np.float64)
    f = load_material(film)
    s = load_material(substrate)
    for mat, role, option in ((f, "film", "`film`"), (s, "substrate", "`substrate`")):
        if mat.role != role:
            choices = ", ".join(m.name for m in list_materials(role))
            raise SwatchError(f"{option} {mat.name} is a {mat.role} table, not a {role}; use one of {choices}")
    n_film = f.nk(wl)
    if film_index_scale != 1.0:
        n_film = film_index_scale * n_film.real + 1j * n_film.imag
    return Coating(f.name, s.name, wl, n_film, s.nk(wl), spread, float(film_index_scale))


def get_coating(film: str = DEFAULT_FILM, substrate: str = DEFAULT_SUBSTRATE, wavelength_nm=None,
                film_index_scale: float = 1.0, spread: ThicknessSpread | None = None) -> Coating:
    """A cached :class:`Coating` for material names and a wavelength grid.

    Parameters
    ----------
    film, substrate : str
        Table names of the clear film and the metal (``swatch materials list``).
    wavelength_nm : array_like or None
        Vacuum wavelengths, nm (default 380–780 nm every 5 nm); within both tables.
    film_index_scale : float
        Multiplies the real part of the film's index (an anodic film's density differs from any
        tabulated film's; a process profile sets it), from 0.5 to 1.5.
    spread : ThicknessSpread or None
        The film's thickness spread (:class:`swatch.physics.spread.ThicknessSpread`); None or zero:
        a uniform film.

    Returns
    -------
    Coating
        Cached on all arguments (the same object for the same request).

    Raises
    ------
    SwatchError
        For an unknown table, a table of the wrong role, a grid outside a table, or a scale out of range.
    """
    scale = float(film_index_scale)
    if not (math.isfinite(scale) and MIN_FILM_INDEX_SCALE <= scale <= MAX_FILM_INDEX_SCALE):
        raise SwatchError(f"film index scale must be from {MIN_FILM_INDEX_SCALE:g} to {MAX_FILM_INDEX_SCALE:g}")
    wl = DEFAULT_WAVELENGTHS_NM if wavelength_nm is None else np.asarray(wavelength_nm, dtype=np.float64)
    return _coating(film, substrate, tuple(wl.tolist()), scale, spread or NO_SPREAD)
