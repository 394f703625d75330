"""``index.html``: a static, self-contained page to browse a catalog from the file system.

No server and no network: inline CSS and JavaScript, the catalog embedded as JSON in a
``<script type="application/json">`` block (``<``, ``>`` and ``&`` written as ``\\u003c`` ... so
no text from a spec can close the block). Every datum reaches the page through ``textContent``
or a validated colour, never ``innerHTML``; a Content-Security-Policy allows only this page's
own script (by hash) and no network fetches.
"""
from __future__ import annotations

import base64
import hashlib
import html
import json

__all__ = ["index_html", "embed_json"]


def embed_json(obj) -> str:
    """JSON safe to place inside a <script type="application/json"> element."""
    text = json.dumps(obj, ensure_ascii=False, sort_keys=False, separators=(",", ":"), allow_nan=False)
    return (text.replace("&", "\\u0026").replace("<", "\\u003c").replace(">", "\\u003e")
            .replace("\u2028", "\\u2028").replace("\u2029", "\\u2029"))


_CSS = """
:root { color-scheme: light; --ink:#1d1d1f; --muted:#5b5b60; --line:#d9d9de; --bg:#f4f4f6; }
* { box-sizing: border-box; }
body { margin: 0; font: 15px/1.45 system-ui, -apple-system, "Segoe UI", "DejaVu Sans", sans-serif;
       color: var(--ink); background: var(--bg); }
header { padding: 18px 24px 10px; background: #fff; border-bottom: 1px solid var(--line); }
h1 { margin: 0 0 4px; font-size: 22px; }
.sub { color: var(--muted); margin: 2px 0; }
.files a { margin-right: 12px; }
form { display: flex; flex-wrap: wrap; gap: 10px 18px; align-items: end; padding: 12px 24px;
       background: #fff; border-bottom: 1px solid var(--line); position: sticky; top: 0; z-index: 1; }
fieldset { border: 0; margin: 0; padding: 0; display: flex; gap: 6px; align-items: end; }
label { display: flex; flex-direction: column; font-size: 12px; color: var(--muted); }
input, select, button { font: inherit; font-size: 14px; padding: 3px 6px; }
input[type=number] { width: 6.5em; }
#count { color: var(--muted); margin-left: auto; }
main { display: grid; grid-template-columns: repeat(auto-fill, minmax(290px, 1fr)); gap: 14px; padding: 18px 24px; }
.card { background: #fff; border: 1px solid var(--line); border-radius: 8px; overflow: hidden; }
.chip { height: 84px; }
.flop { display: flex; height: 18px; border-top: 1px solid #fff; }
.flop span + span { border-left: 1px solid rgba(255,255,255,.6); }
details { margin-top: 4px; font-size: 13px; }
summary { cursor: pointer; color: var(--muted); }
.flop span { flex: 1; }
.body { padding: 8px 12px 10px; }
.title { font-weight: 600; font-size: 16px; }
.hex { font-family: ui-monospace, "DejaVu Sans Mono", monospace; color: var(--muted); float: right; }
table { border-collapse: collapse; width: 100%; margin-top: 4px; font-size: 13px; }
td { padding: 1px 0; vertical-align: top; }
td:first-child { color: var(--muted); width: 42%; }
.num { font-variant-numeric: tabular-nums; }
.links a { margin-right: 10px; font-size: 13px; }
.empty { padding: 24px; color: var(--muted); }
"""

_JS = r"""
"use strict";
(function () {
  const cat = JSON.parse(document.getElementById("catalog-data").textContent);
  const swatches = cat.swatches;
  const main = document.getElementById("swatches");
  const $ = (id) => document.getElementById(id);
  const HEX = /^#[0-9a-f]{6}$/i;
  const fmt = (x, n) => (x === null || x === undefined) ? "–" : Number(x).toFixed(n);
  function el(tag, cls, text) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function row(tbody, k, v) {
    const tr = el("tr"); tr.appendChild(el("td", "", k)); tr.appendChild(el("td", "num", v)); tbody.appendChild(tr);
  }
  function link(parent, href, text) {
    const a = el("a", "", text); a.href = encodeURI(href); parent.appendChild(a);
  }
  function card(s) {
    const c = el("article", "card");
    c.dataset.id = s.id;
    const chip = el("div", "chip");
    if (HEX.test(s.srgb_hex)) chip.style.backgroundColor = s.srgb_hex;
    chip.title = "sRGB " + s.srgb_hex + " at " + cat.catalog.reference_geometry.name;
    c.appendChild(chip);
    const flop = el("div", "flop");
    for (const g of cat.catalog.multi_angle_geometries) {
      const hx = s.multi_angle_srgb_hex[g.name];
      const sp = el("span"); if (HEX.test(hx)) sp.style.backgroundColor = hx;
      sp.title = g.name + ": L*a*b* " + s.multi_angle[g.name].map((v) => fmt(v, 1)).join(" ");
      flop.appendChild(sp);
    }
    c.appendChild(flop);
    const body = el("div", "body");
    const t = el("div", "title", fmt(s.thickness_nm, 1) + " nm · " + fmt(s.voltage_V, 1) + " V");
    t.appendChild(el("span", "hex", s.srgb_hex));
    body.appendChild(t);
    const tb = el("tbody");
    row(tb, "L*a*b* (" + cat.catalog.reference_geometry.name + ")", s.Lab.map((v) => fmt(v, 2)).join("  "));
    row(tb, "L*C*h", fmt(s.LCh[0], 2) + "  " + fmt(s.LCh[1], 2) + "  " + fmt(s.LCh[2], 1) + "°");
    row(tb, "hue", s.hue_family);
    const pw = s.process_window;
    row(tb, "window (" + pw.grade + ")", "−" + fmt(pw.thickness_minus_nm, 1) + " / +" + fmt(pw.thickness_plus_nm, 1) + " nm");
    row(tb, "", "−" + fmt(pw.voltage_minus_V, 2) + " / +" + fmt(pw.voltage_plus_V, 2) + " V");
    row(tb, "ΔE00 prev / next", fmt(s.delta_E_00_to_neighbours.previous, 2) + " / " + fmt(s.delta_E_00_to_neighbours.next, 2));
    const table = el("table"); table.appendChild(tb); body.appendChild(table);
    if (cat.catalog.multi_angle_geometries.length) {
      const det = el("details"); det.appendChild(el("summary", "", "multi-angle L*a*b*"));
      const mt = el("tbody");
      for (const g of cat.catalog.multi_angle_geometries) {
        row(mt, g.name + " (θd " + fmt(g.theta_d_deg, 1) + "°)", s.multi_angle[g.name].map((v) => fmt(v, 2)).join("  "));
      }
      const t2 = el("table"); t2.appendChild(mt); det.appendChild(t2); body.appendChild(det);
    }
    const links = el("div", "links");
    link(links, s.sheet_png, "sheet " + s.sheet + " (PNG)");
    link(links, s.sheet_exr, "EXR");
    body.appendChild(links);
    if (s.presets) {  // 3-D material presets, each with its max ΔE2000 (D65, 2°, facet angles 0–60°)
      const pr = el("div", "links presets"), p = s.presets;
      pr.title = p.conditions;
      link(pr, p.gltf, "glTF ΔE00 " + fmt(p.gltf_max_delta_E_00, 1));
      link(pr, p.blender, "Blender ΔE00 " + fmt(p.blender_max_delta_E_00, 1));
      link(pr, p.materialx, "OpenPBR ΔE00 " + fmt(p.openpbr_max_delta_E_00, 1));
      body.appendChild(pr);
    }
    c.appendChild(body);
    return c;
  }
  const cards = new Map(swatches.map((s) => [s.id, card(s)]));
  function num(id) { const v = $(id).value.trim(); return v === "" ? null : Number(v); }
  function inHue(h, lo, hi) { return lo <= hi ? (h >= lo && h <= hi) : (h >= lo || h <= hi); }
  function update() {
    const tmin = num("tmin"), tmax = num("tmax"), vmin = num("vmin"), vmax = num("vmax");
    const hmin = num("hmin"), hmax = num("hmax"), fam = $("family").value;
    const key = $("sort").value, dir = $("order").value === "desc" ? -1 : 1;
    const shown = swatches.filter((s) =>
      (tmin === null || s.thickness_nm >= tmin) && (tmax === null || s.thickness_nm <= tmax) &&
      (vmin === null || s.voltage_V >= vmin) && (vmax === null || s.voltage_V <= vmax) &&
      (fam === "" || s.hue_family === fam) &&
      ((hmin === null && hmax === null) || inHue(s.LCh[2], hmin === null ? 0 : hmin, hmax === null ? 360 : hmax)));
    const val = (s) => key === "hue" ? s.LCh[2] : key === "voltage" ? s.voltage_V : s.thickness_nm;
    shown.sort((a, b) => dir * (val(a) - val(b)) || (a.index - b.index));
    main.replaceChildren(...shown.map((s) => cards.get(s.id)));
    if (!shown.length) main.appendChild(el("p", "empty", "No swatch matches the filters."));
    $("count").textContent = "showing " + shown.length + " of " + swatches.length;
  }
  const fams = $("family");
  for (const f of cat.hue_families) { const o = el("option", "", f); o.value = f; fams.appendChild(o); }
  $("controls").addEventListener("input", update);
  $("controls").addEventListener("reset", () => setTimeout(update, 0));
  $("controls").addEventListener("submit", (e) => e.preventDefault());
  update();
})();
"""


def index_html(catalog: dict) -> str:
    """The page for a catalog document (the content of catalog.json plus ``hue_families``)."""
    c = catalog["catalog"]
    e = html.escape
    script_hash = base64.b64encode(hashlib.sha256(_JS.encode("utf-8")).digest()).decode("ascii")
    csp = (f"default-src 'none'; style-src 'unsafe-inline'; script-src 'sha256-{script_hash}'; "
           "img-src 'none'; base-uri 'none'; form-action 'none'")
    ref = c["reference_geometry"]
    multi = ", ".join(g["name"] for g in c["multi_angle_geometries"]) or "none"
    files = [("catalog.json", "catalog.json"), ("catalog.csv", "catalog.csv"), (c["exports"]["cxf"], "CxF3"),
             (c["exports"]["ase"], "ASE")]
    files += [(s["png"], f"sheet {s['number']}") for s in catalog["sheets"]]
    links = " ".join(f'<a href="{e(href)}">{e(text)}</a>' for href, text in files)
    pw = c["tolerance"]
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{e(csp)}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{e(c["name"])} · swatch catalog</title>
<style>{_CSS}</style>
</head>
<body>
<header>
<h1 id="catalog-name">{e(c["name"])}</h1>
<p class="sub">{e(c["film"])} on {e(c["substrate"])} · {len(catalog["swatches"])} swatches ·
growth {c["growth_nm_per_V"]:g} nm/V · {e(c["illuminant"])}, CIE {e(c["observer_name"])} ·
L*a*b* at {e(ref["name"])} (light {ref["light_deg"]:g}°, view {ref["view_deg"]:g}°) · model: {e(c["model"])}</p>
<p class="sub">Multi-angle (flop strip under each chip, left to right): {e(multi)}. Process window: thickness and
voltage deviations that keep ΔE2000 to the nominal colour ≤ {pw["max_delta_E_00"]:g} (grade {e(pw["grade"])}, {e(pw["scheme"])}).</p>
<p class="sub files">{links}</p>
</header>
<form id="controls" autocomplete="off">
<fieldset><label>sort by<select id="sort"><option value="thickness">thickness</option>
<option value="voltage">voltage</option><option value="hue">hue angle</option></select></label>
<label>order<select id="order"><option value="asc">ascending</option><option value="desc">descending</option></select></label></fieldset>
<fieldset><label>thickness ≥ nm<input id="tmin" type="number" step="any"></label>
<label>≤ nm<input id="tmax" type="number" step="any"></label></fieldset>
<fieldset><label>voltage ≥ V<input id="vmin" type="number" step="any"></label>
<label>≤ V<input id="vmax" type="number" step="any"></label></fieldset>
<fieldset><label>hue family<select id="family"><option value="">any</option></select></label>
<label>hue from °<input id="hmin" type="number" min="0" max="360" step="any"></label>
<label>to °<input id="hmax" type="number" min="0" max="360" step="any"></label></fieldset>
<fieldset><button type="reset">reset</button></fieldset>
<span id="count"></span>
</form>
<main id="swatches"><noscript>This page needs JavaScript to list the swatches; the same data is in catalog.csv.</noscript></main>
<script type="application/json" id="catalog-data">{embed_json(catalog)}</script>
<script>{_JS}</script>
</body>
</html>
"""
