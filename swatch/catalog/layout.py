"""The catalog folder's layout (issue 21): which subfolders hold which outputs, and the checks on them.

The page, ``catalog.json``/``.csv`` and the exports (CxF, ASE) lie at the top of the folder; the sheets,
print chips, 3-D presets and hero renders in :data:`SUBFOLDERS`. A name read back from a catalog's
metadata is an *output name* (:func:`output_name`): a plain file name, or one subfolder of
:data:`SUBFOLDERS`, ``/`` and a plain file name; nothing else (no ``..``, no other or deeper folder), so
every name resolves inside the folder. A subfolder a name passes through must be a real folder, never
a link (which would send moves elsewhere) nor a file (:func:`check_subfolders`).
"""
from __future__ import annotations

import os
from contextlib import suppress
from pathlib import Path

from swatch.core.errors import SwatchError
from swatch.core.safepath import entry_kind, is_regular_file, make_real_folder, plain_name
from swatch.presets import EXACT_FORMATS, PRESET_FORMATS

__all__ = ["SUBFOLDERS", "SHEETS", "CHIPS", "PRESETS", "HEROES", "output_name", "subfolders_of", "check_subfolders",
           "make_subfolders", "output_files", "drop_empty_subfolders", "layout_summary", "sheet_count", "extra_hero_files",
           "extra_preset_files"]

#: The catalog folder's subfolders (issue 21); everything else (page, JSON/CSV, exports) lies at the top.
SHEETS, CHIPS, PRESETS, HEROES = "sheets", "chips", "presets", "heroes"
SUBFOLDERS = (SHEETS, CHIPS, PRESETS, HEROES)


def output_name(name, what: str) -> str:
    """``name`` if it names a catalog output: a plain file name (at the top of the folder) or ``SUB/NAME``
    with ``SUB`` one of :data:`SUBFOLDERS` and ``NAME`` a plain file name.

    Names read back from a catalog's metadata pass through here, so none reaches outside the folder
    (no ``..``, no absolute path, no deeper or other folder).

    Parameters
    ----------
    name : object
        A name read back from the catalog's metadata (untrusted).
    what : str
        Names the metadata in messages.

    Returns
    -------
    str
        ``name``, checked.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other name.

    Examples
    --------
    >>> output_name("sheets/sheet_01.png", "manifest")
    'sheets/sheet_01.png'
    """
    if isinstance(name, str) and "/" in name:
        sub, _, leaf = name.partition("/")
        if sub in SUBFOLDERS and "/" not in leaf:
            plain_name(leaf, what)
            return name
        raise SwatchError(f"{what}: {name[:80]!r} is not a plain file name nor one in a catalog subfolder; only "
                          f"names of files directly inside the folder or in one of its folders "
                          f"{', '.join(SUBFOLDERS)} are allowed (no '..', no other folder)")
    return plain_name(name, what)


def subfolders_of(names) -> list[str]:
    """The subfolders output names pass through.

    Parameters
    ----------
    names : iterable of str
        Output names (``catalog.json``, ``sheets/sheet_01.png``, ...).

    Returns
    -------
    list of str
        Sorted, each once.

    Examples
    --------
    >>> subfolders_of(["catalog.json", "sheets/sheet_01.png", "chips/a.png", "sheets/sheet_02.png"])
    ['chips', 'sheets']
    """
    return sorted({n.partition("/")[0] for n in names if "/" in n})


def check_subfolders(base: Path, names, what: str, create: bool = False) -> None:
    """Check that every subfolder of ``base`` that ``names`` pass through is absent or a real folder.

    Never a link (which would send moves elsewhere), nor a file.

    Parameters
    ----------
    base : pathlib.Path
        The catalog, staging or ``.previous`` folder.
    names : iterable of str
        Output names.
    what : str
        What ``base`` is, for the error message.
    create : bool, optional
        Make the absent subfolders (real folders).

    Raises
    ------
    SwatchError
        Naming the link or file in the way.
    """
    for sub in subfolders_of(names):
        kind = entry_kind(base / sub)
        if kind not in (None, "dir"):
            raise SwatchError(f"{what}: {base / sub} is {'a symbolic link' if kind == 'link' else 'not a folder'}; "
                              "the catalog keeps its outputs there in a real folder; move it away and build again")
        if create and kind is None:
            make_real_folder(base / sub, f"{what}: subfolder")


def make_subfolders(base: Path) -> None:
    """Create the :data:`SUBFOLDERS` in a staging folder: real folders, links refused.

    Parameters
    ----------
    base : pathlib.Path
        The staging folder.

    Raises
    ------
    SwatchError
        If a link or a file stands where a subfolder goes.
    """
    check_subfolders(base, [f"{sub}/x" for sub in SUBFOLDERS], str(base), create=True)


def output_files(base: Path) -> list[str]:
    """The output names of the files in a staging folder: the top's regular files and those of its
    :data:`SUBFOLDERS` (real folders only), sorted.

    Parameters
    ----------
    base : pathlib.Path
        The staging folder.

    Returns
    -------
    list of str
        Relative POSIX paths (``catalog.json``, ``sheets/…``, ``chips/…``).
    """
    names = [p.name for p in base.iterdir() if is_regular_file(p) and not p.name.startswith(".")]
    for sub in SUBFOLDERS:
        if entry_kind(base / sub) == "dir":
            names += [f"{sub}/{p.name}" for p in (base / sub).iterdir() if is_regular_file(p)]
    return sorted(names)


def drop_empty_subfolders(out: Path, files) -> None:
    """Remove the output subfolders the catalog no longer uses, if empty (``rmdir``: a user's file keeps its folder).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.
    files : iterable of str
        The output names of the new catalog (a manifest's ``files``).
    """
    used = set(subfolders_of(files))
    for sub in SUBFOLDERS:
        if sub not in used and entry_kind(out / sub) == "dir":
            with suppress(OSError):
                os.rmdir(out / sub)


#: Files a swatch has in ``presets/``: one per fitted format, an XML and a JSON per exact (Mitsuba) format.
PRESET_FILES_PER_SWATCH = len(PRESET_FORMATS) + 2 * len(EXACT_FORMATS)


def layout_summary(swatches: int, sheets: int, chips: bool, heroes: bool, presets: bool = True,
                   hero_extra: int = 0, preset_extra: int = 0) -> str:
    """One line: what a build of ``swatches`` swatches on ``sheets`` sheets writes where (``catalog validate``).

    Parameters
    ----------
    swatches, sheets : int
        Swatches and sheets of the catalog.
    chips, heroes, presets : bool
        Whether the spec asks for print chips, hero renders and 3-D presets.
    hero_extra : int, optional
        Hero files besides one per swatch (:func:`extra_hero_files`: the cover, the other finishes').
    preset_extra : int, optional
        Files in ``presets/`` besides the fitted and exact presets (:func:`extra_preset_files`: the ``.usdz``
        of each swatch, the physicallybased.info document and its two pictures per swatch).

    Returns
    -------
    str
        E.g. ``"index.html, catalog.json/.csv, CxF and ASE at the top; sheets/ 10 files, chips/ 114, presets/ 285"``.
    """
    counts = [(SHEETS, 2 * sheets), (CHIPS, 2 * swatches if chips else 0),
              (PRESETS, PRESET_FILES_PER_SWATCH * swatches + preset_extra if presets else 0), (HEROES, swatches + hero_extra if heroes else 0)]
    subs = [f"{sub}/ {n}" for sub, n in counts if n]
    if subs:
        subs[0] += " files"
    return "index.html, catalog.json/.csv, CxF and ASE at the top; " + ", ".join(subs)


def extra_hero_files(cover: bool, finishes: int) -> int:
    """Hero files besides one per swatch: the cover, and the cover swatch's hero (and cover) in each finish offered
    after the first (swatch.catalog.hero).

    Parameters
    ----------
    cover : bool
        Whether the spec asks for a cover (``hero_cover_px`` > 0).
    finishes : int
        Finishes offered (0 or 1: one).

    Returns
    -------
    int
        How many files ``heroes/`` holds beyond one per swatch.

    Examples
    --------
    >>> extra_hero_files(True, 4), extra_hero_files(False, 4), extra_hero_files(True, 0)
    (7, 3, 1)
    """
    per_finish = 2 if cover else 1
    return (1 if cover else 0) + per_finish * max(finishes - 1, 0)


def sheet_count(manifest: dict) -> int:
    """The sheets a catalog's manifest lists (its ``sheets/sheet_NN.png``).

    Parameters
    ----------
    manifest : dict
        A catalog's manifest (its ``files``).

    Returns
    -------
    int
        How many sheets (PNG) the manifest lists.

    Examples
    --------
    >>> sheet_count({"files": {"sheets/sheet_01.png": {}, "sheets/sheet_01.exr": {}, "index.html": {}}})
    1
    """
    return len([k for k in manifest.get("files", {}) if k.startswith(f"{SHEETS}/sheet_") and k.endswith(".png")])


def extra_preset_files(swatches: int, usd: bool, physicallybased: bool) -> int:
    """Files the spec's ``[presets] usd`` / ``physicallybased`` add to ``presets/``.

    Parameters
    ----------
    swatches : int
        Swatches of the catalog.
    usd, physicallybased : bool
        Whether the spec asks for a ``.usdz`` per swatch and the catalog's physicallybased.info document (with
        a 300 and a 600 px picture per swatch).

    Returns
    -------
    int
        Their number.

    Examples
    --------
    >>> extra_preset_files(10, True, True)
    31
    """
    return (swatches if usd else 0) + (1 + 2 * swatches if physicallybased else 0)
