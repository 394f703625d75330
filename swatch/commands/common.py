"""Options and parsing shared by the subcommands."""
from __future__ import annotations

import json
import math
import sys

import click
import numpy as np

from swatch.commands.terminal import unescaped
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_OVERCOATS, MAX_THICKNESS_NM
from swatch.core.ranges import parse_grid, parse_range
from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, wavelength_grid
from swatch.physics.model import check_thickness_nm

_SPREAD_META = "swatch.physics.spread"


def _spread_callback(ctx, param, value):
    from swatch.physics.spread import parse_spread

    ctx.meta[_SPREAD_META] = parse_spread(value)
    return value


def spread_option(f):
    """``--spread NM[,FRACTION]``: the film's thickness spread (1σ), overriding the process profile's.

    The value is kept in the click context (no parameter for the command); :func:`resolve_process`
    applies it, so every command that takes a process takes it the same way.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    return click.option("--spread", "spread", default=None, metavar="NM[,FRACTION]", expose_value=False,
                        callback=_spread_callback,
                        help="thickness spread of the film, 1σ = NM + FRACTION × thickness (e.g. 4 or 3,0.02; "
                             "colours are averaged over it), overriding the process profile's [default: the "
                             "profile's; 0: a uniform film]")(f)


def given_spread():
    """The ``--spread`` of the running command.

    Returns
    -------
    swatch.physics.spread.ThicknessSpread or None
        None when not given or outside a command.
    """
    ctx = click.get_current_context(silent=True)
    return None if ctx is None else ctx.meta.get(_SPREAD_META)


def process_options(f):
    """``--process NAME|FILE`` and its overrides ``--nm-per-volt`` and ``--spread``.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    f = spread_option(f)
    f = click.option("--nm-per-volt", type=float, default=None,
                     help="anodic growth rate, nm/V, overriding the process profile's")(f)
    f = click.option("--process", "process", default=None, metavar="NAME|FILE",
                     help="process profile: a preset of tables/processes (docs/processes.md) or a profile .toml "
                          "[default: titanium-fujii2019, 50.8 nm at 25 V]")(f)
    return f


def resolve_process(process: str | None, film: str | None = None, substrate: str | None = None,
                    nm_per_volt: float | None = None):
    """The :class:`swatch.physics.process.Process` for ``--process`` with ``--film``/``--substrate``/``--nm-per-volt``
    and ``--spread``.

    Parameters
    ----------
    process : str or None
        A preset's name or a profile's path; None: the default profile.
    film, substrate : str or None
        ``--film`` / ``--substrate``: optical table names replacing the profile's; None keeps them.
    nm_per_volt : float or None
        ``--nm-per-volt``: a growth rate replacing the profile's, nm/V; None keeps it.

    Returns
    -------
    swatch.physics.process.Process
        The profile with the overrides (and ``--spread``) applied; its ``origin`` says what was overridden.

    Raises
    ------
    SwatchError
        For an empty ``--process`` or a profile that cannot be read.
    """
    from swatch.physics.process import DEFAULT_PROCESS, load_process

    if process is not None and not process.strip():  # ('' silently took the default)
        raise SwatchError("--process is an empty string; give a preset name or the path of a profile .toml file")
    return load_process(DEFAULT_PROCESS if process is None else process).with_overrides(film, substrate, nm_per_volt, given_spread())


def thickness_options(multiple: bool):
    """``--thickness`` / ``--voltage`` (+ ``--process``, ``--nm-per-volt``) resolving to ``thickness_nm``.

    Parameters
    ----------
    multiple : bool
        Whether the options take ranges (``A:B:STEP`` or lists).

    Returns
    -------
    callable
        The decorator adding the options.
    """
    t_help = "film thickness in nm: A:B:STEP or N,N,..." if multiple else "film thickness in nm"
    v_help = ("anodising voltage in V instead of a thickness (through the process's growth law)"
              + (": A:B:STEP or N,N,..." if multiple else ""))

    def deco(f):
        f = process_options(f)
        f = click.option("--voltage", "voltage", type=str, default=None, help=v_help)(f)
        f = click.option("--thickness", "thickness", type=str, default=None, help=t_help)(f)
        return f

    return deco


def resolve_thickness(thickness: str | None, voltage: str | None, proc, multiple: bool):
    """The thicknesses a command was given, directly or as voltages through ``proc``'s growth law.

    Parameters
    ----------
    thickness, voltage : str or None
        The options' text (exactly one given).
    proc : swatch.physics.process.Process
        The anodising line's profile, whose growth law turns voltages (V) into thicknesses (nm).
    multiple : bool
        Whether a range is allowed.

    Returns
    -------
    thickness_nm : numpy.ndarray
        Checked (the library's checks; the whole range before anything is computed).
    voltage_V : numpy.ndarray or None
        The voltages given, if any.

    Raises
    ------
    SwatchError
        For neither or both, a bad range, a range where one value is allowed, or a value out of range.
    """
    if (thickness is None) == (voltage is None):
        raise SwatchError("give exactly one of --thickness NM or --voltage V")
    v = None if voltage is None else parse_range(voltage, "voltage", "V")
    # one check each, before anything is computed or written (a range whose last value is out of
    # range must not leave its first images behind): the library's, which names `thickness_nm` /
    # `voltage_V` (spoken as --thickness / --voltage); the growth law checks the films it gives
    d = check_thickness_nm(parse_range(str(thickness), "thickness", "nm")) if v is None else proc.thickness_nm(v)
    if not multiple and d.size != 1:
        raise SwatchError("this command takes one thickness (or voltage), not a range")
    return d, v


def material_options(f):
    """``--film`` and ``--substrate`` (default: the process's tables).

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    f = click.option("--substrate", default=None,
                     help=f"substrate table (swatch materials list) [default: the process's; {DEFAULT_SUBSTRATE}]")(f)
    f = click.option("--film", default=None,
                     help=f"film table (swatch materials list) [default: the process's; {DEFAULT_FILM}]")(f)
    return f


def overcoat_option(f):
    """``--overcoat INDEX:NM|TABLE:NM`` (repeatable).

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    return click.option("--overcoat", "overcoats", multiple=True, metavar="INDEX:NM|TABLE:NM",
                         help="a thin clear layer over the oxide, e.g. 1.5:200 (index 1.5, 200 nm) or "
                              "TiO2-Siefke:20; repeat for several, listed from the air side; coherent, so "
                              "at most 1000 nm")(f)


def resolve_coating(proc, wavelengths: str = "380:780:5", overcoats=()):
    """The :class:`swatch.physics.process.Process`'s coating with any ``--overcoat`` layers on top.

    Parameters
    ----------
    proc : swatch.physics.process.Process
        The anodising line's profile (film, substrate, index scale, thickness spread).
    wavelengths : str, optional
        ``--wavelengths`` (START:STOP:STEP, nm).
    overcoats : sequence of str, optional
        The ``--overcoat`` values, from the air side.

    Returns
    -------
    swatch.physics.model.Coating or swatch.physics.overcoat.OvercoatedCoating
        The film on its substrate on the wavelength grid (nm); overcoated when ``overcoats`` are given.

    Raises
    ------
    SwatchError
        For too many layers or a stack thicker than ``MAX_THICKNESS_NM``.
    """
    from swatch.physics.overcoat import OvercoatedCoating, overcoat

    coating = proc.coating(resolve_grid(wavelengths))
    if not overcoats:
        return coating
    if len(overcoats) > MAX_OVERCOATS:
        raise SwatchError(f"{len(overcoats)} --overcoat layers; at most {MAX_OVERCOATS}")
    layers = tuple(overcoat(o, coating.wavelength_nm) for o in overcoats)
    total = sum(o.thickness_nm for o in layers)
    if total > MAX_THICKNESS_NM:
        raise SwatchError(f"the --overcoat layers add up to {total:g} nm; at most {MAX_THICKNESS_NM:g} nm in all "
                          "(a thicker stack is not coherent: its fringes are finer than the wavelength grid)")
    return OvercoatedCoating(coating, layers)


def grid_option(f):
    """``--wavelengths START:STOP:STEP``.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    return click.option("--wavelengths", "wavelengths", default="380:780:5", show_default=True,
                        help="wavelength grid START:STOP:STEP in nm (colorimetry: 1, 5, 10 or 20 nm steps)")(f)


def resolve_grid(text: str) -> np.ndarray:
    """The wavelength grid of ``--wavelengths``.

    Parameters
    ----------
    text : str
        START:STOP:STEP in nm.

    Returns
    -------
    numpy.ndarray
        nm, shape (W,).
    """
    return wavelength_grid(*parse_grid(text))


def _finite(ctx, param, value):
    if value is not None and not math.isfinite(value):
        raise SwatchError(f"--{param.name.replace('_', '-')} must be a finite number of degrees")
    return value


def geometry_options(f):
    """``--light``, ``--view`` (polar, degrees) and ``--light-azimuth``, ``--view-azimuth``.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
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
    """``--illuminant`` and ``--observer``.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option(s).
    """
    f = click.option("--observer", default="10", show_default=True, help="10 (CIE 1964) or 2 (CIE 1931)")(f)
    f = click.option("--illuminant", default="D65", show_default=True, help="CIE illuminant name (D65, D50, A, FL2, ...)")(f)
    return f


def echo_json(obj) -> None:
    """Print ``obj`` as indented UTF-8 JSON (NaN refused: the JSON stays standard).

    Parameters
    ----------
    obj : object
        JSON-ready.
    """
    echo_json_text(json.dumps(obj, indent=2, ensure_ascii=False, allow_nan=False) + "\n")


def echo_json_text(text: str) -> None:
    """Print a JSON text as it is: JSON escapes the control characters itself, and the bytes stay those of the
    file a command writes (the stream underneath the escaping one, :mod:`swatch.commands.terminal`).

    Parameters
    ----------
    text : str
        The JSON, with its final newline.
    """
    click.echo(text, file=unescaped(sys.stdout), nl=False)


def instrument_request(percent=None):
    """The :class:`swatch.io.instruments.Request` of the running command: its geometry, illuminant and
    observer options, and which of them the user gave (those must agree with a measurement file).

    Parameters
    ----------
    percent : bool or None, optional
        The reflectance unit (None: detect).

    Returns
    -------
    swatch.io.instruments.Request
        Light/view angles (degrees), illuminant, observer and unit of the command, with ``given`` naming
        those the user set (``geometry``, ``illuminant``, ``observer``).
    """
    from click.core import ParameterSource

    from swatch.io.instruments import Request

    ctx = click.get_current_context()
    p = ctx.params

    def given(name):
        return name in p and ctx.get_parameter_source(name) not in (ParameterSource.DEFAULT, None)

    keys = set()
    if any(given(n) for n in ("light", "view", "light_azimuth", "view_azimuth")):
        keys.add("geometry")
    keys |= {n for n in ("illuminant", "observer") if given(n)}
    return Request(light_deg=p.get("light", 45.0), view_deg=p.get("view", 0.0),
                   light_azimuth_deg=p.get("light_azimuth", 0.0) or 0.0, view_azimuth_deg=p.get("view_azimuth"),
                   illuminant=p.get("illuminant", "D65"), observer=p.get("observer", "10"), percent=percent,
                   given=frozenset(keys))


def unit_options(help_text: str):
    """``--percent`` / ``--fraction`` (the reflectance unit), passed to the command as ``percent``
    (True, False, or None to detect); both together are refused (with a flag pair the last one won).

    Parameters
    ----------
    help_text : str
        ``--percent``'s help.

    Returns
    -------
    callable
        The decorator.
    """
    import functools

    def deco(f):
        @functools.wraps(f)
        def run(*args, percent_flag=False, fraction_flag=False, **kwargs):
            if percent_flag and fraction_flag:
                raise SwatchError("give --percent or --fraction, not both (the reflectance unit of the spectra)")
            return f(*args, percent=True if percent_flag else False if fraction_flag else None, **kwargs)

        run = click.option("--fraction", "fraction_flag", is_flag=True, help="reflectance is a fraction (0–1)")(run)
        return click.option("--percent", "percent_flag", is_flag=True, help=help_text)(run)
    return deco
