"""The names of preset files (a catalog's ``presets/`` and ``swatch preset``'s output): light, no numpy."""
from __future__ import annotations

__all__ = ["preset_file_name"]


def preset_file_name(ident: str, fmt: str) -> str:
    """A preset's file name (in a catalog folder's ``presets/``, or ``swatch preset``'s folder).

    Parameters
    ----------
    ident : str
        The swatch id (``S001``), or ``<thickness>nm`` for ``swatch preset``.
    fmt : str
        ``gltf``, ``blender``, ``materialx``, ``mitsuba`` (the XML) or ``mitsuba_json``.

    Returns
    -------
    str
        The file name, e.g. ``preset_S001.gltf``.
    """
    return {"gltf": f"preset_{ident}.gltf", "blender": f"preset_{ident}_blender.py",
            "materialx": f"preset_{ident}.mtlx", "mitsuba": f"preset_{ident}_mitsuba.xml",
            "mitsuba_json": f"preset_{ident}_mitsuba.json"}[fmt]
