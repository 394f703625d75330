"""Checks of a decoded catalog spec's values: every message names the file, the key and what is allowed.

:class:`SpecChecker` holds the spec's name for the messages, e.g.
``catalog/x.toml: key thickness.step_nm: must be a number > 0 (got 'a')``; :func:`spec_range`,
:func:`spec_material` and :func:`spec_process` check the three compound entries (a range or list of
thicknesses or voltages, a material table's name, a process profile).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import NoReturn

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_BASE_URL_CHARS, MAX_SWATCHES
from swatch.physics.materials import list_materials, load_material
from swatch.physics.process import load_process, preset_names
from swatch.presets.naming import check_base_url

__all__ = ["SpecChecker", "spec_range", "spec_material", "spec_process"]


class SpecChecker:
    """Checks of a decoded spec's values; every refusal names the file and the key.

    Parameters
    ----------
    source : str
        The spec's file name, for messages.

    Examples
    --------
    >>> SpecChecker("x.toml").number(2.5, "thickness.step_nm", 0.0, None, lo_open=True)
    2.5
    >>> SpecChecker("x.toml").number("a", "thickness.step_nm", 0.0, None, lo_open=True)
    Traceback (most recent call last):
    ...
    swatch.core.errors.SwatchError: x.toml: key thickness.step_nm: must be a number > 0 (got 'a')
    """
    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, what: str, got=None, show_got: bool = True) -> NoReturn:
        """Refuse ``key``.

        Parameters
        ----------
        key : str
            The dotted key.
        what : str
            What is allowed.
        got : object
            The value given (shown shortened).
        show_got : bool
            Append ``(got …)``.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        msg = f"{self.source}: key {key}: {what}"
        if show_got:
            msg += f" (got {_show(got)})"
        raise SwatchError(msg)

    def table(self, data, key: str, allowed: tuple[str, ...]) -> dict:
        """A TOML table with only the ``allowed`` keys.

        Parameters
        ----------
        data : object
            The value read from the TOML (untrusted: any type).
        key : str
            The table's key (empty: the top level).
        allowed : tuple of str
            The keys the table may hold.

        Returns
        -------
        dict
            ``data``, a table with only allowed keys.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        if not isinstance(data, dict):
            self.fail(key, "must be a table", data)
        for k in data:
            if k not in allowed:
                where = f"{key}.{k}" if key else k
                scope = f" in [{key}]" if key else ""
                raise SwatchError(f"{self.source}: unknown key {where}; allowed{scope}: {', '.join(allowed)}")
        return data

    def number(self, value, key: str, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
        """A finite number within bounds (closed unless ``lo_open`` / ``hi_open``).

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message (``thickness.step_nm``).
        lo, hi : float or None
            Bounds (None: none).
        lo_open, hi_open : bool
            Whether ``lo`` / ``hi`` itself is refused.

        Returns
        -------
        float
            The value.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        if ok:
            v = float(value)
            ok = (lo is None or (v > lo if lo_open else v >= lo)) and (hi is None or (v < hi if hi_open else v <= hi))
        if not ok:
            self.fail(key, f"must be a number {_bounds(lo, hi, lo_open, hi_open)}", value)
        return float(value)

    def integer(self, value, key: str, lo: int, hi: int) -> int:
        """A whole number from ``lo`` to ``hi`` (booleans refused).

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message (``thickness.step_nm``).
        lo, hi : int
            The smallest and largest allowed.

        Returns
        -------
        int
            The value.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        if not (isinstance(value, int) and not isinstance(value, bool) and lo <= value <= hi):
            self.fail(key, f"must be a whole number from {lo} to {hi}", value)
        return int(value)

    def string(self, value, key: str, max_len: int = 200, choices=None, multiline: bool = False) -> str:
        """A non-empty text without control characters, optionally one of ``choices`` (case-insensitive).

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message (``thickness.step_nm``).
        max_len : int
            Most characters allowed.
        choices : sequence of str, optional
            Returned in their own spelling.
        multiline : bool
            Allow tabs and line breaks.

        Returns
        -------
        str
            Stripped.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        if not isinstance(value, str) or not value.strip() or len(value) > max_len:
            self.fail(key, f"must be a non-empty text of at most {max_len} characters", value)
        allowed = "\t\n\r" if multiline else ""
        if any(_is_control(ch) and ch not in allowed for ch in value):
            self.fail(key, "must not contain control characters"
                      + (" (other than tab and line breaks)" if multiline else ""), value)
        if choices is not None:
            for c in choices:
                if c.lower() == value.strip().lower():
                    return c
            self.fail(key, f"must be one of {', '.join(choices)}", value)
        return value.strip()

    def base_url(self, value, key: str) -> str:
        """An http(s) address files are served from (:func:`swatch.presets.naming.check_base_url`).

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message.

        Returns
        -------
        str
            The address without its trailing ``/``.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        text = self.string(value, key, MAX_BASE_URL_CHARS)
        try:
            return check_base_url(text)
        except SwatchError:
            self.fail(key, "must be the http(s) address the folder is served from, such as "
                      "https://example.com/catalog/presets, without spaces, query or fragment", value)

    def boolean(self, value, key: str) -> bool:
        """``true`` or ``false``.

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message (``thickness.step_nm``).

        Returns
        -------
        bool
            The value.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        if not isinstance(value, bool):
            self.fail(key, "must be true or false", value)
        return value

    def numbers(self, value, key: str, lo, hi, max_len: int = MAX_SWATCHES) -> list[float]:
        """A non-empty list of numbers within [``lo``, ``hi``], at most ``max_len`` of them.

        Parameters
        ----------
        value : object
            The value read from the TOML (untrusted: any type).
        key : str
            The dotted key, for the message (``thickness.step_nm``).
        lo, hi : float
            Bounds of every entry (closed).
        max_len : int
            Most entries allowed.

        Returns
        -------
        list of float
            The entries, in the given order.

        Raises
        ------
        swatch.core.errors.SwatchError
            ``<file>: key <key>: <what is allowed> (got <value>)``.
        """
        if not isinstance(value, list) or not value:
            self.fail(key, "must be a non-empty list of numbers", value)
        if len(value) > max_len:
            self.fail(key, f"must have at most {max_len} entries", f"{len(value)} entries", True)
        return [self.number(v, f"{key}[{i}]", lo, hi) for i, v in enumerate(value)]


def _is_control(ch: str) -> bool:
    """C0/C1 controls, DEL and the XML non-characters (the exports are XML: CxF3)."""
    o = ord(ch)
    return o < 32 or 127 <= o < 160 or o in (0xFFFE, 0xFFFF) or 0xD800 <= o < 0xE000


def _show(v) -> str:
    if isinstance(v, str):
        return repr(v if len(v) <= 60 else v[:57] + "...")
    if isinstance(v, dict):
        return "a table"
    if isinstance(v, list):
        return "a list"
    if isinstance(v, bool):
        return "true" if v else "false"
    return repr(v)


def _bounds(lo, hi, lo_open, hi_open) -> str:
    if lo is not None and hi is not None:
        return f"{'>' if lo_open else '>='} {lo:g} and {'<' if hi_open else '<='} {hi:g}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if hi_open else '<='} {hi:g}"
    return ""


def spec_range(c: SpecChecker, tbl: dict, key: str, unit: str, hi: float) -> list[float]:
    """A ``[thickness]`` or ``[voltage]`` table: ``start_/stop_/step_`` or ``list_`` (nm or V) → sorted values.

    Range values are ``start + i·step`` rounded to 1e-9 (decimal steps stay exact in the outputs); at
    most :data:`swatch.core.limits.MAX_SWATCHES`, refused before any list is built.

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    tbl : object
        The table.
    key : str
        ``thickness`` or ``voltage``.
    unit : str
        ``nm`` or ``V``.
    hi : float
        The largest value allowed.

    Returns
    -------
    list of float
        The thicknesses (nm) or voltages (V), ascending.

    Raises
    ------
    swatch.core.errors.SwatchError
        ``<file>: key <key>: <what is allowed> (got <value>)``.
    """
    suffix = "nm" if unit == "nm" else "V"
    names = (f"start_{suffix}", f"stop_{suffix}", f"step_{suffix}", f"list_{suffix}")
    c.table(tbl, key, names)
    has_list = f"list_{suffix}" in tbl
    has_range = any(n in tbl for n in names[:3])
    if has_list == has_range:
        raise SwatchError(
            f"{c.source}: [{key}]: give either start_{suffix}, stop_{suffix}, step_{suffix} or list_{suffix}")
    if has_list:
        vals = c.numbers(tbl[f"list_{suffix}"], f"{key}.list_{suffix}", 0.0, hi)
        if len(set(vals)) != len(vals):
            c.fail(f"{key}.list_{suffix}", "must not repeat a value", tbl[f"list_{suffix}"])
        return sorted(vals)
    for n in names[:3]:
        if n not in tbl:
            raise SwatchError(f"{c.source}: [{key}]: missing key {key}.{n} (a number in {unit})")
    start = c.number(tbl[names[0]], f"{key}.{names[0]}", 0.0, hi)
    stop = c.number(tbl[names[1]], f"{key}.{names[1]}", 0.0, hi)
    step = c.number(tbl[names[2]], f"{key}.{names[2]}", 0.0, None, lo_open=True)
    if stop < start:
        c.fail(f"{key}.{names[1]}", f"must be >= {names[0]} ({start:g})", tbl[names[1]])
    span = (stop - start) / step  # inf for a subnormal step: compared before any conversion
    if not span + 1 <= MAX_SWATCHES:
        n = f"{math.floor(span + 1e-9) + 1}" if math.isfinite(span) else "too many"
        c.fail(f"{key}.{names[2]}", f"gives {n} swatches; at most {MAX_SWATCHES} per catalog", tbl[names[2]])
    count = math.floor(span + 1e-9) + 1
    # start + i*step, rounded to 1e-9 to keep decimal steps exact in the outputs
    return [round(start + i * step, 9) for i in range(count)]


def spec_material(c: SpecChecker, value, key: str, role: str) -> str:
    """An optical table's name of the given role that covers 380–780 nm.

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    value : object
        The value read from the TOML (untrusted: any type).
    key : str
        The spec's key (``film`` or ``substrate``), for the message.
    role : str
        ``film`` or ``substrate``.

    Returns
    -------
    str
        The table's own name.

    Raises
    ------
    swatch.core.errors.SwatchError
        ``<file>: key <key>: <what is allowed> (got <value>)``.
    """
    name = c.string(value, key)
    try:
        mat = load_material(name)
    except SwatchError:
        names = [m.name for m in list_materials(role)]
        c.fail(key, f"unknown {role} table; use one of {', '.join(names)}", value)
    if mat.role != role:
        names = [m.name for m in list_materials(role)]
        c.fail(key, f"{mat.name} is a {mat.role} table, not a {role}; use one of {', '.join(names)}", value)
    if mat.wavelength_range_nm[0] > 380 or mat.wavelength_range_nm[1] < 780:
        c.fail(key, f"{mat.name} does not cover 380–780 nm", value)
    return mat.name


def spec_process(c: SpecChecker, value, base_dir: Path | None):
    """The spec's ``process``: a preset name, or a profile ``.toml`` inside the spec's folder.

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    value : object
        The value read from the TOML (untrusted: any type).
    base_dir : pathlib.Path or None
        The spec's folder (None: presets only).

    Returns
    -------
    swatch.physics.process.Process
        The profile, read and checked.

    Raises
    ------
    swatch.core.errors.SwatchError
        ``<file>: key <key>: <what is allowed> (got <value>)``.
    """

    text = c.string(value, "process", 200)
    if text in preset_names() or base_dir is None:
        try:
            return load_process(text)
        except SwatchError as exc:
            c.fail("process", str(exc), value, show_got=False)
    root = base_dir.resolve()
    path = (root / text).resolve()
    if not path.is_relative_to(root):
        c.fail("process", "a profile file must lie inside the spec's folder", value)
    if path.suffix.lower() != ".toml" or not path.is_file():
        c.fail("process", f"is neither a preset ({', '.join(preset_names())}) nor a .toml file next to the spec",
               value)
    return load_process(str(path))
