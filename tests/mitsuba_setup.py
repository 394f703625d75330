"""Shared setup of the Mitsuba tests (#23): the LLVM variant, or a skip where no libLLVM 17+ is installed
(unless SWATCH_REQUIRE_MITSUBA=1, as in CI, where that is a failure)."""
from __future__ import annotations

import os

import numpy as np
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
    """``values`` as a Dr.Jit ``Float`` of the current variant, read from a 64-byte-aligned float32 copy.

    Dr.Jit maps a NumPy buffer without copying it and compiles the kernels that read it for its address
    (``unaligned`` unless it is a multiple of 32 bytes: drjit-core ``jitc_var_mem_map``). NumPy's buffers are
    16-byte aligned, so a test's kernels came out as one of two programs at random and missed Dr.Jit's kernel
    cache (~/.drjit) about half the time: compiled again, about a second for each BSDF kernel (#17). The
    values are those of ``np.float32(values)``; the copy stays alive as long as the array (Dr.Jit holds it).
    """
    import mitsuba as mi

    a = np.ascontiguousarray(values, dtype=np.float32).reshape(-1)
    buf = np.empty(a.size + 16, dtype=np.float32)
    start = (-buf.ctypes.data % 64) // 4
    out = buf[start:start + a.size]
    out[:] = a
    return mi.Float(out)


def jit_of(cls, rows):
    """A Mitsuba vector type (``cls``: ``mi.Vector3f``, ``mi.Point2f`` ...) of NumPy rows, each through
    :func:`jit_float`."""
    return cls(*(jit_float(r) for r in rows))
