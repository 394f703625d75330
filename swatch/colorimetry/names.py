"""Words designers use for anodised colours: a plain name from CIELAB lightness, chroma and hue.

The names are the trade's (bronze, gold, straw, purple, violet, blue, silver blue, magenta, pink,
mauve, teal, green, silver ...) given to regions of L*C*h (the catalog's illuminant and observer,
reference geometry). They are labels for people, not measurements: the numbers stay beside them.
They follow hue as the published titanium anodising voltage charts name it, in their order
(bronze/gold, purple, blue, light blue, yellow/gold, rose/magenta, purple/violet, teal/green …;
tests/production/test_colour_names.py walks the model's colours up the voltage scale against that
order): a blue-violet between purple and blue is "violet", a pale greyish purple (the third
order's 275 nm, #a28bb0) "mauve", not "blue" (issue 35).

:data:`NAME_RULES` is the one definition: rows ``(name, h_from, h_to, C_min, C_max, L_min, L_max)``
tried in order, the first whose bounds all hold wins (hue in ``[h_from, h_to)`` degrees, wrapping
through 0 when ``h_from > h_to``; ``C_min <= C* < C_max``; ``L_min <= L* < L_max``; None = no bound).
The page embeds the same rows for its live readout.

One vocabulary: the sheets' labels, the page (cards, its colour filter, the live readout, compare) and
the ASE swatch names all say these names (issue 21: the sheets said "yellow" for straw and "red" for
plum). ``catalog.json`` and ``catalog.csv`` carry the name as ``colour_name``, beside ``hue_family``,
the coarse CIELAB hue-angle class (:data:`swatch.catalog.records.HUE_FAMILIES`) kept for data users.

References
----------
.. [1] :cite:`Carter2018`: CIELAB and LCh(ab).
"""
from __future__ import annotations

__all__ = ["colour_name", "colour_names", "NAME_RULES", "NEUTRAL_CHROMA"]

#: Below this chroma a colour is "silver" (and its hue family "neutral").
NEUTRAL_CHROMA = 10.0

NAME_RULES: tuple[tuple, ...] = (
    ("silver blue", 180.0, 272.0, 5.0, NEUTRAL_CHROMA, None, None),  # a grey with a cool tint
    ("silver", 0.0, 360.0, None, NEUTRAL_CHROMA, None, None),
    ("silver blue", 228.0, 272.0, None, 25.0, 65.0, None),  # pale light blue
    ("blue", 228.0, 272.0, None, None, None, None),
    ("mauve", 272.0, 325.0, None, 25.0, 50.0, None),  # pale greyish purple (the third order's 275 nm)
    ("violet", 272.0, 295.0, None, None, None, None),  # blue-violet, between purple and blue
    ("teal", 185.0, 228.0, 20.0, None, None, None),
    ("silver blue", 185.0, 228.0, None, None, None, None),
    ("green", 135.0, 185.0, None, None, None, None),
    ("straw", 105.0, 135.0, None, 35.0, None, None),  # pale yellow-green reads as straw
    ("lime", 105.0, 135.0, None, None, None, None),
    ("gold", 75.0, 105.0, 45.0, None, None, None),
    ("straw", 75.0, 105.0, None, None, None, None),
    ("bronze", 35.0, 75.0, None, None, None, 55.0),
    ("gold", 35.0, 75.0, 35.0, None, None, None),
    ("champagne", 35.0, 75.0, None, None, None, None),
    ("plum", 350.0, 35.0, None, None, None, 45.0),
    ("pink", 350.0, 35.0, None, None, None, None),
    ("magenta", 325.0, 350.0, None, None, None, None),
    ("purple", 295.0, 325.0, None, None, None, None),
)


def colour_name(L: float, C: float, h: float) -> str:
    """The plain name of a colour given as CIE L*, C*ab and hue angle h (degrees).

    Parameters
    ----------
    L, C : float
        CIE 1976 lightness L* and chroma C*ab.
    h : float
        Hue angle h_ab, degrees (taken modulo 360).

    Returns
    -------
    str
        The name of the first row of :data:`NAME_RULES` whose bounds all hold.

    Examples
    --------
    >>> colour_name(60.0, 3.0, 40.0)
    'silver'
    """
    h = float(h) % 360.0
    for name, h0, h1, c0, c1, l0, l1 in NAME_RULES:
        in_hue = (h0 <= h < h1) if h0 <= h1 else (h >= h0 or h < h1)
        if (in_hue and (c0 is None or c0 <= C) and (c1 is None or c1 > C)
                and (l0 is None or l0 <= L) and (l1 is None or l1 > L)):
            return name
    raise AssertionError("unreachable: every hue has a row without bounds")


def colour_names() -> tuple[str, ...]:
    """Every name :func:`colour_name` can give, once each, in the order of :data:`NAME_RULES`.

    Returns
    -------
    tuple of str
        The colour names (``"silver blue"``, ``"blue"`` …), each once.
    """
    return tuple(dict.fromkeys(r[0] for r in NAME_RULES))
