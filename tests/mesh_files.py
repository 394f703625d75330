"""Hand-built glTF files for the mesh tests: a JSON document and its binary buffer, written as a .glb (a BIN
chunk) or a .gltf (the buffer embedded as a data: URI), so a test states every accessor, node and sparse
substitution it means instead of trusting an exporter."""
from __future__ import annotations

import base64
import json
import struct

import numpy as np
import trimesh

#: glTF componentType codes.
FLOAT, UINT32 = 5126, 5125


def gltf_doc(positions, indices, nodes=None, normals=None, blobs=()) -> tuple[dict, bytes]:
    """A one-mesh glTF: accessor 0 the positions (float32 VEC3, bufferView 0), 1 the indices (uint32, view 1),
    2 the normals (view 2) when given; ``blobs`` (bytes) are appended as the next buffer views (for sparse
    substitutions). ``nodes`` default to one node placing the mesh; the scene's roots are the nodes no other
    lists as a child. Returns the document and the buffer's bytes."""
    parts = [np.asarray(positions, np.float32).tobytes(), np.asarray(indices, np.uint32).tobytes()]
    if normals is not None:
        parts.append(np.asarray(normals, np.float32).tobytes())
    parts += list(blobs)
    views, payload = [], b""
    for blob in parts:
        views.append({"buffer": 0, "byteOffset": len(payload), "byteLength": len(blob)})
        payload += blob + b"\0" * (-len(blob) % 4)
    p = np.asarray(positions, np.float32).reshape(-1, 3)
    accessors = [{"bufferView": 0, "componentType": FLOAT, "count": len(p), "type": "VEC3",
                  "min": p.min(axis=0).tolist(), "max": p.max(axis=0).tolist()},
                 {"bufferView": 1, "componentType": UINT32, "count": int(np.asarray(indices).size), "type": "SCALAR"}]
    attributes = {"POSITION": 0}
    if normals is not None:
        accessors.append({"bufferView": 2, "componentType": FLOAT, "count": len(p), "type": "VEC3"})
        attributes["NORMAL"] = 2
    nodes = [{"mesh": 0}] if nodes is None else nodes
    children = {c for n in nodes for c in n.get("children", [])}
    doc = {"asset": {"version": "2.0"}, "scene": 0,
           "scenes": [{"nodes": [k for k in range(len(nodes)) if k not in children] or [0]}],
           "nodes": nodes, "meshes": [{"primitives": [{"attributes": attributes, "indices": 1}]}],
           "accessors": accessors, "bufferViews": views, "buffers": [{"byteLength": len(payload)}]}
    return doc, payload


def sparse(doc: dict, accessor: int, indices_view: int, values_view: int, count: int = 1) -> dict:
    """``doc`` with accessor ``accessor`` given a sparse substitution of ``count`` elements (uint32 indices in
    buffer view ``indices_view``, the new values in ``values_view``)."""
    doc["accessors"][accessor]["sparse"] = {"count": count,
                                            "indices": {"bufferView": indices_view, "componentType": UINT32},
                                            "values": {"bufferView": values_view}}
    return doc


def glb(doc: dict, payload: bytes) -> bytes:
    """A binary glTF: the JSON chunk (``doc``, its buffer 0 without a URI) and a BIN chunk of ``payload``."""
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    payload += b"\0" * (-len(payload) % 4)
    return (b"glTF" + struct.pack("<II", 2, 28 + len(js) + len(payload)) + struct.pack("<II", len(js), 0x4E4F534A)
            + js + struct.pack("<II", len(payload), 0x004E4942) + payload)


def gltf_text(doc: dict, payload: bytes) -> bytes:
    """A .gltf: ``doc`` with buffer 0 embedded as a base64 data: URI."""
    doc = json.loads(json.dumps(doc))
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(payload).decode()
    return json.dumps(doc).encode()


def obj_text(vertices, faces) -> bytes:
    """An OBJ of the vertices written exactly (``repr``: shortest round-trip) and 0-based ``faces``."""
    return ("".join(f"v {a!r} {b!r} {c!r}\n" for a, b, c in np.asarray(vertices, np.float64).tolist())
            + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in np.asarray(faces).tolist())).encode()


def ico_5000() -> tuple[np.ndarray, np.ndarray]:
    """A 5,000-triangle mesh (an icosphere's first 5,000 triangles, 2,562 vertices): float32 positions and
    flat uint32 indices."""
    ico = trimesh.creation.icosphere(subdivisions=4)
    return ico.vertices.astype(np.float32), ico.faces[:5000].astype(np.uint32).reshape(-1)


def instanced(n_nodes: int) -> bytes:
    """The issue's hostile part: ``n_nodes`` nodes side by side, each placing the one 5,000-triangle mesh."""
    v, f = ico_5000()
    return glb(*gltf_doc(v, f, nodes=[{"mesh": 0, "translation": [3.0 * k, 0, 0]} for k in range(n_nodes)]))
