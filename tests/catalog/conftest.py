"""Fixtures the catalog-folder tests share (#12, #22): one small catalog, built once per session (per xdist worker;
issue 17 item 7: it was built again for each module). Tests copy it (the ``cat`` fixtures) or only read it."""
from __future__ import annotations

import pytest

from swatch.catalog.build import build_catalog
from tests.catalog.folder_helpers import write_spec


@pytest.fixture(scope="session")
def first_build(tmp_path_factory):
    root = tmp_path_factory.mktemp("hard")
    spec = write_spec(root / "h.toml")
    out = root / "built"
    build_catalog(spec, out, jobs=1)
    return out
