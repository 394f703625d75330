"""Anisotropic (brushed) finishes in the presets' renderers: each format's own parametrisation of
GGX ``α`` along and across the grain, solved for a finish's ``alpha_u`` (along) and ``alpha_v``
(across) (:mod:`swatch.physics.finishes`). The brushing direction is the mesh's tangent in every format.

* **glTF** ``KHR_materials_anisotropy``: ``α_b = roughness²`` across the anisotropy direction and
  ``α_t = mix(roughness², 1, strength²)`` along it (the extension's specification and Khronos'
  sample renderer); the anisotropy direction is the tangent rotated by ``anisotropyRotation``,
  here π/2 (across the grain, where the roughness is larger).
* **Blender** (Cycles' Principled BSDF, ``svm_closure.h``): ``α_x = r²/aspect`` along the
  tangent rotated by ``Anisotropic Rotation`` (in turns), ``α_y = r² · aspect``,
  ``aspect = sqrt(1 − 0.9 · Anisotropic)``; rotation 0.25 (across the grain). Cycles takes the
  tangent from the shader's Tangent input (radial about the object's Z when unconnected).
* **OpenPBR** (MaterialX ``open_pbr_surface``): ``α_t = r² sqrt(2 / (1 + (1 − a)²))`` along the
  geometry tangent, ``α_b = (1 − a) α_t`` (the OpenPBR specification); the preset feeds the
  mesh's bitangent as ``geometry_tangent`` (the larger roughness across the grain).

These follow the formats' documents; no renderer was run on them here.
"""
from __future__ import annotations

import math

__all__ = ["gltf_anisotropy", "blender_anisotropy", "openpbr_anisotropy"]


def gltf_anisotropy(alpha_u: float, alpha_v: float) -> tuple[float, dict]:
    """(roughnessFactor, the ``KHR_materials_anisotropy`` object) for α along / across the grain.

    Parameters
    ----------
    alpha_u, alpha_v : float
        GGX α along and across the grain (0 < alpha_u ≤ alpha_v < 1).

    Returns
    -------
    roughness_factor : float
        The material's ``roughnessFactor``.
    extension : dict
        ``{"anisotropyStrength", "anisotropyRotation"}`` (rotation π/2, radians).

    Examples
    --------
    >>> r, ext = gltf_anisotropy(0.1, 0.1)
    >>> round(r, 6), ext["anisotropyStrength"]
    (0.316228, 0.0)
    """
    strength = math.sqrt(max(alpha_v - alpha_u, 0.0) / (1.0 - alpha_u))
    return math.sqrt(alpha_u), {"anisotropyStrength": round(strength, 6), "anisotropyRotation": round(math.pi / 2, 6)}


def blender_anisotropy(alpha_u: float, alpha_v: float) -> tuple[float, dict]:
    """(Roughness, {"Anisotropic", "Anisotropic Rotation"}) of Cycles' Principled BSDF.

    Parameters
    ----------
    alpha_u, alpha_v : float
        GGX α along and across the grain.

    Returns
    -------
    roughness : float
        ``Roughness`` (α = r² on average).
    inputs : dict
        ``{"Anisotropic", "Anisotropic Rotation"}`` (rotation 0.25 turns).
    """
    rough = (alpha_u * alpha_v) ** 0.25
    aniso = (1.0 - alpha_u / alpha_v) / 0.9
    return rough, {"Anisotropic": round(min(aniso, 1.0), 6), "Anisotropic Rotation": 0.25}


def openpbr_anisotropy(alpha_u: float, alpha_v: float) -> tuple[float, dict]:
    """(specular_roughness, {"specular_roughness_anisotropy"}) of OpenPBR, the tangent across the grain.

    Parameters
    ----------
    alpha_u, alpha_v : float
        GGX α along and across the grain.

    Returns
    -------
    specular_roughness : float
        OpenPBR ``specular_roughness`` (0–1), from which OpenPBR's anisotropy mapping gives back ``alpha_u``, ``alpha_v``.
    inputs : dict
        ``{"specular_roughness_anisotropy"}``.
    """
    a = 1.0 - alpha_u / alpha_v
    rough = math.sqrt(alpha_v / math.sqrt(2.0 / (1.0 + (1.0 - a) ** 2)))
    return rough, {"specular_roughness_anisotropy": round(a, 6)}
