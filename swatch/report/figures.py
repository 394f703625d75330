"""Figures: the labelled angular map and the ΔE map of a fit (uint8 RGB images with axes and labels).

Labels are drawn with OpenImageIO's text rendering (:mod:`swatch.io.drawing`); they are ASCII where
the shipped font lacks a glyph (``dE*ab``, ``deg``).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import OpenImageIO as oiio

from swatch.core.errors import SwatchError
from swatch.fit.result import delta_e_grid
from swatch.io import drawing
from swatch.io.drawing import drawable_text, font_path

if TYPE_CHECKING:
    from swatch.fit.result import FitResult
    from swatch.render.angular import AngularMap

__all__ = ["angular_figure", "delta_e_figure", "colormap"]

#: Viridis anchors (perceptually ordered dark -> light) for the ΔE colour scale.
_VIRIDIS = np.array([
    (68, 1, 84), (71, 44, 122), (59, 81, 139), (44, 113, 142), (33, 144, 141),
    (39, 173, 129), (92, 200, 99), (170, 220, 50), (253, 231, 37),
], dtype=np.float64)


def angular_figure(amap: AngularMap, title: str | None = None, cell_px: int | None = None) -> np.ndarray:
    """A labelled display figure of an angular map: light angle up the side, view angle along the bottom
    (origin bottom-left, so the mirror diagonal, dashed, runs bottom-left to top-right).

    Parameters
    ----------
    amap : swatch.render.angular.AngularMap
        The map (display sRGB, shape (L, V, 3), over light × view polar angles in degrees).
    title : str, optional
        Drawn above the map.
    cell_px : int, optional
        Pixels per map cell (default: about 516 px for the longer side).

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, 3)
        Display sRGB.
    """
    nl, nv = amap.display_rgb.shape[:2]
    cell = int(cell_px or max(1, 516 // max(nl, nv)))
    mh, mw = nl * cell, nv * cell
    left, right, top, bottom = 78, 24, 64, 64
    H, W = top + mh + bottom, left + mw + right
    img = np.full((H, W, 3), 255, dtype=np.uint8)
    block = np.repeat(np.repeat(amap.display_rgb[::-1], cell, axis=0), cell, axis=1)  # light 0 at the bottom
    img[top:top + mh, left:left + mw] = block
    ink = (40, 40, 40)
    img = drawing.draw_rect(img, left - 1, top - 1, left + mw + 1, top + mh + 1, ink, fill=False)
    # The mirror direction (light = view), dotted over the map so it is visible whatever the model.
    lo_m = max(float(amap.light_deg[0]), float(amap.view_deg[0]))
    hi_m = min(float(amap.light_deg[-1]), float(amap.view_deg[-1]))
    if hi_m > lo_m:
        t = np.linspace(lo_m, hi_m, max(2, int(max(mw, mh))))
        xs = (left + (np.interp(t, amap.view_deg, np.arange(nv)) + 0.5) * cell).astype(int)
        ys = (top + mh - (np.interp(t, amap.light_deg, np.arange(nl)) + 0.5) * cell).astype(int)
        on = (np.arange(t.size) % 10) < 6  # dashes of ~6 px, gaps of ~4 px
        for dy, dx, shade in ((1, 1, 60), (0, 0, 255), (0, 1, 255), (1, 0, 255)):  # 2-px stroke, dark edge
            img[np.clip(ys[on] + dy, 0, H - 1), np.clip(xs[on] + dx, 0, W - 1)] = shade

    def ticks(values):
        lo, hi = float(values[0]), float(values[-1])
        step = 15.0 if hi - lo >= 45 else (5.0 if hi - lo >= 10 else 1.0)
        t = np.arange(math.ceil(lo / step) * step, hi + 1e-9, step)
        return t

    for t in ticks(amap.view_deg):  # x axis: view
        j = float(np.interp(t, amap.view_deg, np.arange(nv)))
        x = int(left + (j + 0.5) * cell)
        img = drawing.draw_line(img, x, top + mh, x, top + mh + 6, ink)
        img = drawing.draw_text(img, f"{t:g}", x, top + mh + 22, 15, ink, align="center")
    for t in ticks(amap.light_deg):  # y axis: light (upwards)
        i = float(np.interp(t, amap.light_deg, np.arange(nl)))
        y = int(top + mh - (i + 0.5) * cell)
        img = drawing.draw_line(img, left - 7, y, left - 1, y, ink)
        img = drawing.draw_text(img, f"{t:g}", left - 11, y + 5, 15, ink, align="right")
    img = drawing.draw_text(img, "view angle (deg from normal, opposite side); dashed: mirror", left + mw // 2,
                            H - 14, 16, ink, align="center")
    # Vertical axis label: draw horizontally into a strip, rotate it, paste it.
    label = "light angle (deg)"
    lw = drawing.text_width(label, 16) + 8
    strip = np.full((24, lw, 3), 255, dtype=np.uint8)
    strip = drawing.draw_text(strip, label, 4, 17, 16, ink)
    rot = np.rot90(strip)  # reads bottom to top
    y0 = top + mh // 2 - rot.shape[0] // 2
    if rot.shape[0] <= H - max(0, y0):
        img[max(0, y0):max(0, y0) + rot.shape[0], 6:6 + rot.shape[1]] = rot
    meta = amap.metadata
    volts = meta.get("voltage_V")
    head = title or (f"{amap.thickness_nm:.1f} nm" + (f" (~{volts:.1f} V)" if volts is not None else "")
                     + f"  {meta.get('film')} on {meta.get('substrate')}")
    img = drawing.draw_text(img, head, left, 26, 19, (0, 0, 0))
    sub = (f"{meta.get('model')} model" + (f", {meta.get('distribution')} a={meta.get('roughness'):g}"
                                             if meta.get("model") == "microfacet" else "")
           + f"; {meta.get('illuminant')}, {meta.get('observer')}; exposure x{amap.exposure:.3g}")
    img = drawing.draw_text(img, sub, left, 50, 14, (70, 70, 70))
    return img


def colormap(t: np.ndarray) -> np.ndarray:
    """Viridis-like colours for values in [0, 1] (the ΔE maps' scale; perceptually ordered dark to light).

    Parameters
    ----------
    t : array_like
        Values, any shape; clipped to [0, 1].

    Returns
    -------
    numpy.ndarray of uint8, shape t.shape + (3,)
        Display sRGB.

    Examples
    --------
    >>> colormap([0.0, 1.0]).tolist()
    [[68, 1, 84], [253, 231, 37]]
    """
    t = np.clip(np.asarray(t, dtype=np.float64), 0.0, 1.0) * (len(_VIRIDIS) - 1)
    i = np.minimum(np.floor(t).astype(int), len(_VIRIDIS) - 2)
    f = (t - i)[..., None]
    return np.round(_VIRIDIS[i] * (1 - f) + _VIRIDIS[i + 1] * f).astype(np.uint8)


def _nice_max(x: float) -> float:
    x = max(float(x), 1.0)
    k = 10.0 ** math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * k >= x - 1e-12:
            return m * k
    return 10.0 * k


def delta_e_figure(result: FitResult, title: str) -> tuple[np.ndarray, dict]:
    """The light × view ΔE*ab map of a fit, with labels and a colour scale, and its data.

    Labels are ASCII ("dE*ab", "deg"): the font shipped with OpenImageIO has no Greek letters.

    Parameters
    ----------
    result : swatch.fit.result.FitResult
        The fit (its per-geometry ΔE*ab, CIE 1976).
    title : str
        Drawn above the map.

    Returns
    -------
    image : numpy.ndarray of uint8, shape (H, W, 3)
        Display sRGB.
    data : dict
        ``light_deg``, ``view_deg`` (degrees), ``grid`` (ΔE*ab, NaN where not measured), ``excluded``
        (mirror region), ``signed`` (views on both sides) and ``vmax`` (the scale's top).

    Raises
    ------
    swatch.core.errors.SwatchError
        OpenImageIO cannot draw the labels.
    """

    lv, vv, grid, excluded, signed = delta_e_grid(result, "delta_E_ab")
    nL, nV = grid.shape
    cell = int(np.clip(640 // max(nL, nV), 12, 56))
    ml, mt, mb = 84, 88, 64
    bar_gap, bar_w, bar_lab = 28, 22, 64
    W = ml + nV * cell + bar_gap + bar_w + bar_lab
    H = max(mt + nL * cell + mb, 360)
    img = np.full((H, W, 3), 255, dtype=np.uint8)
    finite = grid[np.isfinite(grid)]
    used_vals = result.delta_E_ab[result.used]
    vmax = _nice_max(used_vals.max() if used_vals.size else (finite.max() if finite.size else 1.0))
    colours = colormap(np.where(np.isfinite(grid), grid, 0.0) / vmax)
    texts = []  # (x, y, text, size, colour, align, valign)
    for i in range(nL):
        y0 = mt + i * cell
        for j in range(nV):
            x0 = ml + j * cell
            if not np.isfinite(grid[i, j]):
                img[y0:y0 + cell, x0:x0 + cell] = 228
                continue
            img[y0:y0 + cell, x0:x0 + cell] = colours[i, j]
            if excluded[i, j]:  # mirror region: black outline
                t = max(2, cell // 14)
                img[y0:y0 + t, x0:x0 + cell] = 0
                img[y0 + cell - t:y0 + cell, x0:x0 + cell] = 0
                img[y0:y0 + cell, x0:x0 + t] = 0
                img[y0:y0 + cell, x0 + cell - t:x0 + cell] = 0
            if cell >= 34:
                lum = colours[i, j] @ np.array([0.2126, 0.7152, 0.0722])
                col = (1, 1, 1) if lum < 140 else (0, 0, 0)
                texts.append((x0 + cell // 2, y0 + cell // 2, f"{grid[i, j]:.1f}", max(10, cell // 4), col, "center", "center"))
    # grid lines between cells
    for j in range(nV + 1):
        x = ml + j * cell
        img[mt:mt + nL * cell, min(x, W - 1)] = 255
    for i in range(nL + 1):
        y = mt + i * cell
        img[min(y, H - 1), ml:ml + nV * cell] = 255
    every_v = max(1, math.ceil(28 / cell))
    every_l = max(1, math.ceil(16 / cell))
    for j in range(0, nV, every_v):
        texts.append((ml + j * cell + cell // 2, mt + nL * cell + 6, f"{vv[j]:g}", 12, (0, 0, 0), "center", "top"))
    for i in range(0, nL, every_l):
        texts.append((ml - 8, mt + i * cell + cell // 2, f"{lv[i]:g}", 12, (0, 0, 0), "right", "center"))
    view_title = "view angle (deg; negative: light's side)" if signed and vv.min() < 0 else "view angle (deg)"
    texts.append((ml + nV * cell // 2, mt + nL * cell + 30, view_title, 14, (0, 0, 0), "center", "top"))
    texts.append((8, mt - 10, "light (deg)", 14, (0, 0, 0), "left", "bottom"))
    texts.append((8, 8, title, 16, (0, 0, 0), "left", "top"))
    texts.append((8, 32, f"mean dE*ab {result.mean_delta_E_ab:.2f} (grade {result.grade} of {result.scheme}); "
                  f"outlined: mirror region (within {result.exclude_mirror_deg:g} deg), left out of the mean",
                  12, (0, 0, 0), "left", "top"))
    # colour bar
    bx = ml + nV * cell + bar_gap
    bh = max(nL * cell, 200)
    ys = np.arange(bh)
    img[mt:mt + bh, bx:bx + bar_w] = colormap(1.0 - ys / max(bh - 1, 1))[:, None, :]
    for k in range(6):
        v = vmax * k / 5
        y = mt + round((1 - k / 5) * (bh - 1))
        img[y, bx + bar_w:bx + bar_w + 5] = 0
        texts.append((bx + bar_w + 8, y, f"{v:g}", 12, (0, 0, 0), "left", "center"))
    texts.append((bx, mt - 10, "dE*ab", 12, (0, 0, 0), "left", "bottom"))

    buf = oiio.ImageBuf(oiio.ImageSpec(W, H, 3, "float"))
    buf.set_pixels(oiio.ROI(0, W, 0, H), img.astype(np.float32) / 255.0)
    font = font_path("DroidSans")
    for x, y, text, size, col, align, valign in texts:
        if not oiio.ImageBufAlgo.render_text(buf, int(x), int(y), drawable_text(text), int(size), font, col, align,
                                             valign):
            raise SwatchError(f"cannot draw text on the ΔE map: {buf.geterror()}")
    pixels = buf.get_pixels(oiio.FLOAT)
    if pixels is None:
        raise SwatchError(f"cannot read back the ΔE map: {buf.geterror()}")
    out = np.clip(np.round(pixels.reshape(H, W, 3) * 255.0), 0, 255).astype(np.uint8)
    data = {"light_deg": lv, "view_deg": vv, "grid": grid, "excluded": excluded, "signed": signed, "vmax": vmax}
    return out, data
