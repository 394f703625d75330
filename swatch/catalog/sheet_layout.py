"""A catalog sheet's pixel geometry (:class:`Layout`) and the text of its tiles' labels.

The label of a tile: thickness and voltage, L*a*b* and L*C*h at the reference geometry, the
sRGB hex with a flat chip of that colour, ΔE2000 to the neighbours, the process window and the
3-D presets' errors (:func:`label_lines`, :func:`chip_line`). The page's explorer places its
tiles with the same :class:`Layout`.
"""
from __future__ import annotations

from swatch.catalog.spec import CatalogSpec
from swatch.catalog.tiles import AMAP_ANGLES_DEG, AMAP_CELL_PX
from swatch.io.drawing import text_width

__all__ = ["Layout", "label_lines", "chip_line", "label_width", "fit_text", "PAGE", "CARD", "INK", "MUTED", "RULE"]

# page colours (display sRGB)
PAGE = (238, 238, 240)
CARD = (255, 255, 255)
INK = (20, 20, 24)
MUTED = (88, 88, 96)
RULE = (200, 200, 206)

class Layout:
    """Pixel geometry of a sheet for a spec: margins, header, footer and the tiles' grid.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec (its sheet grid, render size and angular map).

    Attributes
    ----------
    size : int
        A render's side, px.
    amap : int
        The angular map's side, px (0 without one).
    tile_w, tile_h : int
        A tile's size, px.
    width, height : int
        The sheet's size, px (at least 900 wide).
    cols, rows : int
        Tiles across and down a sheet (the spec's ``[sheet]``).
    """

    PAD = 14
    GAP = 10
    GUTTER = 14
    MARGIN = 28
    HEADER = 112
    FOOTER = 44
    LINE = 20
    LABEL_LINES = 8  # title, 6 colour/window lines, the 3-D presets' errors
    TEXT_W = 250  # room for the longest label line (26 characters of 15 px DroidSansMono)

    def __init__(self, spec: CatalogSpec):
        s = spec.size_px
        n = len(spec.tile_renders)  # the shapes, and the part
        self.size = s
        self.amap = (AMAP_ANGLES_DEG.size * AMAP_CELL_PX) if spec.angular_map else 0
        self.renders_w = n * s + (n - 1) * self.GAP
        self.label_h = self.LABEL_LINES * self.LINE + 6
        text_and_map = self.TEXT_W + (self.amap + self.GAP if self.amap else 0)
        self.tile_w = max(self.renders_w, text_and_map) + 2 * self.PAD
        self.tile_h = self.PAD + s + self.GAP + max(self.label_h, self.amap) + self.PAD
        self.cols, self.rows = spec.columns, spec.rows
        self.width = 2 * self.MARGIN + self.cols * self.tile_w + (self.cols - 1) * self.GUTTER
        self.height = self.HEADER + self.rows * self.tile_h + (self.rows - 1) * self.GUTTER + self.FOOTER + self.MARGIN
        self.width = max(self.width, 900)

    def tile_origin(self, slot: int) -> tuple[int, int]:
        """The top-left corner of a tile slot (row-major).

        Parameters
        ----------
        slot : int
            From 0.

        Returns
        -------
        (int, int)
            (x, y), px.
        """
        r, c = divmod(slot, self.cols)
        return (self.MARGIN + c * (self.tile_w + self.GUTTER), self.HEADER + r * (self.tile_h + self.GUTTER))



def _fmt(x, nd: int) -> str:
    return "–" if x is None else f"{x:.{nd}f}".replace("-", "−")


def fit_text(text: str, size: int, max_w: int, font: str) -> str:
    """``text`` shortened with an ellipsis to fit ``max_w`` pixels.

    Parameters
    ----------
    text : str
        The line to draw.
    size : int
        Font size, px.
    max_w : int
        px.
    font : str
        The font's name (``DroidSans-Bold`` …, a bundled font).

    Returns
    -------
    str
        ``text`` itself when it fits, else its longest prefix that fits followed by ``…``.
    """
    if text_width(text, size, font) <= max_w:
        return text
    # the longest prefix that fits with the ellipsis, by bisection (a prefix is never wider than a longer
    # one): ~log2(len) measurements instead of one per character cut (a 3-column sheet's header and
    # footer lines cost 246 measurements, 0.24 CPU-s a build)
    lo, hi = 0, len(text) - 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if text_width(text[:mid] + "…", size, font) <= max_w:
            lo = mid
        else:
            hi = mid - 1
    return text[:lo] + "…"


def _num(x, width: int, nd: int) -> str:
    return ("–" if x is None else f"{x:.{nd}f}").replace("-", "−").rjust(width)


def label_lines(rec: dict) -> list[str | None]:
    """A tile's label text: the title (thickness to 0.1 nm, voltage), then the colour and window lines in
    DroidSansMono (None: the chip, hex and colour name line, :func:`chip_line`).

    Parameters
    ----------
    rec : dict
        The swatch's record (catalog.json).

    Returns
    -------
    list of str or None
        The lines, top to bottom; None stands for the chip line.
    """
    L, a, b = rec["Lab"]
    _, C, hue = rec["LCh"]
    pw = rec["process_window"]
    n = rec["delta_E_00_to_neighbours"]
    volts = "" if rec["voltage_V"] is None else f"  ·  {rec['voltage_V']:.1f} V"
    lines: list[str | None] = [
        f"{rec['thickness_nm']:.1f} nm{volts}",
        f"L*a*b* {_num(L, 5, 1)}{_num(a, 7, 1)}{_num(b, 7, 1)}",
        f"L*C*h  {_num(L, 5, 1)}{_num(C, 7, 1)}{_num(hue, 6, 0)}°",
        None,  # chip + hex + colour name
        f"ΔE00 prev{_num(n['previous'], 5, 1)} next{_num(n['next'], 5, 1)}",
        # the tolerance the window is judged in is the header's (one a catalog): the line fits the label
        f"window{_num(-pw['thickness_minus_nm'], 5, 1)}/+{pw['thickness_plus_nm']:.1f} nm",
    ]
    if rec.get("presets"):  # max ΔE2000 (0–60°) of the glTF (as three.js shows it) / Blender / MaterialX presets
        p = rec["presets"]
        lines.append(f"glTF {_fmt(p['threejs_max_delta_E_00'], 1)} Bl {_fmt(p['blender_max_delta_E_00'], 1)}"
                     f" MtlX {_fmt(p['materialx_max_delta_E_00'], 1)}")
    return lines


def chip_line(rec: dict) -> str:
    """The text beside a tile's small chip: the hex code and the colour name.

    Parameters
    ----------
    rec : dict
        The swatch's record (catalog.json).

    Returns
    -------
    str
        ``#rrggbb  colour name``.
    """
    return f"{rec['srgb_hex']}  {rec['colour_name']}"


def label_width(lay: Layout) -> int:
    """Width of a tile's label block (beside the angular map when there is one).

    Parameters
    ----------
    lay : Layout
        The sheet's pixel geometry.

    Returns
    -------
    int
        px.
    """
    return lay.tile_w - 2 * lay.PAD - (lay.amap + lay.GAP if lay.amap else 0)
