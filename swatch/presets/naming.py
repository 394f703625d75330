"""The names of preset files (a catalog's ``presets/`` and ``swatch preset``'s output) and the address they are
served from (``base_url``): light, no numpy."""
from __future__ import annotations

import re
from urllib.parse import urlsplit

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_BASE_URL_CHARS

__all__ = ["preset_file_name", "check_base_url"]

#: The characters RFC 3986 allows in a URI (a ``base_url`` has no query or fragment: names follow it).
_URI_CHARS = re.compile(r"(?:[A-Za-z0-9\-._~:/@!$&'()*+,;=]|%[0-9A-Fa-f]{2})+")


def preset_file_name(ident: str, fmt: str) -> str:
    """A preset's file name (in a catalog folder's ``presets/``, or ``swatch preset``'s folder).

    Parameters
    ----------
    ident : str
        The swatch id (``S001``), or ``<thickness>nm`` for ``swatch preset``.
    fmt : str
        ``gltf``, ``blender``, ``materialx``, ``mitsuba`` (the XML), ``mitsuba_json``, ``usd``, ``usdz``,
        ``physicallybased``, ``physicallybased_300`` / ``physicallybased_600`` (its pictures, PNG) or ``viewer``
        (a catalog's ``<model-viewer>`` file, swatch.catalog.ar).

    Returns
    -------
    str
        The file name, e.g. ``preset_S001.gltf``.
    """
    return {"gltf": f"preset_{ident}.gltf", "blender": f"preset_{ident}_blender.py",
            "materialx": f"preset_{ident}.mtlx", "mitsuba": f"preset_{ident}_mitsuba.xml",
            "mitsuba_json": f"preset_{ident}_mitsuba.json", "usd": f"preset_{ident}.usda",
            "usdz": f"preset_{ident}.usdz", "physicallybased": f"preset_{ident}_physicallybased.json",
            "physicallybased_300": f"preset_{ident}_physicallybased_300.png",
            "physicallybased_600": f"preset_{ident}_physicallybased_600.png",
            "viewer": f"preset_{ident}_viewer.gltf"}[fmt]


def check_base_url(base_url: str) -> str:
    """The address the preset files are served from, checked: ``http`` or ``https``, a host, RFC 3986
    characters only, no query or fragment, at most :data:`~swatch.core.limits.MAX_BASE_URL_CHARS`.

    Parameters
    ----------
    base_url : str
        The folder's address (``https://example.com/presets``; a trailing ``/`` is optional).

    Returns
    -------
    str
        The address without its trailing ``/``.

    Raises
    ------
    swatch.core.errors.SwatchError
        For any other address, naming `base_url`.

    Examples
    --------
    >>> check_base_url("https://example.com/presets/")
    'https://example.com/presets'
    >>> check_base_url("example.com/presets")
    Traceback (most recent call last):
    ...
    swatch.core.errors.SwatchError: `base_url` must be an http(s) address ... (got 'example.com/presets')
    """
    text = str(base_url)
    if len(text) > MAX_BASE_URL_CHARS:
        raise SwatchError(f"`base_url` has {len(text)} characters; at most {MAX_BASE_URL_CHARS}")
    try:
        parts = urlsplit(text) if _URI_CHARS.fullmatch(text) else None
        _ = None if parts is None else parts.port  # (a port that is not a number raises)
    except ValueError:
        parts = None
    if parts is None or parts.scheme not in ("http", "https") or not parts.hostname or parts.query or parts.fragment:
        raise SwatchError(f"`base_url` must be an http(s) address of the folder the pictures are served from, "
                          f"such as https://example.com/presets, without spaces, query or fragment (got {text!r})")
    return text.rstrip("/")
