"""Where the browser tests find Chromium: Debian's ``/usr/bin/chromium``, driven by Playwright.

A missing browser skips those tests, unless ``SWATCH_REQUIRE_BROWSER=1`` (CI sets it), when it
fails them instead.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"


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
