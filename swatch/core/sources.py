"""The package's own source files, for the content hashes that key caches and catalog fingerprints.

A catalog (or a tile, or a preset fit) is up to date only while the code that computed it is unchanged;
these helpers list that code in one place, so a module that moves between subpackages is still hashed.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["package_dir", "source_files", "sha256_file"]


def package_dir() -> Path:
    """The installed ``swatch/`` folder (resolved)."""
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
    """The hex SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()
