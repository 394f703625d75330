"""``index.html``: the catalog page — a grid of cards that works without JavaScript, and an
explorer on top of it (live WebGL view, compare, find by colour, ``window.swatchCatalog``).

No server and no network: the page's CSS and JavaScript (``swatch/catalog/web/*.css|js``)
are inlined; the catalog and the colour table (:mod:`swatch.catalog.explorer`) are embedded as
JSON in ``<script type="application/json">`` blocks (``<``, ``>`` and ``&`` written as
``\\u003c`` ... so no text from a spec can close a block). The cards are written here, every
datum escaped; the script fills in the rest through ``textContent`` or validated colours, never
``innerHTML``. The Content-Security-Policy allows only this page's own script (by hash), inline
styles (chip colours), the catalog's own images (the sheet PNGs next to the page, from which
the cards cut their renders and angular maps) and nothing from the network.
"""
from __future__ import annotations

import base64
import hashlib
import html
import json
import re
from importlib import resources

from swatch.catalog.ar import STYLE as AR_STYLE
from swatch.catalog.ar import ar_control_html, ar_csp, has_viewer
from swatch.catalog.words import METRIC_SYMBOLS, explain_html, geometry_list_html, geometry_words, tolerance_words
from swatch.colorimetry.names import colour_names
from swatch.core.choices import POINT_LIGHT, lightings_of
from swatch.physics.growth import voltage_text
from swatch.physics.materials import metal_name

__all__ = ["index_html", "embed_json", "hero_png", "page_script", "page_style", "print_page_style", "css_string"]

#: The page's script files, concatenated in this order inside one strict-mode function.
SCRIPTS = ("colour.js", "microfacet.js", "envlight.js", "view.js", "link.js", "page.js")
#: Labels of the live view's lighting choices (swatch.core.choices.LIGHTINGS): plain words, the name after
#: (short: the menu fits a phone's width).
LIGHTING_LABELS = {"point": "one lamp (point light)", "uniform": "even white light (uniform)",
                   "studio": "photo studio (as the sheets)"}
#: Width (CSS px) of a render and of the angular map in a card.
CARD_IMAGE_PX = 96


def embed_json(obj) -> str:
    r"""JSON safe to place inside a ``<script type="application/json">`` element (``&``, ``<``, ``>`` and
    the line separators escaped).

    Parameters
    ----------
    obj : object
        JSON-serialisable (no NaN).

    Returns
    -------
    str
        Compact JSON (no spaces) with those characters written as ``\uXXXX`` escapes.

    Examples
    --------
    >>> embed_json({"a": "</script>"})
    '{"a":"\\u003c/script\\u003e"}'
    """
    text = json.dumps(obj, ensure_ascii=False, sort_keys=False, separators=(",", ":"), allow_nan=False)
    return (text.replace("&", "\\u0026").replace("<", "\\u003c").replace(">", "\\u003e")
            .replace("\u2028", "\\u2028").replace("\u2029", "\\u2029"))


def _asset(name: str) -> str:
    return resources.files("swatch.catalog").joinpath("web", name).read_text(encoding="utf-8")


def page_script(extra: tuple[str, ...] = ()) -> str:
    """The page's JavaScript: the modules of :data:`SCRIPTS` (then ``extra``) concatenated in one strict-mode function.

    Parameters
    ----------
    extra : tuple of str, optional
        More script files of web/ (``ar.js`` with AR on: swatch.catalog.ar).

    Returns
    -------
    str
        The script text, inlined in the page (its hash goes in the content security policy).
    """
    body = "\n".join(_asset(n) for n in SCRIPTS + tuple(extra))
    return f'\n"use strict";\n(function () {{\n{body}\n}})();\n'


def page_style() -> str:
    """The page's stylesheet (``web/page.css``).

    Returns
    -------
    str
        The CSS text, inlined in the page.
    """
    return _asset("page.css")


def css_string(text: str) -> str:
    """``text`` as a double-quoted CSS string, every character outside printable ASCII letters, digits,
    space and a few marks written as a CSS escape (no text from a spec can end the string or the
    ``<style>`` element).

    Parameters
    ----------
    text : str
        Any text (from a spec: untrusted).

    Returns
    -------
    str
        The quoted, escaped CSS string.
    """
    safe = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 .,:;()+-_/=%")
    return '"' + "".join(ch if ch in safe else f"\\{ord(ch):x} " for ch in str(text)) + '"'


def print_page_style(c: dict) -> str:
    """The printed pages' margin boxes: the catalog and its process at the top of every page, the page
    number at the bottom (CSS paged media, ``@page`` margin boxes).

    Parameters
    ----------
    c : dict
        ``catalog.json``'s ``catalog``.

    Returns
    -------
    str
        CSS ``@page`` rules, their text escaped (:func:`css_string`).
    """
    top = f"{c['name']} · {c['film']} on {c['substrate']} · process {c['process']['name']}: {_growth_text(c['process'])}"
    box = "font: 8pt system-ui, \"DejaVu Sans\", sans-serif; color: #555"
    return (f"@page {{ @top-left {{ content: {css_string(top)}; {box}; }} "
            f"@bottom-right {{ content: \"page \" counter(page) \" of \" counter(pages); {box}; }} }}")


def _fmt(x, n: int) -> str:
    return "–" if x is None else f"{x:.{n}f}"


def _chip_style(hex_code: str, p3=None) -> str:
    style = f"background-color:{hex_code}"
    if p3 is not None:  # browsers without color() drop this declaration and keep the hex
        style += ";background-color:color(display-p3 " + " ".join(f"{v:.4f}" for v in p3) + ")"
    return style


def _sprite(sheet: str, rect, origin, sheet_px, px: int, cls: str, label: str) -> str:
    x, y, w, h = rect
    k = px / w
    style = (f"width:{px}px;height:{round(h * k)}px;background-image:url({html.escape(sheet)});"
             f"background-size:{sheet_px[0] * k:.2f}px {sheet_px[1] * k:.2f}px;"
             f"background-position:{-(origin[0] + x) * k:.2f}px {-(origin[1] + y) * k:.2f}px")
    return f'<div class="{cls}" role="img" aria-label="{html.escape(label)}" data-src-px="{int(w)}" style="{style}"></div>'


#: A hero's file as the page accepts it: a relative path of plain characters, a PNG (the build writes
#: ``heroes/hero_S001.png``; a record read back is not trusted to name anything else).
HERO_PATH = re.compile(r"[A-Za-z0-9_-]+(/[A-Za-z0-9_-]+)*\.png")
#: Largest width (CSS px) of a hero in a card: half its pixels (sharp on a 2x display), at least
#: :data:`CARD_IMAGE_PX` (as the tile renders beside it).
CARD_HERO_MAX_PX = 150


def hero_png(s: dict) -> str | None:
    """The relative path of a record's hero render (``s["hero"]["png"]``), or None when it has none or
    names anything but a plain relative PNG path (:data:`HERO_PATH`).

    Parameters
    ----------
    s : dict
        A swatch record (``catalog.json``).

    Returns
    -------
    str or None
        The path relative to the catalog folder (``heroes/…png``), or None.
    """
    h = s.get("hero")
    png = h.get("png") if isinstance(h, dict) else None
    return png if isinstance(png, str) and HERO_PATH.fullmatch(png) else None


def _hero_img(s: dict) -> str:
    png = hero_png(s)
    if png is None:
        return ""
    size = s["hero"].get("size_px")
    px = min(CARD_HERO_MAX_PX, max(CARD_IMAGE_PX, int(size) // 2)) if isinstance(size, int) and size > 0 else 96
    what = f'{s["hero"].get("shape", "sphere")} under the {s["hero"].get("lighting", "studio")} light'
    data = f' data-px="{int(size)}"' if isinstance(size, int) and size > 0 else ""
    return (f'<img class="hero" src="{html.escape(png)}" width="{px}" height="{px}"{data} loading="lazy" '
            f'alt="{html.escape(s["id"])}: {_fmt(s["thickness_nm"], 1)} nm, path-traced {html.escape(what)}">')


def _card(s: dict, c: dict, tiles: dict | None, chips: dict | None, ar: bool = False) -> str:
    e = html.escape
    ref = c["reference_geometry"]["name"]
    seen = f'seen {geometry_words(c["reference_geometry"])}'  # the reference geometry in plain words
    gam = "" if s["in_srgb_gamut"] else '<span class="gamut">outside sRGB</span>'
    chip_html = (f'<div class="chip{"" if s["in_srgb_gamut"] else " out-of-gamut"}" style="{_chip_style(s["srgb_hex"], chips and chips["p3"])}" title="{e(s["srgb_hex"])} {seen} (sRGB at {e(ref)})">'
                 f'{gam}</div>')
    out = [f'<article class="card" id="card-{e(s["id"])}" data-id="{e(s["id"])}">']
    hero = _hero_img(s)
    # the hero (a path-traced picture of the swatch on the metal) first, the flat chip beside it; else the chip
    out.append(f'<div class="hero-row">{hero}{chip_html}</div>' if hero else chip_html)
    if c["multi_angle_geometries"]:
        out.append('<div class="flop">')
        for g in c["multi_angle_geometries"]:
            lab = " ".join(_fmt(v, 1) for v in s["multi_angle"][g["name"]])
            oog = chips is not None and not chips["multi_in_srgb_gamut"].get(g["name"], True)
            cls, note = (' class="out-of-gamut"', " (outside sRGB: clipped)") if oog else ("", "")
            out.append(f'<span{cls} style="background-color:{e(s["multi_angle_srgb_hex"][g["name"]])}" '
                       f'title="seen {geometry_words(g)} ({e(g["name"])}): L*a*b* {lab}{note}"></span>')
        out.append("</div>")
    if tiles is not None:
        origin = tiles["origins"][s["id"]]
        out.append('<div class="imgs">')
        names = list(c["render"]["shapes"]) + (["part"] if c["render"].get("mesh") else [])
        for shape, rect in zip(names, tiles["renders"], strict=True):
            out.append(_sprite(s["sheet_png"], rect, origin, tiles["sheet_px"], CARD_IMAGE_PX, "render",
                               f"{shape} render, light 45°"))
        if tiles["amap"] is not None:
            lo, hi = tiles["amap_deg"]
            out.append(f'<figure class="map"><span class="ylab">light {lo:g}–{hi:g}° →</span>'
                       + _sprite(s["sheet_png"], tiles["amap"], origin, tiles["sheet_px"], CARD_IMAGE_PX, "amap",
                                 "the colour at every light and view angle (angular map: light up, view across)")
                       + f'<span></span><span class="xlab">view {lo:g}–{hi:g}° →</span></figure>')
        out.append("</div>")
    pw = s["process_window"]
    # plain words first, the code after them (label, code, value)
    rows = [
        (f"colour {seen}", f"L*a*b*, {ref}", "  ".join(_fmt(v, 2) for v in s["Lab"])),
        ("lightness, chroma, hue", "L*C*h", f'{_fmt(s["LCh"][0], 2)}  {_fmt(s["LCh"][1], 2)}  {_fmt(s["LCh"][2], 1)}°'),
        ("forgives a drift of", f'process window, {METRIC_SYMBOLS.get(pw["metric"], pw["metric"])} ≤ {pw["max"]:g}',
         f'−{_fmt(pw["thickness_minus_nm"], 1)} / +{_fmt(pw["thickness_plus_nm"], 1)} nm'),
        ("", "", f'−{_fmt(pw["voltage_minus_V"], 2)} / +{_fmt(pw["voltage_plus_V"], 2)} V'),
        ("step to the neighbours", "ΔE00 previous / next", f'{_fmt(s["delta_E_00_to_neighbours"]["previous"], 2)} / '
                                                           f'{_fmt(s["delta_E_00_to_neighbours"]["next"], 2)}'),
    ]
    out.append('<div class="body">')
    volts = "" if s["voltage_V"] is None else f' · {_fmt(s["voltage_V"], 1)} V'
    out.append(f'<div class="title">{_fmt(s["thickness_nm"], 1)} nm{volts}'
               f'<span class="hex">{e(s["srgb_hex"])}</span></div>')
    # the name holds at the reference geometry (the live view names the colour at its own angle)
    name = s.get("colour_name", "")
    out.append(f'<div class="name">{e(name)} {seen} <span class="code">({e(ref)})</span></div>' if name else
               '<div class="name"></div>')
    out.append("<table><tbody>" + "".join(f'<tr><td>{_label(k, code)}</td><td class="num">{e(v)}</td></tr>'
                                          for k, code, v in rows) + "</tbody></table>")
    if c["multi_angle_geometries"]:
        out.append(f"<details><summary>colour at other angles {_label('', 'multi-angle L*a*b*')}</summary>"
                   '<table class="multi"><tbody>')
        for g in c["multi_angle_geometries"]:
            lab = "  ".join(_fmt(v, 2) for v in s["multi_angle"][g["name"]])
            code = f'{g["name"]}, θd {_fmt(g["theta_d_deg"], 1)}°'
            out.append(f'<tr><td>{_label("seen " + geometry_words(g), code)}</td><td class="num">{lab}</td></tr>')
        out.append("</tbody></table></details>")
    out.append(f'<div class="links"><a href="{e(s["sheet_png"])}">sheet {s["sheet"]} (PNG)</a>'
               f'<a href="{e(s["sheet_exr"])}">EXR</a></div>')
    chip = s.get("print_chip")
    if chip:  # the swatch's print chip: 16-bit sRGB, at print size
        out.append(f'<div class="links chips"><span>print chip {_fmt(chip["size_mm"], 0)} mm, {chip["dpi"]} dpi:</span>'
                   f'<a href="{e(chip["png"])}">PNG</a><a href="{e(chip["tiff"])}">TIFF</a></div>')
    p = s.get("presets")
    if p:  # 3-D material presets, each with its max ΔE2000 in its renderer (glTF: three.js; D65, 2°, 0–60°; title: 0–45°)
        kinds = (("gltf", "glTF", "threejs_max_delta_E_00"), ("blender", "Blender", "blender_max_delta_E_00"),
                 ("materialx", "MaterialX", "materialx_max_delta_E_00"))
        title = ("3-D material presets; max " + str(p.get("conditions", "")) + "; at 0–45°: "
                 + ", ".join(f"{label} {_fmt(p.get(dk + '_45'), 1)}" for _, label, dk in kinds))
        out.append(f'<div class="links presets" title="{e(title)}"><span>3-D material presets (largest colour error, ΔE00):</span>'
                   + "".join(f' <a href="{e(str(p[k]))}">{label} {_fmt(p.get(dk), 1)}</a>'
                             for k, label, dk in kinds if p.get(k))  # a space before each: the line may break there
                   + (f' <a href="{e(str(p["mitsuba"]))}" title="Mitsuba 3 with swatch\'s anodic_film BSDF: the exact '
                      f'model, nothing fitted">Mitsuba (exact)</a> <a href="{e(str(p["mitsuba_json"]))}">JSON</a>'
                      if p.get("mitsuba") and p.get("mitsuba_json") else "")
                   + "</div>")
    out.append((ar_control_html(s) if ar else "") + "</div></article>")
    return "".join(out)


def _label(words: str, code: str) -> str:
    """A label in plain words with its code after it, in parentheses (smaller, on its own line in a card)."""
    e = html.escape
    tail = f' <span class="code">({e(code)})</span>' if code else ""
    return f'<span class="words">{e(words)}</span>{tail}' if words else tail.lstrip()


def _growth_text(process: dict) -> str:
    if process["nm_per_V"] is None:
        return "no growth rate (thicknesses only)"
    text = f"{process['nm_per_V']:g} nm/V + {process['offset_nm']:g} nm"
    if "knee_V" in process:
        text += f" to {voltage_text(process['knee_V'])} V, then {process['nm_per_V_above_knee']:g} nm/V"
    if "spread_nm" in process:
        text += f"; thickness spread {process['spread_nm']:g} nm + {100 * process['spread_fraction']:g} % (1σ)"
    return text


def _palette(swatches: list[dict]) -> str:
    """A band of the catalog's colours in its order (sRGB at the reference geometry): the range at a glance."""
    if not swatches:
        return ""
    e = html.escape
    first, last = swatches[0], swatches[-1]
    label = (f"the catalog's {len(swatches)} colours, {_fmt(first['thickness_nm'], 0)} to "
             f"{_fmt(last['thickness_nm'], 0)} nm, in order")
    return (f'<div class="palette" role="img" aria-label="{e(label)}">'
            + "".join(f'<span style="background-color:{e(s["srgb_hex"])}"></span>' for s in swatches) + "</div>")


def _lighting_select(env: dict | None) -> str:
    """The live view's lighting choice: the point light, and the environments the page embeds."""

    names = [n for n in lightings_of("builtin") if n == POINT_LIGHT or (env is not None and n in env["environments"])]
    # with the heroes' studio set, the studio is theirs (the path tracer's), not the sheets'
    labels = LIGHTING_LABELS | ({"studio": "photo studio (as the path-traced pictures)"} if env is not None and "set" in env else {})
    opts = "".join(f'<option value="{html.escape(n)}">{html.escape(labels.get(n, n))}</option>' for n in names)
    return f'<label>lighting<select id="lighting">{opts}</select></label>'


def _tools(c: dict, env: dict | None = None) -> str:
    ref = c["reference_geometry"]
    return f"""<section id="explorer" class="tool" hidden aria-label="live view">
<div class="stage"><div class="frame"><canvas id="view" width="800" height="600" tabindex="0" role="img"
aria-label="live view of the swatch: drag, or use the arrow keys, to turn it"></canvas>
<p id="hero-badge" hidden></p></div>
<div id="finish-bar" class="finish-bar" role="group" aria-label="finish of the metal" hidden></div>
<p class="hint stage-hint">Drag the picture to turn the part, or focus it and use the arrow keys.</p></div>
<div class="panel">
<h2>Live view</h2>
<form id="live-form" autocomplete="off">
<label><span>thickness <strong id="t-out"></strong> · voltage <strong id="v-out"></strong></span>
<input id="thickness" type="range" step="0.1" aria-label="thickness (nm)"></label>
<label id="voltage-range-label"><span>voltage (through the process's growth law)</span>
<input id="voltage-range" type="range" step="0.05" aria-label="voltage (V)"></label>
<div class="pair"><label>voltage (V)<input id="voltage" type="number" step="0.1"></label>
<label>shape<select id="shape"><option value="plate">plate</option><option value="bent sheet">bent sheet (half cylinder)</option>
<option value="sphere">sphere</option></select></label>
<label>surface<select id="model"><option value="microfacet">realistic metal (microfacet D·G)</option>
<option value="paper">flat colour, no gloss (paper model)</option></select></label></div>
<div class="pair">{_lighting_select(env)}</div>
<label><span>light angle <strong id="l-out"></strong></span><input id="light" type="range" min="0" max="85" step="0.5"></label>
<label><span>light direction around the part <strong id="la-out"></strong> (azimuth)</span><input id="light-azimuth" type="range" min="-180" max="180" step="1"></label>
<label><span>fill light <strong id="f-out"></strong> (with the lamp: white light from all around; 1 shows white paper
as white, 0 is the bare lamp, black where it does not reach)</span><input id="fill" type="range" min="0" max="1" step="0.01"></label>
<label><span>view angle <strong id="w-out"></strong></span><input id="view-deg" type="range" min="0" max="85" step="0.5"></label>
</form>
<div class="readout">
<div class="chip" id="state-chip"></div><div><strong id="state-label">this light and view</strong> <span id="state-gamut" class="gamut-note">(outside sRGB)</span><br><span id="state-text" class="num"></span></div>
<div class="chip" id="ref-chip"></div><div><strong>the catalog's colour, seen {geometry_words(ref)} (reference {html.escape(ref["name"])})</strong><br><span id="ref-text" class="num"></span></div>
</div>
<div><button type="button" id="pin">pin for comparison</button></div>
<p class="hint" id="view-note">The light stays where it is when you turn the part. Lighting: the photo studio of
the sheets' renders, even white light, or one lamp with a fill light (white light from all around).</p>
<details class="how"><summary>How the live view is drawn</summary><p class="hint">Colours are the thin-film
physics of this catalog (embedded table), shaded with the microfacet model. Under the studio or uniform white
the light is integrated over the microfacet lobe at exposure 1 (a white diffuser would be white), as
<code>swatch render --environment</code>; the point light's angle is on its slider, the exposure from the
picture, and its fill (1 = the light that shows white paper as white) shows the side away from the light in the
film's colour, dimmed rather than black. Outlines are antialiased. Where the catalog has path-traced heroes
(Mitsuba), the picture is the hero while the view is at the hero's state, and the live render once you change it.</p></details>
</div>
</section>
<section id="find" class="tool" hidden aria-label="find by colour">
<h2>Find by colour</h2>
<form id="find-form" class="pair" autocomplete="off">
<label>colour code (hex)<input id="find-hex" type="text" size="9" placeholder="#2275b5"></label>
<label>or lightness, a, b (L*a*b*)<input id="find-lab" type="text" size="16" placeholder="47.5, -1.5, -40.8"></label>
<label>or pick a colour<input id="find-picker" type="color" value="#2275b5"></label>
<button type="submit">find</button>
</form>
<div class="find-target" id="find-target"></div>
<div class="find-verdict" id="find-verdict" role="status" hidden></div>
<ol id="find-results"></ol>
</section>
<section id="compare" class="tool" hidden aria-label="compare">
<h2>Compare</h2>
<div id="compare-list"></div>
<table id="compare-delta"></table>
</section>"""


def index_html(catalog: dict, table: dict | None = None, tiles: dict | None = None,
               chips: list[dict] | None = None, env: dict | None = None) -> str:
    """The catalog page (one self-contained HTML file: script and style inline, a content security policy
    with the script's hash).

    Parameters
    ----------
    catalog : dict
        The ``catalog.json`` document.
    table : dict, optional
        :func:`swatch.catalog.explorer.explorer_data` (without it the page is the grid only).
    tiles : dict, optional
        :func:`swatch.catalog.explorer.tile_rects`.
    chips : list of dict, optional
        :func:`swatch.catalog.explorer.chip_colours` (Display P3 chips, multi-angle gamut flags).
    env : dict, optional
        :func:`swatch.catalog.explorer_env.environment_data` (the live view's environment lighting).

    Returns
    -------
    str
        The page's HTML text (UTF-8 when written).
    """
    c = catalog["catalog"]
    e = html.escape
    ar = table is not None and has_viewer(catalog["swatches"])  # "see it in your room" (swatch.catalog.ar)
    script = page_script(("ar.js",) if ar else ()) if table is not None else ""
    script_hash = base64.b64encode(hashlib.sha256(script.encode("utf-8")).digest()).decode("ascii")
    csp = (f"default-src 'none'; style-src 'unsafe-inline'; script-src 'sha256-{script_hash}'; "
           "img-src 'self'; base-uri 'none'; form-action 'none'")
    csp = ar_csp(csp) if ar else csp
    ref = c["reference_geometry"]
    multi = geometry_list_html(c["multi_angle_geometries"])
    files = [("catalog.json", "catalog.json"), ("catalog.csv", "catalog.csv"), (c["exports"]["cxf"], "CxF3"),
             (c["exports"]["ase"], "ASE (Lab D50/2°)")]
    if c["exports"].get("ase_srgb"):
        files.append((c["exports"]["ase_srgb"], "ASE (sRGB)"))
    files += [(s["png"], f"sheet {s['number']}") for s in catalog["sheets"]]
    links = " ".join(f'<a href="{e(href)}">{e(text)}</a>' for href, text in files)
    pw = c["tolerance"]
    swatches = catalog["swatches"]
    volts_text = "" if c["process"]["nm_per_V"] is None else " and its anodising voltage"
    cards = "\n".join(_card(s, c, tiles, None if chips is None else chips[i], ar) for i, s in enumerate(swatches))
    # one vocabulary (swatch.colorimetry.names): the names in the catalog, in the order of NAME_RULES
    present = {s.get("colour_name") for s in swatches}
    families = "".join(f'<option value="{e(n)}">{e(n)}</option>' for n in colour_names() if n in present)
    tools = _tools(c, env) if table is not None else ""
    metal = e(metal_name(c["substrate"]))  # (the page's script says the same of a colour out of reach)
    blocks = f'<script type="application/json" id="catalog-data">{embed_json(catalog)}</script>\n'
    if table is not None:
        blocks += f'<script type="application/json" id="explorer-table">{embed_json(table)}</script>\n'
        if env is not None:
            blocks += f'<script type="application/json" id="explorer-env">{embed_json(env)}</script>\n'
        blocks += f"<script>{script}</script>\n"
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{e(csp)}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{e(c["name"])} · swatch catalog</title>
<style>{page_style()}{AR_STYLE if ar else ""}
{print_page_style(c)}</style>
</head>
<body>
<header>
<div class="head">
<h1 id="catalog-name">{e(c["name"])}</h1>
{_palette(swatches)}
<p class="lede">{len(swatches)} colours of anodised {metal}: a clear oxide film on the metal, coloured by light
interference, not dye. Each card is one film thickness{volts_text}. The picture is the colour on a part in a
photo studio: turn it, or slide through the colours.</p>
<p class="lede how-to"><strong>Choosing:</strong> pick a colour you like; the strip under its chip shows how it
shifts with the viewing angle; prefer a wide process window (it forgives small voltage changes). “Compare”
sets colours side by side; “Find by colour” finds the nearest to a colour code (hex) or L*a*b* numbers, and says
when anodised {metal} cannot make it.</p>
<details class="tech"><summary>Technical details: geometry, codes, tolerance, files</summary>
<p class="sub">{e(c["film"])} on {e(c["substrate"])} · {len(swatches)} swatches ·
process {e(c["process"]["name"])}: {e(_growth_text(c["process"]))} · {e(c["illuminant"])}, CIE {e(c["observer_name"])} ·
L*a*b* seen {geometry_words(ref)} ({e(ref["name"])}: light {ref["light_deg"]:g}°, view {ref["view_deg"]:g}°) · model: {e(c["model"])}
(in plain words: the colour the oxide film's light interference gives, on the tiny facets that mirror the light into the eye)</p>
<p class="sub">The colour at other angles (multi-angle; the strip under each chip, left to right): {multi} (“45as15”: light
at 45°, viewer 15° from the gloss, the mirror direction; “as−15” 15° past it). How forgiving a colour is (process window):
the thickness and voltage deviations that keep the colour difference to the nominal colour within the colour tolerance,
{e(tolerance_words(pw))}{"" if not pw.get("grade_description") else f" ({e(pw['grade_description'])})"}.</p>
{explain_html(c)}
<p class="sub files phone">Download: {links}</p>
</details>
<p class="sub files wide">Download: {links}</p>
</div>
</header>
{tools}
<section id="filters" aria-label="filter and sort the swatches"><form id="controls" autocomplete="off">
<fieldset><label>sort by<select id="sort"><option value="thickness">thickness</option>
<option value="voltage">voltage</option><option value="hue">hue (h°)</option>
<option value="lightness">lightness (L*)</option></select></label>
<label>order<select id="order"><option value="asc">ascending</option><option value="desc">descending</option></select></label></fieldset>
<fieldset><label>thickness from (nm)<input id="tmin" type="number" step="any"></label>
<label>to (nm)<input id="tmax" type="number" step="any"></label></fieldset>
<fieldset><label>voltage from (V)<input id="vmin" type="number" step="any"></label>
<label>to (V)<input id="vmax" type="number" step="any"></label></fieldset>
<fieldset><label>colour name<select id="family"><option value="">any</option>{families}</select></label>
<label>hue from (h°)<input id="hmin" type="number" min="0" max="360" step="any"></label>
<label>to (h°)<input id="hmax" type="number" min="0" max="360" step="any"></label></fieldset>
<fieldset><label>lightness from (L*)<input id="lmin" type="number" min="0" max="100" step="any"></label>
<label>to (L*)<input id="lmax" type="number" min="0" max="100" step="any"></label></fieldset>
<fieldset><button type="reset">reset</button></fieldset>
<span id="count" role="status"></span>
</form></section>
<main id="swatches">
{cards}
</main>
<noscript><p class="empty">JavaScript is off: the live view, compare and find by colour need it; the grid above is complete.</p></noscript>
{blocks}</body>
</html>
"""
