"""The explorer page in real headless Chromium (SwiftShader WebGL2): window.swatchCatalog
against the CLI, the live view following the physics, compare, find by colour, print, JS off.

Skipped when Chromium is absent, unless SWATCH_REQUIRE_BROWSER=1 (then it fails): CI sets it.
"""
from __future__ import annotations

import json
from pathlib import Path
from urllib.parse import unquote, urlparse

import colour  # noqa: F401  (after swatch: its plotting notice stays silenced)
import numpy as np
import pytest

import swatch  # noqa: F401
from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
from swatch.physics.materials import wavelength_grid
from swatch.physics.model import get_coating
from tests.browser import POINT_LIGHT, open_catalog_page, wait_until
from tests.cli_helpers import run_json

pytestmark = [pytest.mark.browser, pytest.mark.slow]

RANGE = (20.0, 300.0)


_open = open_catalog_page


@pytest.fixture(scope="module")
def page(chromium, small_catalog):
    """One page for the file, opened under the point light (no test here reads the environment lighting)."""
    ctx, pg, events = _open(chromium, small_catalog, fragment=POINT_LIGHT)
    yield pg, events, small_catalog
    ctx.close()


def test_color_at_matches_swatch_color(page):
    pg, events, _ = page
    rng = np.random.default_rng(11)
    geometries = [(float(rng.uniform(0, 80)), float(rng.uniform(0, 80)), 0.0, None),
                  (float(rng.uniform(0, 80)), float(rng.uniform(0, 80)), 30.0, 100.0),
                  (80.0, 75.0, 0.0, 0.0)]  # the last one near grazing, on the light's side
    worst = 0.0
    for light, view, laz, vaz in geometries:
        d = np.round(rng.uniform(*RANGE, 8), 3)
        args = ["color", "--thickness", ",".join(f"{x:g}" for x in d), "--light", f"{light:g}", "--view", f"{view:g}",
                "--light-azimuth", f"{laz:g}"]
        if vaz is not None:
            args += ["--view-azimuth", f"{vaz:g}"]
        rows = run_json(*args)["rows"]
        q = [{"thickness_nm": float(x), "light_deg": light, "view_deg": view, "light_azimuth_deg": laz,
              **({} if vaz is None else {"view_azimuth_deg": vaz})} for x in d]
        got = pg.evaluate("qs => qs.map(q => swatchCatalog.colorAt(q))", q)
        Lab_page = np.array([g["Lab"] for g in got])
        Lab_cli = np.array([r["Lab"] for r in rows])
        dE = delta_E_00(Lab_page, Lab_cli)
        worst = max(worst, float(dE.max()))
        assert dE.max() <= 0.5, (light, view, laz, vaz, d, dE)
        for g in got:
            assert g["hex"].startswith("#") and len(g["hex"]) == 7
    assert worst > 0.0  # the page interpolates: not the same numbers by construction
    assert events["errors"] == []


def test_color_at_hex_is_2_degree_srgb(page):
    """The hex is display sRGB from CIE 1931 2° colorimetry, whatever the catalog's observer."""
    pg, _, _ = page
    wl = wavelength_grid(380.0, 780.0, 5.0)
    coating = get_coating("TiO2-Siefke", "Ti-Johnson", wl)
    cm2 = get_colorimeter(wl, "D65", "2")
    d = np.array([35.0, 50.8, 140.0, 230.0])
    enc, _ = cm2.display(cm2.XYZ(coating.reflectance(d, 22.5).R), "srgb")
    want = np.round(enc * 255)
    got = pg.evaluate("ds => ds.map(d => swatchCatalog.colorAt({thickness_nm: d, light_deg: 45, view_deg: 0}).hex)",
                      d.tolist())
    got_rgb = np.array([[int(h[i:i + 2], 16) for i in (1, 3, 5)] for h in got])
    assert np.abs(got_rgb - want).max() <= 1


def test_match_is_swatch_match_over_the_range(page):
    pg, _, _ = page
    for target in ({"hex": "#2275b5"}, {"hex": "#c65ebf"}, {"Lab": [70.0, 5.0, 30.0]}):
        if "hex" in target:
            cli = run_json("match", "--hex", target["hex"][1:], "--range", f"{RANGE[0]:g}:{RANGE[1]:g}", "--top", "3")
        else:
            cli = run_json("match", "--lab", ",".join(map(str, target["Lab"])), "--range", f"{RANGE[0]:g}:{RANGE[1]:g}",
                           "--top", "3")
        got = pg.evaluate("t => swatchCatalog.match(t, 3)", target)
        assert [set(g) for g in got] == [{"thickness_nm", "voltage_V", "delta_E_00"}] * len(got)
        assert len(got) == len(cli["candidates"])
        for g, c in zip(got, cli["candidates"], strict=True):
            # within one search step (0.1 nm): a far candidate's minimum can be flat to 1e-3 over it
            assert g["thickness_nm"] == pytest.approx(c["thickness_nm"], abs=0.1)
            assert g["voltage_V"] == pytest.approx(c["voltage_V"], abs=0.1 / 2.032)
            assert g["delta_E_00"] == pytest.approx(c["delta_E_00"], abs=0.02)


def _canvas_centre(pg):
    return pg.evaluate("""() => { const c = document.getElementById('view'); const gl = c.getContext('webgl2');
        const p = new Uint8Array(4); gl.readPixels(c.width >> 1, c.height >> 1, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, p);
        return Array.from(p.slice(0, 3)); }""")


def test_slider_moves_the_live_view_with_the_physics(page):
    pg, events, _ = page
    pg.evaluate("swatchCatalog.show({thickness_nm: 50.8, light_deg: 45, view_deg: 0, shape: 'plate', model: 'paper'})")
    blue = _canvas_centre(pg)
    # the slider itself (an input event, as a user drags it)
    pg.eval_on_selector("#thickness", "e => { e.value = 140; e.dispatchEvent(new Event('input', {bubbles: true})); }")
    pink = _canvas_centre(pg)
    assert blue != pink
    assert blue[2] > blue[0] + 60 and blue[2] > blue[1]  # 50.8 nm reads blue
    assert pink[0] > pink[1] + 40 and pink[2] > pink[1] + 20  # 140 nm pink (red and blue over green)
    # the paper model at the plate centre is colorAt at 45:0 (the camera looks down the normal)
    want = pg.evaluate("swatchCatalog.colorAt({thickness_nm: 140, light_deg: 45, view_deg: 0}).hex")
    want_rgb = [int(want[i:i + 2], 16) for i in (1, 3, 5)]
    assert max(abs(a - b) for a, b in zip(pink, want_rgb, strict=True)) <= 3
    assert pg.locator("#t-out").text_content() == "140.0 nm"
    # the voltage slider: 25 V is 50.8 nm through the process's growth law (2.032 nm/V), blue again
    assert pg.eval_on_selector("#voltage-range", "e => Number(e.value)") == pytest.approx(140 / 2.032, abs=0.05)
    pg.eval_on_selector("#voltage-range", "e => { e.value = 25; e.dispatchEvent(new Event('input', {bubbles: true})); }")
    assert pg.locator("#t-out").text_content() == "50.8 nm" and pg.locator("#v-out").text_content() == "25.0 V"
    assert _canvas_centre(pg) == blue
    # the light azimuth slider: the light swings round the normal; the readout's θd follows colorAt
    pg.evaluate("swatchCatalog.show({view_deg: 30})")
    pg.eval_on_selector("#light-azimuth", "e => { e.value = 90; e.dispatchEvent(new Event('input', {bubbles: true})); }")
    assert pg.locator("#la-out").text_content() == "90°"
    turned = pg.evaluate("swatchCatalog.colorAt({thickness_nm: 50.8, light_deg: 45, view_deg: 30, light_azimuth_deg: 90, "
                         "view_azimuth_deg: 180}).hex")
    assert turned in pg.locator("#state-text").text_content()
    pg.evaluate("swatchCatalog.show({view_deg: 0, light_azimuth_deg: 0})")
    pg.eval_on_selector("#thickness", "e => { e.value = 140; e.dispatchEvent(new Event('input', {bubbles: true})); }")
    for shape in ("bent sheet", "sphere"):
        pg.select_option("#shape", shape)
        assert _canvas_centre(pg) != [118, 118, 118]  # something drawn over the grey background
    # drag to turn: the view angle follows the pointer and the picture changes
    pg.evaluate("swatchCatalog.show({shape: 'sphere', model: 'microfacet', view_deg: 10})")
    before = _canvas_centre(pg)
    pg.locator("#view").scroll_into_view_if_needed()  # a test before may have scrolled the shared page
    box = pg.locator("#view").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    pg.mouse.move(x, y)
    pg.mouse.down()
    pg.mouse.move(x + 40, y + 120, steps=4)
    pg.mouse.up()
    state = pg.evaluate("swatchCatalog.show({})")
    assert state["view_deg"] == pytest.approx(10 + 120 * 0.3, abs=1.0) and state["view_azimuth_deg"] != 180
    assert _canvas_centre(pg) != before
    assert pg.locator("#view-deg").input_value() == f"{state['view_deg']:g}"
    pg.evaluate("swatchCatalog.show({shape: 'plate', view_deg: 0, view_azimuth_deg: 180})")
    assert events["errors"] == []


def test_compare_and_find(page):
    pg, events, out = page
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    recs = doc["swatches"]
    pg.locator(f"#card-{recs[0]['id']} .tools button", has_text="compare").click()
    pg.locator(f"#card-{recs[3]['id']} .tools button", has_text="compare").click()
    assert pg.locator("#compare .pin").count() == 2
    # ΔE between the two pinned swatches, against colour-science on the catalog's own Lab
    cell = pg.locator("#compare-delta tr").nth(1).locator("td").nth(1).text_content()
    d00 = float(cell.split("/")[0])
    want = float(delta_E_00(np.array(recs[0]["Lab"]), np.array(recs[3]["Lab"])))
    assert d00 == pytest.approx(want, abs=0.3)
    assert pg.locator("#compare .pin").first.locator(".strip .chip").count() == len(doc["catalog"]["multi_angle_geometries"])
    assert pg.locator("#compare .pin").first.locator(".ends .chip").count() == 2
    pg.locator("#compare .unpin").first.click()
    assert pg.locator("#compare .pin").count() == 1
    pg.fill("#find-hex", "#2275b5")
    pg.click("#find-form button[type=submit]")
    first = pg.locator("#find-results li").first.text_content()
    best = pg.evaluate("swatchCatalog.match({hex: '#2275b5'}, 1)[0]")  # = swatch match (test above)
    # plain words first: the colour's name at the geometry it holds at, then the numbers
    name, rest = first.split(" seen face on (45:0) · ", 1)
    assert name and rest.startswith(f"{best['thickness_nm']:.2f}\xa0nm · {best['voltage_V']:.1f}\xa0V · colour difference ΔE00 ")
    # the target's L*a*b* is the one matched: in the catalog's observer (a hex brought into it, swatch match --hex)
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.colorimetry.observers import hex_to_document_Lab

    said = pg.locator("#find-target").text_content()
    c, wl = doc["catalog"], doc["catalog"]["wavelength_nm"]
    cm = get_colorimeter(np.arange(wl["start"], wl["stop"] + wl["step"] / 2, wl["step"]), c["illuminant"], c["observer"])
    shown = [float(v) for v in said.split("L*a*b* ")[1].split(" (")[0].split()]
    assert shown == pytest.approx(list(hex_to_document_Lab("2275b5", cm)), abs=0.02)
    assert f"({c['illuminant']}, {c['observer']}°; the sRGB hex's smoothest reflectance)" in said
    assert pg.locator("#find-results li").count() >= 3
    assert events["errors"] == []
    assert all(u.startswith("file://") for u in events["requests"])


def test_cards_show_their_own_images(page):
    pg, _, out = page
    urls = pg.eval_on_selector_all(".card .render, .card .amap", "els => els.map(e => getComputedStyle(e).backgroundImage)")
    assert urls and all("sheet_0" in u for u in urls)
    loaded = pg.evaluate("""async () => { const u = getComputedStyle(document.querySelector('.card .render'))
        .backgroundImage.slice(5, -2); const i = new Image(); i.src = u; await i.decode(); return [i.naturalWidth, u]; }""")
    img = Path(unquote(urlparse(loaded[1]).path))  # a file of the catalog (sheets/ since the folder groups its outputs)
    assert loaded[0] > 0 and img.is_file() and out.resolve() in img.resolve().parents
    assert "light" in pg.locator(".card figure.map").first.text_content()


def test_print_keeps_the_chips(page, tmp_path):
    pg, events, small_catalog = page
    pg.emulate_media(media="print")
    try:
        assert pg.locator("#explorer").is_hidden() and pg.locator("article.card").first.is_visible()
        style = pg.eval_on_selector(".card .chip", "e => [getComputedStyle(e).printColorAdjust, getComputedStyle(e).breakInside]")
        assert style[0] == "exact"
        assert pg.eval_on_selector(".card", "e => getComputedStyle(e).breakInside") == "avoid"
        pdf = tmp_path / "catalog.pdf"
        pg.evaluate("""() => { const seen = []; window.__seen = seen; addEventListener('beforeprint', () =>
            seen.push(document.querySelectorAll('details:not([open])').length), {once: true}); }""")
        pg.pdf(path=str(pdf), print_background=False)
        assert pg.evaluate("__seen") == [0]  # printing opens the explanations and multi-angle tables
        assert pg.locator("details[open]").count() == 0  # ... and closes them after
    finally:
        pg.emulate_media(media="screen")  # the module's page, as the other tests read it
    data = pdf.read_bytes()
    assert data.startswith(b"%PDF") and len(data) > 20_000
    # the chips survive printing without "background graphics" (print-color-adjust: exact):
    # the PDF paints the swatches' colours
    doc = json.loads((small_catalog / "catalog.json").read_text(encoding="utf-8"))
    found = _colours_present(_pdf_fill_colours(pdf), [r["srgb_hex"] for r in doc["swatches"]])
    assert found >= 3, found
    assert events["errors"] == []


def _pdf_fill_colours(pdf: Path) -> np.ndarray:
    """The RGB fill colours (0–1) a PDF's content streams paint with (``r g b rg`` operators)."""
    import re
    import zlib

    raw = pdf.read_bytes()
    cols = []
    for m in re.finditer(rb"stream\r?\n(.*?)\r?\nendstream", raw, re.S):
        try:
            text = zlib.decompress(m.group(1))
        except zlib.error:
            continue
        for r, g, b in re.findall(rb"([0-9.]+) ([0-9.]+) ([0-9.]+) (?:rg|sc|scn)\b", text):
            cols.append((float(r), float(g), float(b)))
    return np.array(cols).reshape(-1, 3)


def _colours_present(cols: np.ndarray, hexes: list[str]) -> int:
    if cols.size == 0:
        return 0
    found = 0
    for h in hexes:
        rgb = np.array([int(h[i:i + 2], 16) for i in (1, 3, 5)]) / 255.0
        if np.any(np.abs(cols - rgb).max(axis=1) <= 1.5 / 255):
            found += 1
    return found


#: The live view's state (less the exposure, which follows from it), the link, the note and the controls.
_STATE_JS = """() => ({state: (({exposure, ...st}) => st)(swatchCatalog.show({})), link: document.getElementById('view-link').getAttribute('href'),
  note: document.getElementById('link-note').textContent, thickness: document.getElementById('thickness').value,
  inputs: ['shape', 'model', 'lighting', 'light', 'view-deg', 'fill'].map((id) => document.getElementById(id).value)})"""


def test_the_address_opens_the_live_view_in_a_given_state(chromium, small_catalog):
    """The page's address fragment (swatch/catalog/web/link.js; docs/catalog.md): ``#thickness=140&shape=…``
    opens the live view in that state, the controls showing it, and "link to this view" writes the address of the
    view shown; bad values (not a number, a shape or lighting the page lacks, a name given twice, a malformed
    escape) are left out and said so on the page, with no page error, and the rest still applies; a changed
    fragment applies at once (the unit tests of the parser: tests/js/link.test.mjs)."""
    ctx, pg, events = _open(chromium, small_catalog, fragment="thickness=140&shape=bent+sheet&lighting=point&view=30"
                                                             "&view_azimuth=170&fill=0.25&light=50&light_azimuth=1e999"
                                                             "&model=phong&voltage=&x=1&%zz=1")
    try:
        got = pg.evaluate(_STATE_JS)
        st = got["state"]
        assert (st["thickness_nm"], st["shape"], st["lighting"], st["model"]) == (140, "bent sheet", "point", "microfacet")
        assert (st["view_deg"], st["view_azimuth_deg"], st["fill"], st["light_deg"]) == (30, 170, 0.25, 50)
        assert st["light_azimuth_deg"] == 0  # as the page opens without it
        assert float(got["thickness"]) == 140 and got["inputs"] == ["bent sheet", "microfacet", "point", "50", "30", "0.25"]
        assert got["note"] == "(left out of the page's address: light_azimuth=1e999, model=phong, voltage=, x=1, %zz=1)"
        assert got["link"] == ("#thickness=140&light=50&light_azimuth=0&view=30&view_azimuth=170&fill=0.25"
                               "&shape=bent+sheet&model=microfacet&lighting=point")
        # a fragment that is no view state (a link to a section) changes nothing; a changed one applies at once,
        # what is wrong in it left out (the thickness stays), the rest (the light angle) applied
        pg.evaluate("() => { location.hash = '#find'; }")
        pg.evaluate("() => new Promise((done) => setTimeout(done, 0))")  # after the hashchange event
        assert pg.evaluate(_STATE_JS)["state"] == st
        pg.evaluate("() => { location.hash = '#light=20&thickness=abc&shape=cube&lighting=sunset&view=1&view=2&fill=%zz'; }")
        wait_until(pg, "() => swatchCatalog.show({}).light_deg === 20")
        after = pg.evaluate(_STATE_JS)
        assert after["state"] == {**st, "light_deg": 20}
        assert after["note"] == ("(left out of the page's address: thickness=abc, shape=cube, lighting=sunset, view=1, "
                                 "view=2, fill=%zz)")
        # a shape without a view: the shape's own camera, as the shape menu
        pg.evaluate("() => { location.hash = '#shape=sphere&model=paper&zoom=2'; }")
        wait_until(pg, "() => swatchCatalog.show({}).shape === 'sphere'")
        scene = pg.evaluate("JSON.parse(document.getElementById('explorer-table').textContent).scene.sphere")
        got = pg.evaluate(_STATE_JS)
        st = got["state"]
        assert got["note"] == "(left out of the page's address: zoom=2)"
        assert (st["model"], st["lighting"], st["view_deg"], st["view_azimuth_deg"]) == ("paper", "point",
                                                                                         scene["default_view_deg"], 180)
        # following "link to this view" comes back to the same view
        pg.evaluate("swatchCatalog.show({thickness_nm: 87.25, model: 'microfacet', view_deg: 12.5})")
        before = pg.evaluate(_STATE_JS)
        pg.click("#view-link")
        wait_until(pg, "() => document.getElementById('link-note').textContent === ''")  # the hashchange applied it
        back = pg.evaluate(_STATE_JS)
        assert back["state"] == before["state"] and pg.evaluate("location.hash") == before["link"]
        assert events["errors"] == []
    finally:
        ctx.close()


def test_javascript_off_is_still_the_grid(chromium, small_catalog):
    ctx, pg, _events = _open(chromium, small_catalog, js=False)
    doc = json.loads((small_catalog / "catalog.json").read_text(encoding="utf-8"))
    assert pg.locator("article.card").count() == len(doc["swatches"])
    assert pg.locator("#explorer").is_hidden()
    bg = pg.eval_on_selector("article.card .chip", "e => getComputedStyle(e).backgroundColor")
    assert bg.startswith(("rgb(", "color(display-p3"))
    assert pg.locator("article.card .title").first.text_content().startswith(f"{doc['swatches'][0]['thickness_nm']:.1f} nm")
    ctx.close()
