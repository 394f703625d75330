"""The catalog folder's own metadata: lock, manifest, journal, and the commit that moves a build into place.

Layout (issue 21): the page, ``catalog.json``/``.csv`` and the exports lie at the top of the folder, the
rest in one of :data:`SUBFOLDERS` (``sheets/``, ``chips/``, ``presets/``, ``heroes/``). A folder an older
build wrote flat is migrated by the next build through the same journal and commit: its files are
retired (as any file a build no longer produces), the new ones moved into the subfolders.

Trust model: the folder (and its ``.swatch-catalog``) may come from someone else, so everything
read back from it is untrusted input. Every name in the manifest and the journal must be an output
name (:func:`output_name`: a plain file name, or one of :data:`SUBFOLDERS`, ``/`` and a plain file name)
and the staging folder a ``staging-*`` folder of ``.swatch-catalog``; the metadata folder, the cache,
the lock and every subfolder a name passes through (in the catalog folder, the staging folder and its
``.previous``) must not be symbolic links; the metadata files are size-capped and must be regular files. Anything else is refused with one line
(:class:`~swatch.core.errors.SwatchError`) before anything is moved or deleted: a build never writes
or deletes outside its folder.

Every path a journal names (its staging folder, the staging folder's ``.previous``, the files in
both) is checked before anything moves: real folders, no link anywhere in the chain, resolving
inside the metadata folder, regular files in them. A folder without a manifest is a catalog only
if it is empty or holds nothing but files a first build's journal proves it wrote (their hashes),
so a crafted journal in a folder of the user's moves and deletes nothing. A file is retired only if
the previous manifest lists it with its hash; a rollback takes a file back only if its hash is the
new build's.

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

import fcntl
import hashlib
import json
import os
import shutil
import signal
import stat
from contextlib import contextmanager, suppress
from pathlib import Path

from swatch.catalog.layout import SUBFOLDERS, check_subfolders, drop_empty_subfolders, output_name, subfolders_of
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES, MAX_METADATA_BYTES
from swatch.core.safepath import entry_kind, inside, is_regular_file, make_real_folder, plain_name, real_folder

__all__ = ["META_DIR", "MANIFEST", "JOURNAL", "PREVIOUS", "locked", "signals_held", "meta_folder", "cache_folder",
           "load_manifest", "load_journal", "write_journal", "prepare_commit", "commit", "rollback", "recover",
           "is_catalog", "intact", "file_matches", "STAGED_MANIFEST", "ROLLBACK_JOURNAL",
           "write_json_atomic", "read_cache_json", "fsync_dir", "sha256_file", "remove_tree", "check_targets"]

META_DIR = ".swatch-catalog"
MANIFEST = "manifest.json"
JOURNAL = "journal.json"
PREVIOUS = ".previous"  # inside a staging folder: the files a commit replaced or retired
STAGED_MANIFEST = ".manifest.json"  # inside a staging folder: the new manifest, renamed into place
ROLLBACK_JOURNAL = "journal-rollback.json"  # the rollback's journal, written before the commit begins
# -- small file helpers ------------------------------------------------------------------------

def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def write_json_atomic(path: Path, obj) -> None:
    atomic_write_text(path, json.dumps(obj, indent=1, sort_keys=True) + "\n")


def fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def remove_tree(path: Path) -> None:
    """Remove a folder of ours (a link is unlinked, never followed)."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return
    if stat.S_ISDIR(st.st_mode):
        shutil.rmtree(path, ignore_errors=True)
    else:
        Path(path).unlink(missing_ok=True)


def _lexists(p: Path) -> bool:
    return os.path.lexists(p)


def _is_dir(p: Path) -> bool:
    try:
        return stat.S_ISDIR(os.lstat(p).st_mode)
    except OSError:
        return False


# -- folders and lock --------------------------------------------------------------------------

def meta_folder(out: Path) -> Path:
    """``out/.swatch-catalog``, refused if it is a symbolic link or a file."""
    return real_folder(out / META_DIR, "catalog metadata folder")


def cache_folder(meta: Path) -> Path:
    return make_real_folder(meta / "cache", "catalog cache folder")


@contextmanager
def locked(meta: Path, read_only: bool = False):
    """Hold ``meta/lock`` (flock) for one build; another build holding it is refused. ``read_only``: the
    folder cannot be written (a check that it is up to date): the lock is opened for reading and held
    shared, so a writing build still excludes it."""

    busy = f"another catalog build is writing {meta.parent}; wait for it to finish"
    flags = os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK
    try:
        fd = (os.open(meta / "lock", os.O_RDONLY | flags) if read_only
              else os.open(meta / "lock", os.O_RDWR | os.O_CREAT | flags, 0o644))
    except FileNotFoundError:  # the folder went away: a first build that held the lock failed
        raise SwatchError(busy if not read_only else f"{meta.parent} cannot be written and has no build lock; "
                          "build into a writable folder") from None
    except OSError as exc:
        raise SwatchError(f"cannot open the build lock {meta / 'lock'} ({exc.strerror}); it must be a regular "
                          "file of the catalog folder, not a link") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise SwatchError(f"the build lock {meta / 'lock'} is not a regular file; remove it")
        try:
            fcntl.flock(fd, (fcntl.LOCK_SH if read_only else fcntl.LOCK_EX) | fcntl.LOCK_NB)
        except BlockingIOError:
            raise SwatchError(busy) from None
        yield
    finally:
        os.close(fd)


@contextmanager
def signals_held():
    """Defer SIGINT/SIGTERM/SIGHUP while the staged files are moved into place."""

    sigs = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    except (AttributeError, ValueError, OSError):  # not the main thread or no support
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


# -- metadata (untrusted) ----------------------------------------------------------------------

def _read_metadata(path: Path):
    """The JSON in ``path``; None if absent. Refused if not a regular file, too big or not JSON."""
    if not _lexists(path):
        return None
    what = f"catalog metadata {path}"
    if not is_regular_file(path):
        raise SwatchError(f"{what} is not a regular file (a link, folder or device); remove it or use a new folder")
    if path.stat().st_size > MAX_METADATA_BYTES:
        raise SwatchError(f"{what} is larger than {MAX_METADATA_BYTES // (1024 * 1024)} MB; "
                          "not a swatch catalog's metadata")
    try:
        return json.loads(path.read_bytes().decode("utf-8"))
    except (ValueError, RecursionError):
        raise SwatchError(f"{what} is not valid JSON; remove it or use a new folder") from None


def read_cache_json(path: Path):
    """A cache entry's JSON, or None when it is absent or not one we can use (not a regular file, larger
    than :data:`~swatch.core.limits.MAX_CACHE_ENTRY_BYTES`, not UTF-8 JSON, nested too deep to parse): the
    cache is ours to rebuild, so a damaged entry is recomputed, never an error."""
    if not is_regular_file(path):
        return None
    try:
        if path.stat().st_size > MAX_CACHE_ENTRY_BYTES:
            return None
        return json.loads(path.read_bytes().decode("utf-8"))
    except (OSError, ValueError, RecursionError, MemoryError):
        return None


def _check_manifest(doc, what: str) -> dict:
    bad = SwatchError(f"{what}: not a swatch catalog manifest (a table with 'files' of name -> sha256, size)")
    if not isinstance(doc, dict):
        raise bad
    files = doc.get("files", {})
    keys = doc.get("sheet_keys", {})
    if not isinstance(files, dict) or not isinstance(keys, dict) or not isinstance(doc.get("fingerprint", ""), str):
        raise bad
    for name, info in files.items():
        output_name(name, f"{what} 'files'")
        if not (isinstance(info, dict) and isinstance(info.get("sha256"), str)
                and isinstance(info.get("size"), int) and info["size"] >= 0):
            raise bad
    for name, key in keys.items():
        output_name(name, f"{what} 'sheet_keys'")
        if not isinstance(key, str):
            raise bad
    return doc


def load_manifest(meta: Path) -> dict:
    """The manifest of the last build ({} if none), every name checked."""
    path = meta / MANIFEST
    doc = _read_metadata(path)
    return {} if doc is None else _check_manifest(doc, str(path))


def load_journal(meta: Path) -> tuple[dict | None, bool]:
    """The journal (None if none), every name checked, and whether its staging folder is missing.

    Reading it acts on nothing: recovery (:func:`recover`) and the "not a catalog" guard
    (:func:`is_catalog`) decide what to do with it.
    """
    path = meta / JOURNAL
    doc = _read_metadata(path)
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
    _check_manifest(doc.get("manifest"), f"{what} 'manifest'")
    return doc, entry_kind(meta / staging) is None


def write_journal(meta: Path, journal: dict) -> None:
    write_json_atomic(meta / JOURNAL, journal)


def check_targets(out: Path, names) -> None:
    """Refuse before the commit if a folder stands where an output file goes, or a link or a file where
    an output subfolder goes (nothing moved yet)."""
    names = list(names)
    check_subfolders(out, names, f"catalog folder {out}")
    for name in names:
        if _is_dir(out / name):
            raise SwatchError(f"{out / name} is a folder where the catalog writes a file; move it away and "
                              "build again (the previous catalog is unchanged)")


def is_catalog(out: Path, meta: Path) -> bool:
    """Whether ``out`` may be written as a catalog: empty, or holding a manifest, or holding only what a
    first build's journal proves it moved there (each file's hash in the journal's manifest).

    A journal alone proves nothing (it is untrusted): a folder of the user's with a crafted journal
    is not a catalog, and nothing it names is moved or deleted.
    """
    entries = [p for p in out.iterdir() if p.name != META_DIR] if _is_dir(out) else []
    if not entries or _lexists(meta / MANIFEST):
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
    """
    prev = make_real_folder(staging / PREVIOUS, "staging folder's .previous")
    check_subfolders(prev, journal["files"] + journal["remove"], "staging folder's .previous", create=True)
    write_json_atomic(staging / STAGED_MANIFEST, journal["manifest"])
    write_json_atomic(meta / ROLLBACK_JOURNAL, dict(journal, phase="rollback"))
    fsync_dir(staging)
    write_journal(meta, journal)


# -- commit, rollback, recovery ----------------------------------------------------------------

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
    """Move the staged files into place (idempotent: safe to replay after a crash); renames and unlinks only."""
    staging, prev = _checked(out, meta, journal, "commit")
    if prev is None:  # a journal written before .previous was made in advance
        prev = make_real_folder(staging / PREVIOUS, "staging folder's .previous")
    check_subfolders(prev, journal["files"] + journal["remove"], "staging folder's .previous", create=True)
    check_subfolders(out, journal["files"], f"catalog folder {out}", create=True)
    for name in journal["files"]:
        src, dst = staging / name, out / name
        if not _lexists(src):
            continue  # already in place
        kind = entry_kind(dst)
        if kind == "dir":
            raise SwatchError(f"{dst} is a folder where the catalog writes a file; move it away")
        if kind == "link":
            dst.unlink()  # a link is no catalog output: dropped, never followed
        elif kind == "file" and not _lexists(prev / name):
            os.replace(dst, prev / name)
        os.replace(src, dst)
    for name in journal["remove"]:
        dst = out / name
        kind = entry_kind(dst)
        if kind == "link" or (kind == "file" and _lexists(prev / name)):
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
        ready = is_regular_file(staged) and _read_metadata(staged) == manifest
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
        if not _lexists(src) and entry_kind(dst) == "file" and file_matches(dst, info.get(name)):
            os.replace(dst, src)  # take the new file back
        if prev is not None and _lexists(prev / name) and not _lexists(dst):
            os.replace(prev / name, dst)
    for name in journal["remove"]:
        if prev is not None and _lexists(prev / name) and not _lexists(out / name):
            os.replace(prev / name, out / name)
    with suppress(SwatchError):  # the subfolders the commit made for the new files go again, if empty
        drop_empty_subfolders(out, load_manifest(meta).get("files", {}))
    fsync_dir(out)
    _finish(meta, staging)


def recover(out: Path, meta: Path, log=None) -> None:
    """Finish what a killed build left (its journal), then clear stale staging and temp files and heal the
    cache (anything in it that is not a regular file is removed: the cache is ours to rebuild).

    Called with the lock held, so nothing found here belongs to a running build.
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
    if _is_dir(cache):
        for p in cache.iterdir():
            if (p.name.startswith(".") and ".tmp" in p.name) or not is_regular_file(p):
                remove_tree(p)


def file_matches(path: Path, info) -> bool:
    """``path`` is a regular file with the manifest's size and hash (links and devices never match)."""
    if not info or not is_regular_file(path):
        return False
    try:
        return path.stat().st_size == info["size"] and sha256_file(path) == info["sha256"]
    except OSError:
        return False


def intact(out: Path, manifest: dict) -> bool:
    """Every file the manifest lists is in place as written (its subfolders real folders, not links)."""
    files = manifest.get("files") or {}
    return (bool(files) and all(entry_kind(out / sub) == "dir" for sub in subfolders_of(files))
            and all(file_matches(out / name, info) for name, info in files.items()))
