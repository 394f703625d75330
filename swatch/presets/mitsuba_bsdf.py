"""Mitsuba 3 presets: the exact film as swatch's ``anodic_film`` BSDF, a scene dictionary and an XML element.

Unlike the glTF, Blender and MaterialX presets, nothing is fitted: the ``anodic_film`` plugin
(:mod:`swatch.render.mitsuba.bsdf`) evaluates the model the catalog's colours come from — the Airy
reflectance of the film with the tables' complex dispersive indices, s and p averaged, on the
facet of the half vector, per sampled wavelength — so a preset is the swatch's own parameters
written down (thickness, film and substrate tables, film index scale, roughness; ΔE2000 0 by
construction; tests/presets/test_presets_mitsuba.py evaluates the files in Mitsuba 3.9).

A thickness spread (:mod:`swatch.physics.spread`) is written as the plugin's ``spread_nm`` and
``spread_fraction``: the plugin averages with the same Gauss–Hermite quadrature as the catalog
(its node count for Mitsuba's 360–830 nm; the catalog's for 380–780 nm: the averages agree to
far below a visible difference, tests/presets/test_presets_mitsuba.py).

Writing a preset needs no Mitsuba (it is text). Loading one does, with the plugin registered::

    import mitsuba as mi
    mi.set_variant("llvm_ad_spectral")   # a spectral variant: scalar_spectral, cuda_ad_spectral too
    import swatch.mitsuba
    swatch.mitsuba.register()            # BSDF type "anodic_film"
    bsdf = mi.load_dict(json.load(open("preset_S001_mitsuba.json"))["bsdf"])
    # or, in a scene file:  <include filename="preset_S001_mitsuba.xml"/>  then  <ref id="swatch_S001"/>
"""
from __future__ import annotations

import json
import math
from xml.sax.saxutils import quoteattr

from swatch.core.errors import SwatchError
from swatch.physics.model import check_thickness_nm
from swatch.physics.spread import NO_SPREAD, ThicknessSpread

__all__ = ["MITSUBA_VERSION", "PLUGIN", "REGISTER", "bsdf_dict", "mitsuba_json_bytes", "mitsuba_xml_bytes",
           "preset_id"]

#: The Mitsuba release the presets are checked in (pyproject pins mitsuba 3.9.x).
MITSUBA_VERSION = "3.9"
#: The plugin's type name (swatch.mitsuba.PLUGIN_NAME; repeated here: presets sit below the mitsuba layer).
PLUGIN = "anodic_film"
#: How a user makes the plugin available before loading a preset (Python, one line).
REGISTER = ('import mitsuba as mi; mi.set_variant("llvm_ad_spectral"); import swatch.mitsuba; '
            "swatch.mitsuba.register()")
#: The scene-description format version written on the XML element (Mitsuba 3's).
_XML_VERSION = "3.0.0"


def preset_id(ident: str) -> str:
    """The BSDF's ``id`` in the files (``swatch_S001``): what a scene's ``<ref id=…/>`` names.

    Parameters
    ----------
    ident : str
        The swatch id or a thickness label (``150nm``).

    Returns
    -------
    str
        ``"swatch_"`` and ``ident``, every character other than a letter, digit, ``_`` or ``-`` replaced by ``_``.

    Examples
    --------
    >>> preset_id("S001")
    'swatch_S001'
    """
    return "swatch_" + "".join(c if c.isalnum() or c in "_-" else "_" for c in str(ident))


def bsdf_dict(thickness_nm: float, film: str, substrate: str, film_index_scale: float = 1.0,
              alphas: tuple[float, ...] = (0.3,), spread: ThicknessSpread = NO_SPREAD, distribution: str = "ggx",
              ident: str | None = None) -> dict:
    """The Mitsuba scene dictionary of one swatch's BSDF (what ``mitsuba.load_dict`` takes).

    Parameters
    ----------
    thickness_nm : float
        Mean oxide thickness, nm.
    film, substrate : str
        Table names (``swatch materials list``).
    film_index_scale : float
        Factor on the film's real index (a process profile's).
    alphas : tuple of float
        GGX α, one (isotropic) or ``(alpha_u, alpha_v)``: along the surface's ``dp/du`` (for a brushed
        finish the grain) and across it.
    spread : ThicknessSpread
        Thickness non-uniformity: written as the plugin's ``spread_nm`` and ``spread_fraction``
        (omitted without one).
    distribution : str
        ``"ggx"`` (the catalog's) or ``"beckmann"``.
    ident : str, optional
        The BSDF's ``id`` (:func:`preset_id`).

    Returns
    -------
    dict
        JSON-ready: strings and floats.

    Raises
    ------
    SwatchError
        For a thickness outside what the model takes (:func:`swatch.physics.model.check_thickness_nm`)
        or an α outside (0, 1].
    """
    d = float(check_thickness_nm(float(thickness_nm)))
    a = tuple(float(x) for x in alphas)
    if len(a) not in (1, 2) or not all(math.isfinite(x) and 0.0 < x <= 1.0 for x in a):
        raise SwatchError(f"`alphas` must be one or two GGX α in (0, 1] (got {alphas!r})")
    out: dict = {} if ident is None else {"id": preset_id(ident)}
    out |= {"type": PLUGIN, "thickness_nm": d, "film": str(film), "substrate": str(substrate),
            "film_index_scale": float(film_index_scale), "distribution": str(distribution)}
    if len(a) == 1:
        out["alpha"] = a[0]
    else:
        out["alpha_u"], out["alpha_v"] = a
    out["shadowing"] = "correlated"  # Smith height-correlated, the built-in renderer's
    if not spread.is_zero:
        out |= {"spread_nm": float(spread.spread_nm), "spread_fraction": float(spread.spread_fraction)}
    return out


def mitsuba_json_bytes(bsdf: dict, info: dict) -> bytes:
    """The JSON preset: ``{"swatch": info (what it is, how to load it), "bsdf": the scene dictionary}``.

    Parameters
    ----------
    bsdf : dict
        :func:`bsdf_dict`.
    info : dict
        What the preset is (title, thickness, materials, the catalog's colour).

    Returns
    -------
    bytes
        UTF-8 JSON (the same inputs give the same bytes).
    """
    doc = {"swatch": {**info, "mitsuba": f"Mitsuba {MITSUBA_VERSION} (pip install 'mitsuba>=3.9,<3.10'), a spectral "
                                         "variant", "register": REGISTER,
                      "load": 'bsdf = mi.load_dict(json.load(open(path))["bsdf"])'},
           "bsdf": bsdf}
    return (json.dumps(doc, indent=1, ensure_ascii=False) + "\n").encode("utf-8")


def _xml_lines(node: dict) -> list[str]:
    """``<bsdf type=… id=… version=…>`` with one ``<float>``/``<integer>``/``<string>`` per key."""
    attrs = f' type={quoteattr(str(node["type"]))}'
    if "id" in node:
        attrs += f' id={quoteattr(str(node["id"]))}'
    lines = [f'<bsdf{attrs} version="{_XML_VERSION}">']
    for key, value in node.items():
        if key in ("type", "id"):
            continue
        if isinstance(value, float):
            lines.append(f'    <float name={quoteattr(key)} value="{value!r}"/>')
        elif isinstance(value, int):
            lines.append(f'    <integer name={quoteattr(key)} value="{value:d}"/>')
        else:
            lines.append(f"    <string name={quoteattr(key)} value={quoteattr(str(value))}/>")
    return [*lines, "</bsdf>"]


def mitsuba_xml_bytes(bsdf: dict, comment_lines: list[str]) -> bytes:
    """The XML preset: one ``<bsdf>`` element (Mitsuba's scene format, ``version`` on it so that
    ``mitsuba.load_string`` / ``load_file`` and a scene's ``<include>`` take it), the same
    dictionary as the JSON, after a comment saying what it is and how to register the plugin.

    Parameters
    ----------
    bsdf : dict
        :func:`bsdf_dict`.
    comment_lines : list of str
        The comment's lines.

    Returns
    -------
    bytes
        UTF-8 XML.
    """
    text = "\n".join(line.replace("--", "- -") for line in comment_lines)
    head = ['<?xml version="1.0" encoding="utf-8"?>', "<!--", text, "-->"]
    return ("\n".join(head + _xml_lines(bsdf)) + "\n").encode("utf-8")
