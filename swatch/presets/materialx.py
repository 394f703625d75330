"""MaterialX 1.39.5: OpenPBR Surface's thin film on a metal as MaterialX's GLSL evaluates it, in numpy.

Port of the GLSL that MaterialX 1.39.5 (PyPI ``MaterialX``) generates for an ``open_pbr_surface``
with ``base_metalness`` 1, ``thin_film_weight`` 1 (``libraries/bxdf/open_pbr_surface.mtlx``: the
metal is a ``generalized_schlick_bsdf`` with color0 = base_color, color82 = specular_color,
color90 = 1, exponent 5, α = specular_roughness², thinfilm_thickness = thin_film_thickness × 1000
nm), ``libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl``:

- ``mx_fresnel_airy`` for the Schlick model: the metal becomes a *real* index
  ``mx_f0_to_ior(F0)`` (F0 clamped to 0.01–0.99) for the film/metal phase (0 or π), its
  reflectance is ``mx_fresnel_hoffman_schlick`` at the refracted angle, **halved** for each
  polarisation (``R23p = R23s = 0.5·f``), the air/film interface is the polarised dielectric
  Fresnel with a Brewster switch of the p phase, two orders (``AIRY_FRESNEL_ITERATIONS`` 2) of
  the Gaussian CMF fits in XYZ, and the result is converted with MaterialX's
  ``XYZ_TO_RGB`` — CIE 1931 RGB for illuminant E, not Rec.709 — and clamped to [0, 1];
- ``mx_generalized_schlick_bsdf`` under a light: ``D·F·G·comp/(4 N·V)`` with
  ``comp = 1 + F·(1 − Ess)/Ess`` and ``Ess`` from ``mx_ggx_dir_albedo_analytic`` (the rational
  fit, ``DIRECTIONAL_ALBEDO_METHOD`` 0, GenGlsl's default).

:func:`displayed_fresnel` is the colour relative to a white metal (F = 1, comp = 1/Ess) in the
same light: ``F·(Ess + F·(1 − Ess))``, F at the half vector, Ess at N·V. (Measured: equal to
MaterialX's own GLSL renderer to 7 digits; tests/presets/test_presets.py.)
Colours are the document's linear Rec.709.
"""
from __future__ import annotations

import numpy as np

from swatch.presets.spectral import gaussian_sensitivity_xyz

__all__ = ["VERSION", "XYZ_TO_CIE_RGB", "hoffman_schlick", "fresnel_airy", "ggx_dir_albedo", "displayed_fresnel"]

#: The MaterialX version ported (and rendered with in the tests).
VERSION = "1.39.5"
#: ``XYZ_TO_RGB`` of ``mx_fresnel_airy`` (GLSL ``mat3`` is column-major; rows here).
XYZ_TO_CIE_RGB = np.array([[2.3706743, -0.9000405, -0.4706338],
                           [-0.5138850, 1.4253036, 0.0885814],
                           [0.0052982, -0.0146949, 1.0093968]])
_ITERATIONS = 2


def hoffman_schlick(cos_theta, F0, F82, F90=1.0, exponent: float = 5.0):
    """``mx_fresnel_hoffman_schlick``: the F82 generalisation of Schlick (..., 3).

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the incidence angle (clipped to [0, 1]).
    F0, F82 : array_like
        Reflectance at normal incidence and the F82 tint (per channel).
    F90 : array_like, optional
        Reflectance at grazing incidence (per channel, 0–1; default 1).
    exponent : float, optional
        The Schlick exponent (default 5, as ``open_pbr_surface`` uses).

    Returns
    -------
    numpy.ndarray
        Reflectance, broadcast shape.
    """
    cmax = 1.0 / 7.0
    factor = 1.0 / (cmax * (1.0 - cmax) ** 6)
    x = np.clip(cos_theta, 0.0, 1.0)
    a = (F0 + (F90 - F0) * (1.0 - cmax) ** exponent) * (1.0 - F82) * factor
    return F0 + (F90 - F0) * (1.0 - x) ** exponent - a * x * (1.0 - x) ** 6


def _dielectric_polarized(cos_theta, ior):
    """``mx_fresnel_dielectric_polarized``: (Rp, Rs)."""
    c2 = np.clip(cos_theta, 0.0, 1.0) ** 2
    s2 = 1.0 - c2
    t0 = np.maximum(ior * ior - s2, 0.0)
    t1 = t0 + c2
    t2 = 2.0 * np.sqrt(t0) * np.sqrt(c2)
    Rs = (t1 - t2) / (t1 + t2)
    t3 = c2 * t0 + s2 * s2
    t4 = t2 * s2
    return Rs * (t3 - t4) / (t3 + t4), Rs


def fresnel_airy(cos_theta, thickness_nm, film_ior, F0, F82=1.0) -> np.ndarray:
    """``mx_fresnel_airy`` with the generalized-Schlick metal: (..., 3) in MaterialX's output RGB.

    Parameters
    ----------
    cos_theta : array
        Cosine of the angle on the microfacet (V·H).
    thickness_nm, film_ior : array
        ``thinfilm_thickness`` (nm) and ``thinfilm_ior``; broadcast with ``cos_theta``.
    F0, F82 : array (..., 3)
        ``color0`` (base_color) and ``color82`` (specular_color).
    """
    c = np.asarray(cos_theta, dtype=np.float64)
    d = np.asarray(thickness_nm, dtype=np.float64)
    eta = np.asarray(film_ior, dtype=np.float64)
    c, d, eta = np.broadcast_arrays(c, d, eta)
    F0 = np.maximum(np.asarray(F0, dtype=np.float64), 0.0)
    F82 = np.maximum(np.asarray(F82, dtype=np.float64), 0.0)
    eta2 = np.maximum(eta, 1.0)
    sqrt_f0 = np.sqrt(np.clip(F0, 0.01, 0.99))
    eta3 = (1.0 + sqrt_f0) / (1.0 - sqrt_f0)
    cos_t = np.sqrt(1.0 - (1.0 - c ** 2) / eta2 ** 2)
    R12p, R12s = _dielectric_polarized(c, eta2)
    T121p, T121s = 1.0 - R12p, 1.0 - R12s
    f = hoffman_schlick(cos_t[..., None], F0, F82)
    R23 = 0.5 * f  # both polarisations, as MaterialX 1.39.5 writes it
    cos_b = np.cos(np.arctan(eta2))
    phi21p = np.where(c < cos_b, 0.0, np.pi)
    phi23 = np.where(eta3 < eta2[..., None], np.pi, 0.0)
    opd_nm = 2.0 * eta2 * cos_t * d
    out = np.zeros(np.broadcast_shapes((*c.shape, 3), F0.shape))
    for R12, T121, phi21 in ((R12p, T121p, phi21p), (R12s, T121s, np.full_like(c, np.pi))):  # p, then s
        R12, T121 = R12[..., None], T121[..., None]
        r123 = np.maximum(np.sqrt(R12 * R23), 0.0)
        Rs = T121 ** 2 * R23 / (1.0 - R12 * R23)
        out = out + R12 + Rs
        Cm = Rs - T121
        for m in range(1, _ITERATIONS + 1):  # the series' orders, not a per-sample loop
            Cm = Cm * r123
            out = out + Cm * 2.0 * gaussian_sensitivity_xyz(m * opd_nm, m * (phi23 + phi21[..., None]))
    return np.clip((0.5 * out) @ XYZ_TO_CIE_RGB.T, 0.0, 1.0)


def ggx_dir_albedo(cos_nv, alpha):
    """``mx_ggx_dir_albedo_analytic(N·V, α, 1, 1)``: the white GGX lobe's directional albedo Ess.

    Parameters
    ----------
    cos_nv : array_like
        N·V.
    alpha : array_like
        GGX α, broadcast with ``cos_nv``.

    Returns
    -------
    numpy.ndarray
        Ess (the fit's two terms, each clipped to [0, 1], summed).
    """
    x = np.asarray(cos_nv, dtype=np.float64)
    y = np.asarray(alpha, dtype=np.float64)
    x, y = np.broadcast_arrays(x, y)
    x2, y2 = x * x, y * y
    terms = np.stack([np.ones_like(x), x, y, x * y, x2, y2, x2 * y, x * y2, x2 * y2], axis=-1)
    coeff = np.array([[0.1003, 0.9345, 1.0, 1.0], [-0.6303, -2.323, -1.765, 0.2281], [9.748, 2.229, 8.263, 15.94],
                      [-2.038, -3.748, 11.53, -55.83], [29.34, 1.424, 28.96, 13.08], [-8.245, -0.7684, -7.507, 41.26],
                      [-26.44, 1.436, -36.11, 54.9], [19.99, 0.2913, 15.86, 300.2], [-5.448, 0.6286, 33.37, -285.1]])
    r = terms @ coeff
    return np.clip(r[..., 0] / r[..., 2], 0.0, 1.0) + np.clip(r[..., 1] / r[..., 3], 0.0, 1.0)


def displayed_fresnel(cos_theta, thickness_nm, film_ior, base_color, roughness, specular_color=1.0,
                      cos_nv=None) -> np.ndarray:
    """What MaterialX's GLSL shows under a direct light relative to a white metal: (..., 3).

    ``cos_theta`` is V·H; ``cos_nv`` N·V (default V·H: mirror geometries; 1 at 45:0).
    ``roughness`` is ``specular_roughness`` (α = roughness², clamped as MaterialX does).

    Parameters
    ----------
    cos_theta : array_like
        V·H.
    thickness_nm, film_ior : array_like
        ``thin_film_thickness`` (nm) and ``thin_film_ior``.
    base_color : array_like, shape (..., 3)
        The F0 colour.
    roughness : float
        ``specular_roughness``.
    specular_color : array_like, optional
        ``specular_color``, the F82 tint (``color82``; per channel, 0–1; default 1, white).
    cos_nv : array_like, optional
        N·V.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Linear Rec.709, relative to a white metal.
    """
    F = fresnel_airy(cos_theta, thickness_nm, film_ior, base_color, specular_color)
    alpha = np.clip(np.asarray(roughness, dtype=np.float64) ** 2, 1e-6, 1.0)
    nv = cos_theta if cos_nv is None else cos_nv
    ess = ggx_dir_albedo(np.clip(nv, 1e-6, 1.0), alpha)[..., None]
    return F * (ess + F * (1.0 - ess))
