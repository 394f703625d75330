"""Helpers the catalog-folder tests share (#12, #21): a digest of a catalog folder's files."""
from __future__ import annotations

import hashlib
from pathlib import Path

from swatch.catalog.folder import META_DIR


def digest(folder: Path) -> dict[str, str]:
    """The catalog's files (the top and its subfolders, #21; not the metadata) by relative name → SHA-256."""
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and META_DIR not in p.relative_to(folder).parts}
