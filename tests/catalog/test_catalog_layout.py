"""Issue 21 item 5: the catalog folder groups its outputs (``sheets/``, ``chips/``, ``presets/``; the page,
JSON/CSV and exports at the top), an old flat folder is migrated by the next build through the journal
and commit (never a user's file lost, the previous catalog back if the commit fails), and every name
read back from the metadata still resolves inside the folder."""
from __future__ import annotations

import contextlib
import io
import json
import os
import re
import shutil
from pathlib import Path

import pytest

from swatch.catalog.build import build_catalog
from swatch.catalog.folder import JOURNAL, MANIFEST, META_DIR
from swatch.catalog.layout import SUBFOLDERS
from swatch.cli import main
from swatch.core.errors import SwatchError
from tests.catalog import folder_helpers
from tests.catalog.folder_helpers import digest, failing_move

pytestmark = pytest.mark.slow

def write_spec(path: Path, grade: str = "C") -> Path:
    return folder_helpers.write_spec(path, grade, name="Layout", list_nm=(40, 120, 200))


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("layout")
    spec = write_spec(root / "l.toml")
    out = root / "built"
    build_catalog(spec, out, jobs=1)
    return spec, out


@pytest.fixture
def cat(built, tmp_path):
    spec, first = built
    out = tmp_path / "out"
    shutil.copytree(first, out, symlinks=True)
    return spec, out


def flatten(out: Path) -> dict[str, str]:
    """Turn a catalog folder into what the flat layout (before issue 21) wrote: every output at the top,
    the manifest naming them so (and an older fingerprint). Returns the flat folder's digest."""
    meta = out / META_DIR
    man = json.loads((meta / MANIFEST).read_text())
    files, keys = {}, {}
    for name, info in man["files"].items():
        flat = name.rpartition("/")[2]
        if flat != name:
            os.replace(out / name, out / flat)
        files[flat] = info
    for name, key in man["sheet_keys"].items():
        keys[name.rpartition("/")[2]] = key
    for sub in SUBFOLDERS:
        if (out / sub).is_dir():
            (out / sub).rmdir()
    man.update(files=files, sheet_keys=keys, fingerprint="the flat layout's build")
    (meta / MANIFEST).write_text(json.dumps(man, indent=1, sort_keys=True) + "\n")
    return digest(out)


def test_outputs_are_grouped_in_subfolders_and_records_name_them(built):
    """#21: sheets, chips and presets in their folders; the page, data and exports at the top; every
    path catalog.json names is a file of the folder."""
    _, out = built
    top = sorted(p.name for p in out.iterdir() if p.is_file())
    assert top == ["catalog.csv", "catalog.json", "index.html", "layout-srgb.ase", "layout.ase", "layout.cxf"]
    assert sorted(p.name for p in out.iterdir() if p.is_dir()) == [META_DIR, "chips", "presets", "sheets"]
    assert sorted(p.name for p in (out / "sheets").iterdir()) == ["sheet_01.exr", "sheet_01.png",
                                                                 "sheet_02.exr", "sheet_02.png"]
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    named = [s[k] for s in doc["sheets"] for k in ("png", "exr")]
    for r in doc["swatches"]:
        named += [r["sheet_png"], r["sheet_exr"], r["print_chip"]["png"], r["print_chip"]["tiff"],
                  *(r["presets"][f] for f in ("gltf", "blender", "materialx"))]
    assert all((out / n).is_file() for n in named)
    assert {n.partition("/")[0] for n in named} == {"sheets", "chips", "presets"}
    manifest = json.loads((out / META_DIR / MANIFEST).read_text())
    assert set(manifest["files"]) == set(digest(out))
    html = (out / "index.html").read_text(encoding="utf-8")
    assert 'href="sheets/sheet_02.png"' in html and "url(sheets/sheet_01.png)" in html.replace('"', "")


def test_old_flat_catalog_is_migrated_and_users_files_kept(cat, built):
    """#21: a rebuild over a flat folder moves the catalog into the subfolders; a file of the user's
    (not in the manifest, or changed since the build wrote it) stays where it is."""
    spec, out = cat
    flatten(out)
    (out / "notes.txt").write_text("mine", encoding="utf-8")
    (out / "chip_S002.png").write_bytes(b"my edited chip")  # changed since the build: the user's now
    res = build_catalog(spec, out, jobs=1)
    assert not res.noop and res.rendered == 0  # the tiles come from the cache
    expected = digest(built[1])
    got = digest(out)
    assert got.pop("notes.txt") and got.pop("chip_S002.png")
    assert got == expected  # byte for byte what a fresh build writes
    assert (out / "notes.txt").read_text() == "mine" and (out / "chip_S002.png").read_bytes() == b"my edited chip"
    assert not list((out / META_DIR).glob("staging-*")) and not (out / META_DIR / JOURNAL).exists()
    assert build_catalog(spec, out, jobs=1).noop


def test_failed_migration_restores_the_flat_catalog(cat, monkeypatch):
    """#21: a commit that fails part-way through a migration puts the flat catalog back as it was
    (files, manifest, no subfolders left); the next build migrates it."""
    spec, out = cat
    before = flatten(out)
    manifest = (out / META_DIR / MANIFEST).read_bytes()
    # the fourth file moving into one of the new subfolders fails
    with failing_move(monkeypatch, out, 4, lambda dst: OSError(28, "No space left on device", dst), depth=2) \
            as calls, pytest.raises(SwatchError, match="previous catalog was restored"):
        build_catalog(spec, out, jobs=1)
    assert calls["n"] == 4
    assert digest(out) == before
    assert (out / META_DIR / MANIFEST).read_bytes() == manifest
    assert not any((out / sub).exists() for sub in SUBFOLDERS)
    assert not build_catalog(spec, out, jobs=1).noop
    assert (out / "sheets" / "sheet_01.png").is_file() and not (out / "sheet_01.png").exists()


def test_killed_migration_is_finished_by_the_next_build(cat, monkeypatch):
    spec, out = cat
    flatten(out)
    with failing_move(monkeypatch, out, 5, lambda dst: KeyboardInterrupt(), depth=2), pytest.raises(KeyboardInterrupt):
        build_catalog(spec, out, jobs=1)
    assert (out / META_DIR / JOURNAL).exists()
    assert build_catalog(spec, out, jobs=1).noop  # the journal is replayed: the new catalog is complete
    assert not any(p.is_file() for p in out.glob("sheet_*")) and (out / "sheets" / "sheet_02.exr").is_file()


@pytest.mark.parametrize("name", ["sheets/../../victim/precious.txt", "other/x.png", "sheets/a/b.png",
                                  "/tmp/x.png", "sheets/", "sheets/.."])
def test_metadata_names_outside_the_subfolders_are_refused(cat, tmp_path, name):
    """#21 keeps #12's trust model: a manifest name may be a plain file name or SUBFOLDER/plain name only."""
    _, out = cat
    man = json.loads((out / META_DIR / MANIFEST).read_text())
    man["files"][name] = {"sha256": "0" * 64, "size": 1}
    (out / META_DIR / MANIFEST).write_text(json.dumps(man))
    before = digest(out)
    with pytest.raises(SwatchError, match="not a plain file name"):
        build_catalog(write_spec(tmp_path / "g.toml", grade="A"), out, jobs=1)
    assert digest(out) == before


@pytest.mark.parametrize("what", ["link", "file"])
def test_a_link_or_file_where_a_subfolder_goes_is_refused(cat, tmp_path, what):
    """#21: a subfolder replaced by a link (to a folder outside) or a file is refused before anything moves;
    nothing is written through the link."""
    _, out = cat
    victim = tmp_path / "victim"
    victim.mkdir()
    (victim / "precious.txt").write_text("do not delete")
    shutil.rmtree(out / "sheets")
    if what == "link":
        (out / "sheets").symlink_to(victim, target_is_directory=True)
    else:
        (out / "sheets").write_text("mine")
    with pytest.raises(SwatchError, match="sheets"):
        build_catalog(write_spec(tmp_path / "g.toml", grade="A"), out, jobs=1)
    assert sorted(p.name for p in victim.iterdir()) == ["precious.txt"]
    assert os.path.lexists(out / "sheets") and not list((out / META_DIR).glob("staging-*"))


def test_validate_says_what_goes_where_as_the_build_writes_it(built):
    """#21: ``catalog validate`` names the subfolders with the number of files the build puts there."""
    spec, out = built
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["catalog", "validate", str(spec)]) in (0, None)
    line = buf.getvalue().splitlines()[-1]
    assert line.startswith("writes: index.html, catalog.json/.csv, CxF and ASE at the top;")
    said = {m[0]: int(m[1]) for m in re.findall(r"(\w+)/ (\d+)", line)}
    assert said == {sub: len(list((out / sub).iterdir())) for sub in SUBFOLDERS if (out / sub).is_dir()}
