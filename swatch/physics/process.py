"""Process profiles: what one anodising line does, as numbers with their sources.

A profile (TOML; presets in ``tables/processes/``, format in docs/processes.md) names the film and substrate tables,
the growth law ``thickness_nm = offset_nm + nm_per_V × voltage_V``, a film index scale (multiplies the real part of
the film's index: an anodic film's density differs from any tabulated film's), optionally a render roughness, and
the source of every number (``[sources]``), or the calibration that produced them (``[calibration]``, written by
``swatch calibrate``).

A profile file is untrusted input: its size is capped before it is parsed, unknown keys are refused, every number is
range-checked, and every error is one line naming the file.

References
----------
.. [1] :cite:`Fujii2019`: Table 2, titanium-fujii2019.
"""
from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_FILM_INDEX_SCALE,
    MAX_PROFILE_BYTES,
    MAX_PROFILE_NAME_CHARS,
    MAX_PROFILE_TEXT_CHARS,
    MAX_SPREAD_FRACTION,
    MAX_SPREAD_NM,
    MAX_VOLTAGE_V,
    MIN_FILM_INDEX_SCALE,
    read_capped,
)
from swatch.physics.growth import thickness_to_voltage_V, voltage_to_thickness_nm
from swatch.physics.materials import list_materials, tables_dir
from swatch.physics.spread import NO_SPREAD, ThicknessSpread

if TYPE_CHECKING:
    import numpy as np

__all__ = ["DEFAULT_PROCESS", "Process", "load_process", "list_processes", "preset_names", "process_toml"]

#: The profile used when none is given: the paper's titanium (50.8 nm at 25 V).
DEFAULT_PROCESS = "titanium-fujii2019"
RATE_RANGE = (0.1, 10.0)  # nm per volt
OFFSET_RANGE = (-50.0, 100.0)  # nm at 0 V
SCALE_RANGE = (MIN_FILM_INDEX_SCALE, MAX_FILM_INDEX_SCALE)  # dimensionless (swatch.core.limits)
_TOP_KEYS = ("name", "description", "film", "substrate", "nm_per_V", "offset_nm", "film_index_scale", "roughness",
             "spread_nm", "spread_fraction", "knee_V", "nm_per_V_above_knee", "sources", "calibration")
_SOURCE_KEYS = ("nm_per_V", "offset_nm", "film_index_scale", "roughness", "film", "substrate", "spread_nm",
                "spread_fraction", "knee_V", "nm_per_V_above_knee")
_CALIBRATION_NUMBERS = ("coupons", "outliers", "mean_delta_E_00", "max_delta_E_00", "nm_per_V_uncertainty",
                        "offset_nm_uncertainty", "film_index_scale_uncertainty", "held_out_mean_delta_E_00",
                        "held_out_max_delta_E_00", "spread_fraction_uncertainty", "knee_V_uncertainty",
                        "nm_per_V_above_knee_uncertainty")
_CALIBRATION_TEXT = ("source", "measured", "geometry", "illuminant", "observer", "model", "parameters", "fixed",
                     "ranking")


@dataclass(frozen=True)
class Process:
    """One anodising line's profile (see the module docstring and docs/processes.md).

    Attributes
    ----------
    name, description : str
        The profile's name (one line) and what it describes.
    film, substrate : str
        Optical table names of the oxide and the metal.
    nm_per_V : float or None
        Growth rate, nm/V (up to ``knee_V`` in a two-slope law); None when none is known (niobium, tantalum).
    offset_nm : float
        Thickness at 0 V, nm.
    film_index_scale : float
        Multiplies the real part of the film's index (0.5–1.5).
    roughness : float or None
        GGX alpha of the line's finish, when the profile states one.
    spread : ThicknessSpread
        The film's thickness non-uniformity (:mod:`swatch.physics.spread`).
    knee_V, nm_per_V_above_knee : float or None
        A two-slope growth law: ``nm_per_V`` up to ``knee_V`` (V), ``nm_per_V_above_knee`` beyond.
    sources, calibration : tuple of (str, value) pairs
        The source of each number, or the calibration that produced them.
    origin : str
        ``"preset"``, the profile file's name, or ``"..., overridden: ..."``.
    """

    name: str
    description: str
    film: str
    substrate: str
    nm_per_V: float | None
    offset_nm: float = 0.0
    film_index_scale: float = 1.0
    roughness: float | None = None
    spread: ThicknessSpread = NO_SPREAD  # the film's thickness non-uniformity (swatch.physics.spread)
    knee_V: float | None = None  # a two-slope growth law: nm_per_V up to knee_V, nm_per_V_above_knee beyond
    nm_per_V_above_knee: float | None = None
    sources: tuple[tuple[str, str], ...] = ()
    calibration: tuple[tuple[str, object], ...] = ()
    origin: str = "preset"  # "preset", a file name, or "overridden"

    def _rate(self) -> float:
        if self.nm_per_V is None:
            raise SwatchError(f"process {self.name!r} has no growth rate (none published that we could cite); "
                              "give `nm_per_V`, or calibrate the line from coupons (swatch calibrate)")
        return self.nm_per_V

    @property
    def label(self) -> str:
        """The name, with the thickness spread when there is one (for text reports).

        Returns
        -------
        str
            ``name``, followed by ``", thickness spread …"`` when the spread is not zero.
        """
        return self.name + (f", thickness spread{self.spread.text()}" if not self.spread.is_zero else "")

    @property
    def has_growth_law(self) -> bool:
        """Whether the profile has a growth rate (voltages can be turned into thicknesses).

        Returns
        -------
        bool
            True when ``nm_per_V`` is set, False otherwise.
        """
        return self.nm_per_V is not None

    def thickness_nm(self, voltage_V) -> np.ndarray:
        """Oxide thickness grown at a voltage by this line's growth law.

        Parameters
        ----------
        voltage_V : array_like
            Anodising voltage, V (0 to ``MAX_VOLTAGE_V``).

        Returns
        -------
        numpy.ndarray
            Thickness, nm, the shape of ``voltage_V``.

        Raises
        ------
        SwatchError
            Without a growth rate, or for a voltage (or the film it gives) out of range (```voltage_V```).

        Examples
        --------
        >>> float(load_process("titanium-fujii2019").thickness_nm(25.0))
        50.8
        """
        return voltage_to_thickness_nm(voltage_V, self._rate(), self.offset_nm, self.knee_V, self.nm_per_V_above_knee)

    def voltage_V(self, thickness_nm) -> np.ndarray | None:
        """The voltage that grows a thickness (the inverse of :meth:`thickness_nm`).

        Parameters
        ----------
        thickness_nm : array_like
            Oxide thickness, nm.

        Returns
        -------
        numpy.ndarray or None
            Voltage, V, the shape of ``thickness_nm``; None when the profile has no growth rate.
        """
        if self.nm_per_V is None:
            return None
        return thickness_to_voltage_V(thickness_nm, self.nm_per_V, self.offset_nm, self.knee_V,
                                      self.nm_per_V_above_knee)

    def coating(self, wavelength_nm=None):
        """The coating of this profile (film, substrate, index scale, thickness spread).

        Parameters
        ----------
        wavelength_nm : array_like or None, optional
            The grid, nm (default 380–780 nm every 5 nm).

        Returns
        -------
        swatch.physics.model.Coating
            Film and substrate indices on the grid (the film's real index scaled by ``film_index_scale``),
            with the profile's thickness spread.
        """
        from swatch.physics.model import get_coating  # lazy: see tests/test_layers.py

        return get_coating(self.film, self.substrate, wavelength_nm, self.film_index_scale, self.spread)

    def with_overrides(self, film: str | None = None, substrate: str | None = None,
                       nm_per_V: float | None = None, spread: ThicknessSpread | None = None) -> Process:
        """The profile with a caller's overrides (the CLI's ``--film``, ``--substrate``, ``--nm-per-volt``, ``--spread``).

        Parameters
        ----------
        film, substrate : str or None
            Table names replacing the profile's; None keeps them.
        nm_per_V : float or None
            A growth rate replacing the profile's, nm/V.
        spread : ThicknessSpread or None
            A thickness spread replacing the profile's.

        Returns
        -------
        Process
            ``self`` when nothing changes; otherwise a copy whose origin says what was overridden.
        """
        changes: dict = {}
        if spread is not None and spread != self.spread:
            changes["spread"] = spread
        if film is not None and film != self.film:
            changes["film"] = film
        if substrate is not None and substrate != self.substrate:
            changes["substrate"] = substrate
        if nm_per_V is not None and nm_per_V != self.nm_per_V:
            changes["nm_per_V"] = _number(nm_per_V, "`nm_per_V`", *RATE_RANGE)
        if not changes:
            return self
        return dataclasses.replace(self, origin=f"{self.origin}, overridden: {', '.join(sorted(changes))}",
                                   **changes)

    def metadata(self) -> dict:
        """What every output records about the profile (name, origin, materials, growth law, spread).

        Returns
        -------
        dict
            JSON-ready.
        """
        return {
            "process": self.name, "process_origin": self.origin, "film": self.film, "substrate": self.substrate,
            "nm_per_V": self.nm_per_V, "offset_nm": self.offset_nm, "film_index_scale": self.film_index_scale,
            **self.spread.metadata(), **self.knee_metadata(),
        }

    def knee_metadata(self) -> dict:
        """The knee of a two-slope growth law, as metadata.

        Returns
        -------
        dict
            ``{"knee_V", "nm_per_V_above_knee"}`` for a two-slope law, else ``{}``.
        """
        if self.knee_V is None:
            return {}
        return {"knee_V": self.knee_V, "nm_per_V_above_knee": self.nm_per_V_above_knee}


def _fail(source: str, what: str) -> SwatchError:
    return SwatchError(f"{source}: {what}")


def _number(value, key: str, lo: float, hi: float, source: str = "process") -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _fail(source, f"{key} must be a number from {lo:g} to {hi:g}")
    if not lo <= value <= hi:
        raise _fail(source, f"{key} = {value:g} is out of range; allowed {lo:g} to {hi:g}")
    return float(value)


def check_profile_name(name: str, what: str = "--name") -> str:
    """Check a profile name as a profile file may hold it (what ``--process`` reads back).

    Parameters
    ----------
    name : str
        One line of printable text, not empty, at most ``MAX_PROFILE_NAME_CHARS`` characters.
    what : str, optional
        What the name is, for the message.

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    SwatchError
        Otherwise.
    """
    text = str(name)
    if not text.strip() or len(text) > MAX_PROFILE_NAME_CHARS or not text.isprintable():
        raise SwatchError(f"{what} must be one line of printable text of 1 to {MAX_PROFILE_NAME_CHARS} characters "
                          f"(got {len(text)} characters{', with control characters' if not text.isprintable() else ''})")
    return text


def _text(value, key: str, source: str, limit: int = MAX_PROFILE_TEXT_CHARS) -> str:
    if not isinstance(value, str) or len(value) > limit or any(ord(ch) < 32 or ord(ch) == 127 for ch in value):
        raise _fail(source, f"{key} must be one line of text of at most {limit} characters")
    return value


def _material(value, key: str, role: str, source: str) -> str:
    names = [m.name for m in list_materials(role)]
    if value not in names:
        raise _fail(source, f"{key} = {value!r} is not a {role} table; use one of {', '.join(names)}")
    return value


def _from_dict(data: dict, source: str, origin: str) -> Process:
    unknown = sorted(set(data) - set(_TOP_KEYS))
    if unknown:
        raise _fail(source, f"unknown key {unknown[0]!r}; allowed keys: {', '.join(_TOP_KEYS)}")
    for key in ("name", "film", "substrate"):
        if key not in data:
            raise _fail(source, f"missing key {key!r} (a profile needs name, film and substrate)")
    name = _text(data["name"], "name", source, MAX_PROFILE_NAME_CHARS)
    if not name.strip():
        raise _fail(source, "name is empty")
    rate = data.get("nm_per_V")
    sources = data.get("sources", {})
    if not isinstance(sources, dict):
        raise _fail(source, "[sources] must be a table of KEY = \"source text\"")
    bad = sorted(set(sources) - set(_SOURCE_KEYS))
    if bad:
        raise _fail(source, f"unknown key {bad[0]!r} in [sources]; allowed: {', '.join(_SOURCE_KEYS)}")
    calibration = data.get("calibration", {})
    if not isinstance(calibration, dict):
        raise _fail(source, "[calibration] must be a table")
    cal: list[tuple[str, object]] = []
    for key, value in calibration.items():
        if key in ("coupons", "outliers"):
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 100_000:
                raise _fail(source, f"calibration.{key} must be a whole number from 0 to 100000")
            cal.append((key, value))
        elif key in _CALIBRATION_NUMBERS:
            cal.append((key, _number(value, f"calibration.{key}", 0.0, 1e6, source)))
        elif key in _CALIBRATION_TEXT:
            cal.append((key, _text(value, f"calibration.{key}", source)))
        else:
            raise _fail(source, f"unknown key {key!r} in [calibration]; allowed: "
                                f"{', '.join(_CALIBRATION_NUMBERS + _CALIBRATION_TEXT)}")
    rough = data.get("roughness")
    knee, above = data.get("knee_V"), data.get("nm_per_V_above_knee")
    if (knee is None) != (above is None) or (knee is not None and rate is None):
        raise _fail(source, "a two-slope growth law needs nm_per_V, knee_V and nm_per_V_above_knee together")
    return Process(
        name=name,
        description=_text(data.get("description", ""), "description", source),
        film=_material(data["film"], "film", "film", source),
        substrate=_material(data["substrate"], "substrate", "substrate", source),
        nm_per_V=None if rate is None else _number(rate, "nm_per_V", *RATE_RANGE, source),
        offset_nm=_number(data.get("offset_nm", 0.0), "offset_nm", *OFFSET_RANGE, source),
        film_index_scale=_number(data.get("film_index_scale", 1.0), "film_index_scale", *SCALE_RANGE, source),
        roughness=None if rough is None else _number(rough, "roughness", 0.001, 1.0, source),
        spread=ThicknessSpread(_number(data.get("spread_nm", 0.0), "spread_nm", 0.0, MAX_SPREAD_NM, source),
                               _number(data.get("spread_fraction", 0.0), "spread_fraction", 0.0,
                                       MAX_SPREAD_FRACTION, source)),
        sources=tuple((k, _text(v, f"sources.{k}", source)) for k, v in sources.items()),
        calibration=tuple(cal),
        origin=origin,
        knee_V=None if knee is None else _number(knee, "knee_V", 0.0, MAX_VOLTAGE_V, source),
        nm_per_V_above_knee=None if above is None else _number(above, "nm_per_V_above_knee", *RATE_RANGE, source),
    )


def _presets_dir() -> Path:
    return tables_dir() / "processes"


def preset_names() -> list[str]:
    """The names of the preset profiles (``tables/processes/*.toml``).

    Returns
    -------
    list of str
        Sorted.

    Examples
    --------
    >>> "titanium-fujii2019" in preset_names()
    True
    """
    return sorted(p.stem for p in _presets_dir().glob("*.toml"))


def _parse(path: Path, source: str, origin: str) -> Process:
    try:
        raw = read_capped(path, MAX_PROFILE_BYTES, "process profile")
    except OSError:
        raise _fail(source, "cannot read the profile file") from None
    try:
        data = tomllib.loads(raw.decode("utf-8-sig"))  # (a byte-order mark is dropped)
    except UnicodeDecodeError:
        raise _fail(source, "profile is not UTF-8 text") from None
    except tomllib.TOMLDecodeError as exc:
        raise _fail(source, f"not valid TOML: {exc}") from None
    except RecursionError:
        raise _fail(source, "tables or lists nested too deeply for a profile") from None
    return _from_dict(data, source, origin)


def load_process(name_or_path: str) -> Process:
    """A process profile by preset name (``tables/processes/NAME.toml``) or from a TOML file.

    Parameters
    ----------
    name_or_path : str
        A preset's name (``titanium-fujii2019`` …) or a profile ``.toml``'s path (untrusted: capped, checked).

    Returns
    -------
    Process
        The profile, every field range-checked; ``origin`` says ``"preset"`` or the file's name.

    Raises
    ------
    SwatchError
        One line naming the file and what is wrong in it, or the presets available.

    Examples
    --------
    >>> load_process("titanium-fujii2019").nm_per_V
    2.032
    """
    text = str(name_or_path).strip()
    if not text:
        raise SwatchError(f"`process` is empty; give a preset ({', '.join(preset_names())}) or a TOML file")
    if text in preset_names():
        return _parse(_presets_dir() / f"{text}.toml", f"process {text}", "preset")
    path = Path(text)
    if path.suffix.lower() == ".toml" and path.is_file():
        return _parse(path, str(path), path.name)
    raise SwatchError(f"unknown process {text!r}; give a preset ({', '.join(preset_names())}) "
                      "or the path of a profile .toml file")


def list_processes() -> list[Process]:
    """Every preset profile of ``tables/processes/``, sorted by name.

    Returns
    -------
    list of Process
        One profile per preset ``.toml``, sorted by name.
    """
    return [load_process(n) for n in preset_names()]


def _toml_value(value) -> str:
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(value, float):
        return repr(round(value, 6))
    return repr(value)


def process_toml(p: Process, header: str = "") -> str:
    """The TOML text of a profile (deterministic: same profile, same bytes).

    Parameters
    ----------
    p : Process
        The profile to write.
    header : str, optional
        Lines written first as ``#`` comments.

    Returns
    -------
    str
        Readable back by :func:`load_process`.
    """
    lines = [f"# {ln}" for ln in header.splitlines()] if header else []
    lines += [f"name = {_toml_value(p.name)}", f"description = {_toml_value(p.description)}",
              f"film = {_toml_value(p.film)}", f"substrate = {_toml_value(p.substrate)}"]
    if p.nm_per_V is not None:
        lines.append(f"nm_per_V = {_toml_value(float(p.nm_per_V))}")
    lines += [f"offset_nm = {_toml_value(float(p.offset_nm))}",
              f"film_index_scale = {_toml_value(float(p.film_index_scale))}"]
    if p.roughness is not None:
        lines.append(f"roughness = {_toml_value(float(p.roughness))}")
    lines += [f"{k} = {_toml_value(v)}" for k, v in p.spread.metadata().items()]
    lines += [f"{k} = {_toml_value(float(v))}" for k, v in p.knee_metadata().items()]
    for table, items in (("sources", p.sources), ("calibration", p.calibration)):
        if items:
            lines += ["", f"[{table}]"] + [f"{k} = {_toml_value(v)}" for k, v in items]
    return "\n".join(lines) + "\n"
