"""Lighting, resolved once into one :class:`Lighting` that every engine takes (issue 17, 23).

:func:`resolve_lighting` reads a render's ``environment`` for an engine and checks it (and the
camera, the size and the background it implies) before anything is rendered:

* ``builtin`` (:mod:`swatch.render.builtin.env_render`, :mod:`swatch.render.builtin.pointlight`): ``point`` (one
  directional light; the default unless the model is the GGX microfacet one), ``studio`` (the
  built-in studio map, the default), ``uniform``, or an equirectangular ``.exr``/``.hdr`` map,
  resolved into an :class:`swatch.render.environment.Environment` (normalised: a white diffuser
  facing up reflects 1);
* ``mitsuba`` (:mod:`swatch.render.mitsuba.engine`): ``studio`` (Mitsuba's photographic studio:
  cyclorama and soft boxes; the default), ``sun`` (Mitsuba's ``sunsky``, with a :class:`Sun`),
  ``uniform``, or a map, whose pixels are read and checked once
  (:func:`swatch.render.hdri.read_equirect`).

The names, their descriptions and the engines that render each are :data:`swatch.core.choices.LIGHTINGS`;
the default when none is named is :func:`default_environment`'s, the same for the library and the CLI.

Nothing here imports Mitsuba: the built-in path and ``swatch --help`` never load it.
"""
from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from swatch.core.choices import ENGINES, LIGHTINGS, POINT_LIGHT, lightings_of
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_TURBIDITY, MAX_YEAR, MIN_TURBIDITY, MIN_YEAR
from swatch.physics import geometry
from swatch.render.builtin.env_render import check_env_size_px
from swatch.render.environment import Environment, get_environment
from swatch.render.hdri import read_equirect

__all__ = ["Sun", "check_sun", "Lighting", "resolve_lighting", "check_engine", "default_environment",
           "lighting_for"]


@dataclass(frozen=True)
class Sun:
    """The sun and sky of ``sun`` lighting: by angles (``elevation_deg``, ``azimuth_deg`` about +y from
    +z towards +x) or by place and time (``latitude_deg``, ``longitude_deg``, ``timezone_h``, the
    local ``year``, ``month``, ``day``, ``hour``); ``turbidity`` 1–10 (Hosek–Wilkie).

    Attributes
    ----------
    elevation_deg, azimuth_deg : float
        The sun's elevation above the horizon and azimuth about +y from +z towards +x, degrees.
    latitude_deg, longitude_deg : float or None
        The place, degrees (both set: the sun by place and time; the angles are then ignored).
    timezone_h : float
        The local time's offset from UTC, hours.
    year, month, day : int
        The local date.
    hour : float
        The local time, hours.
    turbidity : float
        Atmospheric turbidity of the Hosek–Wilkie sky model, 1–10.

    References
    ----------
    L. Hosek and A. Wilkie, "An Analytic Model for Full Spectral Sky-Dome Radiance", ACM TOG 31(4),
    95 (2012), doi:10.1145/2185520.2185591.
    """

    elevation_deg: float | None = 45.0
    azimuth_deg: float = 0.0
    latitude_deg: float | None = None
    longitude_deg: float | None = None
    timezone_h: float = 0.0
    year: int = 2026
    month: int = 6
    day: int = 21
    hour: float = 12.0
    turbidity: float = 3.0

    @property
    def by_place(self) -> bool:
        """Whether the sun is given by place and time (latitude set) rather than by angles.

        Returns
        -------
        bool
            True when latitude and longitude are set.
        """
        return self.latitude_deg is not None

    def description(self) -> str:
        """One line for metadata and reports.

        Returns
        -------
        str
            The sun and sky in words (angles, or place, date and time; turbidity).
        """
        if self.by_place:
            return (f"sun and sky (Mitsuba sunsky, Hosek-Wilkie) at latitude {self.latitude_deg:g}, longitude "
                    f"{self.longitude_deg:g}, {self.year:04d}-{self.month:02d}-{self.day:02d} {self.hour:g} h "
                    f"(UTC{self.timezone_h:+g}), turbidity {self.turbidity:g}; -z north")
        return (f"sun and sky (Mitsuba sunsky, Hosek-Wilkie), sun {self.elevation_deg:g} deg above the horizon at "
                f"azimuth {self.azimuth_deg:g} deg, turbidity {self.turbidity:g}")



def _finite_in(value, lo: float, hi: float, what: str, unit: str = "") -> float:
    v = float(value)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise SwatchError(f"{what} must be from {lo:g} to {hi:g}{unit}, got {value!r}")
    return v


def check_sun(sun: Sun) -> Sun:
    """The sun, checked: angles, place, a real calendar date in [MIN_YEAR, MAX_YEAR], hour, turbidity.

    Parameters
    ----------
    sun : Sun
        The sun by angles or by place and time.

    Returns
    -------
    Sun
        ``sun`` itself.

    Raises
    ------
    SwatchError
        For a value out of range (one line, what is allowed).
    """
    _finite_in(sun.turbidity, MIN_TURBIDITY, MAX_TURBIDITY, "sun turbidity")
    _finite_in(sun.azimuth_deg, -360.0, 360.0, "sun azimuth", " deg")
    if sun.by_place:
        if sun.longitude_deg is None:
            raise SwatchError("a sun by place needs both latitude and longitude")
        _finite_in(sun.latitude_deg, -90.0, 90.0, "latitude", " deg")
        _finite_in(sun.longitude_deg, -180.0, 180.0, "longitude", " deg")
        _finite_in(sun.timezone_h, -12.0, 14.0, "time zone", " h from UTC")
        if not MIN_YEAR <= int(sun.year) <= MAX_YEAR:
            raise SwatchError(f"sun date: the year must be from {MIN_YEAR} to {MAX_YEAR}, got {sun.year}")
        try:
            dt.date(int(sun.year), int(sun.month), int(sun.day))
        except ValueError as exc:
            raise SwatchError(f"sun date {sun.year}-{sun.month}-{sun.day} is not a calendar date ({exc})") from None
        h = float(sun.hour)
        if not (math.isfinite(h) and 0.0 <= h < 24.0):
            raise SwatchError(f"sun time must be from 00:00 to 23:59, got hour {sun.hour!r}")
    else:
        _finite_in(sun.elevation_deg, 0.0, 90.0, "sun elevation", " deg above the horizon")
    return sun


def default_environment(engine: str, model: str = "microfacet", distribution: str = "ggx") -> str:
    """The lighting an engine renders when none is named (``environment=None``; ``swatch render`` without
    ``--environment``): the one definition of the default.

    Parameters
    ----------
    engine : str
        ``builtin`` or ``mitsuba``.
    model, distribution : str
        The intensity model and facet distribution (the built-in engine's environments need GGX microfacet).

    Returns
    -------
    str
        ``studio`` (mitsuba; builtin with the GGX microfacet model), else ``point`` (the point light).
    """
    if engine == "mitsuba" or (model, distribution) == ("microfacet", "ggx"):
        return "studio"
    return POINT_LIGHT


def check_engine(engine: str) -> str:
    """A render engine's name, checked.

    Parameters
    ----------
    engine : str
        One of :data:`swatch.core.choices.ENGINES` (case and surrounding blanks ignored).

    Returns
    -------
    str
        The name, lower case.

    Raises
    ------
    SwatchError
        For another name (naming ```engine``` and the choices).
    """
    return ENGINES.validate(engine)


@dataclass(frozen=True, eq=False)
class Lighting:
    """A render's lighting, resolved and checked for one engine (:func:`resolve_lighting`).

    Equality is identity (the built-in engine caches a scene's gather per lighting object).

    Attributes
    ----------
    engine : str
        The engine it was resolved for (:data:`swatch.core.choices.ENGINES`).
    kind : str
        A name of :data:`swatch.core.choices.LIGHTINGS` (``point``: the built-in point light, ``studio``,
        ``uniform``, ``sun``: mitsuba) or ``map``.
    name : str
        The built-in name, or a map's file name.
    environment : Environment or None
        The built-in engine's map (None for the point light and for the mitsuba engine).
    sun : Sun or None
        The sun of ``sun`` lighting (checked).
    hdri : numpy.ndarray or None, float32, shape (H, W, 3)
        A map's equirectangular pixels for the mitsuba engine (checked: finite, ≥ 0, 2:1).
    """

    engine: str
    kind: str
    name: str
    environment: Environment | None = None
    sun: Sun | None = None
    hdri: np.ndarray | None = None


def _named(environment, engine: str) -> str | None:
    """The registered name of a lighting of :data:`LIGHTINGS` (None for a map's path); refused where ``engine``
    does not render it."""
    key = str(environment).strip()
    if key not in LIGHTINGS:
        return None
    name = LIGHTINGS.validate(key)
    if engine not in LIGHTINGS[name]:
        if name == POINT_LIGHT:
            raise SwatchError(f"the {engine} engine has no point light; use {', '.join(lightings_of(engine))} "
                              "or a map for `environment`")
        raise SwatchError(f"{name} lighting is the {', '.join(LIGHTINGS[name])} engine's; add `engine='mitsuba'`")
    return name


def _builtin(environment, model: str, distribution: str, size_px, background) -> Lighting:
    if isinstance(environment, Environment):
        env: Environment | None = environment
    else:
        if environment is None:
            environment = default_environment("builtin", model, distribution)
        name = _named(environment, "builtin")
        env = get_environment(environment if name is None else name)
    if env is not None and (model != "microfacet" or distribution != "ggx"):
        raise SwatchError("environment lighting integrates the GGX microfacet BRDF; use `model='microfacet'` "
                          f"`distribution='ggx'`, or `environment='{POINT_LIGHT}'`")
    if env is not None and size_px is not None:
        check_env_size_px(size_px)
    if env is None and background == "environment":
        raise SwatchError("`background=environment` needs an environment; use grey or white with "
                          f"`environment='{POINT_LIGHT}'`")
    if env is None:
        return Lighting("builtin", POINT_LIGHT, POINT_LIGHT)
    kind = env.name if env.name in ("studio", "uniform") else "map"
    return Lighting("builtin", kind, env.name, environment=env)


def _mitsuba(environment, sun: Sun | None) -> Lighting:
    key = default_environment("mitsuba") if environment is None else str(environment).strip()
    name = _named(key, "mitsuba")
    if sun is not None and name != "sun":
        raise SwatchError("the sun options need `environment='sun'`")
    if name == "sun":
        return Lighting("mitsuba", "sun", "sun", sun=check_sun(sun if sun is not None else Sun()))
    if name is not None:
        return Lighting("mitsuba", name, name)
    if not key.lower().endswith((".exr", ".hdr")):
        raise SwatchError(f"unknown lighting {key!r} for the mitsuba engine; use one of "
                          f"{', '.join(lightings_of('mitsuba'))} or an equirectangular .exr or .hdr file")
    return Lighting("mitsuba", "map", Path(key).name, hdri=read_equirect(key))


def resolve_lighting(environment=None, engine: str = "builtin", sun: Sun | None = None, model: str = "microfacet",
                     distribution: str = "ggx", size_px: int | None = None, background: str | None = None,
                     view_deg: float | None = None, view_azimuth_deg: float = 0.0) -> Lighting:
    """The lighting of a render, resolved once for ``engine`` (module documentation).

    Parameters
    ----------
    environment : str, path-like, Environment, Lighting or None
        A name (``point``, ``studio``, ``uniform``, ``sun``), an equirectangular .exr/.hdr path, an
        :class:`Environment` (builtin), or a :class:`Lighting` (returned as it is if it was resolved
        for ``engine``). None: the engine's default (module documentation).
    engine : str
        ``builtin`` or ``mitsuba``.
    sun : Sun, optional
        The sun of ``sun`` lighting (mitsuba; default 45° elevation, azimuth 0, turbidity 3).
    model, distribution : str
        The built-in engine's intensity model and facet distribution (an environment needs GGX microfacet).
    size_px : int, optional
        The image size, checked against the built-in environment renderer's range when given.
    background : str, optional
        ``environment`` needs an environment (builtin).
    view_deg, view_azimuth_deg : float
        The camera (degrees), checked here.

    Returns
    -------
    Lighting
        The lighting checked for ``engine`` (reuse it across renders).

    Raises
    ------
    SwatchError
        For an unknown name, an unusable map, a sun out of range, or a lighting the engine cannot render.
    """
    engine = check_engine(engine)
    if not isinstance(environment, Lighting):
        if view_deg is not None:
            geometry.check_polar_deg(view_deg, "view_deg")
        geometry.check_azimuth_deg(view_azimuth_deg, "view_azimuth_deg")
    return lighting_for(environment, engine, sun, model, distribution, size_px, background)


def lighting_for(environment, engine: str, sun: Sun | None = None, model: str = "microfacet",
                 distribution: str = "ggx", size_px: int | None = None, background: str | None = None) -> Lighting:
    """:func:`resolve_lighting` for an ``engine`` name already checked (:func:`check_engine`), the camera
    checked elsewhere (the render request checks each once; its scene checks the camera).

    Parameters
    ----------
    environment, sun, model, distribution, size_px, background
        As :func:`resolve_lighting`.
    engine : str
        ``builtin`` or ``mitsuba``, lower case.

    Returns
    -------
    Lighting
        The lighting resolved for ``engine``.
    """
    if isinstance(environment, Lighting):
        if environment.engine != engine:
            raise SwatchError(f"this lighting was resolved for the {environment.engine} engine, not {engine}")
        return environment
    if engine == "mitsuba":
        return _mitsuba(environment, sun)
    if sun is not None:
        raise SwatchError("sun and sky lighting is the mitsuba engine's; add `engine='mitsuba'`")
    return _builtin(environment, model, distribution, size_px, background)
