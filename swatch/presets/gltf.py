"""glTF 2.0 ``KHR_materials_iridescence`` on a metal base: the extension's Fresnel, in numpy.

Port of the reference implementation in the ratified extension README,
KhronosGroup/glTF ``extensions/2.0/Khronos/KHR_materials_iridescence/README.md`` at commit
acfcbe65e40c53d6d3aa55a7299982bf2c01c75d, section "Iridescence Fresnel" (``iridescent_fresnel``
with ``IorToFresnel0``, ``Fresnel0ToIor``, ``F_Schlick``, ``evalSensitivity``). For a metal
(``metallicFactor`` 1) the README's ``iridescent_conductor_layer`` uses ``base_f0 = baseColor``
and ``outside_ior = 1``; with ``iridescenceFactor`` 1 the specular Fresnel is this function.

The model, as specified (these are its approximations, not ours):

- the metal is a *real* index derived from F0 (``Fresnel0ToIor(baseF0 + 0.0001)``, no extinction),
  so the film/metal reflection phase is 0 or π instead of the metal's true phase;
- both interfaces use Schlick's approximation, without polarisation;
- the series stops after the second order and integrates against Gaussian fits of the CMFs
  (:func:`swatch.presets.spectral.gltf_sensitivity`), one film IOR for all wavelengths.

Three.js (``MeshPhysicalMaterial``) implements the same function, clamping ``baseF0`` to 0.9999
instead of adding 1e-4 and blending the film IOR to 1 below 0.03 nm of film.
"""
from __future__ import annotations

import numpy as np

from swatch.presets.spectral import gltf_sensitivity

__all__ = ["iridescent_fresnel", "iridescence_series"]


def _schlick(f0, cos_theta):
    return f0 + (1.0 - f0) * (1.0 - cos_theta) ** 5


def _ior_to_f0(transmitted, incident):
    return ((transmitted - incident) / (transmitted + incident)) ** 2


def iridescence_series(cos_theta, thickness_nm, film_ior, base_ior, schlick, outside_ior: float = 1.0) -> np.ndarray:
    """The extension's Airy series (two orders, Gaussian CMF fits) over a metal of real ``base_ior``:
    (..., 3) linear Rec.709. One definition for the extension (:func:`iridescent_fresnel`) and
    three.js (:func:`swatch.presets.threejs.iridescence_fresnel`), which differ only in how they
    derive ``base_ior`` and ``film_ior`` and in their Schlick form.

    Parameters
    ----------
    cos_theta : array
        Cosine of the incidence angle on the film (``VdotH`` in the extension, N·V in three.js).
    thickness_nm, film_ior : array
        Film thickness (nm) and the film's real index; broadcast with ``cos_theta``.
    base_ior : array (..., 3)
        The metal's real index per channel (derived from its F0).
    schlick : callable
        ``schlick(f0, cos) -> F``, the Schlick form in use.
    outside_ior : float
        Index of the ambient (1: air).
    """
    cos1 = np.asarray(cos_theta, dtype=np.float64)
    d = np.asarray(thickness_nm, dtype=np.float64)
    eta2 = np.asarray(film_ior, dtype=np.float64)
    cos1, d, eta2 = np.broadcast_arrays(cos1, d, eta2)
    sin2_sq = (outside_ior / eta2) ** 2 * (1.0 - cos1 ** 2)
    cos2_sq = 1.0 - sin2_sq
    tir = cos2_sq < 0.0
    cos2 = np.sqrt(np.maximum(cos2_sq, 0.0))
    # first interface
    R12 = schlick(_ior_to_f0(eta2, outside_ior), cos1)[..., None]
    T121 = 1.0 - R12
    phi12 = np.where(eta2 < outside_ior, np.pi, 0.0)
    phi21 = np.pi - phi12
    # second interface
    R23 = schlick(_ior_to_f0(base_ior, eta2[..., None]), cos2[..., None])
    phi23 = np.where(base_ior < eta2[..., None], np.pi, 0.0)
    # phase shift
    opd = 2.0 * eta2 * d * cos2
    phi = phi21[..., None] + phi23
    # compound terms and the series (m = 0, 1, 2)
    R123 = np.clip(R12 * R23, 1e-5, 0.9999)
    r123 = np.sqrt(R123)
    Rs = T121 ** 2 * R23 / (1.0 - R123)
    out = R12 + Rs
    Cm = Rs - T121
    for m in (1, 2):  # the two series terms of the specification, not a per-sample loop
        Cm = Cm * r123
        out = out + Cm * 2.0 * gltf_sensitivity(m * opd, m * phi)
    out = np.maximum(out, 0.0)
    return np.where(tir[..., None], 1.0, out)


def iridescent_fresnel(cos_theta, thickness_nm, film_ior, base_f0, outside_ior: float = 1.0) -> np.ndarray:
    """Fresnel factor (..., 3), linear Rec.709, of the iridescent metal.

    Parameters
    ----------
    cos_theta : array
        Cosine of the angle between view and half vector (``VdotH``).
    thickness_nm, film_ior : array
        ``iridescenceThicknessMaximum`` (nm) and ``iridescenceIor``; broadcast with ``cos_theta``.
    base_f0 : array (..., 3)
        ``baseColorFactor`` RGB (linear), the metal's F0.
    """
    sqrt_f0 = np.sqrt(np.asarray(base_f0, dtype=np.float64) + 0.0001)  # Fresnel0ToIor(baseF0 + 0.0001)
    base_ior = (1.0 + sqrt_f0) / (1.0 - sqrt_f0)
    return iridescence_series(cos_theta, thickness_nm, film_ior, base_ior, _schlick, outside_ior)
