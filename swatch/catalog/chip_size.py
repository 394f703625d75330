"""A print chip's size: the defaults of a catalog spec's [chips] table and the pixels they give."""
from __future__ import annotations

__all__ = ["CHIP_SIZE_MM", "CHIP_DPI", "chip_px"]

#: A print chip's default size (mm per side) and resolution (dots per inch).
CHIP_SIZE_MM = 50.0
CHIP_DPI = 300
_MM_PER_INCH = 25.4


def chip_px(size_mm: float, dpi: float) -> int:
    """Pixels per side of a ``size_mm`` chip at ``dpi``.

    Parameters
    ----------
    size_mm : float
        Printed side of the chip, mm.
    dpi : float
        Print resolution, dots per inch.

    Returns
    -------
    int
        Pixels per side, rounded.

    Examples
    --------
    >>> chip_px(50, 300)
    591
    """
    return round(float(size_mm) / _MM_PER_INCH * float(dpi))
