"""Fixtures the catalog-folder tests share (#12, #22): one small catalog built per test module."""
from __future__ import annotations

import pytest

from swatch.catalog.build import build_catalog
from tests.catalog.folder_helpers import write_spec


@pytest.fixture(scope="module")
def first_build(tmp_path_factory):
    root = tmp_path_factory.mktemp("hard")
    spec = write_spec(root / "h.toml")
    out = root / "built"
    build_catalog(spec, out, jobs=1)
    return out
