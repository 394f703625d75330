"""The ``<model-viewer>`` files of a catalog: one shared part (a binary buffer) and a small glTF per swatch.

A viewer file is glTF 2.0 JSON whose one buffer is the shared part, ``viewer_part.bin`` next to it (so a
catalog carries the geometry once): the catalog's part (``[render] mesh``: its triangles and shading
normals, scaled to fit a sphere of :data:`PART_DIAMETER_M`) or else a sphere of that diameter; one
material, the preset's (:func:`swatch.presets.write.gltf_material`). glTF is y-up, in metres: AR shows
the part at that size.
"""
from __future__ import annotations

import json

import numpy as np

from swatch.presets.write import gltf_material

__all__ = ["PART_DIAMETER_M", "PART_BIN", "sphere_part", "mesh_part", "part_bin", "viewer_gltf_bytes"]

#: The viewer part's diameter (a mesh: its bounding sphere's), metres.
PART_DIAMETER_M = 0.1
#: The shared buffer's file name (next to the viewer files).
PART_BIN = "viewer_part.bin"
_RINGS, _SEGMENTS = 32, 64


def sphere_part(diameter_m: float = PART_DIAMETER_M) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A UV sphere (:data:`_RINGS` × :data:`_SEGMENTS` quads) centred on the origin.

    Parameters
    ----------
    diameter_m : float
        Its diameter, metres.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Positions (V, 3) and unit normals (V, 3), float32; triangle indices (T, 3), counter-clockwise from outside.
    """
    theta = np.linspace(0.0, np.pi, _RINGS + 1)[:, None]
    phi = np.linspace(0.0, 2.0 * np.pi, _SEGMENTS + 1)[None, :]
    n = np.stack(np.broadcast_arrays(np.sin(theta) * np.sin(phi), np.cos(theta), np.sin(theta) * np.cos(phi)), -1)
    n = n.reshape(-1, 3)
    i = np.arange(_RINGS)[:, None] * (_SEGMENTS + 1) + np.arange(_SEGMENTS)[None, :]
    a, b, c, d = i, i + _SEGMENTS + 1, i + _SEGMENTS + 2, i + 1
    tris = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return (n * (diameter_m / 2.0)).astype(np.float32), n.astype(np.float32), tris.astype(np.uint32)


def mesh_part(corners, normals, diameter_m: float = PART_DIAMETER_M) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A triangle soup (the catalog's part, placed in the unit sphere) scaled to ``diameter_m``.

    Parameters
    ----------
    corners, normals : array_like, shape (F, 3, 3)
        The triangles' corners (scene units, within the unit sphere) and shading normals
        (:meth:`swatch.render.mesh.MeshShape.triangle_soup`).
    diameter_m : float
        The diameter of the sphere the unit sphere becomes, metres.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Positions (3F, 3), unit normals (3F, 3), float32; indices (F, 3).
    """
    pos = np.asarray(corners, dtype=np.float64).reshape(-1, 3) * (diameter_m / 2.0)
    nrm = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    nrm = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-12)
    return pos.astype(np.float32), nrm.astype(np.float32), np.arange(pos.shape[0], dtype=np.uint32).reshape(-1, 3)


def part_bin(positions, normals, indices) -> tuple[bytes, dict]:
    """The shared buffer (positions, normals, indices; little-endian) and the glTF records describing it.

    Parameters
    ----------
    positions, normals : numpy.ndarray, shape (V, 3)
        float32 vertex positions (metres) and unit normals.
    indices : numpy.ndarray, shape (T, 3)
        Triangle vertex indices.

    Returns
    -------
    (bytes, dict)
        The buffer's bytes and ``{"accessors": …, "bufferViews": …, "byteLength": …}`` for the viewer files.
    """
    pos = np.ascontiguousarray(positions, dtype="<f4")
    nrm = np.ascontiguousarray(normals, dtype="<f4")
    idx = np.ascontiguousarray(indices, dtype="<u4").reshape(-1)
    blob = pos.tobytes() + nrm.tobytes() + idx.tobytes()
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": pos.nbytes, "target": 34962},
             {"buffer": 0, "byteOffset": pos.nbytes, "byteLength": nrm.nbytes, "target": 34962},
             {"buffer": 0, "byteOffset": pos.nbytes + nrm.nbytes, "byteLength": idx.nbytes, "target": 34963}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": int(pos.shape[0]), "type": "VEC3",
                  "min": [round(float(v), 6) for v in pos.min(axis=0)],
                  "max": [round(float(v), 6) for v in pos.max(axis=0)]},
                 {"bufferView": 1, "componentType": 5126, "count": int(nrm.shape[0]), "type": "VEC3"},
                 {"bufferView": 2, "componentType": 5125, "count": int(idx.size), "type": "SCALAR"}]
    return blob, {"accessors": accessors, "bufferViews": views, "byteLength": len(blob)}


def viewer_gltf_bytes(name: str, params, roughness: float, part: dict, extras: dict | None = None) -> bytes:
    """A swatch's viewer file: glTF JSON, the shared part (:data:`PART_BIN`) with the preset's material.

    Parameters
    ----------
    name : str
        The material's and node's name.
    params : array_like, shape (5,)
        ``(thickness_nm, film_ior, base R, G, B)``.
    roughness : float
        ``roughnessFactor``.
    part : dict
        The part's records (:func:`part_bin`).
    extras : dict, optional
        The material's ``extras`` (what it was fitted to).

    Returns
    -------
    bytes
        UTF-8 JSON (deterministic).
    """
    doc = {
        "asset": {"version": "2.0", "generator": "swatch (anodic-swatch) viewer preset"},
        "extensionsUsed": ["KHR_materials_iridescence"],
        "scene": 0,
        "scenes": [{"name": name, "nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{"name": "part", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                                     "material": 0}]}],
        "materials": [gltf_material(name, params, roughness, extras)],
        "accessors": part["accessors"],
        "bufferViews": part["bufferViews"],
        "buffers": [{"byteLength": part["byteLength"], "uri": PART_BIN}],
    }
    return (json.dumps(doc, indent=1, ensure_ascii=False) + "\n").encode("utf-8")
