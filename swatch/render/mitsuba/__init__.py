"""Mitsuba 3 for swatch: the exact thin-film BSDF ``anodic_film`` and the ``--engine mitsuba`` renderer.

``import swatch.mitsuba; mitsuba.set_variant("llvm_ad_spectral"); swatch.mitsuba.register()``
makes BSDF type ``anodic_film`` available to ``mitsuba.load_dict`` (docs/mitsuba.md). Importing
this package points Dr.Jit at a usable system libLLVM first (:mod:`swatch.render.mitsuba.setup`).
"""
from __future__ import annotations

from swatch.render.mitsuba.setup import configure_llvm

configure_llvm()  # before Dr.Jit loads: it reads DRJIT_LIBLLVM_PATH then

from swatch.render.mitsuba.bsdf import PLUGIN_NAME, register  # noqa: E402

__all__ = ["PLUGIN_NAME", "register"]
