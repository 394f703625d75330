"""Setting Mitsuba 3 up: the system libLLVM its JIT needs, the variant and the one-line hint (a render's
size, samples per pixel and seed are checked with the request: :mod:`swatch.render.checks`).

Mitsuba's ``llvm_ad_*`` variants compile kernels with Dr.Jit's LLVM backend, which loads a
system ``libLLVM`` through the LLVM C API at run time. On Debian the one that works with Mitsuba
3.9 is ``libllvm19`` (``libLLVM.so.19.1``): the libLLVM 14–16 that other packages bring crash
inside the JIT ("Cannot select: fminimum"), and PyPI's llvmlite does not export the C API.
:func:`configure_llvm` points ``DRJIT_LIBLLVM_PATH`` at a libLLVM 19 (or newer) found in the
usual places when the variable is unset; it runs before ``mitsuba`` is imported (Dr.Jit reads
the variable when it loads). The ``scalar_*`` variants need no LLVM.
"""
from __future__ import annotations

import glob
import os
import re

from swatch.core.choices import DEFAULT_VARIANT, SPECTRAL_VARIANTS
from swatch.render.checks import check_variant

__all__ = ["ENV_VAR", "INSTALL_HINT", "SPECTRAL_VARIANTS", "DEFAULT_VARIANT", "find_libllvm", "configure_llvm", "llvm_major",
           "check_variant"]

ENV_VAR = "DRJIT_LIBLLVM_PATH"
#: What to install when no usable libLLVM is found (one line, said by ``--engine mitsuba``).
INSTALL_HINT = ("Mitsuba's LLVM backend needs libLLVM 19: on Debian/Ubuntu `apt-get install libllvm19` "
                f"(then {ENV_VAR} is found automatically), or set {ENV_VAR} to a libLLVM.so of version 17-20")
#: Oldest libLLVM major that Mitsuba 3.9's JIT runs with (14–16 fail on ``fminimum``).
OLDEST_LLVM_MAJOR = 17
_SEARCH = ("/usr/lib/x86_64-linux-gnu/libLLVM.so.*", "/usr/lib/x86_64-linux-gnu/libLLVM-*.so*",
           "/usr/lib/aarch64-linux-gnu/libLLVM.so.*", "/usr/lib/aarch64-linux-gnu/libLLVM-*.so*",
           "/usr/lib/llvm-*/lib/libLLVM.so*", "/usr/lib/llvm-*/lib/libLLVM-*.so*", "/usr/lib64/libLLVM.so*",
           "/usr/lib64/libLLVM-*.so*", "/usr/local/lib/libLLVM.so*", "/opt/homebrew/opt/llvm/lib/libLLVM.dylib")


def llvm_major(path: str) -> int:
    """The LLVM major version in a library's file name.

    Parameters
    ----------
    path : str
        E.g. ``/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`` or ``libLLVM-19.so``.

    Returns
    -------
    int
        The major version, 0 when the name does not say.

    Examples
    --------
    >>> llvm_major("/usr/lib/llvm-19/lib/libLLVM.so.19.1"), llvm_major("libLLVM-17.so"), llvm_major("libfoo.so")
    (19, 17, 0)
    """
    m = re.search(r"libLLVM(?:\.so\.|-)(\d+)", os.path.basename(path)) or re.search(r"llvm-(\d+)", path)
    return int(m.group(1)) if m else 0


def find_libllvm() -> str | None:
    """The newest libLLVM of a usable version (≥ 17) in the usual system folders.

    Returns
    -------
    str or None
        Its real path; None when there is none.
    """
    found = [p for pattern in _SEARCH for p in glob.glob(pattern) if os.path.isfile(p)]
    usable = sorted({os.path.realpath(p) for p in found if llvm_major(p) >= OLDEST_LLVM_MAJOR},
                    key=lambda p: (llvm_major(p), p))
    return usable[-1] if usable else None


def configure_llvm() -> str | None:
    """Point ``DRJIT_LIBLLVM_PATH`` at a usable libLLVM when it is unset.

    Returns
    -------
    str or None
        The path in use (the variable's own when set), or None.
    """
    current = os.environ.get(ENV_VAR)
    if current:
        return current
    path = find_libllvm()
    if path is not None:
        os.environ[ENV_VAR] = path
    return path
