"""Numbers, lists and ranges from the text a user types (command-line options).

Bad text raises :class:`swatch.core.errors.SwatchError` saying what was wrong and what is allowed.
"""
from __future__ import annotations

import math

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_RANGE_POINTS

__all__ = ["parse_range", "parse_pair", "parse_grid", "parse_hex", "DEFAULT_STEP"]


#: The step of ``A:B`` without one, per unit: 1 nm, 0.5 V, 1°.
DEFAULT_STEP = {"nm": 1.0, "V": 0.5, "deg": 1.0}


def _strip_unit(tok: str, unit: str) -> str:
    """``50nm``, ``50 nm``, ``25V`` → the number's text (the unit written after a number is allowed)."""
    t = tok.strip()
    for u in (unit, "°") if unit == "deg" else (unit,):
        if t.lower().endswith(u.lower()) and t[: -len(u)].strip():
            return t[: -len(u)].strip()
    return t


def parse_range(text: str, what: str, unit: str) -> np.ndarray:
    """``A:B:STEP`` (inclusive of B when it falls on the grid), ``A:B`` (the unit's :data:`DEFAULT_STEP`),
    ``N,N,...`` or ``N``; each number may carry its unit (``50nm``, ``50 nm``, ``25V``, ``45°``).

    Parameters
    ----------
    text : str
        The option's text.
    what, unit : str
        What the numbers are and their unit, for the error messages.

    Returns
    -------
    numpy.ndarray, float64, shape (N,)
        At most :data:`swatch.core.limits.MAX_RANGE_POINTS` finite values.
    """
    s = str(text).strip()
    if not s:
        raise SwatchError(f"empty {what}; give A:B:STEP or a list N,N,... in {unit}")

    def num(tok: str) -> float:
        try:
            v = float(_strip_unit(tok, unit))
        except ValueError:
            raise SwatchError(f"{what} {tok.strip()!r} is not a number; give A:B:STEP or N,N,... in {unit}") from None
        if not math.isfinite(v):
            raise SwatchError(f"{what} must be finite, got {tok.strip()!r}")
        return v

    if ":" in s:
        parts = s.split(":")
        if len(parts) == 2 and unit in DEFAULT_STEP:
            parts.append(str(DEFAULT_STEP[unit]))
        if len(parts) != 3:
            raise SwatchError(f"{what} range {s!r} must be A:B:STEP or A:B in {unit}")
        a, b, step = (num(p) for p in parts)
        if step <= 0:
            raise SwatchError(f"{what} range {s!r} needs a step > 0")
        if b < a:
            raise SwatchError(f"{what} range {s!r} is reversed; give A <= B")
        span = (b - a) / step  # inf for a subnormal step: compared before any conversion
        if not span < 1e15:  # (inf for a subnormal step) far beyond the cap: no exact count to print
            raise SwatchError(f"{what} range {s!r} has more than {MAX_RANGE_POINTS} points; at most "
                              f"{MAX_RANGE_POINTS}")
        count = math.floor(span + 1e-9) + 1  # the exact number of points the range makes
        if count > MAX_RANGE_POINTS:
            raise SwatchError(f"{what} range {s!r} has {count} points; at most {MAX_RANGE_POINTS}")
        return a + step * np.arange(count)
    parts = s.split(",")
    if len(parts) > MAX_RANGE_POINTS:
        raise SwatchError(f"{what} list has {len(parts)} values; at most {MAX_RANGE_POINTS}")
    if any(not p.strip() for p in parts):
        raise SwatchError(f"{what} list {s[:60]!r} has an empty element; give N,N,... in {unit} with no empty "
                          "entries")
    return np.array([num(p) for p in parts], dtype=np.float64)


def parse_pair(text: str, what: str) -> tuple[float, float]:
    """``A:B`` (nm) as two finite floats, e.g. a search range ``0:400``.

    Parameters
    ----------
    text : str
        ``A:B``; the order of A and B is not checked.
    what : str
        The option's name, for the messages.

    Returns
    -------
    (float, float)
        ``(A, B)`` as given, in the option's unit (nm for a thickness range).

    Raises
    ------
    SwatchError
        Unless there are exactly two finite numbers.
    """
    parts = str(text).split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        a, b = (float(p) for p in parts)
    except ValueError:
        raise SwatchError(f"{what} {text!r} must be A:B in nm, e.g. 0:400") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise SwatchError(f"{what} must be finite numbers")
    return a, b


def parse_grid(text: str) -> tuple[float, float, float]:
    """A wavelength grid ``START:STOP:STEP`` (nm) as three floats (checked by
    :func:`swatch.physics.materials.wavelength_grid`).

    Parameters
    ----------
    text : str
        ``START:STOP:STEP``, nm.

    Returns
    -------
    (float, float, float)
        Start, stop and step, nm (not range-checked here).

    Raises
    ------
    SwatchError
        Unless there are exactly three numbers.
    """
    parts = str(text).split(":")
    if len(parts) != 3:
        raise SwatchError(f"wavelength grid {text!r} must be START:STOP:STEP in nm")
    try:
        a, b, s = (float(p) for p in parts)
    except ValueError:
        raise SwatchError(f"wavelength grid {text!r} must be numbers START:STOP:STEP in nm") from None
    return a, b, s


def parse_hex(hex_code: str) -> np.ndarray:
    """The three sRGB-encoded components of ``RRGGBB`` (a leading ``#`` allowed), 0–1.

    Parameters
    ----------
    hex_code : str
        Six hex digits ``RRGGBB``, optionally after ``#``, any case.

    Returns
    -------
    numpy.ndarray, shape (3,)
        The sRGB-encoded (non-linear) R, G, B, each in [0, 1] (the byte value / 255).

    Raises
    ------
    swatch.core.errors.SwatchError
        Not six hex digits.
    """
    h = str(hex_code).strip().lstrip("#")
    if len(h) != 6 or any(c not in "0123456789abcdefABCDEF" for c in h):
        raise SwatchError(f"bad hex colour {hex_code!r}; give six hex digits like 1f4e9a")
    return np.array([int(h[i:i + 2], 16) for i in (0, 2, 4)], dtype=np.float64) / 255.0
