"""``<model-viewer>`` 4.4.0: the iridescent metal as its bundled three.js (r183) shows it in an even white surround, in numpy.

Google's ``<model-viewer>`` (npm ``@google/model-viewer`` 4.4.0, Apache-2.0; the copy the catalog page
loads is ``swatch/catalog/web/model-viewer/``) bundles three.js 0.183.0 and lights a model with an
environment map only (image-based lighting; no direct light). Port of that bundle's shader chunks for a glTF
material with ``KHR_materials_iridescence`` (``metalness`` 1, ``iridescence`` 1, thickness = the maximum):

- ``lights_fragment_begin``: ``iridescenceFresnelMetallic = evalIridescence(1, iridescenceIOR, N·V,
  thickness, diffuseColor)`` — the same function as r187
  (:func:`swatch.presets.threejs.iridescence_fresnel`);
- ``lights_physical_pars_fragment`` / ``RE_IndirectSpecular_Physical``: the metal's
  ``computeMultiscatteringIridescence(…, iridescenceF0 = that Fresnel, …)``: ``Fr`` = the iridescent
  Fresnel, ``FssEss = Fr·fab.x + fab.y``, ``Ess = fab.x + fab.y``, ``Favg = Fr + (1 − Fr)/21``,
  ``Fms = FssEss·Favg / (1 − (1 − Ess)·Favg)``; radiance × ``FssEss`` + irradiance/π × ``Fms·(1 − Ess)``,
  ``fab`` from the 16×16 DFG LUT (the same half floats as r187's:
  tables/renderers/threejs_dfg_lut.csv, checked equal) at (``max(roughness, 0.0525)``, N·V).

In an even white surround of radiance 1 the prefiltered radiance and irradiance/π are both 1, so the
plate shows ``FssEss + Fms·(1 − Ess)``; a white metal plate (colour 1, no iridescence) shows exactly 1.
:func:`surround_fresnel` is therefore the colour relative to a white metal plate in the same light
(linear Rec.709), the film evaluated at N·V. ``tests/catalog/test_catalog_ar.py`` renders the catalog's
viewer files in the vendored ``<model-viewer>`` in headless Chromium and compares.
"""
from __future__ import annotations

import numpy as np

from swatch.presets.threejs import dfg, iridescence_fresnel

__all__ = ["VERSION", "THREE_REVISION", "ROUGHNESS_FLOOR", "surround_fresnel"]

#: The ``<model-viewer>`` release ported (and vendored for the catalog page).
VERSION = "4.4.0"
#: The three.js revision that release bundles.
THREE_REVISION = "r183"
#: ``material.roughness = max(roughnessFactor, 0.0525)`` in r183's ``lights_physical_fragment``.
ROUGHNESS_FLOOR = 0.0525


def surround_fresnel(cos_nv, thickness_nm, film_ior, base_f0, roughness) -> np.ndarray:
    """What ``<model-viewer>`` shows of the iridescent metal in an even white surround, relative to a
    white metal plate: (..., 3), linear Rec.709.

    Parameters
    ----------
    cos_nv : array_like
        N·V, the cosine of the view angle from the surface normal.
    thickness_nm, film_ior : array_like
        ``iridescenceThicknessMaximum`` (nm) and ``iridescenceIor``; broadcast with ``cos_nv``.
    base_f0 : array_like, shape (..., 3)
        ``baseColorFactor`` RGB (linear), the metal's colour.
    roughness : float
        glTF ``roughnessFactor``.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        ``FssEss + Fms·(1 − Ess)``, linear Rec.709 (1 = the white metal plate).
    """
    F = iridescence_fresnel(cos_nv, thickness_nm, film_ior, base_f0)
    rough = np.clip(np.asarray(roughness, dtype=np.float64), ROUGHNESS_FLOOR, 1.0)
    nv = np.clip(np.asarray(cos_nv, dtype=np.float64), 0.0, 1.0)
    fab = dfg(rough, nv)
    scale, bias = fab[..., 0:1], fab[..., 1:2]
    fss_ess = F * scale + bias
    ems = 1.0 - (scale + bias)
    f_avg = F + (1.0 - F) * 0.047619
    fms = fss_ess * f_avg / (1.0 - ems * f_avg)
    return fss_ess + fms * ems
