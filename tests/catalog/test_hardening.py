"""Issue #12: a catalog folder's own files cannot make a build touch anything outside it, and a
failed build leaves the previous catalog (crafted folders, failures during the commit)."""
from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
from pathlib import Path

import pytest

from swatch.catalog import build as buildmod
from swatch.catalog.build import build_catalog
from swatch.catalog.folder import JOURNAL, MANIFEST, META_DIR
from swatch.core.errors import SwatchError
from tests.catalog.folder_helpers import digest, failing_move, journal, refuse, tree, write_spec

pytestmark = pytest.mark.slow  # builds catalogs or runs processes (seconds per test)

@pytest.mark.parametrize("staging", ["../../../victim", "../../../../victim", "/tmp", "staging-x/../../../victim",
                                     "..", "."])
def test_issue12_journal_staging_outside_is_refused(cat, staging):
    spec, out, victim = cat
    journal(out, staging=staging.replace("/tmp", str(victim)))
    before = tree(out)
    refuse(spec, out, "staging")
    assert (victim / "precious.txt").read_text() == "do not delete"
    assert tree(out) == before  # nothing moved or deleted


@pytest.mark.parametrize("key", ["files", "remove"])
def test_issue12_journal_names_outside_are_refused(cat, key):
    spec, out, victim = cat
    (out / META_DIR / "staging-x").mkdir()
    (out / META_DIR / "staging-x" / "x").write_text("x")
    journal(out, **{key: ["../../../victim/precious.txt"]})
    refuse(spec, out, "not a plain file name")
    assert (victim / "precious.txt").read_text() == "do not delete"


def test_issue12_manifest_entry_outside_is_refused(cat):
    spec, out, victim = cat
    path = out / META_DIR / MANIFEST
    man = json.loads(path.read_text())
    man["files"]["../../../victim/precious.txt"] = {"sha256": "0" * 64, "size": 13}
    path.write_text(json.dumps(man))
    before = tree(out)
    refuse(spec, out, "../../../victim/precious.txt", "not a plain file name")
    assert (victim / "precious.txt").read_text() == "do not delete"
    assert tree(out) == before


@pytest.mark.parametrize("doc", ['{"files": 5}', "[1, 2]", "not json", '{"files": {"a": {"size": "x"}}}'])
def test_issue12_malformed_manifest_is_refused(cat, doc):
    spec, out, _ = cat
    (out / META_DIR / MANIFEST).write_text(doc)
    refuse(spec, out, "manifest")


def test_issue12_symlinked_metadata_folder_is_refused(tmp_path):
    spec = write_spec(tmp_path / "h.toml")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "precious.txt").write_text("x")
    out = tmp_path / "out"
    out.mkdir()
    (out / META_DIR).symlink_to(elsewhere, target_is_directory=True)
    refuse(spec, out, "symbolic link")
    assert sorted(p.name for p in elsewhere.iterdir()) == ["precious.txt"]


@pytest.mark.parametrize("what", ["cache", "lock", MANIFEST])
def test_issue12_symlinks_inside_metadata_are_refused(cat, what):
    spec, out, victim = cat
    link = out / META_DIR / what
    shutil.rmtree(link) if link.is_dir() else link.unlink(missing_ok=True)
    link.symlink_to(victim / "precious.txt" if what != "cache" else victim)
    before = tree(victim)
    refuse(spec, out)
    assert tree(victim) == before


def test_issue12_stale_staging_link_is_unlinked_not_followed(cat):
    spec, out, victim = cat
    (out / META_DIR / "staging-evil").symlink_to(victim, target_is_directory=True)
    build_catalog(spec, out, jobs=1)
    assert (victim / "precious.txt").read_text() == "do not delete"
    assert not os.path.lexists(out / META_DIR / "staging-evil")


def test_issue12_output_links_are_replaced_not_written_through(cat):
    spec, out, victim = cat
    (out / "catalog.json").unlink()
    (out / "catalog.json").symlink_to(victim / "precious.txt")
    build_catalog(spec, out, jobs=1)
    assert (victim / "precious.txt").read_text() == "do not delete"
    assert not (out / "catalog.json").is_symlink()
    assert json.loads((out / "catalog.json").read_text())["catalog"]["tolerance"]["grade"] == "A"


def test_issue12_loser_of_two_first_builds_removes_nothing(tmp_path, monkeypatch):
    """The build that does not get the lock must not delete the folder the winner is writing."""
    spec = write_spec(tmp_path / "h.toml")
    out = tmp_path / "new"
    real = buildmod._prepare_out_dir
    held = {}

    def winner_meanwhile(path):  # the winner creates the folder and takes the lock first
        meta = real(path)
        fd = os.open(meta / "lock", os.O_RDWR | os.O_CREAT)
        fcntl.flock(fd, fcntl.LOCK_EX)
        (meta / "staging-winner").mkdir()
        (meta / "staging-winner" / "sheet_01.png").write_bytes(b"winner's work")
        held["fd"] = fd
        return meta

    monkeypatch.setattr(buildmod, "_prepare_out_dir", winner_meanwhile)
    with pytest.raises(SwatchError, match="another catalog build"):
        build_catalog(spec, out, jobs=1)
    os.close(held["fd"])
    assert (out / META_DIR / "staging-winner" / "sheet_01.png").read_bytes() == b"winner's work"


def test_issue12_folder_in_the_way_is_refused_and_previous_catalog_kept(cat):
    spec, out, _ = cat
    before = digest(out)
    (out / "sheets/sheet_02.png").unlink()  # the file is replaced by a folder of the user's
    (out / "sheets/sheet_02.png").mkdir()
    (out / "sheets/sheet_02.png" / "mine.txt").write_text("mine")
    del before["sheets/sheet_02.png"]
    before["sheets/sheet_02.png/mine.txt"] = hashlib.sha256(b"mine").hexdigest()
    refuse(spec, out, "sheet_02.png", "folder")
    assert digest(out) == before
    assert (out / "sheets/sheet_02.png" / "mine.txt").read_text() == "mine"
    assert not list((out / META_DIR).glob("staging-*")) and not (out / META_DIR / JOURNAL).exists()
    shutil.rmtree(out / "sheets/sheet_02.png")
    res = build_catalog(spec, out, jobs=1)  # the next build recovers
    assert not res.noop and (out / "sheets/sheet_02.png").is_file()


def test_issue12_failure_during_commit_restores_previous_catalog(cat, monkeypatch):
    spec, out, _ = cat
    before = digest(out)
    manifest = (out / META_DIR / MANIFEST).read_bytes()
    with failing_move(monkeypatch, out, 3, lambda dst: OSError(28, "No space left on device", dst)) as calls, \
            pytest.raises(SwatchError, match="previous catalog was restored"):
        build_catalog(spec, out, jobs=1)
    assert calls["n"] == 3
    assert digest(out) == before
    assert (out / META_DIR / MANIFEST).read_bytes() == manifest
    assert not (out / META_DIR / JOURNAL).exists() and not list((out / META_DIR).glob("staging-*"))
    res = build_catalog(spec, out, jobs=1)
    assert not res.noop
    doc = json.loads((out / "catalog.json").read_text())
    assert doc["catalog"]["tolerance"]["grade"] == "A"


def test_issue12_interrupted_rollback_is_finished_by_the_next_build(cat, monkeypatch):
    """A run killed while rolling back leaves a 'rollback' journal; the next run completes it."""
    spec, out, _ = cat
    from swatch.catalog import journal

    before = digest(out)
    real_replace = os.replace
    state = {"n": 0, "rolling": False}

    def replace(src, dst):
        if Path(dst).parent == out and Path(src).parent.name.startswith("staging-"):
            state["n"] += 1
            if state["n"] == 3:
                raise OSError(5, "Input/output error", str(dst))
        if state["rolling"] and Path(dst).parent == out:
            raise KeyboardInterrupt  # killed during the rollback
        return real_replace(src, dst)

    real_rollback = journal.rollback

    def rollback(*a):
        state["rolling"] = True
        return real_rollback(*a)

    monkeypatch.setattr(os, "replace", replace)
    monkeypatch.setattr(buildmod, "rollback", rollback)
    with pytest.raises(KeyboardInterrupt):
        build_catalog(spec, out, jobs=1)
    monkeypatch.setattr(os, "replace", real_replace)
    assert json.loads((out / META_DIR / JOURNAL).read_text())["phase"] == "rollback"
    write_spec(spec, grade="C")  # the spec the previous catalog was built from
    res = build_catalog(spec, out, jobs=1)
    assert res.noop and digest(out) == before
