"""Issue #22 groups 1, 2 and 4: crafted journals (a ``.previous`` that is a link, a folder that is no
catalog but holds a journal), inode exhaustion during the commit, a damaged cache: nothing outside
the catalog folder is touched, nothing of the user's is deleted, the previous catalog survives."""
from __future__ import annotations

import errno
import json
import os
import shutil
from pathlib import Path

import pytest

from swatch.catalog import build as buildmod
from swatch.catalog.build import build_catalog
from swatch.catalog.folder import JOURNAL, MANIFEST, META_DIR, PREVIOUS
from swatch.core.errors import SwatchError
from tests.catalog.folder_helpers import digest, failing_move, journal, refuse, tree, write_spec


def staging_with_linked_previous(out: Path, victim: Path) -> Path:
    staging = out / META_DIR / "staging-x"
    staging.mkdir()
    (staging / PREVIOUS).symlink_to(victim, target_is_directory=True)
    return staging


@pytest.mark.parametrize("names", [["precious.txt"], ["folder"], ["precious.txt", "folder", "catalog.json"]])
def test_issue22_rollback_through_linked_previous_moves_nothing_in(cat, names):
    """Issue #22 group 1: a rollback journal whose staging's .previous links outside moves nothing into the catalog."""
    spec, out, victim = cat
    staging_with_linked_previous(out, victim)
    journal(out, phase="rollback", files=names)
    before, inside = tree(victim), tree(out)
    refuse(spec, out, "symbolic link")
    assert tree(victim) == before
    assert tree(out) == inside


def test_issue22_commit_through_linked_previous_moves_nothing_out(cat):
    """Issue #22 group 1: a commit journal whose .previous links outside moves no catalog file out."""
    spec, out, victim = cat
    staging = staging_with_linked_previous(out, victim)
    (staging / "index.html").write_text("staged", encoding="utf-8")
    (staging / "catalog.json").write_text("{}", encoding="utf-8")
    journal(out, files=["index.html", "catalog.json"], remove=["catalog.csv"])
    before, inside = tree(victim), tree(out)
    refuse(spec, out, "symbolic link")
    assert tree(victim) == before
    assert tree(out) == inside


@pytest.mark.parametrize("what", ["staged-link", "staged-folder", "previous-file", "previous-link-entry"])
def test_issue22_links_and_folders_inside_staging_are_refused(cat, what):
    """Issue #22 group 1: every entry the journal names inside its staging folder must be a regular file."""
    spec, out, victim = cat
    staging = out / META_DIR / "staging-x"
    staging.mkdir()
    if what == "staged-link":
        (staging / "catalog.json").symlink_to(victim / "precious.txt")
    elif what == "staged-folder":
        shutil.copytree(victim / "folder", staging / "catalog.json")
    elif what == "previous-file":
        (staging / PREVIOUS).write_text("not a folder")
    else:
        (staging / PREVIOUS).mkdir()
        (staging / PREVIOUS / "catalog.json").symlink_to(victim / "precious.txt")
        (out / "catalog.json").unlink()
    journal(out, phase="rollback" if what == "previous-link-entry" else "commit", files=["catalog.json"])
    before, inside = tree(victim), tree(out)
    refuse(spec, out)
    assert tree(victim) == before
    assert tree(out) == inside


def test_issue22_folder_with_journal_but_no_manifest_is_not_a_catalog(first_build, tmp_path):
    """Issue #22 group 2: the 'not a catalog' guard holds before any journal is acted on."""
    spec = write_spec(tmp_path / "h.toml")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "my_thesis.txt").write_text("years of work", encoding="utf-8")
    meta = mine / META_DIR
    (meta / "staging-x").mkdir(parents=True)
    (meta / "staging-x" / "my_thesis.txt").write_text("overwritten", encoding="utf-8")
    man = json.loads((first_build / META_DIR / MANIFEST).read_text())
    for phase, files, remove in [("commit", [], ["my_thesis.txt"]), ("commit", ["my_thesis.txt"], []),
                                 ("rollback", ["my_thesis.txt"], [])]:
        (meta / JOURNAL).write_text(json.dumps({"phase": phase, "staging": "staging-x", "files": files,
                                                "remove": remove, "manifest": man}), encoding="utf-8")
        before = tree(mine)
        refuse(spec, mine, "not a swatch catalog")
        assert tree(mine) == before


def test_issue22_remove_list_names_only_files_of_the_previous_catalog(cat):
    """Issue #22 group 2: a journal cannot retire a user's file that the previous catalog did not write."""
    spec, out, _ = cat
    (out / "notes.txt").write_text("the user's notes", encoding="utf-8")
    (out / META_DIR / "staging-x").mkdir()
    journal(out, remove=["notes.txt"])
    refuse(spec, out, "notes.txt")
    assert (out / "notes.txt").read_text() == "the user's notes"


def test_issue22_first_build_killed_in_commit_is_still_finished(tmp_path, monkeypatch):
    """Issue #22 group 2: a real first build's journal (no manifest yet) is still completed by the next build."""
    spec = write_spec(tmp_path / "h.toml")
    out = tmp_path / "new"
    with failing_move(monkeypatch, out, 3, lambda dst: KeyboardInterrupt(), staged=False), \
            pytest.raises(KeyboardInterrupt):
        build_catalog(spec, out, jobs=1)
    assert (out / META_DIR / JOURNAL).exists() and not (out / META_DIR / MANIFEST).exists()
    res = build_catalog(spec, out, jobs=1)
    assert res.noop and (out / META_DIR / MANIFEST).is_file() and not (out / META_DIR / JOURNAL).exists()


def _exhaust_inodes_during_commit(monkeypatch, fail_move: int | None):
    """From the commit on, creating any file or folder fails with ENOSPC (the file system is out of inodes);
    optionally the ``fail_move``-th move into the catalog fails too."""
    real_open, real_mkdir, real_replace, real_commit = os.open, os.mkdir, os.replace, buildmod.commit
    state = {"armed": False, "moves": 0}

    def no_inode():
        return OSError(errno.ENOSPC, "No space left on device")

    def open_(path, flags, *a, **k):
        if state["armed"] and flags & os.O_CREAT and not os.path.lexists(path):
            raise no_inode()
        return real_open(path, flags, *a, **k)

    def mkdir(path, *a, **k):
        if state["armed"]:
            raise no_inode()
        return real_mkdir(path, *a, **k)

    def replace(src, dst, **k):
        if state["armed"] and Path(src).parent.name.startswith("staging-"):
            state["moves"] += 1
            if state["moves"] == fail_move:
                raise no_inode()
        return real_replace(src, dst, **k)

    def commit(*a):
        state["armed"] = True
        return real_commit(*a)

    monkeypatch.setattr(os, "open", open_)
    monkeypatch.setattr(os, "mkdir", mkdir)
    monkeypatch.setattr(os, "replace", replace)
    monkeypatch.setattr(buildmod, "commit", commit)
    return state


def test_issue22_out_of_inodes_during_commit_restores_previous_catalog(cat, monkeypatch):
    """Issue #22 group 4: the rollback needs no new inode, so a commit failing for lack of them leaves no mix."""
    spec, out, _ = cat
    before = digest(out)
    manifest = (out / META_DIR / MANIFEST).read_bytes()
    state = _exhaust_inodes_during_commit(monkeypatch, fail_move=3)
    with pytest.raises(SwatchError, match="previous catalog was restored"):
        build_catalog(spec, out, jobs=1)
    monkeypatch.undo()
    assert state["moves"] >= 3
    assert digest(out) == before
    assert (out / META_DIR / MANIFEST).read_bytes() == manifest
    assert not (out / META_DIR / JOURNAL).exists()


def test_issue22_out_of_inodes_at_commit_time_still_commits(cat, monkeypatch):
    """Issue #22 group 4: the commit itself creates nothing (renames only), so it completes without inodes."""
    spec, out, _ = cat
    _exhaust_inodes_during_commit(monkeypatch, fail_move=None)
    build_catalog(spec, out, jobs=1)
    monkeypatch.undo()
    assert json.loads((out / "catalog.json").read_text())["catalog"]["tolerance"]["grade"] == "A"
    assert build_catalog(spec, out, jobs=1).noop


# -- group 4: a damaged cache heals; a stale journal; validate refuses what the build refuses -----------------

def test_issue22_stale_folders_and_links_in_the_cache_are_healed(cat):
    """Issue #22 group 4: a folder named *.npz, a folder or link where a cache file goes: removed, rebuilt, exit 0."""
    spec, out, victim = cat
    cache = out / META_DIR / "cache"
    (cache / "0123456789abcdef0123456789abcdef01234567.npz").mkdir()
    (cache / "0123456789abcdef0123456789abcdef01234567.npz" / "x").write_text("x")
    for entry in cache.glob("presets-*.json"):
        entry.unlink()
        entry.mkdir()
    for entry in cache.glob("explorer-env-*.json"):
        entry.unlink()
        entry.symlink_to(victim / "precious.txt")
    before = tree(victim)
    build_catalog(spec, out, jobs=1)
    assert tree(victim) == before
    assert all(p.is_file() and not p.is_symlink() for p in cache.iterdir())
    assert build_catalog(spec, out, jobs=1).noop


def test_issue22_deeply_nested_json_in_the_cache_is_recomputed(cat):
    """Issue #22 group 4: cache JSON nested too deep to parse (RecursionError) is a cache miss, not exit 70."""
    spec, out, _ = cat
    cache = out / META_DIR / "cache"
    entries = [*cache.glob("presets-*.json"), *cache.glob("explorer-env-*.json")]
    assert len(entries) == 2
    for entry in entries:
        entry.write_text("[" * 200_000 + "]" * 200_000)
    build_catalog(spec, out, jobs=1)
    assert all(json.loads(e.read_text()) for e in entries)


def test_issue22_npz_that_inflates_beyond_its_shapes_is_rendered_again(cat):
    """Issue #22 group 4: a cache .npz is judged by its zip directory and .npy headers before decompression."""
    import io
    import zipfile

    import numpy as np

    from swatch.catalog import tiles
    from swatch.catalog.spec import load_spec

    spec, out, _ = cat
    want = tiles.tile_shapes(load_spec(spec)[0])
    cache = out / META_DIR / "cache"
    buf = io.BytesIO()
    np.save(buf, np.zeros(16 * 1024 * 1024, dtype=np.uint8))  # 16 MB that deflates to ~16 kB (a 64 px tile: 24 kB)
    bomb = zipfile.ZipInfo("r0_linear.npy")
    bomb.compress_type = zipfile.ZIP_DEFLATED
    for tile in cache.glob("*.npz"):
        with zipfile.ZipFile(tile) as zf:
            members = {n: zf.read(n) for n in zf.namelist() if n != bomb.filename}
        with zipfile.ZipFile(tile, "w") as zf:
            zf.writestr(bomb, buf.getvalue())
            for name, blob in members.items():
                zf.writestr(name, blob)
        assert tile.stat().st_size < 1024 * 1024 and not tiles.npz_fits(tile, want)
    (out / "sheets/sheet_01.png").unlink()  # its sheet is composed again from the cache
    build_catalog(spec, out, jobs=1)
    assert all(tiles.npz_fits(t, want) for t in cache.glob("*.npz"))


def test_issue22_journal_naming_a_missing_staging_folder_is_dropped(cat):
    """Issue #22 group 4: a journal whose staging folder is gone has nothing to restore: dropped, the build goes on."""
    spec, out, _ = cat
    journal(out, staging="staging-gone", files=["catalog.json"])
    build_catalog(spec, out, jobs=1)
    assert not (out / META_DIR / JOURNAL).exists()
    assert json.loads((out / "catalog.json").read_text())["catalog"]["tolerance"]["grade"] == "A"


def test_issue22_validate_and_build_agree_at_the_thickness_limit(tmp_path):
    """Issue #22 group 4: `catalog validate` runs the build's own checks; list_nm = [995] now builds."""
    from tests.cli_helpers import run_swatch

    spec = tmp_path / "edge.toml"
    spec.write_text('name = "Edge"\n[thickness]\nlist_nm = [995]\n[render]\nsize_px = 64\nshapes = ["flat"]\n'
                    'angular_map = false\n', encoding="utf-8")
    assert run_swatch("catalog", "validate", spec).returncode == 0
    proc = run_swatch("catalog", "build", spec, "--out", tmp_path / "out", "-q", "-j", "1")
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("d", [[995], [1000], [0, 1000], [999.95]])
def test_issue22_explorer_axes_stay_within_the_model_thickness_limit(d):
    """Issue #22 group 4: the explorer's margins end at 1000 nm (list_nm = [995] validated ok, then failed)."""
    from swatch.catalog.explorer import GRID_STEP_NM, MATCH_STEP_NM, thickness_axis

    for step in (GRID_STEP_NM, MATCH_STEP_NM):
        lo, hi, n = thickness_axis(d, step)
        assert 0.0 <= lo <= min(d) and max(d) - step < hi <= 1000.0 + 1e-9
        assert abs(lo + (n - 1) * step - hi) < 1e-6


def test_issue22_read_only_catalog_no_op_succeeds_and_a_change_is_refused(cat, monkeypatch):
    """Issue #22 group 8: a no-op rebuild of a read-only catalog was refused; it is answered "up to date",
    and a build that would change it is refused in one line with nothing written. (Root ignores
    permissions, so the folder's unwritability is simulated through os.access.)"""
    spec, out, _ = cat
    write_spec(spec, grade="C")  # the spec the catalog was built from
    before = tree(out)
    monkeypatch.setattr(os, "access", lambda path, mode, **k: not (mode & os.W_OK))
    assert build_catalog(spec, out, jobs=1).noop
    write_spec(spec, grade="A")
    refuse(spec, out, "not writable", "not up to date")
    assert tree(out) == before
