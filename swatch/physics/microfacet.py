"""Microfacet distributions and shadowing–masking: the wavelength-independent part of the BRDF.

The microfacet thin-film BRDF (the paper's "future work") is
``f(l, v, λ) = D(h) G(l, v) F(λ; d, θ_d) / (4 cos θ_l cos θ_v)``, with ``h = (l + v)/|l + v|`` the half vector,
``θ_d`` the incidence angle on the facet (``cos θ_d = h·l``) and ``F`` the Airy thin-film reflectance of
:mod:`swatch.physics.optics`. ``D`` and ``G`` are scalars (no wavelength): this module computes them and the BRDF
scale ``D G / (4 cos θ_l cos θ_v)``.

Conventions
-----------
* All functions take cosines (and plain arrays), are vectorised by broadcasting and never loop.
* ``roughness_alpha`` is the usual roughness parameter ``α`` (GGX/Trowbridge–Reitz ``α``, Beckmann RMS slope
  ``m = α``), in (0, 1]; ``alpha`` alone is never the roughness in swatch (the CLI option and metadata key: ``roughness``).
* ``D`` is normalised so that ``∫ D(h) (n·h) dω_h = 1`` over the hemisphere (Walter et al. 2007 [1]_).
* Shadowing–masking is Smith's, with the exact Λ of each distribution (Heitz 2014 [2]_):

  - GGX:      ``Λ(θ) = (−1 + sqrt(1 + α² tan²θ)) / 2``;
  - Beckmann: ``Λ(θ) = (erf(a) − 1)/2 + exp(−a²) / (2 a sqrt(π))``, ``a = 1/(α tan θ)``.

  ``G1 = χ⁺(h·v)/(1 + Λ(v))``. The joint term ``G`` is **height-correlated** by default,
  ``G = χ⁺(h·l) χ⁺(h·v) / (1 + Λ(l) + Λ(v))`` (Heitz 2014, eq. 99: the more accurate form; it is never below the
  separable product, which counts the correlated shadowing twice), or **separable** ``G = G1(l) G1(v)`` with
  ``correlated=False``. Both conserve energy: with ``F = 1`` the directional albedo ``∫ f cos θ_l dω_l`` is ≤ 1 at
  every view angle (the furnace test in tests/physics/test_microfacet.py).

References
----------
.. [1] :cite:`Walter2007`.
.. [2] :cite:`Heitz2014`.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.special import erf

from swatch.core.choices import DISTRIBUTIONS
from swatch.core.errors import SwatchError
from swatch.core.limits import MIN_ROUGHNESS_ALPHA

__all__ = ["DISTRIBUTIONS", "NormalDistribution", "check_roughness_alpha", "check_distribution", "D", "D_ggx",
           "D_beckmann", "smith_lambda", "G1", "G", "brdf_scale", "ggx_visibility", "D_ratio", "ggx_reflectance_factor_cos",
           "D_ggx_aniso", "smith_lambda_ggx_aniso", "sample_vndf_ggx"]

_TINY = 1e-12


def check_roughness_alpha(roughness_alpha) -> float:
    """The roughness ``α`` as a float.

    Parameters
    ----------
    roughness_alpha : float-like
        The value to check.

    Returns
    -------
    float
        ``α`` in (0, 1].

    Raises
    ------
    SwatchError
        When it is not a number or outside (0, 1].
    """
    try:
        a = float(roughness_alpha)
    except (TypeError, ValueError):
        raise SwatchError(f"roughness {roughness_alpha!r} is not a number; give a value in (0, 1]") from None
    if not np.isfinite(a) or a < MIN_ROUGHNESS_ALPHA or a > 1.0:
        raise SwatchError(f"roughness must be from {MIN_ROUGHNESS_ALPHA:g} to 1, got {str(roughness_alpha)[:40]!r}")
    return a


#: The distribution's key (``DISTRIBUTIONS.validate``: case and blanks ignored; SwatchError naming the choices).
check_distribution = DISTRIBUTIONS.validate


def _tan2(cos_theta):
    c2 = np.clip(np.asarray(cos_theta, dtype=np.float64) ** 2, _TINY, 1.0)  # float64: tan² near 0
    return (1.0 - c2) / c2, c2


# -- GGX: the two polynomials, written once -------------------------------------------------------
def _ggx_ndf_den(cos_h, a2_minus_1):
    """``(α² − 1) cos²θh + 1``: GGX's ``D = α² / (π den²)``. The scalar comes in the caller's precision."""
    return cos_h * cos_h * a2_minus_1 + 1


def _ggx_vis_den(cos_l, cos_v, a2, one_minus_a2):
    """``cos θ_l sqrt(cos²θ_v (1 − α²) + α²) + cos θ_v sqrt(cos²θ_l (1 − α²) + α²)``, which is
    ``2 cos θ_l cos θ_v (1 + Λ_l + Λ_v)``: GGX's height-correlated ``G / (4 cos θ_l cos θ_v) = 0.5 / den``."""
    return cos_l * np.sqrt(cos_v * cos_v * one_minus_a2 + a2) + cos_v * np.sqrt(cos_l * cos_l * one_minus_a2 + a2)


def D_ggx(cos_h, roughness_alpha) -> np.ndarray:
    """GGX / Trowbridge–Reitz: ``α² / (π ((α² − 1) cos²θh + 1)²)``; 0 where ``cos θh <= 0``.

    Parameters
    ----------
    cos_h : array_like
        ``cos θh = n·h``, any shape.
    roughness_alpha : float
        ``α`` in (0, 1].

    Returns
    -------
    numpy.ndarray, the shape of ``cos_h``
        ``D`` in sr⁻¹ (normalised: ``∫ D cos θh dω = 1``).
    """
    c = np.asarray(cos_h)
    a2 = float(roughness_alpha) ** 2
    den = _ggx_ndf_den(c, a2 - 1.0)
    return np.where(c > 0, a2 / (np.pi * den * den), 0.0)


def D_beckmann(cos_h, roughness_alpha) -> np.ndarray:
    """Beckmann: ``exp(−tan²θh / α²) / (π α² cos⁴θh)``; 0 where ``cos θh <= 0``.

    Parameters
    ----------
    cos_h : array_like
        ``cos θh = n·h``, any shape.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).

    Returns
    -------
    numpy.ndarray, the shape of ``cos_h``
        ``D`` in sr⁻¹ (normalised: ``∫ D cos θh dω = 1``).
    """
    c = np.asarray(cos_h)
    a2 = float(roughness_alpha) ** 2
    t2, c2 = _tan2(c)
    return np.where(c > 0, np.exp(-t2 / a2) / (np.pi * a2 * c2 * c2), 0.0)


def D(cos_h, roughness_alpha, distribution: str = "ggx") -> np.ndarray:
    """The normal distribution ``D(h)`` of the named distribution.

    Parameters
    ----------
    cos_h : array_like
        ``cos θh = n·h``, any shape.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution (Walter et al. 2007); checked by :func:`check_distribution`.

    Returns
    -------
    numpy.ndarray, the shape of ``cos_h``
        ``D`` in sr⁻¹.
    """
    return DISTRIBUTIONS[distribution].D(cos_h, roughness_alpha)


def smith_lambda(cos_theta, roughness_alpha, distribution: str = "ggx") -> np.ndarray:
    """Smith's ``Λ`` for a direction at polar angle θ, exact for each distribution (module doc).

    Parameters
    ----------
    cos_theta : array_like
        ``cos θ = n·ω``, any shape.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution whose exact ``Λ`` is used (Heitz 2014).

    Returns
    -------
    numpy.ndarray, the shape of ``cos_theta``
        ``Λ ≥ 0`` (dimensionless; 0 at normal incidence).
    """
    return DISTRIBUTIONS[distribution].smith_lambda(cos_theta, roughness_alpha)


def _smith_lambda_ggx(cos_theta, roughness_alpha) -> np.ndarray:
    """GGX's exact Smith ``Λ`` (:func:`smith_lambda`)."""
    a = float(roughness_alpha)
    return 0.5 * (np.sqrt(1.0 + a * a * _tan2(cos_theta)[0]) - 1.0)


def _smith_lambda_beckmann(cos_theta, roughness_alpha) -> np.ndarray:
    """Beckmann's Smith ``Λ`` (:func:`smith_lambda`), 0 where it underflows."""
    x = 1.0 / np.maximum(float(roughness_alpha) * np.sqrt(_tan2(cos_theta)[0]), _TINY)  # a = 1 / (α tan θ)
    # For large x (near-normal directions) Λ underflows to 0; compute it where it is finite.
    xs = np.minimum(x, 30.0)
    lam = 0.5 * (erf(xs) - 1.0) + np.exp(-xs * xs) / (2.0 * xs * np.sqrt(np.pi))
    return np.where(x >= 30.0, 0.0, np.maximum(lam, 0.0))


class NormalDistribution(NamedTuple):
    """A distribution's functions, behind its name in :data:`swatch.core.choices.DISTRIBUTIONS`.

    Attributes
    ----------
    D, smith_lambda : callable(cos, roughness_alpha) -> numpy.ndarray
        ``D(h)`` (sr⁻¹) of ``cos θh`` and Smith's exact ``Λ`` (dimensionless) of ``cos θ``.
    """

    D: Callable[..., np.ndarray]
    smith_lambda: Callable[..., np.ndarray]


DISTRIBUTIONS.implement("ggx", NormalDistribution(D_ggx, _smith_lambda_ggx))
DISTRIBUTIONS.implement("beckmann", NormalDistribution(D_beckmann, _smith_lambda_beckmann))


def G1(cos_theta, cos_h_omega, roughness_alpha, distribution: str = "ggx") -> np.ndarray:
    """Smith masking of one direction, ``χ⁺(h·ω) / (1 + Λ(ω))``.

    Parameters
    ----------
    cos_theta : array_like
        ``n·ω``.
    cos_h_omega : array_like
        ``h·ω``; broadcasts with ``cos_theta`` to a shape S.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution whose ``Λ`` is used.

    Returns
    -------
    numpy.ndarray, shape S
        ``G1`` in [0, 1].
    """
    lam = smith_lambda(cos_theta, roughness_alpha, distribution)
    ok = (np.asarray(cos_h_omega) > 0) & (np.asarray(cos_theta) > 0)
    return np.where(ok, 1.0 / (1.0 + lam), 0.0)


def G(cos_l, cos_v, cos_hl, cos_hv, roughness_alpha, distribution: str = "ggx", correlated: bool = True) -> np.ndarray:
    """Smith shadowing–masking of light and view.

    Parameters
    ----------
    cos_l, cos_v : array_like
        ``n·l`` and ``n·v``.
    cos_hl, cos_hv : array_like
        ``h·l`` and ``h·v`` (equal for the half vector); all four broadcast to a shape S.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution whose ``Λ`` is used.
    correlated : bool
        Height-correlated ``1 / (1 + Λl + Λv)`` (default; Heitz 2014, eq. 99) or the separable
        product ``G1(l) G1(v)``.

    Returns
    -------
    numpy.ndarray, shape S
        ``G`` in [0, 1]; 0 below either horizon.
    """
    if not correlated:
        return G1(cos_l, cos_hl, roughness_alpha, distribution) * G1(cos_v, cos_hv, roughness_alpha, distribution)
    lam_l = smith_lambda(cos_l, roughness_alpha, distribution)
    lam_v = smith_lambda(cos_v, roughness_alpha, distribution)
    ok = (np.asarray(cos_hl) > 0) & (np.asarray(cos_hv) > 0) & (np.asarray(cos_l) > 0) & (np.asarray(cos_v) > 0)
    return np.where(ok, 1.0 / (1.0 + lam_l + lam_v), 0.0)


def ggx_visibility(cos_l, cos_v, roughness_alpha) -> np.ndarray:
    """``G / (4 cos θl cos θv)`` for GGX with the height-correlated Smith G, in closed form.

    ``0.5 / (cos θl sqrt(cos²θv (1 − α²) + α²) + cos θv sqrt(cos²θl (1 − α²) + α²))``,
    algebraically equal to ``1 / ((1 + Λl + Λv) 4 cos θl cos θv)`` with fewer operations and
    no division by the cosines.

    Parameters
    ----------
    cos_l, cos_v : array_like
        ``n·l`` and ``n·v``, > 0 (the caller masks the rest); broadcast to a shape S.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).

    Returns
    -------
    numpy.ndarray, shape S, in the inputs' precision (at least float32)
        The visibility term, sr⁰ (dimensionless).
    """
    cl = np.asarray(cos_l)
    cv = np.asarray(cos_v)
    a2 = float(roughness_alpha) ** 2
    t = np.result_type(cl, cv, np.float32).type
    den = _ggx_vis_den(cl, cv, t(a2), t(1.0 - a2))
    return t(0.5) / np.maximum(den, t(1e-30))


def ggx_reflectance_factor_cos(cos_l, cos_v, cos_h, roughness_alpha) -> np.ndarray:
    """``π D G / (4 cos θl cos θv) · max(cos θl, 0)`` for GGX with height-correlated G (renders).

    The reflectance factor of an F = 1 surface times the irradiance cosine, in few operations and
    in the inputs' precision. Masking is left to the caller except ``cos θl <= 0 -> 0``: it
    assumes ``cos θv > 0`` (a visible surface), where ``cos θh > 0`` holds automatically.
    Equal to ``π · brdf_scale(...) · max(cos θl, 0)`` (tested).

    Parameters
    ----------
    cos_l, cos_v, cos_h : array_like
        ``n·l``, ``n·v`` and ``n·h``; broadcast to a shape S.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).

    Returns
    -------
    numpy.ndarray, shape S, in the inputs' precision (at least float32)
        Dimensionless (1 for a perfect white diffuser lit and seen along the normal).
    """
    cl = np.maximum(np.asarray(cos_l), 0)
    cv = np.asarray(cos_v)
    ch = np.asarray(cos_h)
    t = np.result_type(cl, cv, ch, np.float32).type
    a2 = t(float(roughness_alpha) ** 2)
    den = _ggx_ndf_den(ch, a2 - t(1.0))
    vis = _ggx_vis_den(cl, cv, a2, t(1.0) - a2)
    # π · a2/(π den²) · 0.5/vis · cl
    return (t(0.5) * a2) * cl / np.maximum(den * den * vis, t(1e-30))


def D_ratio(cos_h, roughness_alpha, distribution: str = "ggx") -> np.ndarray:
    """``D(h) / D(n)``: 1 on the mirror direction, falling off the specular lobe (both D peak at n).

    Parameters
    ----------
    cos_h : array_like
        ``n·h``, any shape.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution.

    Returns
    -------
    numpy.ndarray, the shape of ``cos_h``
        In [0, 1].
    """
    a = float(roughness_alpha)
    return D(cos_h, a, distribution) * (np.pi * a * a)


def brdf_scale(cos_l, cos_v, cos_h, cos_d, roughness_alpha, distribution: str = "ggx", correlated: bool = True) -> np.ndarray:
    """``D(h) G(l, v) / (4 cos θl cos θv)``: the BRDF with F = 1; 0 below the horizon.

    GGX with the height-correlated G goes through :func:`D_ggx` and :func:`ggx_visibility`
    (tests check it against the definition); float32 inputs stay float32.

    Parameters
    ----------
    cos_l, cos_v, cos_h : array_like
        ``n·l``, ``n·v`` and ``n·h``.
    cos_d : array_like
        ``h·l = h·v``; all four broadcast to a shape S.
    roughness_alpha : float
        ``α`` in (0, 1] (GGX α, Beckmann RMS slope).
    distribution : {"ggx", "beckmann"}
        The microfacet distribution of ``D`` and of Smith's ``Λ``.
    correlated : bool
        Height-correlated (default) or separable Smith G.

    Returns
    -------
    numpy.ndarray, shape S
        The BRDF scale in sr⁻¹.
    """
    roughness_alpha = check_roughness_alpha(roughness_alpha)
    distribution = check_distribution(distribution)
    cl = np.asarray(cos_l)
    cv = np.asarray(cos_v)
    if not np.issubdtype(cl.dtype, np.floating):
        cl = cl.astype(np.float64)
    if not np.issubdtype(cv.dtype, np.floating):
        cv = cv.astype(np.float64)
    if distribution == "ggx" and correlated:
        t = np.result_type(cl, cv, np.float32).type
        ch = np.asarray(cos_h)
        ok = (cl > 0) & (cv > 0) & (ch > 0)
        return np.where(ok, D_ggx(ch, roughness_alpha) * ggx_visibility(cl, cv, roughness_alpha), t(0.0))
    d = D(cos_h, roughness_alpha, distribution)
    g = G(cl, cv, cos_d, cos_d, roughness_alpha, distribution, correlated)
    ok = (cl > 0) & (cv > 0)
    return np.where(ok, d * g / (4.0 * np.maximum(cl, _TINY) * np.maximum(cv, _TINY)), 0.0)


# -- anisotropic GGX (brushed finishes) -----------------------------------------------------------
def D_ggx_aniso(h_local, alpha_u: float, alpha_v: float) -> np.ndarray:
    """Anisotropic GGX: ``1 / (π α_u α_v (h_x²/α_u² + h_y²/α_v² + h_z²)²)``; 0 where ``h_z <= 0``.

    Parameters
    ----------
    h_local : array_like, (..., 3)
        Unit half vectors in the tangent frame (x along the tangent, the brushing direction;
        y the bitangent; z the normal).
    alpha_u, alpha_v : float
        GGX α along x and along y, in (0, 1] (Heitz 2014, eq. 85; equal: :func:`D_ggx`).

    Returns
    -------
    numpy.ndarray, shape (...)
        ``D`` in sr⁻¹ (normalised: ``∫ D h_z dω = 1``).
    """
    h = np.asarray(h_local, dtype=np.float64)
    au, av = check_roughness_alpha(alpha_u), check_roughness_alpha(alpha_v)
    x, y, z = h[..., 0], h[..., 1], h[..., 2]
    den = x * x / (au * au) + y * y / (av * av) + z * z
    return np.where(z > 0, 1.0 / (np.pi * au * av * den * den), 0.0)


def smith_lambda_ggx_aniso(w_local, alpha_u: float, alpha_v: float) -> np.ndarray:
    """Smith's ``Λ`` of anisotropic GGX for directions in the tangent frame:
    ``(−1 + sqrt(1 + (α_u² ω_x² + α_v² ω_y²) / ω_z²)) / 2`` (Heitz 2014, eq. 86).

    Parameters
    ----------
    w_local : array_like, (..., 3)
        Unit directions in the tangent frame (z the normal; ``ω_z > 0``).
    alpha_u, alpha_v : float
        GGX α along the tangent and the bitangent, in (0, 1].

    Returns
    -------
    numpy.ndarray, shape (...)
        ``Λ ≥ 0``.
    """
    w = np.asarray(w_local, dtype=np.float64)
    au, av = float(alpha_u), float(alpha_v)
    z2 = np.maximum(w[..., 2] * w[..., 2], _TINY)
    return 0.5 * (np.sqrt(1.0 + (au * au * w[..., 0] ** 2 + av * av * w[..., 1] ** 2) / z2) - 1.0)


def sample_vndf_ggx(views, alpha_u: float, alpha_v: float, u1, u2):
    """GGX visible-normal samples, isotropic or anisotropic: the one sampler of the renderer's
    environment path (Heitz 2018, listing 1; pbrt-v4's ``TrowbridgeReitzDistribution::Sample_wm``).
    The view is stretched by ``(α_u, α_v, 1)``, a disk point is warped onto the visible hemisphere
    and the normal unstretched; ``l`` is the view mirrored about it.

    Parameters
    ----------
    views : array_like, shape (B, 3)
        Unit views in the tangent frame (z the normal, x along ``alpha_u``; ``ω_z > 0``).
    alpha_u, alpha_v : float
        GGX α along x and y (equal: isotropic).
    u1, u2 : array_like, shape (N,)
        Points in [0, 1)² (radius² and angle on the disk).

    Returns
    -------
    l : numpy.ndarray, shape (B, N, 3)
        Light directions (tangent frame).
    weight : numpy.ndarray, shape (B, N)
        ``f cos θ_l / pdf / F = G2 / G1(v)`` (height-correlated Smith), 0 below the horizon.
    cos_d : numpy.ndarray, shape (B, N)
        ``v·h`` in [0, 1].
    pdf : numpy.ndarray, shape (B, N)
        The density of ``l``, ``G1(v) D(h) / (4 cos θ_v)``, sr⁻¹.

    References
    ----------
    :cite:`Heitz2018`; :cite:`Pharr2023`, §9.6.4.
    """
    V = np.asarray(views, dtype=np.float64)
    au, av = float(alpha_u), float(alpha_v)
    vh = np.stack([au * V[:, 0], av * V[:, 1], V[:, 2]], -1)
    vh /= np.linalg.norm(vh, axis=-1, keepdims=True)
    lensq = vh[:, 0] ** 2 + vh[:, 1] ** 2
    inv = 1.0 / np.sqrt(np.where(lensq > 0, lensq, 1.0))
    t1 = np.where((lensq > 0)[:, None], np.stack([-vh[:, 1] * inv, vh[:, 0] * inv, 0 * inv], -1), np.array([1.0, 0.0, 0.0]))
    t2 = np.cross(vh, t1)
    r = np.sqrt(np.asarray(u1, dtype=np.float64))[None, :]
    ph = 2.0 * np.pi * np.asarray(u2, dtype=np.float64)[None, :]
    p1, p2 = r * np.cos(ph), r * np.sin(ph)
    s = 0.5 * (1.0 + vh[:, 2:3])
    p2 = (1.0 - s) * np.sqrt(np.maximum(1.0 - p1 * p1, 0.0)) + s * p2
    pz = np.sqrt(np.maximum(1.0 - p1 * p1 - p2 * p2, 0.0))
    nh = p1[..., None] * t1[:, None, :] + p2[..., None] * t2[:, None, :] + pz[..., None] * vh[:, None, :]
    h = np.stack([au * nh[..., 0], av * nh[..., 1], np.maximum(nh[..., 2], 0.0)], -1)
    h /= np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
    vdh = np.clip(np.einsum("bnk,bk->bn", h, V), 0.0, 1.0)
    l = 2.0 * vdh[..., None] * h - V[:, None, :]
    lam_v = smith_lambda_ggx_aniso(V, au, av)[:, None]
    lam_l = smith_lambda_ggx_aniso(np.where(l[..., 2:3] > 0, l, np.array([0.0, 0.0, 1.0])), au, av)
    w = np.where(l[..., 2] > 0, (1.0 + lam_v) / (1.0 + lam_v + lam_l), 0.0)
    pdf = D_ggx_aniso(h, au, av) / ((1.0 + lam_v) * 4.0 * np.maximum(V[:, 2:3], 1e-6))
    return l, w, vdh, pdf
