"""What a catalog's outputs depend on, as hashes: the code, the tables and the libraries' versions
(:func:`code_fingerprint`), hashed with the validated spec into the build's fingerprint
(:func:`hash_json`); a build whose fingerprint equals the manifest's is a no-op. Light on purpose
(no colour-science): the no-op rebuild runs only this.
"""
from __future__ import annotations

import hashlib
import json
from importlib import metadata

from swatch.core.sources import package_dir, sha256_file, source_files
from swatch.physics.materials import tables_dir

__all__ = ["FORMAT_VERSION", "code_fingerprint", "hash_json", "slug"]

#: The catalog folder's format (catalog.json, manifest).
FORMAT_VERSION = 1



def hash_json(obj) -> str:
    """SHA-256 of a JSON-ready object (sorted keys, compact).

    Parameters
    ----------
    obj : object
        A JSON-serialisable value.

    Returns
    -------
    str
        64 hex digits.
    """
    return hashlib.sha256(json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def code_fingerprint() -> dict:
    """Hashes of the code and tables the outputs depend on, and the libraries' versions.

    Every module of the package (recursively) and the page's script and style; the optical and
    tolerance tables; colour-science, numpy, OpenImageIO, OpenEXR, colour-cxf and Pillow versions.

    Returns
    -------
    dict
        ``code``, ``tables`` ({name: sha256}), ``versions`` and ``format``.
    """

    pkg = package_dir()
    # every module of the package, recursively (a hand-kept list missed the environment, process
    # and export modules, so a change there left an existing catalog \"up to date\"), ...
    files = source_files()
    files += sorted((pkg / "catalog" / "web").glob("*.*"))  # the page's script and style
    files += sorted((pkg / "catalog" / "web" / "model-viewer").glob("*"))  # the viewer a catalog with AR carries
    code = {f.relative_to(pkg).as_posix(): sha256_file(f) for f in files if f.exists()}
    tdir = tables_dir()
    tables = {p.relative_to(tdir).as_posix(): sha256_file(p)
              for p in [*sorted(tdir.glob("optical/*.csv")), tdir / "tolerance_grades.csv"]}
    versions: dict[str, str | None] = {}
    for dist in ("colour-science", "numpy", "OpenImageIO", "OpenEXR", "colour-cxf", "pillow"):
        try:
            versions[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            versions[dist] = None
    return {"code": code, "tables": tables, "versions": versions, "format": FORMAT_VERSION}


def slug(name: str) -> str:
    """A file-name stem from a catalog's name: lower-case ASCII letters and digits, ``-`` between words,
    at most 60 characters (``catalog`` when nothing is left).

    Parameters
    ----------
    name : str
        The catalog's name.

    Returns
    -------
    str
        The stem, e.g. ``titanium-20-300-nm``.

    Examples
    --------
    >>> slug("Titanium — 20–300 nm"), slug("チタン")
    ('titanium-20-300-nm', 'catalog')
    """
    out = "".join(ch.lower() if ch.isascii() and ch.isalnum() else "-" for ch in name)
    out = "-".join(p for p in out.split("-") if p)
    return out[:60] or "catalog"
