"""One swatch's record: a typed, immutable object with one serialiser (``catalog.json`` → ``swatches``).

:func:`swatch.catalog.records.compute` makes a :class:`SwatchRecord` per swatch; the build adds the
print chip, the 3-D presets and the hero renders (each stage returns its entry, the build puts them
on with :func:`dataclasses.replace`) and serialises every record once with :meth:`SwatchRecord.to_json`.
The JSON view is what the writers (sheets, chips, exports, page) read; nothing mutates it.
The keys and their order are those of ``catalog.json`` (docs/catalog.md).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

__all__ = ["SwatchRecord", "ProcessWindowEntry", "Neighbours", "PrintChip", "to_json"]

#: Trailing entries written only when a stage set them (in this order).
OPTIONAL = ("print_chip", "presets", "hero", "hero_finishes")


def to_json(value):
    """A record's value as JSON-ready Python: dataclasses as dicts (field order), tuples as lists.

    Parameters
    ----------
    value : object
        A dataclass instance, tuple, list, dict or scalar.

    Returns
    -------
    object
        The same value with dataclasses turned into dicts and tuples into lists, recursively.

    Examples
    --------
    >>> to_json(Neighbours(previous=None, next=2.5))
    {'previous': None, 'next': 2.5}
    >>> to_json({"a": (1, 2)})
    {'a': [1, 2]}
    """
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_json(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, (list, tuple)):
        return [to_json(v) for v in value]
    if isinstance(value, dict):
        return {k: to_json(v) for k, v in value.items()}
    return value


@dataclass(frozen=True)
class Neighbours:
    """A colour difference to the previous and the next swatch.

    Attributes
    ----------
    previous, next : float or None
        In the metric's units (ΔE*ab or ΔE2000); None at the ends.
    """

    previous: float | None
    next: float | None


@dataclass(frozen=True)
class ProcessWindowEntry:
    """The process window of one swatch (see :func:`swatch.catalog.records.process_window`).

    Attributes
    ----------
    grade, scheme, metric : str, str or None, str
        The tolerance: its label, its scheme (None for a written bound) and the colour difference it bounds.
    max : float
        The bound, in ``metric``.
    thickness_minus_nm, thickness_plus_nm : float or None
        The window's extent below and above the nominal thickness, nm (0.001 nm).
    voltage_minus_V, voltage_plus_V : float or None
        The same in volts through the process's growth law; None without a rate.
    minus_capped, plus_capped : bool
        The edge is the search limit (or zero thickness), not a crossing of the bound.
    """

    grade: str
    scheme: str | None
    metric: str
    max: float
    thickness_minus_nm: float | None
    thickness_plus_nm: float | None
    voltage_minus_V: float | None
    voltage_plus_V: float | None
    minus_capped: bool
    plus_capped: bool


@dataclass(frozen=True)
class PrintChip:
    """A swatch's print chip files.

    Attributes
    ----------
    png, tiff : str
        Catalog-relative file names.
    size_mm : float
        The chip's side, mm.
    dpi : int
        Resolution, dots per inch.
    """

    png: str
    tiff: str
    size_mm: float
    dpi: int


@dataclass(frozen=True)
class SwatchRecord:
    """Everything ``catalog.json`` says about one swatch (numbers rounded as written).

    Attributes
    ----------
    id : str
        ``S001`` …
    index : int
        From 1.
    thickness_nm, voltage_V : float or None
        nm; V through the process's growth law (None without a rate).
    Lab, LCh, XYZ : tuple of float
        At the reference geometry, under the catalog's illuminant and observer (XYZ: Y = 100 white).
    Lab_D50_2 : tuple of float
        The same under D50, CIE 1931 2° (ICC PCS).
    srgb_hex : str
        ``#rrggbb``, sRGB from CIE 1931 2° colorimetry (clipped when outside the gamut).
    in_srgb_gamut : bool
        Whether the colour is inside sRGB.
    hue_family, colour_name : str
        The CIELAB hue family (``blue``, ``neutral`` …) and the colour's name (:mod:`swatch.colorimetry.names`).
    multi_angle, multi_angle_LCh, multi_angle_srgb_hex : dict
        Keyed by geometry name (``45as15`` …).
    delta_E_ab_to_neighbours, delta_E_00_to_neighbours : Neighbours
        ΔE*ab and ΔE2000 to the previous and the next swatch at the reference geometry.
    process_window : ProcessWindowEntry
        How far the thickness (nm) and voltage (V) may stray before the colour leaves the tolerance.
    sheet : int
        The sheet the swatch is on, from 1.
    sheet_png, sheet_exr : str
        The sheet's files, relative to the catalog folder.
    tile : (int, int)
        (row, column) on ``sheet``, from 1.
    print_chip, presets, hero : PrintChip, dict or None
        Set by their stages (None: absent from the JSON).
    hero_finishes : dict or None
        Finish name to a hero entry shaped as ``hero`` (every finish the swatch has a hero in, the first
        included); set by the hero stage when the spec names finishes.
    """

    id: str
    index: int
    thickness_nm: float | None
    voltage_V: float | None
    Lab: tuple[float | None, ...]
    LCh: tuple[float | None, ...]
    XYZ: tuple[float | None, ...]
    Lab_D50_2: tuple[float | None, ...]
    srgb_hex: str
    in_srgb_gamut: bool
    hue_family: str
    colour_name: str
    multi_angle: dict[str, list]
    multi_angle_LCh: dict[str, list]
    multi_angle_srgb_hex: dict[str, str]
    delta_E_ab_to_neighbours: Neighbours
    delta_E_00_to_neighbours: Neighbours
    process_window: ProcessWindowEntry
    sheet: int
    sheet_png: str
    sheet_exr: str
    tile: tuple[int, int]
    print_chip: PrintChip | None = None
    presets: dict | None = None
    hero: dict | None = None
    hero_finishes: dict | None = None

    def to_json(self) -> dict:
        """The record as ``catalog.json`` writes it (the one serialiser): keys in field order, the
        optional stages' entries only when set.

        Returns
        -------
        dict
            JSON-ready (lists, dicts, str, float, int, bool, None).
        """
        out = {f.name: to_json(getattr(self, f.name)) for f in dataclasses.fields(self) if f.name not in OPTIONAL}
        for name in OPTIONAL:
            value = getattr(self, name)
            if value is not None:
                out[name] = to_json(value)
        return out
