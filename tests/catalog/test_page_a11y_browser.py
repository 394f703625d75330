"""The page's first view, its accessibility and its heroes (issue 37): it opens on a hero, or on the live sphere
under the studio at the catalog's most vivid colour; it passes axe-core's checks (tests/vendor/axe-core, run in
the page) at a desktop and a phone width; it works from the keyboard; on a phone the picture stays in view while
the controls scroll; the cards show a catalog's heroes first and the live view shows a hero while it is at the
hero's state."""
from __future__ import annotations

import io
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from tests.browser import open_catalog_page, wait_until

AXE = Path(__file__).resolve().parents[1] / "vendor" / "axe-core" / "axe.min.js"
#: The rule sets the page must pass: WCAG 2.0 / 2.1 A and AA, and axe's best practices.
AXE_TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa", "best-practice"]


def _axe(pg) -> list[dict]:
    """axe-core's violations on the page as it is (its ids, impacts and the first few offending nodes)."""
    pg.evaluate(AXE.read_text(encoding="utf-8"))  # through the DevTools protocol: outside the page's CSP
    res = pg.evaluate("tags => axe.run(document, {runOnly: {type: 'tag', values: tags}, resultTypes: ['violations']})",
                      AXE_TAGS)
    return [{"id": v["id"], "impact": v["impact"], "nodes": [n["target"] for n in v["nodes"][:5]]}
            for v in res["violations"]]


def _most_vivid(records: list[dict]) -> dict:
    inside = [r for r in records if r["in_srgb_gamut"]] or records
    return max(inside, key=lambda r: r["LCh"][1])


@pytest.mark.parametrize("width", [1280, 390])
def test_page_passes_axe_core(chromium, small_catalog, width):
    """No axe-core violation (WCAG 2.1 A/AA and best practices) at a desktop and a phone width, with the
    technical details and a card's multi-angle table opened (what is folded away is checked too), a pin in
    compare and find's answer to a colour titanium cannot make."""
    ctx, pg, events = open_catalog_page(chromium, small_catalog, viewport=(width, 900), fragment="lighting=point")
    try:
        pg.evaluate("() => document.querySelectorAll('details').forEach((d) => { d.open = true; })")
        pg.click("article.card .tools button")  # a pin: the compare section is on the page too
        pg.fill("#find-hex", "#00ff00")  # a colour titanium cannot make: the sentence saying so, and the matches
        pg.click("#find-form button[type=submit]")
        assert pg.locator("#find-verdict").is_visible()
        assert _axe(pg) == []
        # axe does find what it checks (an unlabelled field added here)
        pg.evaluate("() => document.querySelector('#find-form').append(document.createElement('input'))")
        assert "label" in {v["id"] for v in _axe(pg)}
        assert events["errors"] == []
    finally:
        ctx.close()


def test_first_view_is_the_live_sphere_under_the_studio_at_a_vivid_colour(chromium, small_catalog):
    """Without heroes the page opens on the sphere under the studio light, at the most chromatic swatch inside
    sRGB (the small catalog's swatches span 20–300 nm: not its first, a 20 nm beige)."""
    doc = json.loads((small_catalog / "catalog.json").read_text(encoding="utf-8"))
    want = _most_vivid(doc["swatches"])
    assert want["id"] != doc["swatches"][0]["id"]  # the check can fail: the page opened on its first swatch before
    ctx, pg, events = open_catalog_page(chromium, small_catalog)
    try:
        st = pg.evaluate("swatchCatalog.show({})")
        assert (st["shape"], st["lighting"], st["model"]) == ("sphere", "studio", "microfacet")
        assert st["thickness_nm"] == pytest.approx(want["thickness_nm"])
        assert pg.evaluate("swatchCatalog.hero()") is None and pg.locator("#hero-view").is_hidden()
        # the header: plain words first, the technical terms one click away
        assert pg.locator("header .lede").first.is_visible()
        assert not pg.locator("header details.tech .sub").first.is_visible()
        pg.click("header details.tech > summary")
        assert pg.locator("header details.tech .sub").first.is_visible()
        assert events["errors"] == []
    finally:
        ctx.close()


def test_keyboard_reaches_every_control_with_a_visible_focus_and_no_trap(chromium, small_catalog):
    """Tab walks the page's controls in document order, each showing a focus outline, and leaves the page
    (no trap); the picture turns with the arrow keys and the thickness slider moves with them."""
    ctx, pg, events = open_catalog_page(chromium, small_catalog, fragment="lighting=point")
    try:
        n = pg.evaluate("""() => [...document.querySelectorAll('a[href], button, input, select, summary, [tabindex]')]
            .filter((e) => e.checkVisibility() && !e.disabled && e.tabIndex >= 0).length""")
        seen, order = [], []
        for _ in range(n + 3):
            pg.keyboard.press("Tab")
            got = pg.evaluate("""() => { const e = document.activeElement;
                if (!e || e === document.body) return null;
                const s = getComputedStyle(e);
                return {key: e.id || e.tagName + ':' + (e.textContent || '').trim().slice(0, 30),
                        y: e.getBoundingClientRect().top + window.scrollY,
                        outline: s.outlineStyle !== 'none' && parseFloat(s.outlineWidth) >= 2};
              }""")
            if got is None:
                break
            assert got["outline"], got["key"]
            seen.append(got["key"])
            order.append(got["y"])
        assert len(seen) == n, (len(seen), n)  # everything reached, and then focus left the page: no trap
        assert {"view", "thickness", "voltage-range", "shape", "lighting", "pin", "sort", "find-hex"} <= set(seen)
        assert seen.index("view") < seen.index("thickness") < seen.index("sort")  # picture, its controls, the filters
        # the picture turns from the keyboard
        pg.focus("#view")
        before = pg.evaluate("swatchCatalog.show({})")
        pg.keyboard.press("ArrowLeft")
        pg.keyboard.press("ArrowDown")
        after = pg.evaluate("swatchCatalog.show({})")
        assert after["view_azimuth_deg"] == pytest.approx(before["view_azimuth_deg"] + 5)
        assert after["view_deg"] == pytest.approx(before["view_deg"] + 2.5)
        # a slider moves with the arrow keys
        pg.focus("#thickness")
        t0 = after["thickness_nm"]
        for _ in range(5):
            pg.keyboard.press("ArrowLeft")
        assert pg.evaluate("swatchCatalog.show({})")["thickness_nm"] == pytest.approx(t0 - 0.5, abs=1e-6)
        assert events["errors"] == []
    finally:
        ctx.close()


def test_on_a_phone_the_picture_stays_in_view_while_the_controls_scroll(chromium, small_catalog):
    ctx, pg, events = open_catalog_page(chromium, small_catalog, viewport=(390, 844), fragment="lighting=point")
    try:
        pg.locator("#view").scroll_into_view_if_needed()
        pg.evaluate("() => window.scrollBy(0, document.getElementById('view').getBoundingClientRect().top)")
        before = {s: pg.locator(s).bounding_box() for s in ("#view", "#thickness", "#view-deg")}
        assert before["#view"]["y"] == pytest.approx(8, abs=2)
        pg.evaluate("() => window.scrollBy(0, 260)")
        after = {s: pg.locator(s).bounding_box() for s in ("#view", "#thickness", "#view-deg")}
        assert after["#view"]["y"] == pytest.approx(before["#view"]["y"], abs=1)  # the picture stays
        assert after["#view-deg"]["y"] == pytest.approx(before["#view-deg"]["y"] - 260, abs=1)  # the controls move
        # the slider scrolled under the picture is not hidden behind it when it has the focus
        pg.focus("#view-deg")
        box, pic = pg.locator("#view-deg").bounding_box(), pg.locator("#view").bounding_box()
        assert box["y"] >= pic["y"] + pic["height"] - 1 or box["y"] + box["height"] <= pic["y"]
        assert events["errors"] == []
    finally:
        ctx.close()


# -- heroes ----------------------------------------------------------------------------------------------------

def _fake_hero(hex_code: str, size: int = 128) -> bytes:
    """A stand-in hero (a disc of the swatch's colour on a ground from dark to light): the page's code is under test here, not
    Mitsuba's (tests/catalog/test_catalog_hero.py renders real ones)."""
    y, x = np.mgrid[0:size, 0:size]
    disc = (x - size / 2 + 0.5) ** 2 + (y - size / 2 + 0.5) ** 2 < (0.4 * size) ** 2
    rgb = np.array([int(hex_code[i:i + 2], 16) for i in (1, 3, 5)], dtype=np.uint8)
    ground = np.repeat((30 + 100 * y // size).astype(np.uint8)[..., None], 3, axis=2)  # a backdrop, dark to light
    im = np.where(disc[..., None], rgb, ground).astype(np.uint8)
    buf = io.BytesIO()
    Image.fromarray(im, "RGB").save(buf, format="PNG")
    return buf.getvalue()


@pytest.fixture(scope="module")
def hero_catalog(tmp_path_factory, chromium):
    """The small page-test catalog with heroes on (``hero = true``), the heroes of all but the first swatch
    stand-ins written through the build's own path (swatch.catalog.execute.catalog_heroes replaced)."""
    from swatch.catalog import execute, hero
    from swatch.catalog.build import build_catalog
    from tests.browser import SMALL_CATALOG_SPEC

    root = tmp_path_factory.mktemp("hero-catalog")
    spec = root / "spec.toml"
    spec.write_text(SMALL_CATALOG_SPEC.format(name="hero page").replace("[render]\n", "[render]\nhero = true\n"),
                    encoding="utf-8")

    def fake(spec_, records, cache, say=None, mesh=None, render_many=None):
        files, entries = {}, []
        for k, rec in enumerate(records):
            if k == 0:  # a swatch without a hero: the page handles both
                entries.append(None)
                continue
            name = hero.hero_name(rec)
            files[name] = _fake_hero(rec["srgb_hex"])
            entries.append({"png": name, "edges": hero.edge_colours(files[name]), "engine": "mitsuba",
                            "shape": "sphere", "lighting": "studio", "size_px": 128, "spp": 64})
        first = hero.cover_index(records[1:]) + 1  # the most vivid of those with a hero: its cover, larger
        files[hero.cover_name(records[first])] = _fake_hero(records[first]["srgb_hex"], 256)
        entries[first] = dict(entries[first], cover={"png": hero.cover_name(records[first]), "size_px": 256})
        return files, set(), entries

    mp = pytest.MonkeyPatch()
    mp.setattr(execute, "catalog_heroes", fake)  # the name the build calls (catalog.execute)
    try:
        out = root / "out"
        build_catalog(spec, out, jobs=1)
    finally:
        mp.undo()
    yield out
    shutil.rmtree(root, ignore_errors=True)


def test_cards_show_their_hero_first_and_the_live_view_shows_it_at_its_state(chromium, hero_catalog):
    doc = json.loads((hero_catalog / "catalog.json").read_text(encoding="utf-8"))
    with_hero = [r for r in doc["swatches"] if r.get("hero")]
    assert len(with_hero) == len(doc["swatches"]) - 1
    # a 360 px screen, one device pixel a CSS pixel: the frame is 234 px tall, so the test's 256 px cover is shown
    # (a picture is never shown larger than it was made: on a desktop's 480 px frame the live view takes its place,
    # tests/catalog/test_live_studio_browser.py)
    ctx, pg, events = open_catalog_page(chromium, hero_catalog, viewport=(360, 800))
    try:
        # the cards: the hero first (loaded), beside the chip; the card without one opens on its chip
        for rec in doc["swatches"]:
            card = pg.locator(f"#card-{rec['id']}")
            first = card.locator(":scope > *").first
            if rec.get("hero"):
                img = first.locator("img.hero")
                assert img.get_attribute("src") == rec["hero"]["png"]
                img.scroll_into_view_if_needed()
                wait_until(pg, f"() => document.querySelector('#card-{rec['id']} img.hero').naturalWidth === 128")
            else:
                assert "chip" in first.get_attribute("class") and card.locator("img.hero").count() == 0
        # the first view: the most vivid swatch's hero, as its cover (larger), over the canvas; the frame's sides
        # continue the picture's edges
        want = _most_vivid(with_hero)
        assert want["hero"]["cover"]["png"] == f"heroes/cover_{want['id']}.png"
        assert [r["id"] for r in with_hero if "cover" in r["hero"]] == [want["id"]]
        assert pg.evaluate("swatchCatalog.hero()") == want["id"]
        st = pg.evaluate("swatchCatalog.show({})")
        assert (st["shape"], st["lighting"], st["thickness_nm"]) == ("sphere", "studio", pytest.approx(want["thickness_nm"]))
        assert pg.locator("#hero-view").is_visible() and pg.locator("#hero-badge").is_visible()
        assert pg.locator("#hero-view").get_attribute("src") == want["hero"]["cover"]["png"]
        wait_until(pg, "() => document.getElementById('hero-view').naturalWidth === 256")
        background = pg.evaluate("getComputedStyle(document.getElementById('hero-view')).backgroundImage")
        assert background.count("linear-gradient") == 2, background
        left = [tuple(int(c[i:i + 2], 16) for i in (1, 3, 5)) for c in want["hero"]["edges"]["left"]]
        assert left[0] != left[-1] and all(f"rgb({r}, {g}, {b})" in background for r, g, b in (left[0], left[-1]))
        # the user changes the state: the live render; back at the hero's state: the hero again
        pg.evaluate("q => swatchCatalog.show(q)", {"thickness_nm": want["thickness_nm"] - 1})
        assert pg.evaluate("swatchCatalog.hero()") is None and pg.locator("#hero-view").is_hidden()
        pg.evaluate("q => swatchCatalog.show(q)", {"thickness_nm": want["thickness_nm"]})
        assert pg.evaluate("swatchCatalog.hero()") == want["id"]
        pg.evaluate("swatchCatalog.show({lighting: 'point'})")
        assert pg.locator("#hero-view").is_hidden()
        # a card's "live view" opens its hero's state; its 128 px picture would be stretched over the 234 px frame,
        # so the live view shows instead
        other = next(r for r in with_hero if r["id"] != want["id"])
        pg.locator(f"#card-{other['id']} .tools button", has_text="live view").click()
        assert pg.evaluate("swatchCatalog.hero()") == other["id"] and pg.locator("#hero-view").is_hidden()
        # the first swatch has none: its live view is the live render
        pg.locator(f"#card-{doc['swatches'][0]['id']} .tools button", has_text="live view").click()
        assert pg.evaluate("swatchCatalog.hero()") is None
        assert _axe(pg) == []
        assert events["errors"] == []
    finally:
        ctx.close()


@pytest.mark.parametrize("png", ["../../etc/x.png", "javascript:alert(1)//.png", "/abs/hero.png", "heroes/a b.png",
                                 'heroes/x.png" onerror="alert(1)', "heroes/x.svg", 7])
def test_a_hero_path_that_is_not_a_plain_relative_png_is_left_out(png):
    """A record read back is not trusted: a hero whose ``png`` is anything but a plain relative PNG path
    (swatch.catalog.html.HERO_PATH) is not put on the page, by the build's HTML or by the script (HERO_PNG)."""
    from swatch.catalog.html import HERO_PATH, hero_png

    assert hero_png({"hero": {"png": png}}) is None
    assert hero_png({"hero": {"png": "heroes/hero_S001.png"}}) == "heroes/hero_S001.png"
    script = (Path(__file__).resolve().parents[2] / "swatch" / "catalog" / "web" / "page.js").read_text(encoding="utf-8")
    js = re.search(r"const HERO_PNG = /(.*)/;", script).group(1).replace("\\/", "/")
    assert js == "^" + HERO_PATH.pattern + "$"  # the script's rule is the build's
