"""index.html in a real headless browser (Debian's Chromium through Playwright: tests/browser.py).

Skipped when Chromium is absent, unless SWATCH_REQUIRE_BROWSER=1 (then it fails): CI sets it.
"""
from __future__ import annotations

import json
from pathlib import Path

import colour  # noqa: F401  (after swatch: its plotting notice stays silenced)
import pytest

import swatch  # noqa: F401
from swatch.catalog.build import build_catalog
from tests.browser import POINT_LIGHT, open_catalog_page, require_chromium, wait_until

EVIL = 'Ti <script>alert(1)</script> & "co" </script><img src=x onerror=alert(2)>'

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SPEC = """
name = {name}
description = "escaping test <b>bold</b>"
[voltage]
list_V = [10, 20, 25, 40, 60, 80, 100]
[render]
size_px = 64
angular_map = false
[sheet]
columns = 4
rows = 1
"""


@pytest.fixture(scope="module")
def catalog_out(tmp_path_factory):
    require_chromium()
    root = tmp_path_factory.mktemp("page")
    spec = root / "evil.toml"
    spec.write_text(SPEC.format(name=json.dumps(EVIL)), encoding="utf-8")
    out = root / "out"
    build_catalog(spec, out, jobs=1)
    return out


@pytest.fixture(scope="module")
def loaded(chromium, catalog_out):
    """One page on the catalog for the file (issue 17: a page load was ~6 CPU-s of Chromium, most of it the
    live view's first frame under the studio: it opens under the point light, tests.browser.POINT_LIGHT);
    ``page`` gives it to each test with the filters reset."""
    ctx, pg, events = open_catalog_page(chromium, catalog_out, fragment=POINT_LIGHT)  # no test reads the live view
    pg.wait_for_selector("article.card")
    yield pg, events, catalog_out
    ctx.close()


@pytest.fixture
def page(loaded):
    """The module's page with its filter form reset (every card shown, sorted by thickness, ascending), as it
    opened: the tests do not depend on each other's order."""
    pg, _, out = loaded
    pg.click("button[type=reset]")
    pg.evaluate("() => new Promise((done) => setTimeout(done, 0))")  # after the page's own update (a timeout too)
    n = len(json.loads((out / "catalog.json").read_text(encoding="utf-8"))["swatches"])
    wait_until(pg, f"() => document.querySelectorAll('article.card').length === {n}")
    return loaded


def shown(pg) -> list[str]:
    return pg.eval_on_selector_all("article.card .title", "els => els.map(e => e.firstChild.textContent)")


def test_page_loads_and_shows_every_swatch(page):
    pg, events, out = page
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    n = len(doc["swatches"])
    assert pg.locator("article.card").count() == n == 7
    assert pg.locator("#count").text_content() == f"showing {n} of {n}"
    titles = shown(pg)
    for rec, title in zip(doc["swatches"], titles, strict=True):
        assert f"{rec['voltage_V']:.1f} V" in title and f"{rec['thickness_nm']:.1f} nm" in title
    # the chip shows the record's colour
    # (sRGB hex first; a Display P3 declaration after it wins where the browser has color())
    styles = pg.eval_on_selector_all("article.card > .chip", "els => els.map(e => e.getAttribute('style'))")
    assert styles[0].startswith(f"background-color:{doc['swatches'][0]['srgb_hex']};")
    shown_bg = pg.eval_on_selector("article.card > .chip", "e => getComputedStyle(e).backgroundColor")
    r, g, b = (int(doc["swatches"][0]["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5))
    assert shown_bg == f"rgb({r}, {g}, {b})" or shown_bg.startswith("color(display-p3 ")
    # links to the sheets resolve to files next to the page
    hrefs = pg.eval_on_selector_all("article.card .links a", "els => els.map(e => e.href)")
    assert any(h.endswith("/sheet_02.png") for h in hrefs)
    for h in hrefs:
        assert Path(h.replace("file://", "")).exists()
    assert events["errors"] == []
    assert all(u.startswith("file://") for u in events["requests"])


def test_spec_text_is_escaped(page):
    pg, events, _ = page
    assert events["dialogs"] == []
    assert pg.locator("#catalog-name").text_content() == EVIL
    assert EVIL in pg.title()
    assert pg.locator("img").count() == 0  # the <img onerror> in the name is text, not an element
    assert pg.locator("script").count() == 4  # the data blocks (catalog, colour table, environments), the page's script
    assert pg.locator("b").count() == 0


def test_filter_and_sort(page):
    pg, _, out = page
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    recs = doc["swatches"]
    pg.fill("#vmin", "20")
    pg.fill("#vmax", "60")
    want = [r for r in recs if 20 <= r["voltage_V"] <= 60]
    assert len(shown(pg)) == len(want) == 4
    assert pg.locator("#count").text_content() == f"showing 4 of {len(recs)}"
    pg.click("button[type=reset]")
    wait_until(pg, f"() => document.querySelectorAll('article.card').length === {len(recs)}")
    pg.fill("#tmin", "100")
    assert len(shown(pg)) == len([r for r in recs if r["thickness_nm"] >= 100])
    pg.fill("#tmin", "")
    # colour name: one list, each name once (issue 21: "blue" and "blue (name)" for the same set)
    fam = recs[3]["colour_name"]
    options = pg.eval_on_selector_all("#family option", "els => els.map(e => e.textContent)")
    assert options[0] == "any" and len(options) == len(set(options)) and fam in options
    assert set(options[1:]) == {r["colour_name"] for r in recs}
    pg.select_option("#family", fam)
    assert len(shown(pg)) == len([r for r in recs if r["colour_name"] == fam])
    pg.select_option("#family", "")
    # hue range wrapping through 0°
    pg.fill("#hmin", "300")
    pg.fill("#hmax", "60")
    assert len(shown(pg)) == len([r for r in recs if r["LCh"][2] >= 300 or r["LCh"][2] <= 60])
    pg.fill("#hmin", "")
    pg.fill("#hmax", "")
    # sort by hue, descending
    pg.select_option("#sort", "hue")
    pg.select_option("#order", "desc")
    ids = pg.eval_on_selector_all("article.card", "els => els.map(e => e.dataset.id)")
    assert ids == [r["id"] for r in sorted(recs, key=lambda r: -r["LCh"][2])]
    pg.select_option("#sort", "voltage")
    pg.select_option("#order", "asc")
    ids = pg.eval_on_selector_all("article.card", "els => els.map(e => e.dataset.id)")
    assert ids == [r["id"] for r in sorted(recs, key=lambda r: r["voltage_V"])]
    # lightness L* (issue 46: docs/designer.md promised it, the page had no such filter): a band, then sorted by it
    lights = sorted(r["LCh"][0] for r in recs)
    lo, hi = (lights[1] + lights[2]) / 2, (lights[4] + lights[5]) / 2  # between swatches: three inside
    assert pg.locator("label:has(#lmin)").text_content() == "lightness from (L*)"
    pg.fill("#lmin", f"{lo:.3f}")
    pg.fill("#lmax", f"{hi:.3f}")
    want = [r["id"] for r in recs if lo <= r["LCh"][0] <= hi]
    assert len(want) == 3 and sorted(pg.eval_on_selector_all("article.card", "els => els.map(e => e.dataset.id)")) == sorted(want)
    pg.select_option("#sort", "lightness")
    pg.select_option("#order", "desc")
    ids = pg.eval_on_selector_all("article.card", "els => els.map(e => e.dataset.id)")
    assert ids == [r["id"] for r in sorted(recs, key=lambda r: -r["LCh"][0]) if r["id"] in want]
    pg.fill("#lmin", "")
    pg.fill("#lmax", "")
    assert len(shown(pg)) == len(recs)
    # nothing matches
    pg.fill("#tmin", "5000")
    assert pg.locator("article.card").count() == 0
    assert "No swatch" in pg.locator("main").text_content()
