"""physicallybased.info presets: each swatch as a material of that database's v2 schema (CC0).

The database (Anton Palmqvist, https://physicallybased.info, API v2.1) describes anodised titanium as
a metal under a thin film: ``color`` (the metal's linear Rec.709 colour), ``metalness`` 1,
``complexIor`` (n, k per colour channel), ``thinFilmThickness`` (nm) and ``thinFilmIor``; its
"Titanium (Anodized)" entry gives ``thinFilmIor`` 2.488 (anatase, Jolivet) over 20–300 nm. A swatch's
entry gives the same fields for its own film: one thickness, and the index of the film table the
catalog's model uses (``TiO2-Siefke`` by default: n at :data:`INDEX_WAVELENGTH_NM`, times the process's
film index scale). Why that index and not anatase's: it is the film whose Airy colours the catalog
shows, so a renderer's thin film given these values starts from the same physics; the renderers'
fitted values are the ``.mtlx``/glTF presets' (fitted, not physical). The metal's ``color`` is the substrate table's reflectance at normal
incidence (D65, CIE 1931 2°, ASTM E308 weights, linear Rec.709) and ``complexIor`` its n and k averaged
over each Rec.709 channel's colour-matching weight (the positive part under D65).

The document: ``{"$schema", "header", "data": [materials]}`` as the database's own
``materials.json`` (the schema requires ``header.origin`` to be an ``https://api.physicallybased.info/v2``
address, so ``origin`` names the schema's API). The schema requires ``images`` on each material: the
URLs of a 300 and a 600 px render (the database's own are Cycles renders on its shader ball). swatch's are
its own: the built-in engine's sphere under its studio (:mod:`swatch.report.physicallybased` renders them,
:data:`PICTURE_TEXT` says so in each description), PNG files written beside the document. Their URLs are
relative references to those files (:func:`image_entries`), or, given a ``base_url`` (the address the
files are served from; the database wants hosted URLs), absolute ``http(s)`` URLs.
tests/presets/test_presets_usd.py validates both against the vendored schema, the absolute ones with
``format: uri`` asserted.

References
----------
.. [1] :cite:`Palmqvist`: API v2 (CC0 1.0).
.. [2] :cite:`Siefke2016`.
"""
from __future__ import annotations

import json

import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.physics.materials import load_material, metal_name, wavelength_grid
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00
from swatch.presets.naming import check_base_url
from swatch.presets.spectral import rgb_to_xyz_matrix

__all__ = ["SCHEMA_URL", "HEADER", "INDEX_WAVELENGTH_NM", "film_index", "metal_color_and_ior",
           "physical_values_delta_E_00", "material_entry", "document_bytes", "IMAGE_SIZES_PX", "IMAGE_FORMAT",
           "PICTURE_TEXT", "image_entries"]

#: The v2 material schema the documents follow (vendored in tests/vendor/physicallybased/).
SCHEMA_URL = ("https://raw.githubusercontent.com/AntonPalmqvist/physically-based-api/main/schemas/components/"
              "schemas/Material.json")
#: The header: schema version 2.1 and, as ``updated``, that schema's release (2026-04-26 14:35), so the
#: bytes do not depend on the day they were written.
HEADER = {"schemaVersion": 2.1, "updated": 202604261435, "license": "CC0 1.0 Universal",
          "origin": "https://api.physicallybased.info/v2/materials", "deprecated": False}
#: The wavelength at which the film's dispersive index is stated as one ``thinFilmIor`` (nm).
INDEX_WAVELENGTH_NM = 550.0
#: The sides of the pictures the schema's ``images`` name (its keys ``"300"`` and ``"600"``), pixels.
IMAGE_SIZES_PX = (300, 600)
#: The pictures' file format (the schema's ``images[].format``).
IMAGE_FORMAT = "png"
#: What the pictures show, in each material's description (the database's own are Cycles on its shader ball).
PICTURE_TEXT = (" images: swatch's built-in engine (not Cycles), a sphere under its studio light (soft boxes),"
                " grey ground.")


def film_index(film: str, film_index_scale: float = 1.0) -> float:
    """The film table's real index at :data:`INDEX_WAVELENGTH_NM`, times the process's scale.

    Parameters
    ----------
    film : str
        Film table name.
    film_index_scale : float, optional
        The process profile's factor on the film's real index.

    Returns
    -------
    float
        n (dimensionless), to 1e-3.
    """
    nk = load_material(film).nk(np.array([INDEX_WAVELENGTH_NM]))[0]
    return round(float(nk.real) * float(film_index_scale), 3)


def metal_color_and_ior(substrate: str) -> tuple[list[float], list[float], list[float]]:
    """The substrate's colour at normal incidence and its n, k per Rec.709 channel.

    Parameters
    ----------
    substrate : str
        Substrate table name.

    Returns
    -------
    color, n, k : list of float
        Linear Rec.709 reflectance (to 1e-3), and n, k (to 1e-5) each averaged over a channel's
        colour-matching weight (D65, CIE 1931 2°, clipped at 0).
    """
    wl = wavelength_grid(380.0, 780.0, 5.0)
    cm = get_colorimeter(wl, "D65", "2")
    nk = load_material(substrate).nk(wl)
    r = np.abs((nk - 1.0) / (nk + 1.0)) ** 2  # normal incidence from air
    matrix, _ = rgb_to_xyz_matrix()
    to_rgb = np.linalg.inv(matrix)
    rgb = to_rgb @ (cm.XYZ(r) / 100.0)
    w = np.clip(np.asarray(cm.weights) @ to_rgb.T, 0.0, None)  # (W, 3) per channel
    w = w / w.sum(axis=0)
    return ([round(float(v), 3) for v in np.clip(rgb, 0.0, 1.0)], [round(float(v), 5) for v in nk.real @ w],
            [round(float(v), 5) for v in nk.imag @ w])


def physical_values_delta_E_00(thickness_nm: float, film: str, substrate: str, film_index_scale: float,
                               roughness: float, spread=None) -> float:
    """The largest ΔE2000 of these physical values as an OpenPBR thin film in MaterialX 1.39.5's GLSL
    (:mod:`swatch.presets.materialx`: base colour the bare metal's, the real thickness, :func:`film_index`)
    against the exact colour over mirror geometries 0–60° (D65, CIE 1931 2°).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    film, substrate : str
        Table names.
    film_index_scale : float
        The process's factor on the film's real index.
    roughness : float
        ``specular_roughness`` (√α).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread, in the exact colour as in the catalog's figures; None: uniform.

    Returns
    -------
    float
        ΔE2000.
    """
    color, _, _ = metal_color_and_ior(substrate)
    params = np.array([[float(thickness_nm), film_index(film, film_index_scale), *color]])
    return float(errors_delta_E_00("materialx", params, [float(thickness_nm)], FIT_ANGLES_DEG, film, substrate,
                                   film_index_scale, spread, roughness).max())


def _reference(material) -> dict:
    out = {"title": f"{material.name} optical constants", "url": f"https://doi.org/{material.doi}" if material.doi else
           "https://refractiveindex.info", "author": material.reference[:200]}
    if material.doi:
        out["doi"] = f"https://doi.org/{material.doi}"
    return out


def material_entry(name: str, thickness_nm: float, film: str, substrate: str, film_index_scale: float,
                   roughness: float, images: list[dict] | None = None, note: str = "", spread=None) -> dict:
    """One material of the v2 schema for an oxide of ``thickness_nm``.

    Parameters
    ----------
    name : str
        The material's name.
    thickness_nm : float
        Film thickness, nm.
    film, substrate : str
        Table names.
    film_index_scale : float
        The process's factor on the film's real index.
    roughness : float
        The renderers' roughness (√α of GGX).
    images : list of dict, optional
        The schema's ``images`` entries (:func:`image_entries`: swatch's renders of it, described by
        :data:`PICTURE_TEXT`); None: left out (the document then misses a property the schema requires).
    note : str, optional
        Appended to the description (what it was made from).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread (the stated ΔE2000 is against the colour with it); None: uniform.

    Returns
    -------
    dict
        The material (JSON types only).
    """
    color, n, k = metal_color_and_ior(substrate)
    eta = film_index(film, film_index_scale)
    dE = physical_values_delta_E_00(thickness_nm, film, substrate, film_index_scale, roughness, spread)
    metal = metal_name(substrate)
    anatase = ", not anatase's 2.488" if load_material(film).formula == "TiO2" else ""  # (the database's titanium)
    text = (f"Anodised {metal}, oxide {thickness_nm:g} nm, written by swatch (anodic-swatch). thinFilmIor {eta:g}: "
            f"{film} at {INDEX_WAVELENGTH_NM:g} nm (x{film_index_scale:g}), the index of swatch's model"
            f"{anatase}. color, complexIor: bare {substrate}. Physical values: as an OpenPBR thin film "
            f"in MaterialX 1.39.5 they show ΔE2000 up to {dE:.1f} (mirror 0-60°, D65, 2°); for the colour use "
            "swatch's fitted .mtlx preset." + (PICTURE_TEXT if images else "") + note)
    entry = {"name": name, "color": [{"colorSpace": "srgb-linear", "color": color}], "metalness": 1,
             "roughness": round(float(roughness), 4),
             "complexIor": [{"colorSpace": "srgb-linear", "n": n, "k": k}],
             "thinFilmThickness": [round(float(thickness_nm), 3)], "thinFilmIor": eta, "category": ["Metal"],
             "group": f"{metal.capitalize()} (Anodized)", "description": text[:500],
             "tags": [f"anodised {metal}", "swatch"],
             "references": [{"title": "Physically Based API (v2)", "author": "Palmqvist, A.",
                             "url": "https://github.com/AntonPalmqvist/physically-based-api"},
                            _reference(load_material(film)), _reference(load_material(substrate))]}
    if images:
        entry["images"] = images
    return entry


def document_bytes(materials: list[dict]) -> bytes:
    """The JSON document of ``materials`` (``$schema``, ``header``, ``data``).

    Parameters
    ----------
    materials : list of dict
        :func:`material_entry` results.

    Returns
    -------
    bytes
        UTF-8 JSON, byte-identical for the same materials.
    """
    doc = {"$schema": SCHEMA_URL, "header": HEADER, "data": materials}
    return (json.dumps(doc, indent=1, ensure_ascii=False) + "\n").encode("utf-8")


def image_entries(names: dict[int, str], base_url: str | None = None) -> list[dict]:
    """The schema's ``images`` for pictures named ``names``: relative references, or URLs under ``base_url``.

    Parameters
    ----------
    names : dict
        Picture side in pixels (each of :data:`IMAGE_SIZES_PX`) -> the file's name, beside the document.
    base_url : str, optional
        The address the document's folder is served from (checked by :func:`swatch.presets.naming.check_base_url`); None: the
        names as relative references.

    Returns
    -------
    list of dict
        One entry: ``format`` (:data:`IMAGE_FORMAT`) and ``"300"``, ``"600"``.
    """
    base = None if base_url is None else check_base_url(base_url)
    entry: dict = {"format": IMAGE_FORMAT}
    for size in IMAGE_SIZES_PX:
        entry[str(size)] = names[size] if base is None else f"{base}/{names[size]}"
    return [entry]
