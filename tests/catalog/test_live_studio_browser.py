"""The designer's view (#46): the live view draws the heroes' studio set and matches the path-traced heroes; no
picture is shown larger than it was made; the finish is one click away; the catalog's own part turns in the live view.

Headless Chromium (SwiftShader WebGL2) on small catalogs with heroes (Mitsuba). The live-vs-hero figures are the
bench's (benchmarks/live_view.py): CIEDE2000 between the live frame at the hero's pose and size and the hero PNG.
"""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from benchmarks.live_view import hero_records, live_vs_hero
from tests.browser import open_catalog_page, require_chromium, wait_until
from tests.mitsuba_setup import mitsuba_variant

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]

SPEC = """
name = "Live studio"
[thickness]
list_nm = [50.8, 120, 210]
[render]
shapes = ["flat"]
size_px = 64
angular_map = false
finishes = ["polished", "satin"]
hero = true
hero_size_px = 128
hero_spp = 16
hero_cover_px = 0
[sheet]
columns = 3
rows = 1
"""

PART_SPEC = """
name = "Live part"
[thickness]
list_nm = [80, 140]
[render]
shapes = ["flat"]
size_px = 64
angular_map = false
mesh = "part.glb"
hero = true
hero_size_px = 128
hero_spp = 16
hero_cover_px = 0
[sheet]
columns = 2
rows = 1
"""

#: Every picture of the page drawn at no more than one device pixel for each of its pixels: the <img>s (the live
#: view's hero over the canvas is drawn square, contained in its frame) and the renders cut from the sheets
#: (``data-src-px``: their side in the sheet's pixels). The offenders, as [what, drawn device px, its px].
UPSCALED_JS = """() => { const dpr = window.devicePixelRatio || 1, bad = [];
  for (const img of document.querySelectorAll('img')) {
    const r = img.getBoundingClientRect();
    if (img.hidden || r.width === 0 || !img.complete) continue;
    const drawn = (img.id === 'hero-view' ? Math.min(r.width, r.height) : r.width) * dpr;
    if (drawn > img.naturalWidth + 0.5) bad.push([img.id || img.className, drawn, img.naturalWidth]);
  }
  for (const d of document.querySelectorAll('[data-src-px]')) {
    const r = d.getBoundingClientRect();
    if (r.width > 0 && r.width * dpr > Number(d.dataset.srcPx) + 0.5) bad.push([d.className, r.width * dpr, d.dataset.srcPx]);
  }
  return bad; }"""


def _build(tmp_path_factory, name: str, text: str, part: bool = False) -> Path:
    require_chromium()
    mitsuba_variant()
    from swatch.catalog.build import build_catalog

    root = tmp_path_factory.mktemp(name)
    spec = root / f"{name}.toml"
    spec.write_text(text, encoding="utf-8")
    if part:
        shutil.copy(ROOT / "examples" / "part.glb", root / "part.glb")
    out = root / "out"
    build_catalog(spec, out, jobs=1)
    return out


@pytest.fixture(scope="module")
def studio_catalog(tmp_path_factory):
    return _build(tmp_path_factory, "live-studio", SPEC)


@pytest.fixture(scope="module")
def part_catalog(tmp_path_factory):
    return _build(tmp_path_factory, "live-part", PART_SPEC, part=True)


def test_the_live_view_matches_the_path_traced_heroes(chromium, studio_catalog):
    """At each hero's pose and size the live frame is within ΔE00 2.5 of the hero over the whole frame and 2.0 over
    the sphere (the issue's bound; the default catalog's figures are in the bench)."""
    ctx, page, events = open_catalog_page(chromium, studio_catalog)
    try:
        res = live_vs_hero(page, studio_catalog, hero_records(studio_catalog), save=studio_catalog.parent)
    finally:
        ctx.close()
    assert len(res) == 3 and not events["errors"]
    for r in res:
        assert r["frame"] <= 2.5 and r["object"] <= 2.0, r


def test_the_live_view_draws_the_set_and_keeps_it_when_turned(chromium, studio_catalog):
    """Under the studio the background is the set (a floor lit unevenly, darker in the sphere's contact shadow, a back
    wall), not the plain grey of the point light; turned by dragging, it is still there; the point light keeps the
    plain background."""
    ctx, page, events = open_catalog_page(chromium, studio_catalog)
    try:
        page.evaluate("swatchCatalog.show({lighting: 'studio', shape: 'sphere', view_deg: 70, view_azimuth_deg: 180})")
        w, h = page.evaluate("[document.getElementById('view').width, document.getElementById('view').height]")
        px = lambda x, y: page.evaluate(f"swatchCatalog.pixel({{x: {x}, y: {y}}}).rgb")  # noqa: E731
        wall, floor_side, under = px(w // 2, 3), px(6, h - 4), px(w // 2, int(h * 0.95))
        grey = page.evaluate("(() => { swatchCatalog.show({lighting: 'point'}); return swatchCatalog.pixel({x: 3, y: 3}).rgb; })()")
        assert wall != grey and floor_side != grey
        assert sum(under) < sum(floor_side) - 30  # the contact shadow
        page.evaluate("swatchCatalog.show({lighting: 'studio'})")
        canvas = page.locator("#view").bounding_box()
        page.mouse.move(canvas["x"] + 300, canvas["y"] + 200)
        page.mouse.down()
        page.mouse.move(canvas["x"] + 420, canvas["y"] + 230, steps=4)
        page.mouse.up()
        turned = [px(x, y) for x, y in ((3, 3), (w - 4, 3), (6, h - 4), (w - 6, h - 4))]
        assert all(c != grey for c in turned) and len({tuple(c) for c in turned}) > 1
    finally:
        ctx.close()
    assert not events["errors"]


@pytest.mark.parametrize("viewport,scale", [((1280, 900), 1), ((390, 844), 3)])
def test_no_picture_is_shown_larger_than_it_was_made(chromium, studio_catalog, viewport, scale):
    """At DPR 1 on a desktop and DPR 3 on a phone, first view, after "live view" on a card (its 128 px hero would
    fill the 480 px frame: the live view takes its place) and down the cards: no image drawn upscaled. The check
    itself fails on a stretched picture."""
    ctx, page, events = open_catalog_page(chromium, studio_catalog, viewport=viewport, scale=scale)
    try:
        page.wait_for_timeout(500)
        assert page.evaluate(UPSCALED_JS) == []
        page.locator("article.card .tools button", has_text="live view").first.click()
        assert page.evaluate("document.getElementById('hero-view').hidden")  # the live view, not the 128 px hero
        assert page.evaluate(UPSCALED_JS) == []
        for _ in range(4):
            page.mouse.wheel(0, 1500)
            page.wait_for_timeout(300)
            assert page.evaluate(UPSCALED_JS) == []
        page.evaluate("document.querySelector('img.hero').style.width = '600px'")
        assert page.evaluate(UPSCALED_JS) != []
    finally:
        ctx.close()
    assert not events["errors"]


def test_the_finish_is_one_click_away(chromium, studio_catalog):
    """The spec's finishes are buttons under the picture, the first pressed; a click changes the live view (a
    blurrier highlight), the address and the hero shown; a finish the catalog does not offer is refused."""
    ctx, page, events = open_catalog_page(chromium, studio_catalog)
    try:
        names = page.evaluate("[...document.querySelectorAll('#finish-bar button')].map((b) => b.dataset.finish)")
        assert names == ["polished", "satin"]
        assert page.evaluate("document.querySelector('#finish-bar button[aria-pressed=true]').dataset.finish") == "polished"
        page.evaluate("swatchCatalog.show({thickness_nm: 120, shape: 'sphere', lighting: 'studio', view_deg: 50})")
        w, h = page.evaluate("[document.getElementById('view').width, document.getElementById('view').height]")
        row = lambda: [tuple(page.evaluate(f"swatchCatalog.pixel({{x: {x}, y: {h // 3}}}).rgb")) for x in range(w // 3, 2 * w // 3, 8)]  # noqa: E731
        polished = row()
        page.locator('#finish-bar button[data-finish="satin"]').click()
        assert page.evaluate("swatchCatalog.show({}).finish") == "satin"
        assert "finish=satin" in page.evaluate("document.getElementById('view-link').getAttribute('href')")
        satin = row()
        assert polished != satin
        # the sharper finish has the larger spread of brightness across the highlight row
        spread = lambda r: max(map(sum, r)) - min(map(sum, r))  # noqa: E731
        assert spread(polished) > spread(satin)
        with pytest.raises(Exception, match="finish must be one of polished, satin"):
            page.evaluate("swatchCatalog.show({finish: 'brushed'})")
    finally:
        ctx.close()
    assert not events["errors"]


def test_the_part_turns_in_the_live_view(chromium, part_catalog):
    """A spec's part is a shape of the live view: WebGL2 triangles shaded as the other shapes in the set; at its
    heroes' pose the frame is within the bound the part reaches today (its own reflections are not drawn: see
    docs/catalog.md), and it turns."""
    from swatch.render.mesh import load_mesh

    ctx, page, events = open_catalog_page(chromium, part_catalog)
    try:
        assert page.evaluate("[...document.getElementById('shape').options].some((o) => o.value === 'part')")
        res = live_vs_hero(page, part_catalog, hero_records(part_catalog), mesh=load_mesh(part_catalog.parent / "part.glb"),
                           save=part_catalog.parent)
        assert len(res) == 2
        for r in res:
            assert r["frame"] <= 4.0 and r["object"] <= 6.0, r
        page.evaluate("swatchCatalog.show({shape: 'part', view_deg: 40, view_azimuth_deg: 120})")
        wait_until(page, "() => swatchCatalog.show({}).shape === 'part'")
        w, h = page.evaluate("[document.getElementById('view').width, document.getElementById('view').height]")
        centre = page.evaluate(f"swatchCatalog.pixel({{x: {w // 2}, y: {h // 2}}}).rgb")
        corner = page.evaluate("swatchCatalog.pixel({x: 3, y: 3}).rgb")
        assert centre != corner
    finally:
        ctx.close()
    assert not events["errors"]
