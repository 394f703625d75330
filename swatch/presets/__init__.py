"""3-D material presets: each swatch as a glTF, Blender (Cycles), OpenPBR/MaterialX and Mitsuba 3 material.

Renderers describe an anodised finish with their own thin-film models: a film of one real
IOR over a metal whose reflectance is given as a colour. Those models are ported here from
their specifications and sources (numpy, one module per model), their parameters are fitted
per swatch to the exact Airy colour of the catalog (``fit``), and the fitted materials are
written as files (``write``):

- :mod:`swatch.presets.threejs` — what three.js r187 shows of that glTF (the film at N·V, its
  direct-light multiscatter factor): the glTF presets are fitted to it;
- :mod:`swatch.presets.gltf` — glTF 2.0 ``KHR_materials_iridescence`` on a metal base, as specified;
- :mod:`swatch.presets.cycles` — Blender Cycles' Principled BSDF thin film on a metallic base;
- :mod:`swatch.presets.materialx` — OpenPBR Surface as MaterialX 1.39.5's GLSL evaluates it
  (``mx_fresnel_airy``): the MaterialX presets are fitted to it;
- :mod:`swatch.presets.openpbr` — OpenPBR Surface thin film as the specification recommends
  (Belcour–Barla, Gulbrandsen metal; no renderer checked);
- :mod:`swatch.presets.spectral` — the Fourier-space colour-matching sensitivities they share;
- :mod:`swatch.presets.mitsuba_bsdf` — Mitsuba 3 with swatch's own ``anodic_film`` BSDF: the exact
  model, nothing fitted (a scene dictionary and an XML element).

Every model maps (cos of the incidence angle on the microfacet, material parameters) to the
Fresnel factor in linear Rec.709 RGB; :func:`swatch.presets.spectral.rgb_to_Lab` turns that into
CIELAB (D65, CIE 1931 2°) for comparison with the exact colour.
"""
from __future__ import annotations

#: The preset formats, one name per target renderer model.
PRESET_FORMATS = ("gltf", "blender", "materialx")
#: Which ported model each format is judged with.
FORMAT_MODEL = {"gltf": "threejs", "blender": "cycles", "materialx": "materialx"}
#: The exact presets (nothing fitted): Mitsuba 3 with swatch's ``anodic_film`` BSDF (:mod:`swatch.presets.mitsuba_bsdf`).
EXACT_FORMATS = ("mitsuba",)
#: The USD presets (the OpenPBR network of ``materialx`` and a UsdPreviewSurface fallback; :mod:`swatch.presets.usd`)
#: and the physicallybased.info v2 document (:mod:`swatch.presets.physicallybased`).
USD_FORMATS = ("usd", "usdz")
DATABASE_FORMATS = ("physicallybased",)

__all__ = ["PRESET_FORMATS", "FORMAT_MODEL", "EXACT_FORMATS", "USD_FORMATS", "DATABASE_FORMATS"]
