"""Options and parsing shared by the subcommands."""
from __future__ import annotations

import json
import math
import sys

import click
import numpy as np

from swatch.errors import SwatchError
from swatch.limits import MAX_RANGE_POINTS
from swatch.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, wavelength_grid
from swatch.model import DEFAULT_NM_PER_V, check_thickness_nm, voltage_to_thickness_nm



def parse_range(text: str, what: str, unit: str) -> np.ndarray:
    """``A:B:STEP`` (inclusive of B when it falls on the grid), ``N,N,...`` or ``N``."""
    s = str(text).strip()
    if not s:
        raise SwatchError(f"empty {what}; give A:B:STEP or a list N,N,... in {unit}")

    def num(tok: str) -> float:
        try:
            v = float(tok)
        except ValueError:
            raise SwatchError(f"{what} {tok.strip()!r} is not a number; give A:B:STEP or N,N,... in {unit}") from None
        if not math.isfinite(v):
            raise SwatchError(f"{what} must be finite, got {tok.strip()!r}")
        return v

    if ":" in s:
        parts = s.split(":")
        if len(parts) != 3:
            raise SwatchError(f"{what} range {s!r} must be A:B:STEP in {unit}")
        a, b, step = (num(p) for p in parts)
        if step <= 0:
            raise SwatchError(f"{what} range {s!r} needs a step > 0")
        if b < a:
            raise SwatchError(f"{what} range {s!r} is reversed; give A <= B")
        span = (b - a) / step  # inf for a subnormal step: compared before any conversion
        if not span + 1 <= MAX_RANGE_POINTS:
            n = f"{span + 1:.3g}" if math.isfinite(span) else "too many"
            raise SwatchError(f"{what} range {s!r} has {n} points; at most {MAX_RANGE_POINTS}")
        count = int(math.floor(span + 1e-9)) + 1
        return a + step * np.arange(count)
    parts = s.split(",")
    if len(parts) > MAX_RANGE_POINTS:
        raise SwatchError(f"{what} list has {len(parts)} values; at most {MAX_RANGE_POINTS}")
    if any(not p.strip() for p in parts):
        raise SwatchError(f"{what} list {s[:60]!r} has an empty element; give N,N,... in {unit} with no empty "
                          "entries")
    return np.array([num(p) for p in parts], dtype=np.float64)


def process_options(f):
    """``--process NAME|FILE`` and its growth-rate override ``--nm-per-volt``."""
    f = click.option("--nm-per-volt", type=float, default=None,
                     help="anodic growth rate, nm/V, overriding the process profile's")(f)
    f = click.option("--process", "process", default=None, metavar="NAME|FILE",
                     help="process profile: a preset of tables/processes (docs/processes.md) or a profile .toml "
                          "[default: titanium-fujii2019, 50.8 nm at 25 V]")(f)
    return f


def resolve_process(process: str | None, film: str | None = None, substrate: str | None = None,
                    nm_per_volt: float | None = None):
    """The :class:`swatch.process.Process` for ``--process`` with ``--film``/``--substrate``/``--nm-per-volt``."""
    from swatch.process import DEFAULT_PROCESS, load_process

    return load_process(process or DEFAULT_PROCESS).with_overrides(film, substrate, nm_per_volt)


def thickness_options(multiple: bool):
    """``--thickness`` / ``--voltage`` (+ ``--process``, ``--nm-per-volt``) resolving to ``thickness_nm``."""
    t_help = "film thickness in nm: A:B:STEP or N,N,..." if multiple else "film thickness in nm"
    v_help = ("anodising voltage in V instead of a thickness (through the process's growth law)"
              + (": A:B:STEP or N,N,..." if multiple else ""))

    def deco(f):
        f = process_options(f)
        f = click.option("--voltage", "voltage", type=str, default=None, help=v_help)(f)
        f = click.option("--thickness", "thickness", type=str, default=None, help=t_help)(f)
        return f

    return deco


def resolve_thickness(thickness: str | None, voltage: str | None, nm_per_volt, multiple: bool):
    """Return (thickness_nm array, voltage_V array or None).

    ``nm_per_volt`` is a growth rate in nm/V or a :class:`swatch.process.Process` (its growth law).
    """
    if (thickness is None) == (voltage is None):
        raise SwatchError("give exactly one of --thickness NM or --voltage V")
    if thickness is not None:
        d = parse_range(thickness, "thickness", "nm")
        v = None
    else:
        v = parse_range(voltage, "voltage", "V")
        d = (nm_per_volt.thickness_nm(v) if hasattr(nm_per_volt, "thickness_nm")
             else voltage_to_thickness_nm(v, DEFAULT_NM_PER_V if nm_per_volt is None else nm_per_volt))
    if not multiple and d.size != 1:
        raise SwatchError("this command takes one thickness (or voltage), not a range")
    return check_thickness_nm(d), v


def material_options(f):
    f = click.option("--substrate", default=None,
                     help=f"substrate table (swatch materials list) [default: the process's; {DEFAULT_SUBSTRATE}]")(f)
    f = click.option("--film", default=None,
                     help=f"film table (swatch materials list) [default: the process's; {DEFAULT_FILM}]")(f)
    return f


def overcoat_option(f):
    return click.option("--overcoat", "overcoats", multiple=True, metavar="INDEX:NM|TABLE:NM",
                         help="a thin clear layer over the oxide, e.g. 1.5:200 (index 1.5, 200 nm) or "
                              "TiO2-Siefke:20; repeat for several, listed from the air side; coherent, so "
                              "at most 1000 nm")(f)


def resolve_coating(film, substrate: str | None = None, wavelengths: str = "380:780:5", overcoats=()):
    """The coating for the material options (or a :class:`swatch.process.Process` as ``film``), with
    any ``--overcoat`` layers on top."""
    from swatch.model import OvercoatedCoating, get_coating, overcoat

    if hasattr(film, "coating"):
        coating = film.coating(resolve_grid(wavelengths))
    else:
        coating = get_coating(film or DEFAULT_FILM, substrate or DEFAULT_SUBSTRATE, resolve_grid(wavelengths))
    if not overcoats:
        return coating
    return OvercoatedCoating(coating, tuple(overcoat(o, coating.wavelength_nm) for o in overcoats))


def grid_option(f):
    return click.option("--wavelengths", "wavelengths", default="380:780:5", show_default=True,
                        help="wavelength grid START:STOP:STEP in nm (colorimetry: 1, 5, 10 or 20 nm steps)")(f)


def resolve_grid(text: str) -> np.ndarray:
    parts = str(text).split(":")
    if len(parts) != 3:
        raise SwatchError(f"wavelength grid {text!r} must be START:STOP:STEP in nm")
    try:
        a, b, s = (float(p) for p in parts)
    except ValueError:
        raise SwatchError(f"wavelength grid {text!r} must be numbers START:STOP:STEP in nm") from None
    return wavelength_grid(a, b, s)


def _finite(ctx, param, value):
    if value is not None and not math.isfinite(value):
        raise SwatchError(f"--{param.name.replace('_', '-')} must be a finite number of degrees")
    return value


def geometry_options(f):
    f = click.option("--view-azimuth", "view_azimuth", type=float, default=None, callback=_finite,
                     help="view azimuth in degrees (default: light azimuth + 180, the plane of incidence)")(f)
    f = click.option("--light-azimuth", "light_azimuth", type=float, default=0.0, show_default=True, callback=_finite,
                     help="light azimuth in degrees")(f)
    f = click.option("--view", "view", type=float, default=0.0, show_default=True,
                     help="view polar angle from the normal, degrees [0, 90)")(f)
    f = click.option("--light", "light", type=float, default=45.0, show_default=True,
                     help="light polar angle from the normal, degrees [0, 90)")(f)
    return f


def colour_options(f):
    f = click.option("--observer", default="10", show_default=True, help="10 (CIE 1964) or 2 (CIE 1931)")(f)
    f = click.option("--illuminant", default="D65", show_default=True, help="CIE illuminant name (D65, D50, A, FL2, ...)")(f)
    return f


def echo_json(obj) -> None:
    click.echo(json.dumps(obj, indent=2, ensure_ascii=False, allow_nan=False))


def is_terminal() -> bool:
    return sys.stderr.isatty()
