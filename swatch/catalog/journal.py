"""The catalog build's journal: the commit that moves a build into place, its rollback, and recovery.

Every path a journal names (its staging folder, the staging folder's ``.previous``, the files in
both) is checked before anything moves: real folders, no link anywhere in the chain, resolving
inside the metadata folder, regular files in them. The staging folder must be a ``staging-*`` folder
of ``.swatch-catalog``. A folder without a manifest is a catalog only if it is empty or holds nothing
but files a first build's journal proves it wrote (their hashes), so a crafted journal in a folder of
the user's moves and deletes nothing. A file is retired only if the previous manifest lists it with
its hash; a rollback takes a file back only if its hash is the new build's. (The trust model and the
metadata checks: :mod:`swatch.catalog.folder`.)

Commit protocol (idempotent, so a run killed at any step is finished by the next one): the journal
lists the staged files and the files to retire and holds the new manifest. Before it is written,
``.previous``, the new manifest (in the staging folder) and the rollback's journal are created, so
the commit and the rollback are renames and unlinks only (out of inodes or space, a rename can fail,
the rollback cannot). Each file in the way is first moved into ``<staging>/.previous``, then the
staged file takes its place. A commit that fails (not killed) is rolled back from ``.previous``: the
previous catalog comes back as it was. The journal's ``phase`` says which way a later run must
finish it (``commit`` or ``rollback``).
"""
from __future__ import annotations

import os
from collections.abc import Callable
from contextlib import suppress
from pathlib import Path

from swatch.catalog.folder import (
    JOURNAL,
    MANIFEST,
    META_DIR,
    PREVIOUS,
    ROLLBACK_JOURNAL,
    STAGED_MANIFEST,
    check_manifest,
    file_matches,
    fsync_dir,
    is_real_dir,
    load_manifest,
    read_metadata,
    remove_tree,
    write_json_atomic,
)
from swatch.catalog.layout import SUBFOLDERS, check_subfolders, drop_empty_subfolders, output_name
from swatch.core.errors import SwatchError
from swatch.core.safepath import entry_kind, inside, is_regular_file, make_real_folder, plain_name, real_folder

__all__ = ["load_journal", "write_journal", "is_catalog", "prepare_commit", "commit", "rollback", "recover"]


def load_journal(meta: Path) -> tuple[dict | None, bool]:
    """The journal of an unfinished build, every name checked, and whether its staging folder is missing.

    Reading it acts on nothing: recovery (:func:`recover`) and the "not a catalog" guard
    (:func:`is_catalog`) decide what to do with it.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder.

    Returns
    -------
    journal : dict or None
        ``files`` and ``remove`` (output names), ``staging`` (a ``staging-*`` folder name), ``phase``
        (``commit`` or ``rollback``) and ``manifest``; None if there is no journal.
    missing : bool
        Whether the staging folder is gone.

    Raises
    ------
    SwatchError
        For a journal that is not one, a name that is not an output name, or a staging folder that is
        not a ``staging-*`` real folder of ``meta``.
    """
    path = meta / JOURNAL
    doc = read_metadata(path)
    if doc is None:
        return None, False
    what = str(path)
    if not (isinstance(doc, dict) and isinstance(doc.get("files"), list) and isinstance(doc.get("remove"), list)
            and isinstance(doc.get("staging"), str) and doc.get("phase", "commit") in ("commit", "rollback")):
        raise SwatchError(f"{what}: not a swatch catalog journal; remove it or use a new folder")
    staging = plain_name(doc["staging"], f"{what} 'staging'")
    if not staging.startswith("staging-"):
        raise SwatchError(f"{what} 'staging': {staging[:80]!r} is not a staging-* folder of {meta}")
    real_folder(meta / staging, f"{what} 'staging'")
    for key in ("files", "remove"):
        for name in doc[key]:
            output_name(name, f"{what} '{key}'")
    check_manifest(doc.get("manifest"), f"{what} 'manifest'")
    return doc, entry_kind(meta / staging) is None


def write_journal(meta: Path, journal: dict) -> None:
    """Write the journal atomically.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder.
    journal : dict
        As :func:`load_journal` returns it.
    """
    write_json_atomic(meta / JOURNAL, journal)


def is_catalog(out: Path, meta: Path) -> bool:
    """Whether ``out`` may be written as a catalog.

    It may if it is empty, holds a manifest, or holds only what a first build's journal proves it
    moved there (each file's hash in the journal's manifest). A journal alone proves nothing (it is
    untrusted): a folder of the user's with a crafted journal is not a catalog, and nothing it names
    is moved or deleted.

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder (may be absent).
    meta : pathlib.Path
        Its metadata folder.

    Returns
    -------
    bool
        True when writing the catalog there destroys nothing the build did not write.
    """
    entries = [p for p in out.iterdir() if p.name != META_DIR] if is_real_dir(out) else []
    if not entries or os.path.lexists(meta / MANIFEST):
        return True
    try:
        doc, missing = load_journal(meta)
    except SwatchError:
        return False
    if doc is None or missing or doc["remove"]:
        return False
    info = doc["manifest"].get("files", {})
    staged = set(doc["files"])
    names = []
    for p in entries:  # a subfolder counts if it is a real one holding only what the journal staged
        if p.name in SUBFOLDERS and entry_kind(p) == "dir":
            names += [(f"{p.name}/{q.name}", q) for q in p.iterdir()]
        else:
            names.append((p.name, p))
    return all(n in staged and file_matches(q, info.get(n)) for n, q in names)


def prepare_commit(meta: Path, staging: Path, journal: dict) -> None:
    """Create what the commit and its rollback need, then write the journal (the commit has begun).

    ``.previous``, the new manifest (in the staging folder) and the rollback's journal are created
    here, so that moving the build into place and undoing it are renames and unlinks only: a file
    system out of inodes or space during the commit can fail a rename, never the rollback.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder.
    staging : pathlib.Path
        The build's staging folder (``meta/staging-*``), holding the new files.
    journal : dict
        As :func:`load_journal` returns it (phase ``commit``).
    """
    prev = make_real_folder(staging / PREVIOUS, "staging folder's .previous")
    check_subfolders(prev, journal["files"] + journal["remove"], "staging folder's .previous", create=True)
    write_json_atomic(staging / STAGED_MANIFEST, journal["manifest"])
    write_json_atomic(meta / ROLLBACK_JOURNAL, dict(journal, phase="rollback"))
    fsync_dir(staging)
    write_journal(meta, journal)


def _checked(out: Path, meta: Path, journal: dict, phase: str) -> tuple[Path, Path | None]:
    """The staging folder and its ``.previous`` (None if absent), after every path the journal names is
    checked: real folders (no link anywhere in the chain) resolving inside the metadata folder, regular
    files (or nothing) inside them, and (commit) files to retire that the previous catalog wrote.
    Raises SwatchError before anything is moved."""
    what = f"catalog journal {meta / JOURNAL}"
    staging = meta / journal["staging"]
    if entry_kind(staging) != "dir":
        raise SwatchError(f"{what}: its staging folder {staging} is not a folder (a link or a file); "
                          "remove the journal and build again")
    inside(staging, meta, f"{what}: staging folder")
    prev = staging / PREVIOUS
    kind = entry_kind(prev)
    if kind not in (None, "dir"):
        raise SwatchError(f"{what}: {prev} is a symbolic link or a file; it must be a real folder inside the "
                          "catalog folder (a link would move files outside it); remove the journal and build again")
    if kind == "dir":
        inside(prev, staging, f"{what}: .previous")
    everything = journal["files"] + journal["remove"]
    check_subfolders(staging, journal["files"], what)
    check_subfolders(out, everything, what)
    if kind == "dir":
        check_subfolders(prev, everything, what)
    named = [staging / n for n in journal["files"]]
    if kind == "dir":
        named += [prev / n for n in everything]
    for path in named:
        if entry_kind(path) not in (None, "file"):
            raise SwatchError(f"{what}: {path} is not a regular file (a link, folder or device); "
                              "remove the journal and build again")
    for name in journal["files"] + journal["remove"]:
        if entry_kind(out / name) == "other":
            raise SwatchError(f"{out / name} is a device, pipe or socket where the catalog writes a file; move it away")
    if phase == "commit":  # (a replay after the manifest was written finds these files gone already)
        old = load_manifest(meta).get("files", {})
        for name in journal["remove"]:
            if entry_kind(out / name) == "file" and not file_matches(out / name, old.get(name)):
                raise SwatchError(f"{what} would retire {out / name}, which the previous catalog did not write "
                                  "(not in its manifest, or changed since); remove the journal and build again")
    return staging, prev if kind == "dir" else None


def commit(out: Path, meta: Path, journal: dict) -> None:
    """Move the staged files into place; renames and unlinks only, idempotent (safe to replay after a crash).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    meta : pathlib.Path
        Its metadata folder.
    journal : dict
        The written journal (:func:`prepare_commit`).

    Raises
    ------
    SwatchError
        Before anything moves, for a path the journal names that is not what it must be; during the
        move, for a folder where a file goes. OSError from a rename (the caller rolls back).
    """
    staging, prev = _checked(out, meta, journal, "commit")
    if prev is None:  # a journal written before .previous was made in advance
        prev = make_real_folder(staging / PREVIOUS, "staging folder's .previous")
    check_subfolders(prev, journal["files"] + journal["remove"], "staging folder's .previous", create=True)
    check_subfolders(out, journal["files"], f"catalog folder {out}", create=True)
    for name in journal["files"]:
        src, dst = staging / name, out / name
        if not os.path.lexists(src):
            continue  # already in place
        kind = entry_kind(dst)
        if kind == "dir":
            raise SwatchError(f"{dst} is a folder where the catalog writes a file; move it away")
        if kind == "link":
            dst.unlink()  # a link is no catalog output: dropped, never followed
        elif kind == "file" and not os.path.lexists(prev / name):
            os.replace(dst, prev / name)
        os.replace(src, dst)
    for name in journal["remove"]:
        dst = out / name
        kind = entry_kind(dst)
        if kind == "link" or (kind == "file" and os.path.lexists(prev / name)):
            dst.unlink()
        elif kind == "file":
            os.replace(dst, prev / name)
    _put_manifest(meta, staging, journal["manifest"])
    drop_empty_subfolders(out, journal["manifest"].get("files", {}))
    fsync_dir(out)
    _finish(meta, staging)


def _put_manifest(meta: Path, staging: Path, manifest: dict) -> None:
    staged = staging / STAGED_MANIFEST
    try:
        ready = is_regular_file(staged) and read_metadata(staged) == manifest
    except SwatchError:
        ready = False
    if ready:
        os.replace(staged, meta / MANIFEST)
    elif load_manifest(meta) != manifest:
        write_json_atomic(meta / MANIFEST, manifest)


def _finish(meta: Path, staging: Path) -> None:
    (meta / ROLLBACK_JOURNAL).unlink(missing_ok=True)
    (meta / JOURNAL).unlink(missing_ok=True)
    fsync_dir(meta)
    remove_tree(staging)


def rollback(out: Path, meta: Path, journal: dict) -> None:
    """Undo a commit that failed part-way: the previous files come back (idempotent; renames only).

    A file is taken back from the catalog folder only if its hash is the journal's (this build wrote it).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    meta : pathlib.Path
        Its metadata folder.
    journal : dict
        The journal of the failed commit (phase ``commit`` or ``rollback``).

    Raises
    ------
    SwatchError
        Before anything moves, for a path the journal names that is not what it must be.
    """
    staging, prev = _checked(out, meta, journal, "rollback")
    if journal.get("phase") != "rollback":  # the journal now says: finish the rollback
        if is_regular_file(meta / ROLLBACK_JOURNAL):
            os.replace(meta / ROLLBACK_JOURNAL, meta / JOURNAL)
        else:
            write_journal(meta, dict(journal, phase="rollback"))
    info = journal["manifest"].get("files", {})
    for name in journal["files"]:
        src, dst = staging / name, out / name
        if not os.path.lexists(src) and entry_kind(dst) == "file" and file_matches(dst, info.get(name)):
            os.replace(dst, src)  # take the new file back
        if prev is not None and os.path.lexists(prev / name) and not os.path.lexists(dst):
            os.replace(prev / name, dst)
    for name in journal["remove"]:
        if prev is not None and os.path.lexists(prev / name) and not os.path.lexists(out / name):
            os.replace(prev / name, out / name)
    with suppress(SwatchError):  # the subfolders the commit made for the new files go again, if empty
        drop_empty_subfolders(out, load_manifest(meta).get("files", {}))
    fsync_dir(out)
    _finish(meta, staging)


def recover(out: Path, meta: Path, log: Callable[[str], object] | None = None) -> None:
    """Finish what a killed build left (its journal), then clear stale staging and temp files and heal the cache.

    Anything in the cache that is not a regular file is removed (the cache is ours to rebuild). Called
    with the lock held, so nothing found here belongs to a running build.

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    meta : pathlib.Path
        Its metadata folder.
    log : callable, optional
        Takes one line (a note when a journal is dropped).

    Raises
    ------
    SwatchError
        For crafted metadata (refused, not rolled back).
    """
    journal, missing = load_journal(meta)
    if journal is not None and missing:  # nothing to restore from: the manifest and the files decide
        if log is not None:
            log(f"note: {meta / JOURNAL} named a staging folder that is gone; journal dropped, "
                "files not matching the manifest are rebuilt")
        (meta / ROLLBACK_JOURNAL).unlink(missing_ok=True)
        (meta / JOURNAL).unlink()
    elif journal is not None:
        if journal.get("phase") == "rollback":
            rollback(out, meta, journal)
        else:
            _checked(out, meta, journal, "commit")  # crafted metadata is refused, not rolled back
            try:
                commit(out, meta, journal)
            except (OSError, SwatchError):
                rollback(out, meta, journal)
    (meta / ROLLBACK_JOURNAL).unlink(missing_ok=True)
    for p in meta.iterdir():
        if p.name.startswith("staging-") or (p.name.startswith(".") and ".tmp" in p.name):
            remove_tree(p)
    cache = meta / "cache"
    if is_real_dir(cache):
        for p in cache.iterdir():
            if (p.name.startswith(".") and ".tmp" in p.name) or not is_regular_file(p):
                remove_tree(p)
