"""Renderers: scene, shading, display, the point-light and environment engines, meshes, render metadata.

:func:`render_swatch` (:mod:`swatch.render.dispatch`) is the one entry point: it checks the inputs once
into a :class:`RenderRequest` (:func:`render_request`) and hands it to an engine of :data:`ENGINES`
(``builtin``, ``mitsuba``); every engine returns a :class:`swatch.render.image.SwatchImage`.
The names below are loaded on first use (PEP 562), so that
importing one render module (e.g. :mod:`swatch.render.metadata`) does not load every engine.
"""
from __future__ import annotations

import importlib

__all__ = ["render_swatch", "ENGINES", "RenderRequest", "render_request", "SwatchImage"]

_LAZY = {"render_swatch": "swatch.render.dispatch", "ENGINES": "swatch.render.dispatch",
         "RenderRequest": "swatch.render.request", "render_request": "swatch.render.request",
         "SwatchImage": "swatch.render.image"}


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
