"""Plain words for the catalog page: what a designer reads first, the technical code after it.

The page's codes (the measuring geometries ``45:0`` and ``45as-15``, the tolerance ``csaj grade C``,
the metric ``dEab``) stay on the page, each after a plain label: ``seen from the side (45as-15, θd
52.5°)``, ``CSAJ grade C, ΔE*ab ≤ 6.5``. The page's script names the geometries by the same rule
(``geometryWords`` in ``web/page.js``; tests/catalog/test_catalog_layout_browser.py compares them).
"""
from __future__ import annotations

import html

from swatch.physics.materials import metal_name

__all__ = ["METRIC_SYMBOLS", "SCHEME_NAMES", "aspecular_deg", "geometry_words", "tolerance_words", "explain_html",
           "geometry_list_html"]

#: How the page writes a colour-difference metric (swatch.colorimetry.tolerance.METRICS).
METRIC_SYMBOLS = {"dEab": "ΔE*ab", "dE00": "ΔE00"}
#: How the page writes a tolerance scheme (tables/tolerance_grades.csv).
SCHEME_NAMES = {"csaj": "CSAJ", "nbs": "NBS"}
#: A view closer than this to the surface's normal (degrees) is "face on".
FACE_ON_DEG = 2.5


def aspecular_deg(g: dict) -> float:
    """The aspecular angle of an in-plane geometry: the view's angle from the mirror direction, towards
    the light (ASTM E2194; negative: past the mirror direction, away from the light).

    Parameters
    ----------
    g : dict
        A geometry of ``catalog.json`` (``light_deg``, ``view_deg``, ``view_side``; its ``aspecular_deg``
        where it has one).

    Returns
    -------
    float
        The aspecular angle, degrees.

    Examples
    --------
    >>> aspecular_deg({"light_deg": 45.0, "view_deg": 0.0, "view_side": "opposite"})
    45.0
    >>> aspecular_deg({"light_deg": 45.0, "view_deg": 65.0, "view_side": "light"})
    110.0
    """
    if g.get("aspecular_deg") is not None:
        return float(g["aspecular_deg"])
    view = float(g["view_deg"])
    return float(g["light_deg"]) + (view if g.get("view_side") == "light" else -view)


def geometry_words(g: dict) -> str:
    """Where a geometry looks from, in plain words: ``face on``, ``from the side`` (past the gloss, the
    mirror direction), ``near the gloss``, ``off the gloss``, ``far from the gloss`` or ``from beside the
    light``, by its view and aspecular angles (:func:`aspecular_deg`).

    Parameters
    ----------
    g : dict
        A geometry of ``catalog.json`` (``light_deg``, ``view_deg``, ``view_side``, optional ``aspecular_deg``).

    Returns
    -------
    str
        The plain name; the page writes the geometry's code after it.

    Examples
    --------
    >>> geometry_words({"light_deg": 45.0, "view_deg": 0.0, "view_side": "opposite"})
    'face on'
    >>> [geometry_words({"light_deg": 45.0, "view_deg": v, "view_side": side})  # 45as-15, 15, 25, 75, 110
    ...  for v, side in ((60, "opposite"), (30, "opposite"), (20, "opposite"), (30, "light"), (65, "light"))]
    ['from the side', 'near the gloss', 'off the gloss', 'far from the gloss', 'from beside the light']
    """
    if float(g["view_deg"]) < FACE_ON_DEG:
        return "face on"
    a = aspecular_deg(g)
    if a < 0:
        return "from the side"
    if a <= 20:
        return "near the gloss"
    if a <= 60:
        return "off the gloss"
    if a <= 90:
        return "far from the gloss"
    return "from beside the light"


def tolerance_words(t: dict) -> str:
    """A tolerance as the page writes it: the grade's scheme and name where it has one, then its bound in
    its own metric (``CSAJ grade C, ΔE*ab ≤ 6.5``; a written tolerance: ``ΔE00 ≤ 2``).

    Parameters
    ----------
    t : dict
        ``catalog.json``'s ``tolerance``, or a record's ``process_window`` (``scheme``, ``grade``,
        ``metric``, ``max``).

    Returns
    -------
    str
        The tolerance in short words.

    Examples
    --------
    >>> tolerance_words({"scheme": "csaj", "grade": "C", "metric": "dEab", "max": 6.5})
    'CSAJ grade C, ΔE*ab ≤ 6.5'
    >>> tolerance_words({"scheme": None, "grade": "dE00 ≤ 2", "metric": "dE00", "max": 2.0})
    'ΔE00 ≤ 2'
    """
    bound = f"{METRIC_SYMBOLS.get(t['metric'], t['metric'])} ≤ {t['max']:g}"
    scheme = t.get("scheme")
    if not scheme:
        return bound
    return f"{SCHEME_NAMES.get(scheme, scheme)} grade {t.get('grade')}, {bound}"


def explain_html(c: dict) -> str:
    """The page's explanations under *Technical details*: how the colour is measured, the colour at other
    angles, how forgiving a colour is, screen colours; each summary in plain words with its code after it.

    Parameters
    ----------
    c : dict
        ``catalog.json``'s ``catalog`` (its reference and multi-angle geometries and its tolerance).

    Returns
    -------
    str
        HTML (every text from the catalog escaped): a ``div.explain`` of ``details`` elements.
    """
    e = html.escape
    ref = c["reference_geometry"]
    pw = c["tolerance"]
    names = geometry_list_html(c["multi_angle_geometries"])
    return f"""<div class="explain">
<details><summary>How the colour is measured ({e(ref["name"])})</summary><p>The colour numbers are measured as a
colour instrument does: light from {ref["light_deg"]:g}° off the surface's normal, viewed at
{ref["view_deg"]:g}° (straight on for 0°). The film's colour is that of the tiny facets tilted to
reflect the light into your eye; at {e(ref["name"])} they meet the light at θd = {ref["theta_d_deg"]:g}°.
Anodised {e(metal_name(c["substrate"]))} changes colour with angle, so every number says its geometry.</p></details>
<details><summary>The colour at other angles (multi-angle codes)</summary><p>Under each chip, left to right: {names}. The light
stays at 45°; “as15” means the viewer is 15° away from the gloss (the mirror direction), “as−15” 15°
past it (further from the light), “as110” far from it, beside the light. Near the gloss the colour is the brightest and
shifts most; far from it you see the colour at grazing facets.</p></details>
<details><summary>How forgiving a colour is (process window and grade)</summary><p>How far the oxide may drift (thinner / thicker,
and the anodising voltage that makes that drift) before the colour moves further from the nominal swatch
than the colour tolerance, {e(tolerance_words(pw))}, judged in the metric it is defined in{
"" if not pw.get("grade_description") else f" ({e(pw['grade_description'])})"}. A wide window means a forgiving
colour; a narrow one needs tight voltage control.</p></details>
<details><summary>Screen colours and dashed chips (sRGB, Display P3)</summary><p>Chips are CIE 1931 2° colorimetry
shown in sRGB, or in Display P3 on wide-gamut screens. Some interference colours lie outside sRGB:
those chips are clipped, marked “outside sRGB” and outlined with a dashed line (multi-angle patches
too).</p></details>
</div>"""


def geometry_list_html(geometries: list[dict]) -> str:
    """The multi-angle geometries in plain words, each with its code after it.

    Parameters
    ----------
    geometries : list of dict
        ``catalog.json``'s ``multi_angle_geometries``, in the page's order.

    Returns
    -------
    str
        ``from the side (45as-15), near the gloss (45as15), …`` (HTML, the codes escaped), or ``none``.
    """
    return ", ".join(f'{geometry_words(g)} ({html.escape(g["name"])})' for g in geometries) or "none"
