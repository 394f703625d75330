"""Blender Cycles: the Principled BSDF's thin film on a metallic base, in numpy.

Port of Cycles' thin-film Fresnel (blender/blender, 2025 sources as stored for this work):

- ``intern/cycles/kernel/closure/bsdf_util.h``: ``fresnel_dielectric_polarized`` (amplitudes
  and the sign of the reflection phase), ``fresnel_conductor_polarized`` (Born & Wolf 14.4.1
  with ``n + ik``; reflectance from the F82 model when an F82 value is passed, phasors from n, k),
  ``fresnel_f82``/``fresnel_f82_B``/``fresnel_f82tint_B``, ``iridescence_airy_summation``
  (Belcour & Barla eq. 10, truncated after m = 3) and ``fresnel_iridescence`` (film IOR blended
  to the ambient below 1 nm, OPD = 2·η·d·cos θ₂, s and p averaged, saturated);
- ``intern/cycles/kernel/closure/bsdf_microfacet.h`` (blender/blender
  571102576548c2188007c984a9359f33facf3104), ``microfacet_fresnel``, case ``F82_TINT`` with a
  thin film: the metal's n and k are estimated from F0 = Base Color and the F82 reflectance
  (Specular Tint × Schlick at cos = 1/7) as Gulbrandsen's r and g, and the F82 value is passed on;
- ``intern/cycles/kernel/svm/closure.h``: the Principled metallic component sets
  ``f0 = clamp(base_color)``, ``f82 = min(specular_tint, 1)`` and the Thin Film Thickness / IOR;
- the sensitivity table: :func:`swatch.presets.spectral.cmf_sensitivity`.

Colours are linear Rec.709 (Blender's default scene-linear space).
"""
from __future__ import annotations

import numpy as np

from swatch.presets.spectral import cmf_sensitivity

__all__ = ["principled_metal_fresnel", "airy_summation", "dielectric_polarized", "conductor_polarized",
           "gulbrandsen_nk", "f82", "f82_B", "f82tint_B", "sensitivities"]

_COS_82 = 1.0 / 7.0


def f82_B(F0, F82):
    """``fresnel_f82_B``: the B factor giving reflectance F82 at cos = 1/7.

    Parameters
    ----------
    F0, F82 : array_like
        Reflectance at normal incidence and at cos θ = 1/7 (per channel).

    Returns
    -------
    numpy.ndarray
        B, broadcast shape.
    """
    f = 6.0 / 7.0
    f5 = f ** 5
    schlick = F0 + (1.0 - F0) * f5
    return (7.0 / (f5 * f)) * (schlick - F82)


def f82tint_B(F0, tint):
    """``fresnel_f82tint_B``: the B factor for a tint of the Schlick value at cos = 1/7.

    Parameters
    ----------
    F0 : array_like
        Reflectance at normal incidence (per channel).
    tint : array_like
        The F82 tint (Specular Tint), 1 = Schlick.

    Returns
    -------
    numpy.ndarray
        B, broadcast shape.
    """
    f = 6.0 / 7.0
    f5 = f ** 5
    schlick = F0 + (1.0 - F0) * f5
    return schlick * (7.0 / (f5 * f)) * (1.0 - tint)


def f82(cos_i, F0, B):
    """``fresnel_f82``: Schlick minus B·cos·(1-cos)^6, clamped to [0, 1].

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle.
    F0, B : array_like
        Normal-incidence reflectance and the F82 factor (:func:`f82_B`), broadcast with ``cos_i``.

    Returns
    -------
    numpy.ndarray
        Reflectance in [0, 1].
    """
    s = np.clip(1.0 - cos_i, 0.0, 1.0)
    s5 = s ** 5
    return np.clip(F0 + (1.0 - F0) * s5 - B * cos_i * s5 * s, 0.0, 1.0)


def gulbrandsen_nk(r, g):
    """n, k of a metal from reflectance r at normal incidence and edge value g (Gulbrandsen 2014).

    Parameters
    ----------
    r : array_like
        Reflectance at normal incidence (clamped to 0.999).
    g : array_like
        The edge tint in [0, 1].

    Returns
    -------
    n, k : numpy.ndarray
        Real and imaginary index, broadcast shape.

    References
    ----------
    :cite:`Gulbrandsen2014`.
    """
    r = np.minimum(r, 0.999)
    sqrt_r = np.sqrt(r)
    n_min = (1.0 - r) / (1.0 + r)
    n_max = (1.0 + sqrt_r) / (1.0 - sqrt_r)
    n = n_max + g * (n_min - n_max)
    k = np.sqrt(np.maximum((r * (n + 1.0) ** 2 - (n - 1.0) ** 2) / (1.0 - r), 0.0))
    return n, k


def dielectric_polarized(cos_i, eta):
    """(R_s, R_p, sign_s, sign_p, cos_t) at a dielectric interface of relative IOR ``eta``.

    ``cos_t`` is returned positive (Cycles returns it negative, relative to the normal); the signs
    are those of Cycles' amplitudes r_s = (cos_i − η cos_t)/(cos_i + η cos_t),
    r_p = (η cos_i − cos_t)/(η cos_i + cos_t). Total internal reflection gives R = 1, sign +1.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle.
    eta : array_like
        Relative IOR (transmitted over incident), broadcast with ``cos_i``.

    Returns
    -------
    R_s, R_p, sign_s, sign_p, cos_t : numpy.ndarray
        Reflectances, amplitude signs (±1) and the transmitted cosine.
    """
    eta_cos_t_sq = eta ** 2 - (1.0 - cos_i ** 2)
    tir = eta_cos_t_sq <= 0.0
    cos_t = np.sqrt(np.maximum(eta_cos_t_sq, 0.0)) / eta
    r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    one = np.ones_like(r_s)
    return (np.where(tir, 1.0, r_s ** 2), np.where(tir, 1.0, r_p ** 2),
            np.where(tir, 1.0, np.where(r_s >= 0.0, 1.0, -1.0)), np.where(tir, one, np.where(r_p >= 0.0, 1.0, -1.0)),
            cos_t)


def conductor_polarized(cos_i, ambient_ior, n, k, F82=None):
    """(R_s, R_p, phasor_s, phasor_p) at an ambient/conductor interface (``fresnel_conductor_polarized``).

    The complex amplitudes r_s = (η₁cos − w)/(η₁cos + w), r_p = (ñ²cos − η₁w)/(ñ²cos + η₁w) with
    ñ = n + ik and w = ñ cos θ_t = u + iv are the formulas Cycles evaluates in real arithmetic;
    the phasors are r/|r|. With ``F82`` the reflectances come from the F82 model with F0 of the
    metal relative to the ambient (film) index, as Cycles does.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle in the ambient (the film).
    ambient_ior : array_like
        The ambient's real index.
    n, k : array_like
        The metal's complex index ``n + ik``, per channel.
    F82 : array_like, optional
        The F82 reflectance: the reflectances then come from the F82 model.

    Returns
    -------
    R_s, R_p : numpy.ndarray
        Reflectances.
    phasor_s, phasor_p : numpy.ndarray
        Unit complex phases of the amplitudes.
    """
    nc = n + 1j * k
    eta1 = ambient_ior
    w = np.sqrt(nc ** 2 - (eta1 ** 2) * (1.0 - cos_i ** 2) + 0j)
    a = eta1 * cos_i
    r_s = (a - w) / (a + w)
    A = nc ** 2 * cos_i
    r_p = (A - eta1 * w) / (A + eta1 * w)

    def phasor(r):
        mag = np.abs(r)
        return np.where(mag == 0.0, 1.0 + 0j, r / np.where(mag == 0.0, 1.0, mag))

    if F82 is not None:
        nn = n / eta1
        kk = (k / eta1) ** 2
        F0 = ((nn - 1.0) ** 2 + kk) / ((nn + 1.0) ** 2 + kk)
        R = f82(cos_i, F0, f82_B(F0, F82))
        return R, R, phasor(r_s), phasor(r_p)
    return np.abs(r_s) ** 2, np.abs(r_p) ** 2, phasor(r_s), phasor(r_p)


def sensitivities(opd_nm, sensitivity=cmf_sensitivity, orders: int = 3) -> list:
    """The sensitivity at m·OPD for m = 1..orders (shared by the s and p sums).

    Parameters
    ----------
    opd_nm : array_like
        Optical path difference, nm.
    sensitivity : callable, optional
        OPD (nm) -> complex (..., 3) (:func:`swatch.presets.spectral.cmf_sensitivity`).
    orders : int, optional
        The series' orders.

    Returns
    -------
    list of numpy.ndarray
        One complex (..., 3) array per order.
    """
    return [sensitivity(m * opd_nm) for m in range(1, orders + 1)]


def airy_summation(R12, R23, S, phasor):
    """``iridescence_airy_summation``: Belcour & Barla eq. 10, (..., 3); ``S`` from :func:`sensitivities`.

    Parameters
    ----------
    R12, R23 : array_like
        Reflectances at the ambient/film and film/base interfaces (..., 1 or 3).
    S : list of numpy.ndarray
        :func:`sensitivities`.
    phasor : numpy.ndarray
        The round trip's unit phase (both interfaces' phases), complex (..., 3).

    Returns
    -------
    numpy.ndarray
        The spectrally integrated reflectance, linear Rec.709 (..., 3).

    References
    ----------
    :cite:`Belcour2017`.
    """
    T121 = 1.0 - R12
    R123 = R12 * R23
    r123 = np.sqrt(R123)
    Rs = T121 ** 2 * R23 / (1.0 - R123)
    out = Rs + R12
    Cm = Rs - T121
    acc = phasor
    for Sm in S:  # the series' orders (m = 1, 2, ...), not a per-sample loop
        Cm = Cm * r123
        out = out + Cm * 2.0 * (acc.real * Sm.real + acc.imag * Sm.imag)
        acc = acc * phasor
    return out


def principled_metal_fresnel(cos_theta, thickness_nm, film_ior, base_color, specular_tint=1.0) -> np.ndarray:
    """Fresnel (..., 3) of a Principled BSDF with Metallic 1 and Thin Film Thickness/IOR set.

    Parameters
    ----------
    cos_theta : array
        Cosine of the incidence angle on the microfacet.
    thickness_nm, film_ior : array
        Thin Film Thickness (nm) and Thin Film IOR; broadcast with ``cos_theta``.
    base_color : array (..., 3)
        Base Color (linear Rec.709), the metal's F0.
    specular_tint : array (..., 3) or float
        Specular Tint (the F82 tint), default white.
    """
    cos1 = np.asarray(cos_theta, dtype=np.float64)
    d = np.asarray(thickness_nm, dtype=np.float64)
    eta = np.asarray(film_ior, dtype=np.float64)
    cos1, d, eta = np.broadcast_arrays(cos1, d, eta)
    F0 = np.clip(np.asarray(base_color, dtype=np.float64), 0.0, 1.0)
    tint = np.minimum(np.asarray(specular_tint, dtype=np.float64), 1.0)
    B = f82tint_B(F0, tint)
    # microfacet_fresnel, F82_TINT with a thin film: n, k from F0 and the F82 reflectance
    g = f82(_COS_82, F0, B)
    n, k = gulbrandsen_nk(np.minimum(F0, 0.999), g)
    # fresnel_iridescence (ambient IOR 1)
    eta = np.where(d < 1.0, 1.0 + (eta - 1.0) * _smoothstep(d), eta)
    R12_s, R12_p, sgn_s, sgn_p, cos2 = dielectric_polarized(cos1, eta)
    top_tir = (R12_s == 1.0) & (R12_p == 1.0)
    e = eta[..., None]
    c2 = cos2[..., None]
    R23_s, R23_p, ph_s, ph_p = conductor_polarized(c2, e, n, k, F82=g)
    opd = (2.0 * eta * d * cos2)[..., None]
    ph_s = ph_s * -sgn_s[..., None]
    ph_p = ph_p * -sgn_p[..., None]
    S = sensitivities(opd[..., 0])
    Rs = airy_summation(R12_s[..., None], R23_s, S, ph_s)
    Rp = airy_summation(R12_p[..., None], R23_p, S, ph_p)
    out = np.clip(0.5 * (Rs + Rp), 0.0, 1.0)
    return np.where(top_tir[..., None], 1.0, out)


def _smoothstep(x):
    t = np.clip(x, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def film_on_dielectric_fresnel(cos_theta, thickness_nm, film_ior, base_ior) -> np.ndarray:
    """``fresnel_iridescence<float>``: the same film on a dielectric of real IOR ``base_ior``, (..., 3).

    Cycles' dielectric branch (used by its Principled BSDF for non-metals); with real indices and
    no dispersion it is exact up to the series truncation and the table, so it is what the port
    is checked with against a transfer-matrix reference.

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the incidence angle on the facet.
    thickness_nm, film_ior : array_like
        Film thickness (nm) and IOR, broadcast with ``cos_theta``.
    base_ior : array_like
        The dielectric base's real IOR.

    Returns
    -------
    numpy.ndarray
        Fresnel factor, linear Rec.709 (..., 3) in [0, 1].
    """
    cos1 = np.asarray(cos_theta, dtype=np.float64)
    d = np.asarray(thickness_nm, dtype=np.float64)
    eta = np.asarray(film_ior, dtype=np.float64)
    cos1, d, eta = np.broadcast_arrays(cos1, d, eta)
    eta = np.where(d < 1.0, 1.0 + (eta - 1.0) * _smoothstep(d), eta)
    R12_s, R12_p, sgn12_s, sgn12_p, cos2 = dielectric_polarized(cos1, eta)
    R23_s, R23_p, sgn23_s, sgn23_p, _ = dielectric_polarized(cos2, np.asarray(base_ior, dtype=np.float64) / eta)
    opd = 2.0 * eta * d * cos2
    S = sensitivities(opd)
    Rs = airy_summation(R12_s[..., None], R23_s[..., None], S, (sgn23_s * -sgn12_s)[..., None] + 0j)
    Rp = airy_summation(R12_p[..., None], R23_p[..., None], S, (sgn23_p * -sgn12_p)[..., None] + 0j)
    return np.clip(0.5 * (Rs + Rp), 0.0, 1.0)
