"""Where catalog specs are found: the specs bundled with the package, and a command's SPEC argument (a file or
a bundled name) resolved to the file to read (:func:`resolve_spec_path`)."""
from __future__ import annotations

from pathlib import Path

from swatch.core.errors import SwatchError

__all__ = ["SPECS_DIR", "bundled_specs", "resolve_spec_path"]

#: The catalog specs shipped inside the package (``swatch/catalog/specs/*.toml``, package data; in the
#: repository a link to its ``catalog/`` folder), found by name: ``swatch catalog build titanium``.
SPECS_DIR = Path(__file__).resolve().parents[1] / "specs"


def bundled_specs() -> dict[str, Path]:
    """The catalog specs shipped with the package, by name.

    Returns
    -------
    dict of str to pathlib.Path
        Name (the file's stem, e.g. ``"titanium"``) to the spec file in :data:`SPECS_DIR`, sorted by name.
    """
    return {p.stem: p for p in sorted(SPECS_DIR.glob("*.toml"))}


def resolve_spec_path(spec) -> Path:
    """The spec file that ``spec`` names: a path to a TOML file, or the name of a bundled spec.

    A file that exists wins; otherwise a bare name (no folder, no suffix) is looked up in
    :func:`bundled_specs`, so ``"titanium"`` works in an empty folder, and in one where a catalog was
    built into ``titanium/``.

    Parameters
    ----------
    spec : str or path-like
        A spec file's path (``"catalog/titanium.toml"``, ``"mine.toml"``) or a bundled name (``"titanium"``).

    Returns
    -------
    pathlib.Path
        The file to read (:func:`load_spec` reports a missing one).

    Raises
    ------
    swatch.core.errors.SwatchError
        ``spec`` is a bare name that is neither a file here nor a bundled spec.
    """
    p = Path(spec)
    if p.is_file() or p.suffix or len(p.parts) != 1:
        return p
    bundled = bundled_specs()
    if p.name in bundled:
        return bundled[p.name]
    if p.exists():
        raise SwatchError(f"{spec} is a folder, not a catalog spec; give a TOML file or one of: {', '.join(bundled)}")
    raise SwatchError(f"{spec}: no such file here, nor a bundled catalog spec; give a TOML file or one of: "
                      f"{', '.join(bundled) or '(none bundled)'}")
