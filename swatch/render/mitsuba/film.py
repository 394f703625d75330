"""The Airy thin-film reflectance written in Dr.Jit arithmetic (for the Mitsuba plugin).

The same physics and conventions as :mod:`swatch.physics.optics` (air / film / substrate, complex indices
``n + i k`` with ``k ≥ 0``, ``q = n cos θ`` on the decaying branch, the Fresnel amplitudes of
:func:`swatch.physics.optics.fresnel_r`, the round-trip phase ``4 π d q₁ / λ``), evaluated on Dr.Jit
arrays so that one call covers every lane and the four wavelengths a spectral Mitsuba variant
samples per path: no Python loop. Complex numbers are carried as (real, imaginary) pairs of
arrays. ``tests/mitsuba/test_mitsuba_plugin.py`` checks it against :func:`swatch.physics.optics.film_reflectance`
(double precision) and ``tmm``.
"""
from __future__ import annotations

import math

import drjit as dr

__all__ = ["airy_reflectance"]


def _mul(a, b):
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]


def _add(a, b):
    return a[0] + b[0], a[1] + b[1]


def _sub(a, b):
    return a[0] - b[0], a[1] - b[1]


def _div(a, b):
    inv = dr.rcp(dr.maximum(b[0] * b[0] + b[1] * b[1], 1e-30))
    return (a[0] * b[0] + a[1] * b[1]) * inv, (a[1] * b[0] - a[0] * b[1]) * inv


def _abs2(a):
    return a[0] * a[0] + a[1] * a[1]


def _sqrt_decaying(re, im):
    """``sqrt(re + i im)`` for ``im ≥ 0``: the root with ``Im ≥ 0`` (and ``Re ≥ 0``), without the
    cancellation of ``sqrt((|z| ± re)/2)`` on the small component."""
    m = dr.sqrt(re * re + im * im)
    big = dr.sqrt(dr.maximum(0.5 * (m + dr.abs(re)), 0.0))
    small = im * dr.rcp(dr.maximum(2.0 * big, 1e-30))
    pos = re >= 0
    return dr.select(pos, big, small), dr.select(pos, small, big)


def airy_reflectance(cos_incidence, wavelength_nm, n_film, k_film, n_sub, k_sub, thickness_nm):
    """Unpolarised reflectance (mean of s and p) of air / film / substrate at the incidence cosine.

    Parameters
    ----------
    cos_incidence : drjit array
        Cosine of the incidence angle on the facet, clamped to [0, 1].
    wavelength_nm : drjit array
        Vacuum wavelengths in nm (a spectral variant's ``si.wavelengths``).
    n_film, k_film, n_sub, k_sub : drjit arrays
        Real and imaginary parts of the film's and the substrate's indices at those wavelengths.
    thickness_nm : drjit array or float
        Film thickness in nm (≥ 0).

    Returns
    -------
    drjit array
        ``R = (R_s + R_p) / 2`` (fraction), the broadcast shape of the inputs.
    """
    c0 = dr.clip(cos_incidence, 0.0, 1.0)
    kx2 = 1.0 - c0 * c0  # (n0 sin θ0)², n0 = 1
    eps1 = (n_film * n_film - k_film * k_film, 2.0 * n_film * k_film)  # N1²
    eps2 = (n_sub * n_sub - k_sub * k_sub, 2.0 * n_sub * k_sub)  # N2²
    q0 = (c0, 0.0 * c0)
    q1 = _sqrt_decaying(eps1[0] - kx2, eps1[1])
    q2 = _sqrt_decaying(eps2[0] - kx2, eps2[1])
    # round-trip phase factor E = exp(i 4π d q1 / λ)
    scale = (4.0 * math.pi) * thickness_nm * dr.rcp(wavelength_nm)
    sin_p, cos_p = dr.sincos(scale * q1[0])
    decay = dr.exp(-scale * q1[1])
    E = (decay * cos_p, decay * sin_p)
    one = (1.0 + 0.0 * c0, 0.0 * c0)
    r01s = _div(_sub(q0, q1), _add(q0, q1))
    r12s = _div(_sub(q1, q2), _add(q1, q2))
    a01, b01 = _mul(eps1, q0), q1  # (N1² q0 - 1 q1) / (N1² q0 + q1)
    r01p = _div(_sub(a01, b01), _add(a01, b01))
    a12, b12 = _mul(eps2, q1), _mul(eps1, q2)
    r12p = _div(_sub(a12, b12), _add(a12, b12))
    R = 0.0
    for r01, r12 in ((r01s, r12s), (r01p, r12p)):  # the two polarisations
        r12E = _mul(r12, E)
        num = _add(r01, r12E)
        den = _add(one, _mul(r01, r12E))
        R = R + 0.5 * _abs2(num) * dr.rcp(dr.maximum(_abs2(den), 1e-30))
    return R
