"""The package's own source files, for the content hashes that key caches and catalog fingerprints.

A catalog (or a tile, or a preset fit) is up to date only while the code that computed it is unchanged;
these helpers list that code in one place, so a module that moves between subpackages is still hashed.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["package_dir", "source_files", "sha256_file"]


def package_dir() -> Path:
    """The installed ``swatch/`` folder (resolved).

    Returns
    -------
    pathlib.Path
        The absolute, resolved path of the ``swatch`` package folder (the one this module is in).
    """
    return Path(__file__).resolve().parent.parent


def source_files(exclude: tuple[str, ...] = ()) -> list[Path]:
    """Every ``.py`` file under ``swatch/`` (recursively, sorted by relative path).

    Parameters
    ----------
    exclude
        Top-level subpackage names (e.g. ``("catalog", "commands")``) whose files are left out.
    """
    pkg = package_dir()
    files = [p for p in pkg.rglob("*.py")
             if "__pycache__" not in p.parts and p.relative_to(pkg).parts[0] not in exclude]
    return sorted(files, key=lambda p: p.relative_to(pkg).as_posix())


def sha256_file(path: Path) -> str:
    """The SHA-256 of a file's bytes, read in 1 MiB chunks (the one definition: sources, caches, manifests).

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()
