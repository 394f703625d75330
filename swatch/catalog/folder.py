"""The catalog folder's own metadata: names, lock, the manifest, and the checks on what is read back.

Layout (issue 21): the page, ``catalog.json``/``.csv`` and the exports lie at the top of the folder, the
rest in one of :data:`~swatch.catalog.layout.SUBFOLDERS` (``sheets/``, ``chips/``, ``presets/``,
``heroes/``). A folder an older build wrote flat is migrated by the next build through the same journal
and commit (:mod:`swatch.catalog.journal`): its files are retired (as any file a build no longer
produces), the new ones moved into the subfolders.

Trust model: the folder (and its ``.swatch-catalog``) may come from someone else, so everything
read back from it is untrusted input. Every name in the manifest and the journal must be an output
name (:func:`~swatch.catalog.layout.output_name`: a plain file name, or one of the subfolders, ``/`` and
a plain file name); the metadata folder, the cache, the lock and every subfolder a name passes through
must not be symbolic links; the metadata files are size-capped
(:data:`~swatch.core.limits.MAX_METADATA_BYTES`) and must be regular files. Anything else is refused
with one line (:class:`~swatch.core.errors.SwatchError`) before anything is moved or deleted: a build
never writes or deletes outside its folder. The commit protocol (journal, commit, rollback, recovery)
is :mod:`swatch.catalog.journal`.
"""
from __future__ import annotations

import fcntl
import json
import os
import shutil
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from swatch.catalog.layout import check_subfolders, output_name, subfolders_of
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES, MAX_METADATA_BYTES
from swatch.core.procguard import signals_held  # (named here too: the build takes it from the folder it guards)
from swatch.core.safepath import entry_kind, is_regular_file, make_real_folder, real_folder
from swatch.core.sources import sha256_file

__all__ = ["META_DIR", "MANIFEST", "JOURNAL", "PREVIOUS", "STAGED_MANIFEST", "ROLLBACK_JOURNAL",
           "locked", "signals_held", "meta_folder", "cache_folder", "read_metadata", "check_manifest",
           "load_manifest", "intact", "file_matches", "write_json_atomic", "read_cache_json", "fsync_dir",
           "remove_tree", "is_real_dir", "check_targets"]

META_DIR = ".swatch-catalog"
MANIFEST = "manifest.json"
JOURNAL = "journal.json"
PREVIOUS = ".previous"  # inside a staging folder: the files a commit replaced or retired
STAGED_MANIFEST = ".manifest.json"  # inside a staging folder: the new manifest, renamed into place
ROLLBACK_JOURNAL = "journal-rollback.json"  # the rollback's journal, written before the commit begins


# -- small file helpers ------------------------------------------------------------------------

def write_json_atomic(path: Path, obj) -> None:
    """Write JSON (indent 1, sorted keys, a final newline) atomically: the same object gives the same bytes.

    Parameters
    ----------
    path : pathlib.Path
        The file (replaced as a whole; never half-written).
    obj : object
        Anything :func:`json.dumps` takes.
    """
    atomic_write_text(path, json.dumps(obj, indent=1, sort_keys=True) + "\n")


def fsync_dir(path: Path) -> None:
    """Flush a folder's entries to disk (renames in it survive a crash); errors are ignored.

    Parameters
    ----------
    path : pathlib.Path
        The folder.
    """
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
    """Remove a folder of ours, or a file; a link is unlinked, never followed; absent is fine.

    Parameters
    ----------
    path : pathlib.Path
        The folder, file or link.
    """
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return
    if stat.S_ISDIR(st.st_mode):
        shutil.rmtree(path, ignore_errors=True)
    else:
        Path(path).unlink(missing_ok=True)


def is_real_dir(path: Path) -> bool:
    """Whether ``path`` is a folder itself (not a link to one); False when it cannot be examined.

    Parameters
    ----------
    path : pathlib.Path
        The path to examine.

    Returns
    -------
    bool
        True for a real folder; False for a link, a file, a missing path or one that cannot be read.
    """
    try:
        return stat.S_ISDIR(os.lstat(path).st_mode)
    except OSError:
        return False


# -- folders and lock --------------------------------------------------------------------------

def meta_folder(out: Path) -> Path:
    """The catalog's metadata folder ``out/.swatch-catalog`` (not created).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.

    Returns
    -------
    pathlib.Path
        ``out / ".swatch-catalog"``.

    Raises
    ------
    SwatchError
        If it is a symbolic link or a file.
    """
    return real_folder(out / META_DIR, "catalog metadata folder")


def cache_folder(meta: Path) -> Path:
    """The build cache ``meta/cache``, created if absent.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder (:func:`meta_folder`).

    Returns
    -------
    pathlib.Path
        ``meta / "cache"``, existing.

    Raises
    ------
    SwatchError
        If it is a symbolic link or a file.
    """
    return make_real_folder(meta / "cache", "catalog cache folder")


@contextmanager
def locked(meta: Path, read_only: bool = False) -> Iterator[None]:
    """Hold ``meta/lock`` (flock) for one build; another build holding it is refused.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder.
    read_only : bool, optional
        The folder cannot be written (a check that it is up to date): the lock is opened for reading
        and held shared, so a writing build still excludes it.

    Yields
    ------
    None
        While the lock is held.

    Raises
    ------
    SwatchError
        When another build holds it, or the lock is a link or not a regular file.
    """
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


# -- metadata (untrusted) ----------------------------------------------------------------------

def read_metadata(path: Path) -> Any:
    """The JSON in a metadata file (untrusted), or None if absent.

    Parameters
    ----------
    path : pathlib.Path
        The file (at most :data:`~swatch.core.limits.MAX_METADATA_BYTES`).

    Returns
    -------
    object or None
        The parsed JSON, unchecked.

    Raises
    ------
    SwatchError
        If it is not a regular file (a link, folder or device), too big, or not UTF-8 JSON.
    """
    if not os.path.lexists(path):
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


def read_cache_json(path: Path) -> Any:
    """A cache entry's JSON, or None when it is absent or not one we can use.

    The cache is ours to rebuild, so a damaged entry (not a regular file, larger than
    :data:`~swatch.core.limits.MAX_CACHE_ENTRY_BYTES`, not UTF-8 JSON, nested too deep to parse) is
    recomputed, never an error.

    Parameters
    ----------
    path : pathlib.Path
        The cache entry.

    Returns
    -------
    object or None
        The parsed JSON (to be validated by the caller), or None.
    """
    if not is_regular_file(path):
        return None
    try:
        if path.stat().st_size > MAX_CACHE_ENTRY_BYTES:
            return None
        return json.loads(path.read_bytes().decode("utf-8"))
    except (OSError, ValueError, RecursionError, MemoryError):
        return None


def check_manifest(doc, what: str) -> dict:
    """Check an (untrusted) manifest's shape and every name in it.

    Parameters
    ----------
    doc : object
        The parsed JSON: a table with ``files`` (output name -> ``{"sha256": str, "size": int ≥ 0}``),
        ``sheet_keys`` (output name -> str) and ``fingerprint`` (str), each optional.
    what : str
        Where it came from, for the error message.

    Returns
    -------
    dict
        ``doc`` itself.

    Raises
    ------
    SwatchError
        For any other shape, or a name that is not an output name.
    """
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
    """The manifest of the last build, every name checked.

    Parameters
    ----------
    meta : pathlib.Path
        The metadata folder.

    Returns
    -------
    dict
        The manifest (:func:`check_manifest`), ``{}`` if there is none.

    Raises
    ------
    SwatchError
        For a manifest that is not one (:func:`read_metadata`, :func:`check_manifest`).
    """
    path = meta / MANIFEST
    doc = read_metadata(path)
    return {} if doc is None else check_manifest(doc, str(path))


def check_targets(out: Path, names) -> None:
    """Refuse, before the commit, a folder where an output file goes or a link or file where a subfolder goes.

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    names : iterable of str
        The output names the commit will write.

    Raises
    ------
    SwatchError
        Naming the path in the way (nothing moved yet; the previous catalog is unchanged).
    """
    names = list(names)
    check_subfolders(out, names, f"catalog folder {out}")
    for name in names:
        if is_real_dir(out / name):
            raise SwatchError(f"{out / name} is a folder where the catalog writes a file; move it away and "
                              "build again (the previous catalog is unchanged)")


def file_matches(path: Path, info) -> bool:
    """Whether a file is a regular file with the manifest's size and hash (links and devices never match).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    info : dict or None
        Its manifest entry (``{"sha256": str, "size": int}``); None or empty never matches.

    Returns
    -------
    bool
        True when the file's size and SHA-256 equal the entry's.
    """
    if not info or not is_regular_file(path):
        return False
    try:
        return path.stat().st_size == info["size"] and sha256_file(path) == info["sha256"]
    except OSError:
        return False


def intact(out: Path, manifest: dict) -> bool:
    """Whether every file a manifest lists is in place as written (its subfolders real folders, not links).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    manifest : dict
        A checked manifest (:func:`load_manifest`).

    Returns
    -------
    bool
        False too for a manifest without files.
    """
    files = manifest.get("files") or {}
    return (bool(files) and all(entry_kind(out / sub) == "dir" for sub in subfolders_of(files))
            and all(file_matches(out / name, info) for name, info in files.items()))
