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
