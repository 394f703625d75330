"""Fixtures the catalog-folder tests share (#12, #22): one small catalog, built once per session (per xdist worker;
issue 17 item 7: it was built again for each module). Tests copy it (the ``cat`` fixtures) or only read it."""
from __future__ import annotations

import shutil

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


@pytest.fixture
def cat(first_build, tmp_path):
    """(spec, catalog folder, victim folder outside it with a file and a folder of the user's): a fresh copy of the
    built catalog, and a spec of grade A (the build's is C)."""
    out = tmp_path / "a" / "b" / "out"
    shutil.copytree(first_build, out, symlinks=True)
    victim = tmp_path / "victim"
    victim.mkdir()
    (victim / "precious.txt").write_text("do not delete", encoding="utf-8")
    (victim / "catalog.json").write_text("the user's own catalog.json", encoding="utf-8")
    (victim / "folder").mkdir()
    (victim / "folder" / "inside.txt").write_text("mine", encoding="utf-8")
    return write_spec(tmp_path / "h.toml", grade="A"), out, victim
