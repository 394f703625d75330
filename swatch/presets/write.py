"""Write fitted presets: glTF 2.0 (.gltf), Blender (a .py script) and MaterialX/OpenPBR (.mtlx).

Each writer returns the file's bytes, deterministic for given inputs (no timestamps; numbers
rounded to fixed digits). ``params`` is one row of :class:`swatch.presets.fit.PresetFit`:
(model thickness in nm, film IOR, base colour linear Rec.709 R, G, B).

- glTF: a 10 cm square plate (two triangles, normals +Y, y-up) with its buffer embedded as a
  base64 data URI, and one material: ``baseColorFactor`` = base colour, ``metallicFactor`` 1,
  ``roughnessFactor`` = the catalog roughness, ``KHR_materials_iridescence`` with
  ``iridescenceFactor`` 1, ``iridescenceIor``, ``iridescenceThicknessMaximum`` = the fitted
  thickness and no thickness texture (so the thickness is the maximum), listed in ``extensionsUsed``.
- Blender: a script for Blender ≥ 5.0 (Principled BSDF with Thin Film inputs and the GGX
  distribution it was fitted for; 4.2–4.5 ignore the thin film on a metal, so the script refuses them). Run it from the Text Editor or ``blender
  --python FILE``: it creates (or updates) the material and assigns it to the selected mesh
  objects (tests/presets_blender/mirror.py runs it in real Blender).
- MaterialX: a 1.39 document with an ``open_pbr_surface`` (base_metalness 1, base_color,
  specular_roughness, thin_film_weight 1, thin_film_thickness in µm, thin_film_ior), built and
  validated with the MaterialX library against its standard data libraries.
"""
from __future__ import annotations

import base64
import functools
import json

import MaterialX as mx
import numpy as np

from swatch.core.errors import SwatchError

__all__ = ["gltf_bytes", "gltf_material", "blender_bytes", "materialx_bytes", "PLATE_SIZE_M"]

PLATE_SIZE_M = 0.1


def _r(x, nd=6) -> float:
    return round(float(x), nd)


def _plate_buffer(tangents: bool = False) -> tuple[bytes, list, list]:
    h = PLATE_SIZE_M / 2.0
    pos = np.array([[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]], dtype="<f4")
    nrm = np.tile(np.array([0, 1, 0], dtype="<f4"), (4, 1))
    idx = np.array([0, 2, 1, 0, 3, 2], dtype="<u2")  # counter-clockwise seen from +Y
    blob = pos.tobytes() + nrm.tobytes() + idx.tobytes()
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
        {"buffer": 0, "byteOffset": 48, "byteLength": 48, "target": 34962},
        {"buffer": 0, "byteOffset": 96, "byteLength": 12, "target": 34963},
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [_r(v) for v in pos.min(axis=0)], "max": [_r(v) for v in pos.max(axis=0)]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]
    if tangents:  # +x with handedness +1: the brushing direction of an anisotropic finish
        tan = np.tile(np.array([1, 0, 0, 1], dtype="<f4"), (4, 1))
        blob += b"\0" * (-len(blob) % 4)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": 64, "target": 34962})
        accessors.append({"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC4"})
        blob += tan.tobytes()
    return blob + b"\0" * (-len(blob) % 4), views, accessors


def _check(params, roughness) -> tuple[float, float, list[float], float]:
    p = np.asarray(params, dtype=np.float64)
    if p.shape != (5,) or not np.all(np.isfinite(p)):
        raise SwatchError("a preset needs 5 finite parameters (thickness, film IOR, base R, G, B)")
    r = float(roughness)
    if not 0.0 <= r <= 1.0:
        raise SwatchError(f"roughness must be within 0..1 (got {r})")
    return float(p[0]), float(p[1]), [float(v) for v in np.clip(p[2:], 0.0, 1.0)], r


def gltf_material(name: str, params, roughness: float, extras: dict | None = None) -> dict:
    """The glTF material of a preset: the metal (``baseColorFactor``, ``metallicFactor`` 1,
    ``roughnessFactor``) with ``KHR_materials_iridescence`` (factor 1, IOR, thickness maximum).

    Parameters
    ----------
    name : str
        The material's name.
    params : array_like, shape (5,)
        ``(thickness_nm, film_ior, base R, G, B)`` (base linear Rec.709).
    roughness : float
        ``roughnessFactor``.
    extras : dict, optional
        The material's ``extras`` (what it was fitted to).

    Returns
    -------
    dict
        The ``materials`` entry (numbers rounded as written).
    """
    d, eta, base, rough = _check(params, roughness)
    material: dict = {
        "name": name,
        "pbrMetallicRoughness": {"baseColorFactor": [_r(v) for v in base] + [1.0], "metallicFactor": 1.0,
                                 "roughnessFactor": _r(rough)},
        "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": _r(eta),
                                                     "iridescenceThicknessMaximum": _r(d, 3)}},
    }
    if extras:
        material["extras"] = extras
    return material


def gltf_bytes(name: str, params, roughness: float, extras: dict | None = None, anisotropy: dict | None = None) -> bytes:
    """A .gltf (JSON, embedded buffer) with a plate carrying the iridescent metal material;
    ``anisotropy``: a ``KHR_materials_anisotropy`` object (brushed finishes; the plate then has
    tangents along +x, the brushing direction).

    Parameters
    ----------
    name : str
        The material's name.
    params : array_like, shape (5,)
        ``(thickness_nm, film_ior, base R, G, B)``.
    roughness : float
        ``roughnessFactor``.
    extras : dict, optional
        The material's ``extras`` (what it was fitted to).
    anisotropy : dict, optional
        The ``KHR_materials_anisotropy`` object of a brushed finish
        (:func:`swatch.presets.anisotropy.gltf_anisotropy`); None: isotropic, no tangents.

    Returns
    -------
    bytes
        UTF-8 JSON (deterministic).
    """
    blob, views, accessors = _plate_buffer(tangents=anisotropy is not None)
    material = gltf_material(name, params, roughness, extras)
    extensions = material["extensions"]
    used = ["KHR_materials_iridescence"]
    attributes = {"POSITION": 0, "NORMAL": 1}
    if anisotropy is not None:
        extensions["KHR_materials_anisotropy"] = dict(anisotropy)
        used.append("KHR_materials_anisotropy")
        attributes["TANGENT"] = 3
    doc = {
        "asset": {"version": "2.0", "generator": "swatch (anodic-swatch) preset"},
        "extensionsUsed": used,
        "scene": 0,
        "scenes": [{"name": name, "nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{"name": "plate", "primitives": [{"attributes": attributes,
                                                      "indices": 2, "material": 0}]}],
        "materials": [material],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode("ascii")}],
    }
    return (json.dumps(doc, indent=1, ensure_ascii=False) + "\n").encode("utf-8")


_BLENDER = '''# Blender >= 5.0 (Cycles) material preset written by swatch (anodic-swatch): {title}
# Run in Blender's Text Editor (Run Script) or:  blender --python {file}
# Creates or updates material {name!r} (Principled BSDF, metallic, thin film) and assigns it to
# the selected mesh objects. Fitted to Cycles' thin film on a metal against the exact colour: {note}
import bpy

# Blender 4.2-4.5 ignore Thin Film on a metallic Principled BSDF: there the material would render
# as its bare Base Color, a different colour. Refuse rather than mislead. Checked in Blender 5.0
# and 5.2 (bpy 5.0.1 and 5.2.3).
if bpy.app.version < (5, 0, 0):
    raise RuntimeError("this swatch preset needs Blender 5.0 or later (Blender "
                       + bpy.app.version_string + " ignores Thin Film on metals)")

NAME = {name!r}
INPUTS = {{
    "Base Color": ({r}, {g}, {b}, 1.0),  # linear Rec.709 (scene linear)
    "Metallic": 1.0,
    "Roughness": {rough},
    "Thin Film Thickness": {d},  # nm
    "Thin Film IOR": {eta},{aniso}
}}

mat = bpy.data.materials.get(NAME) or bpy.data.materials.new(NAME)  # with a Principled BSDF node
bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
# The fit assumes single-scatter GGX. Blender's default, Multiscatter GGX, adds the energy of
# inter-reflections between microfacets and renders these colours up to ~2 L* off at this roughness.
bsdf.distribution = "GGX"
for key, value in INPUTS.items():
    bsdf.inputs[key].default_value = value
for obj in bpy.context.selected_objects:
    if obj.type == "MESH":
        if obj.data.materials:
            obj.data.materials[0] = mat
        else:
            obj.data.materials.append(mat)
'''


def blender_bytes(name: str, params, roughness: float, file_name: str, note: str = "",
                  anisotropy: dict | None = None) -> bytes:
    """A Blender Python script that builds the Principled BSDF material (``anisotropy``: the
    Principled inputs ``Anisotropic`` and ``Anisotropic Rotation`` of a brushed finish).

    Parameters
    ----------
    name : str
        The material's name.
    params : array_like, shape (5,)
        ``(thickness_nm, film_ior, base R, G, B)`` (base linear Rec.709, 0–1).
    roughness : float
        The Principled BSDF ``Roughness`` (0–1).
    file_name : str
        The script's own file name (for its usage line).
    note : str, optional
        What the preset was fitted to, written in the script's header comment (default: ``see catalog.json``).
    anisotropy : dict, optional
        The Principled inputs ``Anisotropic`` and ``Anisotropic Rotation`` of a brushed finish
        (:func:`swatch.presets.anisotropy.blender_anisotropy`); None: isotropic.

    Returns
    -------
    bytes
        UTF-8 Python (for ``blender --python``).
    """
    d, eta, base, rough = _check(params, roughness)
    aniso = "".join(f"\n    {k!r}: {_r(v)},  # brushed finish: swatch.presets.anisotropy" for k, v in
                    (anisotropy or {}).items())
    text = _BLENDER.format(title=name, file=file_name, name=name, note=note or "see catalog.json",
                           r=_r(base[0]), g=_r(base[1]), b=_r(base[2]), rough=_r(rough), d=_r(d, 3), eta=_r(eta),
                           aniso=aniso)
    return text.encode("utf-8")


@functools.lru_cache(maxsize=1)
def _materialx_library():
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    return lib


def materialx_bytes(name: str, params, roughness: float, note: str = "", anisotropy: dict | None = None) -> bytes:
    """A MaterialX 1.39 document with an OpenPBR surface, validated with the MaterialX library
    (``note``: what it was fitted to and its error, in the material's doc string; ``anisotropy``:
    ``specular_roughness_anisotropy`` of a brushed finish, the geometry tangent then the mesh's
    bitangent, across the grain).

    Parameters
    ----------
    name : str
        The material's name (made a valid MaterialX name).
    params : array_like, shape (5,)
        ``(thickness_nm, film_ior, base R, G, B)`` (base linear Rec.709, 0–1); written as ``thin_film_thickness`` in µm.
    roughness : float
        ``specular_roughness``.
    note : str, optional
        What the preset was fitted to and its error, written as the material's doc string.
    anisotropy : dict, optional
        ``{"specular_roughness_anisotropy": ...}`` of a brushed finish
        (:func:`swatch.presets.anisotropy.openpbr_anisotropy`); None: isotropic.

    Returns
    -------
    bytes
        UTF-8 XML.
    """

    d, eta, base, rough = _check(params, roughness)
    ident = mx.createValidName(name)
    doc = mx.createDocument()
    doc.setColorSpace("lin_rec709")
    shader = doc.addNode("open_pbr_surface", f"{ident}_surface", "surfaceshader")
    shader.setInputValue("base_color", mx.Color3(*[_r(v) for v in base]), "color3")
    shader.setInputValue("base_metalness", 1.0, "float")
    shader.setInputValue("specular_roughness", _r(rough), "float")
    shader.setInputValue("thin_film_weight", 1.0, "float")
    shader.setInputValue("thin_film_thickness", _r(d / 1000.0, 6), "float")  # µm
    shader.setInputValue("thin_film_ior", _r(eta), "float")
    if anisotropy is not None:
        shader.setInputValue("specular_roughness_anisotropy", _r(anisotropy["specular_roughness_anisotropy"]), "float")
        across = doc.addNode("bitangent", f"{ident}_across_grain", "vector3")
        shader.addInput("geometry_tangent", "vector3").setConnectedNode(across)
    material = doc.addMaterialNode(ident, shader)
    material.setDocString(f"swatch preset {name}" + (f"; {note}" if note else ""))
    doc.setDataLibrary(_materialx_library())  # referenced for validation, not written
    ok, message = doc.validate()
    if not ok:  # our own document failed the library's validation: a bug, not bad input
        raise RuntimeError(f"MaterialX validation failed: {message}")
    return mx.writeToXmlString(doc).encode("utf-8")
