"""Where the browser tests find Chromium: Debian's build, driven by Playwright.

Debian's ``chromium-headless-shell`` where it is installed (CI installs it), else its ``chromium``
(:data:`CHROMIUM`). A missing browser skips those tests, unless ``SWATCH_REQUIRE_BROWSER=1`` (CI sets it),
when it fails them instead.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

#: Debian's Chromium builds the tests can drive, preferred first. The headless shell (package
#: ``chromium-headless-shell``, the same Chromium release) is Blink, V8 and SwiftShader WebGL without the
#: browser's own user interface: what Playwright itself runs for headless tests. Issue 17: the browser files
#: took 34 CPU-s of Chromium with ``chromium`` (its browser process 6.2, a renderer for its top-chrome WebUI
#: 6.5) and 23 with the shell (browser 1.5, no WebUI renderer), the same 32 tests passing (one process,
#: 2026-12-03); the GPU process, where WebGL draws, is the same 15 CPU-s.
CHROMIUM_BUILDS = ("/usr/bin/chromium-headless-shell", "/usr/bin/chromium")
CHROMIUM = next((path for path in CHROMIUM_BUILDS if Path(path).exists()), CHROMIUM_BUILDS[-1])


def require_chromium() -> None:
    """Skip (or, with ``SWATCH_REQUIRE_BROWSER=1``, fail) the calling test when Chromium or
    Playwright is missing."""
    if not Path(CHROMIUM).exists():
        if os.environ.get("SWATCH_REQUIRE_BROWSER") == "1":
            pytest.fail(f"{CHROMIUM} is missing and SWATCH_REQUIRE_BROWSER=1")
        pytest.skip(f"{CHROMIUM} not installed")
    pytest.importorskip("playwright")


def wait_until(page, function_js: str, timeout_s: float = 30.0) -> None:
    """Poll ``page.evaluate(function_js)`` until it returns a truthy value.

    Playwright's ``wait_for_function`` evaluates its predicate with ``eval`` inside the page, which
    the catalog page's Content-Security-Policy forbids (no ``'unsafe-eval'``); CI's Chromium reported
    that as an ``EvalError``. ``page.evaluate`` of a function is compiled by the DevTools protocol,
    outside the page's CSP, so polling it tests the page under its real policy.
    """
    import time

    deadline = time.monotonic() + timeout_s
    while not page.evaluate(function_js):
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout_s} s waiting for {function_js}")
        page.wait_for_timeout(50)


def save_canvas(page, path: Path) -> None:
    """Write the live view's canvas (its drawing buffer, as drawn) to ``path`` as PNG, to look at.

    ``canvas.toDataURL`` in the page: ~0.1 s, where a Playwright element screenshot (a compositor frame
    of the page in software GL) took ~0.75 s on this 2-core VM (issue 17: 24 of them were 18 s of a file).
    """
    import base64

    url = page.evaluate("() => document.getElementById('view').toDataURL('image/png')")
    path.write_bytes(base64.b64decode(url.split(",", 1)[1]))


#: Chromium flags for the WebGL pages: headless, SwiftShader WebGL2, nothing fetched in the background; the
#: page itself composited and rasterised in software (WebGL still draws in SwiftShader). Issue 17: on this
#: 2-core VM the GPU process spent 30 CPU-s of the browser files (one process, 2026-12-02) compositing
#: pages through SwiftShader GL; with both flags 17 CPU-s, the same tests passing. The one thing it changes
#: is a console note, :data:`GPU_PERFORMANCE_NOTE`, which :func:`open_catalog_page` does not count as an error.
WEBGL_ARGS = ["--headless", "--no-sandbox", "--no-first-run", "--disable-background-networking",
              "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-compositing",
              "--disable-gpu-rasterization"]

#: Chromium's GL driver notes of category Performance ("[.WebGL-0x…]GL Driver Message (OpenGL, Performance,
#: …): GPU stall due to ReadPixels"): with software compositing the compositor reads each WebGL frame back
#: from SwiftShader and Chromium says so on the page's console. A note about the test browser's set-up,
#: not a page error; any other message (and any other GL driver message) still fails the test.
GPU_PERFORMANCE_NOTE = re.compile(r"\[\.WebGL-0x[0-9a-f]+\]GL Driver Message \(OpenGL, Performance, ")


def page_error(message) -> str | None:
    """The text of a console message the browser tests count as an error (type error or warning), or None
    for other messages and for :data:`GPU_PERFORMANCE_NOTE`."""
    if message.type not in ("error", "warning") or GPU_PERFORMANCE_NOTE.match(message.text):
        return None
    return message.text


#: A small catalog for the page tests (20–300 nm every 70 nm, 64 px renders, one sheet of 4); ``{name}``.
#: Built once per session by the ``small_catalog`` fixture (tests/conftest.py).
SMALL_CATALOG_SPEC = """
name = "{name}"
[thickness]
start_nm = 20
stop_nm = 300
step_nm = 70
[render]
size_px = 64
[sheet]
columns = 4
rows = 1
"""


#: The page's address fragment for tests that do not look at the environment lighting: the live view opens
#: under the point light (the page's own link syntax, swatch/catalog/web/link.js), not the studio, whose first
#: frame is a gather pass of 128 samples a pixel (~1.2 CPU-s in SwiftShader, on both cores, at every page load).
POINT_LIGHT = "lighting=point"


def open_catalog_page(browser, out: Path, js: bool = True, viewport=(1280, 900), scale: float = 1.0,
                      fragment: str = ""):
    """A new context and page on ``out/index.html`` (``scale``: device pixels a CSS pixel; ``fragment``: the
    address's fragment without its ``#``, the view the page opens in, e.g. :data:`POINT_LIGHT`): (context, page,
    events) where events collects page errors, console errors and warnings, every request URL, and the message
    of every dialog (dismissed: an ``alert`` from an injected script is caught from the first load on)."""
    ctx = browser.new_context(java_script_enabled=js, viewport={"width": viewport[0], "height": viewport[1]},
                              device_scale_factor=scale)
    pg = ctx.new_page()
    events: dict = {"errors": [], "requests": [], "dialogs": []}
    pg.on("dialog", lambda d: (events["dialogs"].append(d.message), d.dismiss()))
    pg.on("pageerror", lambda e: events["errors"].append(str(e)))
    pg.on("console", lambda m: events["errors"].append(text) if (text := page_error(m)) is not None else None)
    pg.on("request", lambda r: events["requests"].append(r.url))
    pg.goto((out / "index.html").resolve().as_uri() + (f"#{fragment}" if fragment else ""))
    if js:
        wait_until(pg, "() => window.swatchCatalog !== undefined")
    return ctx, pg, events
