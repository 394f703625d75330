"""Thin-film optics: Airy reflectance of ambient / film / substrate and coherent multilayer stacks.

Conventions (the same as Byrnes' ``tmm`` package, our reference):

* complex refractive index ``n + i k`` with ``k >= 0`` for absorption (fields ``exp(i (k z - w t))``);
* in a layer j, ``q_j = n_j cos(theta_j) = sqrt(n_j**2 - (n_0 sin theta_0)**2)`` (complex Snell's law), on the
  branch whose wave decays (or, when lossless, travels) away from the interface: ``Im q > 0``, or ``Im q == 0``
  and ``Re q > 0``;
* Fresnel amplitudes ``r_s = (q_i - q_j) / (q_i + q_j)`` and
  ``r_p = (n_j**2 q_i - n_i**2 q_j) / (n_j**2 q_i + n_i**2 q_j)``
  (equal to tmm's ``(n_j cos th_i - n_i cos th_j) / (n_j cos th_i + n_i cos th_j)``);
* one-way phase in a film of thickness d: ``delta = 2 pi d q / lambda``; the paper's eq. 3 is ``2 delta``.

Shapes: ``thickness_nm`` and ``incidence_deg`` broadcast together to a shape S; the index arrays are given on the
wavelength grid (shape (W,)); results have shape ``S + (W,)``. Everything is float64 / complex128 and vectorised
by broadcasting: no loops over thickness, angle or wavelength.

References
----------
.. [1] :cite:`Born1999`: §1.6, Airy's formula.
.. [2] :cite:`Heavens1955`.
.. [3] :cite:`Byrnes2016`: the formulation of ``tmm``, our reference.
.. [4] :cite:`Fujii2019`: eqs. 2–4.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from swatch.core.errors import SwatchError

__all__ = ["Reflectance", "FilmAtAngles", "layer_q", "fresnel_r", "film_reflectance", "film_reflectance_cos",
           "film_reflectance_sweep", "check_index", "check_film_geometry", "check_wavelengths"]


@dataclass(frozen=True)
class Reflectance:
    """Reflectance of a coated surface for s and p polarisation (and the unpolarised mean).

    Parameters
    ----------
    R_s, R_p : numpy.ndarray, float, one shape (..., W)
        Intensity reflectance (fraction, 0–1) for s and p polarisation.
    r_s, r_p : numpy.ndarray, complex, the same shape, or None
        The complex amplitude coefficients (``None`` when not requested).
    """

    R_s: np.ndarray
    R_p: np.ndarray
    r_s: np.ndarray | None = None
    r_p: np.ndarray | None = None

    @property
    def R(self) -> np.ndarray:
        """Unpolarised reflectance: the mean of s and p.

        Returns
        -------
        numpy.ndarray
            The shape of ``R_s``.
        """
        return 0.5 * (self.R_s + self.R_p)


def layer_q(n_layer: np.ndarray, kx: np.ndarray) -> np.ndarray:
    """``q = n cos θ`` in a layer of complex index ``n`` for the tangential index ``kx``.

    ``kx = n0 sin θ0`` is conserved across planar interfaces (Snell's law). The square root's
    branch is the one of a forward wave: decaying into an absorbing medium (``Im q > 0``), or
    propagating forwards (``Re q > 0``) when lossless.

    Parameters
    ----------
    n_layer : array_like, complex
        The layer's index, shape (W,) or broadcastable with ``kx``.
    kx : array_like, real
        ``n0 sin θ0``, shape (..., 1) or (..., W).

    Returns
    -------
    numpy.ndarray, complex128, the broadcast shape
        ``q = n cos θ`` in the layer (dimensionless), on the forward-wave branch.
    """
    q = np.sqrt(np.asarray(n_layer, dtype=np.complex128) ** 2 - np.asarray(kx) ** 2)
    # The principal root already has Re q >= 0; a negative-zero imaginary part of the radicand
    # (lossless, evanescent) would give Im q < 0, the growing wave: flip it.
    return np.where(q.imag < 0, -q, q)


def fresnel_r(n_i, q_i, n_j, q_j) -> tuple[np.ndarray, np.ndarray]:
    """Fresnel amplitude reflection coefficients from medium i into medium j.

    Parameters
    ----------
    n_i, n_j : array_like, complex
        Indices of the two media.
    q_i, q_j : array_like, complex
        ``n cos θ`` in each medium (:func:`layer_q`); all four broadcast to a shape S.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray), complex, shape S
        ``r_s`` and ``r_p`` (formulas in the module's conventions).
    """
    r_s = (q_i - q_j) / (q_i + q_j)
    a = n_j * n_j * q_i
    b = n_i * n_i * q_j
    r_p = (a - b) / (a + b)
    return r_s, r_p


def check_index(n, wavelength_nm: np.ndarray, what: str) -> np.ndarray:
    """A medium's complex index on the grid, checked: finite, ``k >= 0``.

    Parameters
    ----------
    n : array_like
        Complex index, scalar or shape (W,).
    wavelength_nm : numpy.ndarray
        The grid, shape (W,).
    what : str
        The medium, for the message.

    Returns
    -------
    numpy.ndarray
        complex128, shape (W,); SwatchError for non-finite values or ``k < 0``.
    """
    arr = np.broadcast_to(np.asarray(n, dtype=np.complex128), wavelength_nm.shape)
    if not np.all(np.isfinite(arr)):
        raise SwatchError(f"{what} refractive index has non-finite values; give finite n and k")
    if np.any(arr.imag < 0):
        raise SwatchError(f"{what} refractive index has k < 0; k must be >= 0 (absorption)")
    return arr


def check_film_geometry(thickness_nm: np.ndarray, incidence_deg: np.ndarray) -> None:
    """Check film thicknesses (finite, ≥ 0 nm) and incidence angles (in [0, 90) degrees).

    Parameters
    ----------
    thickness_nm, incidence_deg : numpy.ndarray
        Film thicknesses (nm) and incidence angles (degrees from the normal), any shapes.

    Raises
    ------
    SwatchError
        Naming the parameter out of range.
    """
    if not np.all(np.isfinite(thickness_nm)) or np.any(thickness_nm < 0):
        raise SwatchError("`thickness_nm` must be finite and >= 0 nm")
    if not np.all(np.isfinite(incidence_deg)) or np.any(incidence_deg < 0) or np.any(incidence_deg >= 90):
        raise SwatchError("`incidence_deg` must be in [0, 90) degrees")


def check_wavelengths(wavelength_nm) -> np.ndarray:
    """A wavelength grid, checked: a non-empty 1-D array of positive, finite nm.

    Parameters
    ----------
    wavelength_nm : array_like
        The wavelength grid, nm, one dimension.

    Returns
    -------
    numpy.ndarray
        float64, shape (W,); SwatchError otherwise (naming ``wavelength_nm``).
    """
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    if wl.ndim != 1 or wl.size == 0 or not np.all(np.isfinite(wl)) or np.any(wl <= 0):
        raise SwatchError("`wavelength_nm` must be a non-empty 1-D array of positive nm values")
    return wl


class FilmAtAngles:
    """Ambient / film / substrate at fixed incidence angles: evaluate any number of thicknesses.

    The Fresnel coefficients depend on (angle, wavelength) only and are computed once here;
    the thickness enters only through the round-trip phase factor
    ``E = exp(2 i delta) = rho e^(i phi)`` (``2 delta = 4 pi d q1 / lambda``), and

    ``R = |r01 + r12 E|^2 / |1 + r01 r12 E|^2 = K |E - z_num|^2 / |E - z_den|^2``

    (:func:`_pole_form`). The differences ``E - z`` are formed before taking moduli, so the cancellation near total
    reflection (grazing incidence, ``|r01 r12| -> 1``) keeps its relative precision. Used by
    :func:`film_reflectance_cos`, :func:`film_reflectance_sweep` and the thickness fitter.

    Parameters
    ----------
    cos_incidence : array_like, shape A
        Cosine of the incidence angle in the ambient medium, in (0, 1].
    wavelength_nm : array_like, shape (W,), nm
        Positive wavelengths.
    n_film, n_substrate : array_like, complex, shape (W,) or scalar
        Refractive indices ``n + i k`` (k ≥ 0) of the film and the substrate on the grid.
    n_ambient : float
        Real index of the ambient medium (1.0: air).
    """

    def __init__(self, cos_incidence, wavelength_nm, n_film, n_substrate, n_ambient: float = 1.0):
        wl = check_wavelengths(wavelength_nm)
        n1 = check_index(n_film, wl, "film")
        n2 = check_index(n_substrate, wl, "substrate")
        n0 = float(np.real(n_ambient))
        cos0 = np.asarray(cos_incidence, dtype=np.float64)[..., None]
        sin0 = np.sqrt(np.clip(1.0 - cos0 * cos0, 0.0, 1.0))
        kx = n0 * sin0
        q0 = (n0 * cos0).astype(np.complex128)
        q1 = layer_q(n1, kx)
        q2 = layer_q(n2, kx)
        self.wavelength_nm = wl
        self.r01 = fresnel_r(n0, q0, n1, q1)  # (s, p)
        self.r12 = fresnel_r(n1, q1, n2, q2)
        #: ``4 pi q1 / lambda``: the round-trip phase per nm of film, complex (A..., W).
        self.k4 = (4.0 * np.pi / wl) * q1
        self._ik4 = 1j * self.k4
        #: per polarisation (s, p): ``(K, z_num, z_den)``.
        self.poles = []
        for r01, r12 in zip(self.r01, self.r12, strict=True):
            K_num, z_num = _pole_form(r01, r12)
            K_den, z_den = _pole_form(1.0 + 0j, r01 * r12)
            self.poles.append((K_num / K_den, z_num, z_den))

    def phase_factor(self, thickness_nm) -> np.ndarray:
        """The round-trip phase factor ``E = exp(i k4 d)`` of thicknesses.

        Parameters
        ----------
        thickness_nm : array_like, nm
            Film thicknesses, shape broadcasting with A (the angles' shape) to S.

        Returns
        -------
        numpy.ndarray, complex128, shape S + (W,)
            ``E = exp(i k4 d)`` per thickness and wavelength (dimensionless; ``|E| ≤ 1``, < 1 in an absorbing film).
        """
        d = np.asarray(thickness_nm, dtype=np.float64)[..., None]
        return np.exp(d * self._ik4)  # one complex exponential per sample (e^(-d Im k4) (cos + i sin) in one pass)

    def reflectance_from_phase(self, E: np.ndarray, out_s=None, out_p=None, work=None):
        """R_s, R_p for phase factors (the thin film's poles and zeros form; no complex division per sample).

        Parameters
        ----------
        E : numpy.ndarray
            Phase factors ``exp(2iδ)`` (:meth:`phase_factor`), complex, shape E.
        out_s, out_p : numpy.ndarray, optional
            Output arrays of shape E (float64).
        work : tuple of numpy.ndarray, optional
            A complex and a real work array of shape E.

        Returns
        -------
        tuple of numpy.ndarray
            ``(R_s, R_p)``, shape E.
        """
        if work is None:
            work = (np.empty(E.shape, dtype=np.complex128), np.empty(E.shape))
        w, den = work
        result = []
        for (K, z_num, z_den), out in zip(self.poles, (out_s, out_p), strict=True):
            out = np.empty(E.shape) if out is None else out
            np.abs(np.subtract(E, z_num, out=w), out=out)
            np.abs(np.subtract(E, z_den, out=w), out=den)
            out /= den
            out *= out
            out *= K
            result.append(out)
        return result[0], result[1]

    def reflectance(self, thickness_nm, amplitudes: bool = False) -> Reflectance:
        """Reflectance of thicknesses at the fixed angles.

        Parameters
        ----------
        thickness_nm : array_like, nm
            Film thicknesses ≥ 0, broadcasting with A to S.
        amplitudes : bool
            Also return the complex ``r_s``, ``r_p``.

        Returns
        -------
        Reflectance
            ``R_s``, ``R_p`` (fractions) of shape S + (W,), and ``r_s``, ``r_p`` when requested.
        """
        E = self.phase_factor(thickness_nm)
        R_s, R_p = self.reflectance_from_phase(E)
        if not amplitudes:
            return Reflectance(R_s=R_s, R_p=R_p)
        (r01s, r01p), (r12s, r12p) = self.r01, self.r12
        r_s = (r01s + r12s * E) / (1.0 + r01s * r12s * E)
        r_p = (r01p + r12p * E) / (1.0 + r01p * r12p * E)
        return Reflectance(R_s=R_s, R_p=R_p, r_s=r_s, r_p=r_p)

    def sweep(self, thickness_start_nm: float, thickness_step_nm: float, count: int) -> Reflectance:
        """Reflectance over ``start + step * j``, ``j < count`` (see :func:`film_reflectance_sweep`).

        Parameters
        ----------
        thickness_start_nm, thickness_step_nm : float
            The first thickness and the step, nm.
        count : int
            The number of thicknesses.

        Returns
        -------
        Reflectance
            ``R_s``, ``R_p`` of shape (count,) + A + (W,).
        """
        return _sweep(self, thickness_start_nm, thickness_step_nm, count)


def film_reflectance_cos(thickness_nm, cos_incidence, wavelength_nm, n_film, n_substrate, n_ambient: float = 1.0,
                         amplitudes: bool = False) -> Reflectance:
    """Airy reflectance of one film, with the incidence angle given by its cosine.

    Parameters
    ----------
    thickness_nm : array_like, nm
        Film thicknesses ≥ 0.
    cos_incidence : array_like
        Cosine of the incidence angle, in (0, 1]; broadcasts with ``thickness_nm`` to S.
    wavelength_nm, n_film, n_substrate, n_ambient
        As :class:`FilmAtAngles`: the grid (nm, shape (W,)), the film's and substrate's ``n + i k`` on it, the ambient's n.
    amplitudes : bool
        Also return the complex ``r_s``, ``r_p``.

    Returns
    -------
    Reflectance
        ``R_s``, ``R_p`` (and the unpolarised ``R``) of shape S + (W,).
    """
    film = FilmAtAngles(cos_incidence, wavelength_nm, n_film, n_substrate, n_ambient)
    return film.reflectance(thickness_nm, amplitudes)


_FAR = 1e100
#: Sweeps smaller than this many spectral samples run on one thread.
_THREADED_MIN_SAMPLES = 200_000


def _workers(samples: int, blocks: int) -> int:
    if samples < _THREADED_MIN_SAMPLES or blocks < 2:
        return 1
    return max(1, min(blocks, os.cpu_count() or 1, 4))


def _pole_form(a: np.ndarray | complex, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Write ``|a + b E|^2`` as ``K |E - z|^2`` (``z = -a / b``, ``K = |b|^2``).

    Where ``|b|`` is negligible against ``|a|`` (or ``|b|^2`` underflows) the pole is put far away (``|z| = 1e100``) with
    ``K = |a|^2 / |z|^2``, which gives ``|a|^2`` to rounding for any ``|E| <= 1`` without
    dividing by zero.
    """
    a = np.broadcast_to(np.asarray(a, dtype=np.complex128), np.shape(b))
    abs2_a = a.real * a.real + a.imag * a.imag
    abs2_b = b.real * b.real + b.imag * b.imag
    # |b|^2 below the smallest normal double (both coefficients vanishing, e.g. a film and a
    # substrate of the ambient's index) would make 1 / |b|^2 overflow and z = 0 * inf = NaN.
    degenerate = (abs2_b <= abs2_a / (_FAR * _FAR)) | (abs2_b < np.finfo(np.float64).tiny)
    inv = np.divide(1.0, abs2_b, out=np.zeros_like(abs2_b), where=~degenerate)
    z = -(a * np.conj(b)) * inv  # -a / b
    z[degenerate] = _FAR
    K = np.where(degenerate, abs2_a / (_FAR * _FAR), abs2_b)
    return K, z


def film_reflectance_sweep(thickness_start_nm: float, thickness_step_nm: float, count: int, incidence_deg, wavelength_nm,
                           n_film, n_substrate, n_ambient: float = 1.0) -> Reflectance:
    """Reflectance over an evenly spaced thickness sweep ``start + step * j``, ``j < count``.

    It equals :func:`film_reflectance` on the same thicknesses to rounding, and is faster for
    sweeps (thickness tables, fitting searches, process windows, the benchmark grid):

    * the phase factor is split as ``E_(kB+i) = O_k I_i`` with ``B ~ sqrt(count)``; the inner
      factors ``I_i = E_step**i`` and the block factors ``O_k = E_start E_(B step)**k`` come
      from cumulative products (rounding grows as ``sqrt(count) * eps``), so only three rows
      need transcendental functions and each sample costs one complex multiplication;
    * then ``R = K |E - z_num|^2 / |E - z_den|^2`` per polarisation (see :class:`FilmAtAngles`);
    * blocks of B thicknesses keep the temporaries in cache, and a large sweep shares its blocks
      among threads, one per core (numpy releases the GIL; results are identical).

    Parameters
    ----------
    thickness_start_nm, thickness_step_nm : float, nm
        First thickness and spacing (the last, ``start + step (count − 1)``, must be ≥ 0).
    count : int
        Number of thicknesses, ≥ 1.
    incidence_deg : array_like, shape A, degrees
        Incidence angles in [0, 90).
    wavelength_nm, n_film, n_substrate, n_ambient
        As :class:`FilmAtAngles`: the grid (nm, shape (W,)), the film's and substrate's ``n + i k`` on it, the ambient's n.

    Returns
    -------
    Reflectance
        ``R_s``, ``R_p`` of shape (count,) + A + (W,).
    """
    check_film_geometry(np.zeros(1), np.asarray(incidence_deg, dtype=np.float64))
    film = FilmAtAngles(np.cos(np.radians(np.asarray(incidence_deg, dtype=np.float64))),
                        wavelength_nm, n_film, n_substrate, n_ambient)
    return film.sweep(thickness_start_nm, thickness_step_nm, count)


def _sweep(film: FilmAtAngles, thickness_start_nm: float, thickness_step_nm: float, count: int) -> Reflectance:
    count = int(count)
    if count < 1:
        raise SwatchError("a thickness sweep needs at least one thickness")
    start = float(thickness_start_nm)
    step = float(thickness_step_nm)
    check_film_geometry(np.array([start, start + step * (count - 1)]), np.zeros(1))
    rows = film.k4.shape

    B = max(1, int(np.ceil(np.sqrt(count))))
    nblocks = -(-count // B)
    # E_{kB+i} = E_start E_B**k E_step**i = O_k I_i with I_i = E_step**(i+1) and
    # O_k = E_start E_B**(k+1) / (E_B E_step), both by cumulative products.
    e_step, e_block = film.phase_factor(step), film.phase_factor(step * B)
    inner = np.cumprod(np.broadcast_to(e_step, (B, *rows)), axis=0)
    outer = np.cumprod(np.broadcast_to(e_block, (nblocks, *rows)), axis=0)
    outer *= film.phase_factor(start) / (e_block * e_step)

    R_s = np.empty((count, *rows))
    R_p = np.empty((count, *rows))

    def run_blocks(blocks: range) -> None:
        E = np.empty((B, *rows), dtype=np.complex128)
        work = (np.empty((B, *rows), dtype=np.complex128), np.empty((B, *rows)))
        for k in blocks:  # blocks of B thicknesses (not a per-sample loop)
            lo, hi = k * B, min(count, (k + 1) * B)
            n = hi - lo
            e = np.multiply(inner[:n], outer[k], out=E[:n])
            film.reflectance_from_phase(e, R_s[lo:hi], R_p[lo:hi], (work[0][:n], work[1][:n]))

    # numpy releases the GIL in ufuncs: large sweeps split their blocks over the cores.
    workers = _workers(count * int(np.prod(rows)), nblocks)
    if workers == 1:
        run_blocks(range(nblocks))
    else:
        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(run_blocks, [range(i, nblocks, workers) for i in range(workers)]))
    return Reflectance(R_s=R_s, R_p=R_p)


def film_reflectance(thickness_nm, incidence_deg, wavelength_nm, n_film, n_substrate, n_ambient: float = 1.0,
                     amplitudes: bool = False) -> Reflectance:
    """Airy reflectance (multiple reflections included) of ambient / film / substrate.

    Parameters
    ----------
    thickness_nm : array_like, nm
        Film thicknesses ≥ 0.
    incidence_deg : array_like, degrees
        Incidence angles from the surface normal, in [0, 90); broadcast with ``thickness_nm`` to S.
    wavelength_nm : array_like, shape (W,), nm
        The wavelength grid, positive nm.
    n_film, n_substrate : array_like, complex, shape (W,) or scalar
        Refractive indices ``n + i k`` (k ≥ 0) of the film and the substrate on the grid.
    n_ambient : float
        Real index of the ambient medium (1.0: air).
    amplitudes : bool
        Also return the complex ``r_s``, ``r_p``.

    Returns
    -------
    Reflectance
        ``R_s``, ``R_p`` (fractions; ``R`` their mean) of shape S + (W,).
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    theta = np.asarray(incidence_deg, dtype=np.float64)
    check_film_geometry(d, theta)
    return film_reflectance_cos(
        d, np.cos(np.radians(theta)), wavelength_nm, n_film, n_substrate, n_ambient, amplitudes
    )
