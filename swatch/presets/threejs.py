"""three.js r187: the iridescent metal as ``MeshPhysicalMaterial`` shows it under a direct light, in numpy.

Port of three.js 0.187.0 (npm ``three``, MIT; the copy in tests/vendor/three is the one the tests
render with), ``build/three.module.js`` shader chunks, as ``GLTFLoader`` maps a glTF material with
``KHR_materials_iridescence`` (``iridescence`` = factor, ``iridescenceIOR``, thickness = the
maximum when there is no thickness texture; ``metalness`` 1, ``color`` = baseColorFactor):

- ``iridescence_fragment``: ``evalIridescence(1, iridescenceIOR, cosTheta1, thickness, baseF0)`` —
  the extension's Airy series (two orders, Gaussian fits of the CMF transforms, the correct
  XYZ→Rec.709 matrix) with ``F_Schlick`` in three.js's spherical-Gaussian form
  ``exp2((−5.55473 c − 6.98316) c)``, ``baseF0`` clamped to 0.9999 before ``Fresnel0ToIor``, and the
  film IOR blended to 1 over the first 0.03 nm of film;
- ``lights_fragment_begin``: it is evaluated once per pixel at **N·V** (``dotNVi``), not at the
  half vector as the extension specifies; ``BRDF_GGX`` then uses it as F for every light;
- ``lights_fragment_begin`` / ``RE_Direct_Physical``: direct specular is multiplied by
  ``multiScatteringCompensation = 1 + specularColorBlended·(1/Ess − 1)`` (``specularColorBlended``
  = the base colour for a metal, not the iridescent F), ``Ess = dfg.x + dfg.y`` read from the
  16×16 DFG LUT at (roughness, N·V) with bilinear filtering (tables/renderers/threejs_dfg_lut.csv).

:func:`displayed_fresnel` is the colour a plate shows relative to a white metal plate (colour 1,
no iridescence: F = 1, compensation 1/Ess) under the same direct light: ``F_irid(N·V)·(Ess +
base·(1 − Ess))``. Colours are linear Rec.709.
"""
from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from swatch.presets.gltf import iridescence_series

__all__ = ["REVISION", "iridescence_fresnel", "dfg", "displayed_fresnel"]

#: The three.js revision ported (and vendored for the tests).
REVISION = "r187"
_LUT_PATH = Path(__file__).resolve().parent.parent / "tables" / "renderers" / "threejs_dfg_lut.csv"


def _f_schlick(f0, f90, cos_theta):
    fresnel = np.exp2((-5.55473 * cos_theta - 6.98316) * cos_theta)
    return f0 * (1.0 - fresnel) + f90 * fresnel


def _schlick_1(f0, cos_theta):
    return _f_schlick(f0, 1.0, cos_theta)


def _smoothstep(edge0: float, edge1: float, x):
    t = np.clip((x - edge0) / (edge1 - edge0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def iridescence_fresnel(cos_nv, thickness_nm, film_ior, base_f0) -> np.ndarray:
    """``evalIridescence(1.0, film_ior, cos_nv, thickness_nm, base_f0)``: (..., 3) linear Rec.709.

    Parameters
    ----------
    cos_nv : array
        N·V (three.js evaluates the film there, once per pixel).
    thickness_nm, film_ior : array
        Film thickness (nm) and ``iridescenceIOR``; broadcast with ``cos_nv``.
    base_f0 : array (..., 3)
        The metal's colour (``color``, linear).
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    f0 = np.clip(np.asarray(base_f0, dtype=np.float64), 0.0, 0.9999)
    ior = 1.0 + (np.asarray(film_ior, dtype=np.float64) - 1.0) * _smoothstep(0.0, 0.03, d)
    sqrt_f0 = np.sqrt(f0)
    base_ior = (1.0 + sqrt_f0) / (1.0 - sqrt_f0)
    return iridescence_series(cos_nv, d, ior, base_ior, _schlick_1)  # the extension's series, one definition


@functools.lru_cache(maxsize=1)
def _lut() -> np.ndarray:
    """The (16 N·V rows, 16 roughness columns, 2) DFG table."""
    rows = np.loadtxt(_LUT_PATH, delimiter=",", comments="#", skiprows=4)
    return rows[:, 1:].reshape(16, 16, 2)


def dfg(roughness, cos_nv) -> np.ndarray:
    """``texture2D(dfgLUT, vec2(roughness, N·V)).rg`` (..., 2): bilinear, clamped to the edges.

    Parameters
    ----------
    roughness : array_like
        glTF roughness.
    cos_nv : array_like
        N·V, broadcast with ``roughness``.

    Returns
    -------
    numpy.ndarray, shape (..., 2)
        The scale and bias of the split-sum DFG term.
    """
    lut = _lut()
    r = np.asarray(roughness, dtype=np.float64)
    c = np.asarray(cos_nv, dtype=np.float64)
    r, c = np.broadcast_arrays(r, c)

    def axis(t):
        x = np.clip(t * 16.0 - 0.5, 0.0, 15.0)
        i0 = np.minimum(np.floor(x).astype(np.int64), 14)
        return i0, (x - i0)[..., None]

    i, fx = axis(r)  # columns: roughness
    j, fy = axis(c)  # rows: N·V
    top = lut[j, i] * (1.0 - fx) + lut[j, i + 1] * fx
    bottom = lut[j + 1, i] * (1.0 - fx) + lut[j + 1, i + 1] * fx
    return top * (1.0 - fy) + bottom * fy


def displayed_fresnel(cos_nv, thickness_nm, film_ior, base_f0, roughness) -> np.ndarray:
    """What three.js shows under a direct light relative to a white metal plate: (..., 3).

    ``F_irid(N·V) · (1 + base·(1/Ess − 1)) · Ess`` with ``Ess`` from the DFG LUT at
    (``max(roughness, 0.045)``, N·V); ``roughness`` is the glTF ``roughnessFactor``.

    Parameters
    ----------
    cos_nv : array_like
        N·V.
    thickness_nm, film_ior : array_like
        Film thickness (nm) and ``iridescenceIOR``.
    base_f0 : array_like, shape (..., 3)
        The metal's colour (linear).
    roughness : float
        glTF ``roughnessFactor``.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Linear Rec.709.
    """
    F = iridescence_fresnel(cos_nv, thickness_nm, film_ior, base_f0)
    rough = np.clip(np.asarray(roughness, dtype=np.float64), 0.045, 1.0)
    nv = np.clip(np.asarray(cos_nv, dtype=np.float64), 0.0, 1.0)
    ess = dfg(rough, nv).sum(axis=-1)
    base = np.clip(np.asarray(base_f0, dtype=np.float64), 0.0, 1.0)
    return F * (ess[..., None] + base * (1.0 - ess[..., None]))
