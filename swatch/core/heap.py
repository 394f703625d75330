"""The C heap's thresholds for array work: freed temporaries are reused, not handed back and faulted in again.

numpy takes every array's memory from the C library's ``malloc``. glibc maps an allocation above its
mmap threshold afresh and unmaps it when freed, and trims the heap's free top back to the system
above its trim threshold; both thresholds start low (128 KiB) and the mmap one only rises with
the arrays freed. A command whose steps allocate and free arrays of a few MB again and again (the
calibration's batched residuals, a chunked colour table under overcoats, a render's shading) then
spends up to a quarter of its CPU time in the kernel, mapping and zero-filling pages it had a moment
before. :func:`keep_freed_memory` fixes them once per process: arrays up to :data:`MMAP_THRESHOLD_BYTES`
come from the heap, and up to :data:`TRIM_THRESHOLD_BYTES` of free heap is kept for the next ones
(both at most 1/16 of the run's budget :data:`swatch.core.limits.MAX_RUN_BYTES`, so the memory held
beyond what a run uses stays a small part of its budget: ``calibrate`` at its cap peaks 0.06 GB
higher). Larger arrays are still mapped and returned when freed. Elsewhere than glibc it does nothing.

References
----------
``mallopt(3)``, the GNU C Library manual: "Memory Allocation Tunables" (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import functools
import sys

from swatch.core.limits import MAX_RUN_BYTES

__all__ = ["keep_freed_memory", "MMAP_THRESHOLD_BYTES", "TRIM_THRESHOLD_BYTES"]

#: Allocations up to this come from the heap (glibc's dynamic threshold stops at 32 MiB too).
MMAP_THRESHOLD_BYTES = min(32 * 1024 ** 2, MAX_RUN_BYTES // 16)
#: Free heap kept for reuse instead of trimmed back to the system.
TRIM_THRESHOLD_BYTES = min(128 * 1024 ** 2, MAX_RUN_BYTES // 16)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h


@functools.cache
def keep_freed_memory() -> bool:
    """Set glibc's mmap and trim thresholds for array work (once per process; see the module docstring).

    Returns
    -------
    bool
        True when they are set (glibc on Linux), False where there is no ``mallopt``.
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):  # musl and other C libraries: nothing to tune
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES)) and bool(mallopt(_M_TRIM_THRESHOLD,
                                                                                   TRIM_THRESHOLD_BYTES))
