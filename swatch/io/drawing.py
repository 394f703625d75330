"""Raster drawing on uint8 images through OpenImageIO: anti-aliased text in the fonts its wheel ships
(DroidSans, DroidSans-Bold, DroidSansMono), rectangles and axis-parallel lines (figures, catalog sheets).

A character the font has no glyph for is drawn as ``?`` (:func:`drawable_text`) so text is never
silently invisible; metadata keeps the original text.
"""
from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from swatch.core.errors import SwatchError
from swatch.io.imageio import as_hwc

__all__ = ["font_path", "draw_text", "text_width", "drawable_text", "draw_rect", "draw_line"]


@functools.lru_cache(maxsize=4)
def font_path(name: str = "DroidSans") -> str:
    """A TrueType font shipped inside the OpenImageIO wheel (``share/fonts/OpenImageIO/<name>.ttf``).

    Parameters
    ----------
    name : str
        ``DroidSans``, ``DroidSans-Bold``, ``DroidSansMono`` …

    Returns
    -------
    str
        The font file's path.

    Raises
    ------
    swatch.core.errors.SwatchError
        The wheel has no such font.
    """
    base = Path(oiio.__file__).resolve().parent
    for cand in (base / "share" / "fonts" / "OpenImageIO" / f"{name}.ttf",):
        if cand.is_file():
            return str(cand)
    found = sorted(base.rglob(f"{name}.ttf"))
    if found:
        return str(found[0])
    raise SwatchError(f"font {name}.ttf not found in the OpenImageIO package at {base}")


def _color_tuple(color, nch: int) -> tuple:
    c = np.asarray(color, dtype=np.float64).reshape(-1)
    if c.size == 1:
        c = np.repeat(c, 3)
    c = c / 255.0 if c.max(initial=0) > 1.0 else c
    vals = list(c[:nch]) + [1.0] * (nch - min(c.size, nch))
    return tuple(float(v) for v in vals[:nch])


@functools.lru_cache(maxsize=4096)
def _has_glyph(char: str, font: str) -> bool:
    """Whether ``font`` draws ``char`` (a missing glyph has an advance but leaves no ink)."""
    if char.isspace():
        return True
    roi = oiio.ImageBufAlgo.text_size(char, 32, font_path(font))
    return bool(roi.defined and roi.width > 1)


def drawable_text(text: str, font: str = "DroidSans") -> str:
    """``text`` with the characters the font cannot draw (CJK, many symbols) replaced by ``?``.

    Parameters
    ----------
    text : str
        The label to draw.
    font : str
        A font of :func:`font_path`.

    Returns
    -------
    str
        The same length as ``text``; unchanged when the font has every character.

    Examples
    --------
    >>> drawable_text("50 nm 色")
    '50 nm ?'
    """
    return "".join(ch if _has_glyph(ch, font) else "?" for ch in str(text))


def text_width(text: str, size_px: int, font: str = "DroidSans") -> int:
    """Width of ``text`` rendered at ``size_px`` (what :func:`draw_text` draws).

    Parameters
    ----------
    text : str
        The label (characters the font lacks measured as ``?``).
    size_px : int
        Font size, pixels.
    font : str
        A font of :func:`font_path`.

    Returns
    -------
    int
        Pixels.
    """
    roi = oiio.ImageBufAlgo.text_size(drawable_text(text, font), int(size_px), font_path(font))
    return int(roi.width) if roi.defined else 0


def draw_text(image_uint8, text: str, x: int, y: int, size_px: int = 16, color=(0, 0, 0),
              align: str = "left", valign: str = "baseline", font: str = "DroidSans",
              inplace: bool = False) -> np.ndarray:
    """Render ``text`` into an (H, W, C) uint8 image with OpenImageIO (anti-aliased).

    Only the band of rows the text can reach is converted, so a label costs the same on a tall
    figure as on a small one.

    Parameters
    ----------
    image_uint8 : numpy.ndarray of uint8, shape (H, W, C)
        Display-encoded pixels (C channels, 0–255) to draw on.
    text : str
        Characters the font lacks are drawn as ``?``.
    x, y : int
        The anchor, pixels.
    size_px : int
        Font size, pixels.
    color : sequence of float
        0–255 or 0–1 values.
    align : str
        ``left``, ``center`` or ``right`` of the anchor.
    valign : str
        ``baseline``, ``top``, ``center`` or ``bottom``.
    font : str
        A font of :func:`font_path`.
    inplace : bool
        Draw on the input itself (a figure of many labels: no copy per label).

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, C)
        A new image (the input unchanged), or the input with ``inplace``.

    Raises
    ------
    swatch.core.errors.SwatchError
        The image is not uint8, or OpenImageIO cannot draw the text.
    """
    img = as_hwc(image_uint8, "image")
    if img.dtype != np.uint8:
        raise SwatchError("draw_text works on uint8 images")
    h, w, c = img.shape
    pad = 2 * int(size_px) + 4  # the glyphs lie within two sizes of the anchor, whatever the valign
    y0, y1 = max(0, int(y) - pad), min(h, int(y) + pad)
    out_img = img if inplace else img.copy()
    if y1 <= y0:
        return out_img
    # and only the columns it can reach: no glyph is wider than two sizes (so a short label on a wide
    # figure converts a small window, not the figure's width)
    em = 2 * int(size_px) + 4
    span = (len(text) + 1) * em
    lo = {"left": int(x) - em, "right": int(x) - span}.get(align, int(x) - span // 2 - em)
    x0, x1 = max(0, lo), min(w, lo + span + 2 * em)
    if x1 <= x0:
        return out_img
    band = img[y0:y1, x0:x1]
    buf = oiio.ImageBuf(oiio.ImageSpec(x1 - x0, y1 - y0, c, "float"))
    buf.set_pixels(oiio.ROI(0, x1 - x0, 0, y1 - y0), band.astype(np.float32) / 255.0)
    ok = oiio.ImageBufAlgo.render_text(buf, int(x) - x0, int(y) - y0, drawable_text(text, font), int(size_px),
                                       font_path(font), _color_tuple(color, c), align, valign)
    if not ok:
        raise SwatchError(f"cannot draw text: {buf.geterror()}")
    px = buf.get_pixels(oiio.FLOAT)
    if px is None:
        raise SwatchError(f"cannot draw text: {buf.geterror()}")
    out = px.reshape(y1 - y0, x1 - x0, c)
    out_img[y0:y1, x0:x1] = np.clip(np.round(out * 255.0), 0, 255).astype(np.uint8)
    return out_img


def draw_rect(image_uint8, x0: int, y0: int, x1: int, y1: int, color, fill: bool = True, width: int = 1,
              inplace: bool = False) -> np.ndarray:
    """A filled (or outlined) axis-aligned rectangle [x0, x1) × [y0, y1), clipped to the image.

    Parameters
    ----------
    image_uint8 : numpy.ndarray of uint8, shape (H, W, C)
        Display-encoded pixels (C channels, 0–255) to draw on.
    x0, y0, x1, y1 : int
        Corners, pixels.
    color : sequence of float
        0–255 or 0–1 values.
    fill : bool
        Filled, or an outline of ``width`` pixels.
    width : int
        The outline's width, pixels, inside the rectangle (unused when ``fill``).
    inplace : bool
        Draw on the input itself, not a copy.

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, C)
        A new image (the input unchanged), or the input with ``inplace``.

    Examples
    --------
    >>> img = draw_rect(np.zeros((4, 4, 3), np.uint8), 1, 1, 3, 3, (255, 0, 0))
    >>> img[:, :, 0].tolist()
    [[0, 0, 0, 0], [0, 255, 255, 0], [0, 255, 255, 0], [0, 0, 0, 0]]
    """
    img = as_hwc(image_uint8, "image")
    img = img if inplace else img.copy()
    col = np.round(np.asarray(_color_tuple(color, img.shape[2])) * 255).astype(np.uint8)
    h, w = img.shape[:2]
    x0, x1 = max(0, int(x0)), min(w, int(x1))
    y0, y1 = max(0, int(y0)), min(h, int(y1))
    if x1 <= x0 or y1 <= y0:
        return img
    if fill:
        img[y0:y1, x0:x1] = col
    else:
        t = int(width)
        img[y0:min(y1, y0 + t), x0:x1] = col
        img[max(y0, y1 - t):y1, x0:x1] = col
        img[y0:y1, x0:min(x1, x0 + t)] = col
        img[y0:y1, max(x0, x1 - t):x1] = col
    return img


def draw_line(image_uint8, x0: int, y0: int, x1: int, y1: int, color, width: int = 1,
              inplace: bool = False) -> np.ndarray:
    """A horizontal or vertical line (axes, ticks) of ``width`` pixels.

    Parameters
    ----------
    image_uint8 : numpy.ndarray of uint8, shape (H, W, C)
        Display-encoded pixels (C channels, 0–255) to draw on.
    x0, y0, x1, y1 : int
        End points, pixels (x0 == x1 or y0 == y1).
    color : sequence of float
        0–255 or 0–1 values.
    width : int
        The line's thickness, pixels.
    inplace : bool
        Draw on the input itself, not a copy.

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, C)
        A new image (the input unchanged), or the input with ``inplace``.

    Raises
    ------
    swatch.core.errors.SwatchError
        A slanted line.
    """
    if x0 != x1 and y0 != y1:
        raise SwatchError("draw_line draws horizontal or vertical lines only")
    t = int(width)
    if y0 == y1:
        return draw_rect(image_uint8, min(x0, x1), y0 - t // 2, max(x0, x1) + 1, y0 - t // 2 + t, color,
                         inplace=inplace)
    return draw_rect(image_uint8, x0 - t // 2, min(y0, y1), x0 - t // 2 + t, max(y0, y1) + 1, color,
                     inplace=inplace)
