"""Test-suite configuration: the fixtures every browser test shares (issue 17 item 7).

One Chromium for all browser tests (``chromium``, session-scoped, SwiftShader WebGL2) and one small
catalog built once for the page tests (``small_catalog``, :data:`tests.browser.SMALL_CATALOG_SPEC`):
before, each browser file launched its own Chromium and built its own copy of the same catalog.
Under pytest-xdist (``python3 dev.py test`` runs the whole suite on two workers, ``--dist loadfile``)
each worker starts them at most once, when it runs a browser file.

Markers are set in each test file (``pytestmark = pytest.mark.slow``: builds catalogs, drives
Chromium or runs processes; ``pytest -m "not slow"`` leaves them out, CI runs every test).
"""
from __future__ import annotations

import pytest

from tests.browser import CHROMIUM, SMALL_CATALOG_SPEC, WEBGL_ARGS, require_chromium


@pytest.fixture(scope="session")
def playwright_session():
    """Playwright's sync API, started once (a second ``sync_playwright()`` in the same thread while
    one runs is refused by Playwright: everything that drives Chromium goes through this one)."""
    require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        yield p


@pytest.fixture(scope="session")
def chromium(playwright_session):
    """The one headless Chromium of the suite (Debian's /usr/bin/chromium, SwiftShader WebGL2).
    Tests open their own context or page on it and close it."""
    browser = playwright_session.chromium.launch(executable_path=CHROMIUM, args=WEBGL_ARGS)
    yield browser
    browser.close()


@pytest.fixture(scope="session")
def small_catalog(tmp_path_factory):
    """The small page-test catalog (20–300 nm every 70 nm, 64 px, one sheet of 4), built once per
    session; its output folder. Tests read it and never write into it (screenshots go to its parent)."""
    from swatch.catalog.build import build_catalog

    require_chromium()
    root = tmp_path_factory.mktemp("small-catalog")
    spec = root / "spec.toml"
    spec.write_text(SMALL_CATALOG_SPEC.format(name="page test"), encoding="utf-8")
    build_catalog(spec, root / "out", jobs=1)
    return root / "out"
