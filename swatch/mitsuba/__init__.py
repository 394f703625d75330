"""The public face of the Mitsuba 3 BSDF plugin: ``import swatch.mitsuba; swatch.mitsuba.register()``.

``mitsuba.set_variant("llvm_ad_spectral"); swatch.mitsuba.register()`` makes BSDF type
``anodic_film`` available to ``mitsuba.load_dict`` (docs/mitsuba.md). The engine itself lives in
:mod:`swatch.render.mitsuba` (reached through ``swatch.render.render_swatch(..., engine="mitsuba")``);
importing this face points Dr.Jit at a usable system libLLVM first (:mod:`swatch.render.mitsuba.setup`).
"""
from __future__ import annotations

from swatch.render.mitsuba import PLUGIN_NAME, register

__all__ = ["PLUGIN_NAME", "register"]
