"""Safe output: atomic writes (temp file in the same folder, then rename) that never overwrite a
user's file unless asked (``force``), and checks that an output folder is usable.

:func:`output_batch` makes the several files of one output (a report: images, tables) all-or-nothing:
every atomic write inside it is renamed into place only when the whole batch has been written, and
a batch that fails (a full disk, Ctrl-C) leaves neither its files nor the folders it created.
"""
from __future__ import annotations

import contextlib
import contextvars
import os
import stat
import tempfile
from pathlib import Path

from swatch.core.errors import SwatchError

__all__ = ["check_writable_dir", "check_creatable_dir", "check_new", "atomic_write_bytes", "atomic_write_text",
           "atomic_path", "output_batch"]


def check_writable_dir(path, create: bool = True) -> Path:
    """The folder as a Path, created if needed; SwatchError if it cannot be written.

    Parameters
    ----------
    path : str or os.PathLike
        The output folder.
    create : bool
        Create it (with its parents) when absent (default); False: refuse an absent folder.

    Returns
    -------
    pathlib.Path
        ``Path(path)``, an existing writable folder (not resolved).

    Raises
    ------
    SwatchError
        For an empty path, a file, an absent folder (with ``create=False``), one that cannot be
        created, or one not writable and searchable.
    """
    if not str(path).strip():
        raise SwatchError("output folder is an empty string; give a folder path")
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise SwatchError(f"output folder {p} is a file; give a folder")
    if not p.exists():
        if not create:
            raise SwatchError(f"output folder {p} does not exist")
        try:
            p.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise SwatchError(f"cannot create output folder {p}: {exc.strerror}") from None
    if not os.access(p, os.W_OK | os.X_OK):
        raise SwatchError(f"output folder {p} is not writable")
    return p


def check_creatable_dir(path) -> Path:
    """Check, before any work, that the output folder ``path`` exists or could be created; create nothing.

    Parameters
    ----------
    path : str or os.PathLike
        The output folder (or the folder an output file goes into).

    Returns
    -------
    pathlib.Path
        ``Path(path)`` (not resolved); nothing is created.

    Raises
    ------
    SwatchError
        For an empty path, a file where the folder (or one above it) would be, or a folder that is
        not writable where it would be created.
    """
    if not str(path).strip():
        raise SwatchError("output folder is an empty string; give a folder path")
    p = Path(path)
    above = p
    while not os.path.lexists(above) and above != above.parent:
        above = above.parent
    if not above.is_dir():
        what = "is a file" if above == p else f"cannot be created: {above} is a file"
        raise SwatchError(f"output folder {p} {what}; give a folder")
    if not os.access(above, os.W_OK | os.X_OK):
        what = "is not writable" if above == p else f"cannot be created: {above} is not writable"
        raise SwatchError(f"output folder {p} {what}; give a folder you can write")
    return p


def check_new(paths, force: bool) -> None:
    """Refuse to overwrite existing files unless ``force``; names the first one found.

    A folder (or anything but a file) where an output goes is refused even with ``force``, before
    any output of the batch is written.

    Parameters
    ----------
    paths : iterable of str or os.PathLike
        The outputs of a batch (iterated more than once: give a list or tuple).
    force : bool
        Allow replacing existing files.

    Raises
    ------
    SwatchError
        For a non-file at an output path; without ``force``, for an existing file (with the count of
        the others).
    """
    for p in paths:
        if Path(p).exists() and not Path(p).is_file():
            raise SwatchError(f"{p} is a folder or special file where an output goes; `force` replaces "
                              "files only; move it away")
    if force:
        return
    existing = [str(p) for p in paths if Path(p).exists()]
    if existing:
        more = f" (and {len(existing) - 1} more)" if len(existing) > 1 else ""
        raise SwatchError(f"{existing[0]}{more} already exists; use `force` to overwrite")


class atomic_path:  # noqa: N801  (used like a function: `with atomic_path(p) as tmp`)
    """Context manager giving a temporary path next to ``path``; renamed onto it on success.

    On an exception the temporary file is removed and ``path`` is left as it was. Used as::

        with atomic_path("out.exr") as tmp:  # write tmp with any library
            write(tmp)

    Parameters
    ----------
    path : str or os.PathLike
        The final file; its folder must exist.
    suffix : str or None
        The temporary file's extension (default: ``path``'s, so that writers choose the format by it).
    """

    def __init__(self, path, suffix: str | None = None):
        self.path = Path(path)
        self.suffix = self.path.suffix if suffix is None else suffix

    def __enter__(self) -> Path:
        _remove_stale_temps(self.path.parent, f".{self.path.stem}.{TEMP_MARK}.", f".tmp{self.suffix}")
        # mkstemp: O_EXCL, mode 0600 until the rename (chmod 0644 then): with the marker in the name, what
        # _remove_stale_temps can prove is a temporary file of ours
        fd, tmp = tempfile.mkstemp(prefix=f".{self.path.stem}.{TEMP_MARK}.{os.getpid()}.", suffix=f".tmp{self.suffix}",
                                   dir=self.path.parent)
        os.close(fd)
        self.tmp = Path(tmp)
        return self.tmp

    def __exit__(self, exc_type, exc, tb):
        batch = _BATCH.get()
        if exc_type is None and batch is not None:  # renamed with the rest of the batch
            os.chmod(self.tmp, 0o644)
            batch.append((self.tmp, self.path))
            return False
        try:
            if exc_type is None:
                os.chmod(self.tmp, 0o644)
                os.replace(self.tmp, self.path)
        finally:
            self.tmp.unlink(missing_ok=True)  # (gone after a successful rename)
        if isinstance(exc, OSError) and exc.errno is not None:  # a full disk, a quota: say which output
            raise SwatchError(f"cannot write {self.path}: {exc.strerror}") from None
        return False


class _Batch:
    def __init__(self):
        self.staged: list[tuple[Path, Path]] = []  # (temporary file, final path), in writing order
        self.created: list[Path] = []  # folders this batch created

    def append(self, pair: tuple[Path, Path]) -> None:
        self.staged.append(pair)

    def rollback(self) -> None:
        for tmp, _ in self.staged:
            tmp.unlink(missing_ok=True)
        for d in sorted(self.created, key=lambda d: len(d.absolute().parts), reverse=True):
            # deepest first; each only if empty (a concurrent run's files are kept)
            with contextlib.suppress(OSError):
                d.rmdir()


#: The :func:`output_batch` being written, or None.
_BATCH: contextvars.ContextVar[_Batch | None] = contextvars.ContextVar("swatch_batch", default=None)


@contextlib.contextmanager
def output_batch(folder=None):
    """Write several outputs all-or-nothing: each :class:`atomic_path` inside is renamed into place
    only once the block has finished; on an exception none is, and the temporaries are removed.

    A batch inside a batch joins it (its files are renamed, or removed, with the outer batch's).

    Parameters
    ----------
    folder : str or os.PathLike or None
        The batch's output folder: created (with its parents) when absent, and removed again, with
        the parents created here, when the batch fails. None: the outputs' folders exist.

    Yields
    ------
    pathlib.Path or None
        ``folder``.
    """
    outer = _BATCH.get()
    batch = outer if outer is not None else _Batch()
    token = _BATCH.set(batch) if outer is None else None
    try:
        try:
            if folder is not None:
                p = Path(folder)
                while not os.path.lexists(p) and p != p.parent:
                    batch.created.append(p)
                    p = p.parent
                check_writable_dir(folder)
            yield None if folder is None else Path(folder)
        finally:
            if token is not None:
                _BATCH.reset(token)
        if outer is None:
            for tmp, final in batch.staged:  # (renames: no space needed, the data are written)
                os.replace(tmp, final)
    except BaseException:
        if outer is None:
            batch.rollback()
        raise


#: In every temporary file's name (``.<stem>.swtmp.<pid>.<random>.tmp<suffix>``).
TEMP_MARK = "swtmp"


def _remove_stale_temps(folder: Path, prefix: str, suffix: str) -> None:
    """Remove temporary files ``<prefix><pid>.<random><suffix>`` left by runs that were killed.

    Only what is provably such a file is removed: the marked name, a regular file (not a link) of
    this user still at mkstemp's mode 0600, whose process is gone (a concurrent run's is kept). A
    user's file that merely looks like one (another name, or its mode changed) is never touched.
    """
    try:
        names = [n for n in os.listdir(folder) if n.startswith(prefix) and n.endswith(suffix)]
    except OSError:
        return
    for name in names:
        pid, _, rand = name[len(prefix):len(name) - len(suffix)].partition(".")
        if not pid.isdigit() or len(rand) != 8 or "." in rand or int(pid) == os.getpid():
            continue  # not ours (another output's stem), or this process's own
        try:
            st = os.lstat(folder / name)
        except OSError:
            continue
        if not stat.S_ISREG(st.st_mode) or stat.S_IMODE(st.st_mode) != 0o600 or st.st_uid != os.getuid():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            with contextlib.suppress(OSError):
                (folder / name).unlink()
        except (PermissionError, OverflowError):
            pass


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (:class:`atomic_path`); file mode 0644.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its folder must exist.
    data : bytes
        The file's whole content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically as UTF-8 (:func:`atomic_write_bytes`).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its folder must exist.
    text : str
        The file's whole content, encoded as UTF-8 (no byte-order mark; newlines as given).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return atomic_write_bytes(path, text.encode("utf-8"))
