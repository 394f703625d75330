"""Shared setup of the Mitsuba tests (#23): the LLVM variant, or a skip where no libLLVM 17+ is installed
(unless SWATCH_REQUIRE_MITSUBA=1, as in CI, where that is a failure)."""
from __future__ import annotations

import os

import pytest

from swatch.render.mitsuba.setup import configure_llvm


def mitsuba_variant(variant: str = "llvm_ad_spectral"):
    """Set ``variant`` and register the plugin; returns the ``mitsuba`` module (or skips)."""
    if configure_llvm() is None and variant.startswith("llvm"):
        if os.environ.get("SWATCH_REQUIRE_MITSUBA") == "1":
            pytest.fail("no libLLVM 17+ for Mitsuba's LLVM variant (apt-get install libllvm19)")
        pytest.skip("no libLLVM 17+ for Mitsuba's LLVM variant (apt-get install libllvm19)")
    import mitsuba as mi

    from swatch.render.mitsuba.engine import use_variant

    use_variant(variant)
    return mi


def irregular_spectrum(wl, values) -> dict:
    """A Mitsuba ``irregular`` spectrum of ``values`` at ``wl`` (nm), 300–900 nm (Mitsuba's range)."""
    keep = (wl > 300) & (wl < 900)
    return {"type": "irregular", "wavelengths": ", ".join(f"{x:.9g}" for x in wl[keep]),
            "values": ", ".join(f"{x:.9g}" for x in values[keep])}


def jit_float(values):
    """``values`` as a Dr.Jit ``Float`` in aligned memory: :func:`swatch.render.mitsuba.scene.jit_float` (NumPy's
    16-byte-aligned buffers made the kernels reading them one of two programs at random, so the BSDF tests
    missed Dr.Jit's kernel cache about half the time, #17). Imported here, once a test runs, so that collecting
    the tests does not load Mitsuba."""
    from swatch.render.mitsuba.scene import jit_float as upload

    return upload(values)


def jit_of(cls, rows):
    """A Mitsuba vector type (``cls``: ``mi.Vector3f``, ``mi.Point2f`` ...) of NumPy rows, each through
    :func:`jit_float`."""
    return cls(*(jit_float(r) for r in rows))
