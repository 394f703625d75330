"""Test-suite configuration: the ``slow`` marker for a local quick loop (``make quick``).

The files below build catalogs, drive Chromium or run the CLI in subprocesses (seconds per test);
``pytest -m "not slow"`` leaves them out. CI (``.ci/run``) runs every test.
"""
from __future__ import annotations

import pytest

SLOW_FILES = {"test_catalog_build.py", "test_catalog_browser.py", "test_catalog_explorer_browser.py",
              "test_catalog_explorer_env_browser.py",
              "test_hardening.py", "test_hardening_runs.py", "test_presets.py", "test_designer_exports.py"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.path.name in SLOW_FILES:
            item.add_marker(pytest.mark.slow)
