"""Paths read from files are untrusted: they must name something inside the folder they belong to.

A catalog folder (its ``.swatch-catalog`` metadata: manifest, journal, cache) may come from
someone else, so every name read back from it is checked before anything is opened, moved or
deleted: :func:`plain_name` for entries that can only be file names (so they resolve directly
inside the folder), :func:`real_folder` for a folder that must not be a symbolic link (which
would redirect writes elsewhere), :func:`is_regular_file` before reading a file back. Failures raise
:class:`~swatch.core.errors.SwatchError` (one line, exit 2), before anything is touched.
"""
from __future__ import annotations

import contextlib
import os
import stat
from pathlib import Path

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_NAME_CHARS

__all__ = ["plain_name", "real_folder", "make_real_folder", "is_regular_file", "inside", "entry_kind"]


def plain_name(name, what: str) -> str:
    """``name`` if it is one plain file name (no folder part, not ``.``/``..``, no control characters).

    Parameters
    ----------
    name : str
        The name (at most ``MAX_NAME_CHARS`` characters).
    what : str
        Where it comes from, for the message.

    Returns
    -------
    str
        ``name`` unchanged.

    Raises
    ------
    SwatchError
        For a non-string, an empty name, ``.``, ``..``, a ``/`` or ``\\``, a control character, or too long.
    """
    if not isinstance(name, str):
        raise SwatchError(f"{what}: a file name must be a text (got {type(name).__name__})")
    bad = (not name or name in (".", "..") or "/" in name or "\\" in name or len(name) > MAX_NAME_CHARS
           or any(ord(ch) < 32 or ord(ch) == 127 for ch in name))
    if bad:
        raise SwatchError(f"{what}: {name[:80]!r} is not a plain file name; only names of files directly inside "
                          f"the folder are allowed (no '/', '..' or control characters, at most "
                          f"{MAX_NAME_CHARS} characters)")
    return name


def real_folder(path, what: str) -> Path:
    """``path`` if it is absent or a real folder (not a symbolic link, not a file).

    Parameters
    ----------
    path : str or os.PathLike
        The folder to check.
    what : str
        What the folder is, for the message.

    Returns
    -------
    pathlib.Path
        ``Path(path)`` (not resolved): absent, or a real folder.

    Raises
    ------
    SwatchError
        For a symbolic link or anything but a folder.
    """
    p = Path(path)
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        return p
    if stat.S_ISLNK(st.st_mode):
        raise SwatchError(f"{what} {p} is a symbolic link; it must be a real folder inside the catalog folder "
                          "(a link would send the build's writes elsewhere)")
    if not stat.S_ISDIR(st.st_mode):
        raise SwatchError(f"{what} {p} is not a folder")
    return p


def is_regular_file(path) -> bool:
    """True for a regular file that is not a symbolic link (False for links, folders, devices, FIFOs).

    Parameters
    ----------
    path : str or os.PathLike
        The path to examine; a symbolic link is not followed.

    Returns
    -------
    bool
        False too when ``path`` cannot be examined (absent, no permission).
    """
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def make_real_folder(path, what: str) -> Path:
    """Create ``path`` (one level) unless it exists; it must then be a real folder, not a link.

    ``Path.mkdir(exist_ok=True)`` accepts a symbolic link to a folder anywhere; this does not.

    Parameters
    ----------
    path : str or os.PathLike
        The folder; its parent must exist.
    what : str
        What the folder is, for the message.

    Returns
    -------
    pathlib.Path
        ``Path(path)`` (not resolved), a real folder that now exists.

    Raises
    ------
    SwatchError
        When ``path`` exists as a link or a non-folder (:func:`real_folder`).
    OSError
        When it cannot be created.
    """
    p = Path(path)
    with contextlib.suppress(FileExistsError):
        os.mkdir(p)
    real_folder(p, what)
    return p


def inside(path, folder, what: str) -> Path:
    """``path`` if, with every link resolved, it lies inside ``folder`` (resolved too).

    Parameters
    ----------
    path, folder : str or os.PathLike
        The path to check and the folder it must stay inside; links are resolved in both.
    what : str
        What ``path`` is, for the message.

    Returns
    -------
    pathlib.Path
        ``path`` as given (not resolved); ``folder`` itself counts as inside.

    Raises
    ------
    SwatchError
        When it resolves outside ``folder``.
    """
    p, root = Path(path), os.path.realpath(folder)
    real = os.path.realpath(p)
    if real != root and not real.startswith(root.rstrip(os.sep) + os.sep):
        raise SwatchError(f"{what} {p} resolves outside {folder}; refused (nothing was moved)")
    return p


def entry_kind(path) -> str | None:
    """What ``path`` is, links not followed: None (absent), ``file``, ``dir``, ``link`` or ``other``.

    Parameters
    ----------
    path : str or os.PathLike
        The path to examine; a symbolic link is reported as ``link``, not followed.

    Returns
    -------
    str or None
        None too when a parent is not a folder.
    """
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None
    except NotADirectoryError:
        return None
    if stat.S_ISREG(mode):
        return "file"
    if stat.S_ISDIR(mode):
        return "dir"
    return "link" if stat.S_ISLNK(mode) else "other"
