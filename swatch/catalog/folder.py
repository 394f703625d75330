"""The catalog folder's own metadata: lock, manifest, journal, and the commit that moves a build into place.

Trust model: the folder (and its ``.swatch-catalog``) may come from someone else, so everything
read back from it is untrusted input. Every name in the manifest and the journal must be a plain
file name (outputs live directly in the folder) and the staging folder a ``staging-*`` folder of
``.swatch-catalog``; the metadata folder, the cache and the lock must not be symbolic links; the
metadata files are size-capped and must be regular files. Anything else is refused with one line
(:class:`~swatch.errors.SwatchError`) before anything is moved or deleted: a build never writes
or deletes outside its folder.

Commit protocol (idempotent, so a run killed at any step is finished by the next one): the journal
lists the staged files and the files to retire and holds the new manifest. Each file in the way
is first moved into ``<staging>/.previous``, then the staged file takes its place. A commit that
fails (not killed) is rolled back from ``.previous``: the previous catalog comes back as it was.
The journal's ``phase`` says which way a later run must finish it (``commit`` or ``rollback``).
"""
from __future__ import annotations

import json
import os
import shutil
import stat
from contextlib import contextmanager
from pathlib import Path

from swatch.errors import SwatchError
from swatch.limits import MAX_METADATA_BYTES
from swatch.safepath import is_regular_file, plain_name, real_folder

__all__ = ["META_DIR", "MANIFEST", "JOURNAL", "PREVIOUS", "locked", "signals_held", "meta_folder", "cache_folder",
           "load_manifest", "write_journal", "commit", "rollback", "recover", "intact", "file_matches",
           "write_json_atomic", "fsync_dir", "sha256_file", "remove_tree", "check_targets"]

META_DIR = ".swatch-catalog"
MANIFEST = "manifest.json"
JOURNAL = "journal.json"
PREVIOUS = ".previous"  # inside a staging folder: the files a commit replaced or retired


# -- small file helpers ------------------------------------------------------------------------

def sha256_file(path: Path) -> str:
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def write_json_atomic(path: Path, obj) -> None:
    from swatch.fileio import atomic_write_text

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
    cache = real_folder(meta / "cache", "catalog cache folder")
    cache.mkdir(exist_ok=True)
    return cache


@contextmanager
def locked(meta: Path):
    """Hold ``meta/lock`` (flock) for one build; another build holding it is refused."""
    import fcntl

    busy = f"another catalog build is writing {meta.parent}; wait for it to finish"
    try:
        fd = os.open(meta / "lock", os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK, 0o644)
    except FileNotFoundError:  # the folder went away: a first build that held the lock failed
        raise SwatchError(busy) from None
    except OSError as exc:
        raise SwatchError(f"cannot open the build lock {meta / 'lock'} ({exc.strerror}); it must be a regular "
                          "file of the catalog folder, not a link") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise SwatchError(f"the build lock {meta / 'lock'} is not a regular file; remove it")
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise SwatchError(busy) from None
        yield
    finally:
        os.close(fd)


@contextmanager
def signals_held():
    """Defer SIGINT/SIGTERM/SIGHUP while the staged files are moved into place."""
    import signal

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


def _check_manifest(doc, what: str) -> dict:
    bad = SwatchError(f"{what}: not a swatch catalog manifest (a table with 'files' of name -> sha256, size)")
    if not isinstance(doc, dict):
        raise bad
    files = doc.get("files", {})
    keys = doc.get("sheet_keys", {})
    if not isinstance(files, dict) or not isinstance(keys, dict) or not isinstance(doc.get("fingerprint", ""), str):
        raise bad
    for name, info in files.items():
        plain_name(name, f"{what} 'files'")
        if not (isinstance(info, dict) and isinstance(info.get("sha256"), str)
                and isinstance(info.get("size"), int) and info["size"] >= 0):
            raise bad
    for name, key in keys.items():
        plain_name(name, f"{what} 'sheet_keys'")
        if not isinstance(key, str):
            raise bad
    return doc


def load_manifest(meta: Path) -> dict:
    """The manifest of the last build ({} if none), every name checked."""
    path = meta / MANIFEST
    doc = _read_metadata(path)
    return {} if doc is None else _check_manifest(doc, str(path))


def _load_journal(meta: Path) -> dict | None:
    path = meta / JOURNAL
    doc = _read_metadata(path)
    if doc is None:
        return None
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
            plain_name(name, f"{what} '{key}'")
    _check_manifest(doc.get("manifest"), f"{what} 'manifest'")
    return doc


def write_journal(meta: Path, journal: dict) -> None:
    write_json_atomic(meta / JOURNAL, journal)


def check_targets(out: Path, names) -> None:
    """Refuse before the commit if a folder stands where an output file goes (nothing moved yet)."""
    for name in names:
        if _is_dir(out / name):
            raise SwatchError(f"{out / name} is a folder where the catalog writes a file; move it away and "
                              "build again (the previous catalog is unchanged)")


# -- commit, rollback, recovery ----------------------------------------------------------------

def commit(out: Path, meta: Path, journal: dict) -> None:
    """Move the staged files into place (idempotent: safe to replay after a crash)."""
    staging = meta / journal["staging"]
    prev = staging / PREVIOUS
    prev.mkdir(exist_ok=True)
    for name in journal["files"]:
        src, dst = staging / name, out / name
        if not _lexists(src):
            continue  # already in place
        if _is_dir(dst):
            raise SwatchError(f"{dst} is a folder where the catalog writes a file; move it away")
        if _lexists(dst) and not _lexists(prev / name):
            os.replace(dst, prev / name)
        os.replace(src, dst)
    for name in journal["remove"]:
        dst = out / name
        if _lexists(dst) and not _is_dir(dst):
            if _lexists(prev / name):
                dst.unlink()
            else:
                os.replace(dst, prev / name)
    write_json_atomic(meta / MANIFEST, journal["manifest"])
    fsync_dir(out)
    (meta / JOURNAL).unlink(missing_ok=True)
    fsync_dir(meta)
    remove_tree(staging)


def rollback(out: Path, meta: Path, journal: dict) -> None:
    """Undo a commit that failed part-way: the previous files come back (idempotent)."""
    journal = dict(journal, phase="rollback")
    write_journal(meta, journal)
    staging = meta / journal["staging"]
    prev = staging / PREVIOUS
    for name in journal["files"]:
        src, dst = staging / name, out / name
        if not _lexists(src) and _lexists(dst) and not _is_dir(dst):
            os.replace(dst, src)  # take the new file back
        if _lexists(prev / name) and not _lexists(dst):
            os.replace(prev / name, dst)
    for name in journal["remove"]:
        if _lexists(prev / name) and not _lexists(out / name):
            os.replace(prev / name, out / name)
    fsync_dir(out)
    (meta / JOURNAL).unlink(missing_ok=True)
    fsync_dir(meta)
    remove_tree(staging)


def recover(out: Path, meta: Path) -> None:
    """Finish what a killed build left (its journal), then clear stale staging and temp files.

    Called with the lock held, so nothing found here belongs to a running build.
    """
    journal = _load_journal(meta)
    if journal is not None:
        if journal.get("phase") == "rollback":
            rollback(out, meta, journal)
        else:
            try:
                commit(out, meta, journal)
            except (OSError, SwatchError):
                rollback(out, meta, journal)
    for p in meta.iterdir():
        if p.name.startswith("staging-") or (p.name.startswith(".") and ".tmp" in p.name):
            remove_tree(p)
    cache = meta / "cache"
    if _is_dir(cache):
        for p in cache.iterdir():
            if p.name.startswith(".") and ".tmp" in p.name:
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
    files = manifest.get("files") or {}
    return bool(files) and all(file_matches(out / name, info) for name, info in files.items())
