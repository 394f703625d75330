"""A mesh file's bytes checked before a reader builds anything from them (untrusted input).

Functions
---------
* :func:`check_mesh_bytes`: what :func:`swatch.render.mesh.load_mesh` asks of a file before trimesh reads it:
  UTF-8 text where the format is text; a glTF (``.gltf``, ``.glb``) with at most
  :data:`swatch.core.limits.MAX_MESH_JSON_ITEMS` objects and lists in its JSON (counted before it is parsed),
  self-contained (every ``uri`` an embedded ``data:`` one), without a required extension that changes the
  geometry, its buffers, buffer views and accessors consistent, no sparse accessor in its geometry (trimesh
  reads the base values and drops the substitution), its nodes trees (no cycle, one parent at most)
  within :data:`swatch.core.limits.MAX_MESH_NODES` and :data:`swatch.core.limits.MAX_MESH_NODE_DEPTH`, and
  the triangles and vertices its nodes place (each node instancing its mesh) within
  :data:`swatch.core.limits.MAX_MESH_TRIANGLES` and :data:`swatch.core.limits.MAX_MESH_VERTICES`, counted
  from the accessors' counts before anything is built (trimesh flattens the scene, a copy of the mesh per
  node: a 1 MB file of 20 000 nodes instancing one 5 000-triangle mesh reached 5–8 GB); a PLY's header
  counts within the same caps.
* :func:`is_binary_stl`: whether bytes are a binary STL (84 bytes + 50 a triangle).

References
----------
* The Khronos Group, "glTF 2.0 Specification" (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html):
  accessors (sparse accessors), buffer views, the node hierarchy ("a set of disjoint strict trees").
* P. Bourke, "PLY - Polygon File Format" (https://paulbourke.net/dataformats/ply/): the header's ``element``
  lines.
"""
from __future__ import annotations

import json
import re
import struct
from typing import TypeGuard

from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_HEADER_COUNT_CHARS,
    MAX_MESH_BYTES,
    MAX_MESH_JSON_ITEMS,
    MAX_MESH_NODE_DEPTH,
    MAX_MESH_NODES,
    MAX_MESH_TRIANGLES,
    MAX_MESH_VERTICES,
)

__all__ = ["check_mesh_bytes", "is_binary_stl"]

#: Required glTF extensions that change only materials or textures (not read: the surface is the film).
_HARMLESS_EXTENSION = ("KHR_materials_", "KHR_texture_transform")
#: Bytes of an accessor's component (its ``componentType``) and components of an element (its ``type``).
_COMPONENT_BYTES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
_TYPE_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
#: A primitive's ``mode``: triangles (three indices each), a strip and a fan (one a vertex after the second).
_TRIANGLES, _STRIPS = 4, (5, 6)


def check_mesh_bytes(data: bytes, fmt: str, source: str) -> bytes:
    """Check a mesh file's bytes before a reader sees them (see the module documentation).

    Parameters
    ----------
    data : bytes
        The file's content (at most :data:`swatch.core.limits.MAX_MESH_BYTES`).
    fmt : str
        Its format, one of :data:`swatch.core.choices.MESH_FORMATS` (``obj``, ``ply``, ``stl``, ``glb``, ``gltf``).
    source : str
        The file's name, for the messages.

    Returns
    -------
    bytes
        ``data`` for the reader: a text file's UTF-8 byte-order mark removed.

    Raises
    ------
    swatch.core.errors.SwatchError
        One line naming the file, what was wrong and what is allowed.
    """
    if fmt == "gltf":
        _check_gltf(data, source)
    elif fmt == "glb":
        _check_glb(data, source)
    data = _as_utf8_text(data, fmt, source)
    if fmt == "ply":
        _check_ply_header(data, source)
    return data


def is_binary_stl(data: bytes) -> bool:
    """Whether ``data`` is a binary STL: 84 bytes (an 80-byte header and the triangle count) and 50 a triangle.

    Parameters
    ----------
    data : bytes
        An STL file's content.

    Returns
    -------
    bool
        True when its length is exactly what its triangle count says.
    """
    return len(data) >= 84 and len(data) == 84 + 50 * struct.unpack_from("<I", data, 80)[0]


def _as_utf8_text(data: bytes, fmt: str, source: str) -> bytes:
    """The text of an OBJ, ASCII STL, ASCII PLY header or glTF, checked to be UTF-8 (a byte-order mark
    removed): trimesh would guess another encoding with charset_normalizer (not installed: an
    ImportError) and parse what it guessed."""
    if fmt in ("glb", "ply") or (fmt == "stl" and is_binary_stl(data)):
        head = data.split(b"end_header", 1)[0] if fmt == "ply" and b"end_header" in data[:65536] else b""
        text, what = head, "PLY header"
    else:
        text, what = data, f"{fmt.upper()} file"
    try:
        text.decode("utf-8")
    except UnicodeDecodeError as exc:
        allowed = ("an STL file is binary (84 bytes + 50 a triangle) or ASCII/UTF-8 text" if fmt == "stl" else
                   f"{'an' if what[0] in 'AEFHILMNORSX' else 'a'} {what} is ASCII or UTF-8 text")
        raise SwatchError(f"{source}: not UTF-8 text (byte 0x{text[exc.start]:02x} at offset {exc.start}); "
                          f"{allowed}") from None
    return data[3:] if data.startswith(b"\xef\xbb\xbf") and text is data else data


def _check_ply_header(data: bytes, source: str) -> None:
    """A PLY's ``element vertex N`` and ``element face N`` within the caps (each face is a triangle at least),
    read from its header before the reader allocates for them."""
    head = data.split(b"end_header", 1)[0] if b"end_header" in data[:65536] else b""
    for line in head.decode("utf-8", "replace").splitlines():  # (any bytes: a count not of ASCII digits is refused)
        words = line.split()
        if len(words) != 3 or words[0] != "element" or words[1] not in ("vertex", "face"):
            continue
        cap, what = (MAX_MESH_VERTICES, "vertices") if words[1] == "vertex" else (MAX_MESH_TRIANGLES, "faces")
        if len(words[2]) > MAX_HEADER_COUNT_CHARS or re.fullmatch(r"[0-9]+", words[2]) is None:  # (str.isdigit
            # takes '²' and int() refuses it; int() also refuses over 4 300 digits)
            raise SwatchError(f"{source}: the PLY header's element {words[1]} count {words[2][:40]!r} is not a "
                              f"whole number of at most {MAX_HEADER_COUNT_CHARS} digits")
        if int(words[2]) > cap:
            raise SwatchError(f"{source}: the PLY header declares {int(words[2])} {what}; a mesh may have at most "
                              f"{cap} {'vertices' if what == 'vertices' else 'triangles'}")


def _uris(node, found: list[str]) -> list[str]:
    """Every ``uri`` string anywhere in a glTF JSON tree (buffers, images, and any extension's)."""
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            for key, value in item.items():
                if key == "uri" and isinstance(value, str):
                    found.append(value)
                else:
                    stack.append(value)
        elif isinstance(item, list):
            stack.extend(item)
    return found


def _data_uri_bytes(uri: str) -> int:
    """Decoded size of a ``data:`` URI, bytes."""
    head, _, payload = uri.partition(",")
    return len(payload) * 3 // 4 - payload[-2:].count("=") if head.endswith(";base64") else len(payload)


def _check_glb(data: bytes, source: str) -> None:
    """The JSON chunk of a .glb is checked as a .gltf's (its BIN chunk, if any, holds buffer 0's bytes)."""
    if len(data) < 20 or data[:4] != b"glTF":
        raise SwatchError(f"{source}: not a binary glTF (.glb) file")
    length, kind = struct.unpack_from("<II", data, 12)
    if kind != 0x4E4F534A or 20 + length > len(data):
        raise SwatchError(f"{source}: not a binary glTF (.glb) file")
    end = 20 + length
    bin_bytes = struct.unpack_from("<I", data, end)[0] if end + 8 <= len(data) else 0
    _check_gltf(data[20:end], source, min(bin_bytes, max(len(data) - end - 8, 0)))


def _list(doc: dict, key: str, source: str) -> list:
    """``doc[key]``, a JSON array (an empty one when absent)."""
    value = doc.get(key, [])
    if not isinstance(value, list):
        raise SwatchError(f"{source}: the glTF's {key!r} is not a list; the file is inconsistent")
    return value


def _index(value, size: int) -> TypeGuard[int]:
    """Whether ``value`` is an index into a list of ``size`` items (a JSON integer, not a boolean)."""
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value < size


def _check_gltf(data: bytes, source: str, bin_bytes: int = 0) -> None:
    """A glTF's JSON, checked before the reader sees it (the module documentation): the references in it, its
    buffers' and buffer views' sizes, its accessors, its node trees and what they place."""
    items = data.count(b"{") + data.count(b"[")  # (neither is in base64: an embedded buffer has none)
    if items > MAX_MESH_JSON_ITEMS:
        raise SwatchError(f"{source}: its JSON holds {items} objects and lists; a glTF's JSON may hold at most "
                          f"{MAX_MESH_JSON_ITEMS}")
    try:
        doc = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        raise SwatchError(f"{source}: not a glTF JSON document") from None
    if not isinstance(doc, dict):
        raise SwatchError(f"{source}: not a glTF JSON document")
    for uri in _uris(doc, []):
        if not uri.startswith("data:"):
            raise SwatchError(f"{source}: refers to the external file {uri[:80]!r}; give a .glb or a .gltf "
                              "with embedded (data:) buffers")
    required = doc.get("extensionsRequired", [])
    for ext in required if isinstance(required, list) else [required]:
        if not (isinstance(ext, str) and ext.startswith(_HARMLESS_EXTENSION)):
            raise SwatchError(f"{source}: requires the glTF extension {str(ext)[:60]!r}, which swatch does not read "
                              "(compressed geometry: Draco, meshopt); export the mesh without it")
    sizes: list[int] = []
    for k, buf in enumerate(_list(doc, "buffers", source)):
        size = buf.get("byteLength") if isinstance(buf, dict) else None
        buf_uri = buf.get("uri") if isinstance(buf, dict) else None
        held = _data_uri_bytes(buf_uri) if isinstance(buf_uri, str) else (bin_bytes if k == 0 else 0)
        if not (isinstance(size, int) and 0 <= size <= min(MAX_MESH_BYTES, held)):
            raise SwatchError(f"{source}: buffer {k} claims {size!r} bytes but holds {held}; a buffer's "
                              f"byteLength is at most what it holds (and at most {MAX_MESH_BYTES} bytes)")
        sizes.append(size)
    views: list[tuple[int, int]] = []  # (byteLength, byteStride or 0)
    for k, view in enumerate(_list(doc, "bufferViews", source)):
        b, off, length, stride = ((view.get("buffer"), view.get("byteOffset", 0), view.get("byteLength"),
                                   view.get("byteStride", 0)) if isinstance(view, dict) else (None,) * 4)
        if not (_index(b, len(sizes)) and isinstance(off, int) and isinstance(length, int) and off >= 0
                and length >= 0 and off + length <= sizes[b] and isinstance(stride, int) and stride >= 0):
            raise SwatchError(f"{source}: bufferView {k} lies outside its buffer; the file is inconsistent")
        views.append((length, stride))
    counts = _check_accessors(doc, views, source)
    _check_placed(doc, counts, source)


def _check_accessors(doc: dict, views: list[tuple[int, int]], source: str) -> list[int]:
    """Each accessor's elements inside its buffer view, and all of them together within the file cap (the reader
    makes an array of each, a copy where the view is strided, zeros where it has no view): their counts."""
    counts: list[int] = []
    total = 0
    for k, acc in enumerate(_list(doc, "accessors", source)):
        count, component, kind, view, offset = ((acc.get("count"), acc.get("componentType"), acc.get("type"),
                                                 acc.get("bufferView"), acc.get("byteOffset", 0))
                                                if isinstance(acc, dict) else (None,) * 5)
        if not (isinstance(count, int) and count >= 0 and component in _COMPONENT_BYTES
                and kind in _TYPE_COMPONENTS and isinstance(offset, int) and offset >= 0):
            raise SwatchError(f"{source}: accessor {k} has no valid count, componentType or type; the file is "
                              "inconsistent")
        element = _COMPONENT_BYTES[component] * _TYPE_COMPONENTS[kind]
        if view is not None:
            if not _index(view, len(views)):
                raise SwatchError(f"{source}: accessor {k} refers to bufferView {str(view)[:20]}, which does not "
                                  "exist; the file is inconsistent")
            length, stride = views[view]
            if count and offset + (count - 1) * (stride or element) + element > length:
                raise SwatchError(f"{source}: accessor {k} ({count} elements) reads past its bufferView; the file "
                                  "is inconsistent")
        total += count * element
        counts.append(count)
    if total > MAX_MESH_BYTES:
        raise SwatchError(f"{source}: its accessors hold {total} bytes together; a glTF's accessors may hold at most "
                          f"{MAX_MESH_BYTES} bytes (the file cap)")
    return counts


def _mesh_sizes(doc: dict, counts: list[int], source: str) -> list[tuple[int, int, int]]:
    """(triangles, vertices, primitives) of each of the glTF's meshes, from its accessors' counts; a sparse
    accessor in a primitive (its attributes: positions, normals, …; its indices) is refused."""
    accessors = doc.get("accessors", [])
    sizes = []
    for m, mesh in enumerate(_list(doc, "meshes", source)):
        prims = mesh.get("primitives") if isinstance(mesh, dict) else None
        if not isinstance(prims, list):
            raise SwatchError(f"{source}: mesh {m} has no list of primitives; the file is inconsistent")
        triangles = vertices = 0
        for p in prims:
            attrs = p.get("attributes") if isinstance(p, dict) else None
            if not isinstance(attrs, dict):
                raise SwatchError(f"{source}: a primitive of mesh {m} has no attributes; the file is inconsistent")
            used = {**attrs, **({"indices": p["indices"]} if "indices" in p else {})}
            for name, a in used.items():
                if not _index(a, len(counts)):
                    raise SwatchError(f"{source}: mesh {m}'s {str(name)[:40]} refers to accessor {str(a)[:20]}, "
                                      "which does not exist; the file is inconsistent")
                if "sparse" in accessors[a]:
                    raise SwatchError(f"{source}: mesh {m}'s {str(name)[:40]} is sparse accessor {a}; sparse "
                                      "accessors are not supported (export the mesh without them)")
            corners = counts[attrs["POSITION"]] if "POSITION" in attrs else 0
            drawn = counts[p["indices"]] if "indices" in p else corners
            mode = p.get("mode", _TRIANGLES)
            triangles += drawn // 3 if mode == _TRIANGLES else max(drawn - 2, 0) if mode in _STRIPS else 0
            vertices += corners
        sizes.append((triangles, vertices, len(prims)))
    return sizes


def _check_placed(doc: dict, counts: list[int], source: str) -> None:
    """The node hierarchy trees (one parent at most, no cycle) within the node and depth caps, and what the nodes
    place (each node an instance of its mesh; a mesh no node places counted once, as the reader makes it) within
    the triangle and vertex caps; the scene graph's frames (nodes, and each placed mesh's primitives) within the
    node cap."""
    nodes = _list(doc, "nodes", source)
    meshes = _mesh_sizes(doc, counts, source)
    if len(nodes) > MAX_MESH_NODES:
        raise SwatchError(f"{source}: {len(nodes)} nodes; a glTF may have at most {MAX_MESH_NODES}")
    parent = [-1] * len(nodes)
    instances = [0] * len(meshes)
    for k, node in enumerate(nodes):
        children = node.get("children", []) if isinstance(node, dict) else None
        if not isinstance(children, list) or ("mesh" in node and not _index(node["mesh"], len(meshes))):
            raise SwatchError(f"{source}: node {k} has no valid children or mesh; the file is inconsistent")
        if "mesh" in node:
            instances[node["mesh"]] += 1
        for c in children:
            if not _index(c, len(nodes)):
                raise SwatchError(f"{source}: node {k} has child {str(c)[:20]}, which does not exist; the file is "
                                  "inconsistent")
            if parent[c] >= 0 or c == k:
                raise SwatchError(f"{source}: node {c} has two parents or is its own child; a glTF's nodes form "
                                  "trees (one parent at most, no cycle)")
            parent[c] = k
    depth = [0] * len(nodes)
    stack = [k for k in range(len(nodes)) if parent[k] < 0]
    reached = len(stack)
    while stack:
        k = stack.pop()
        for c in nodes[k].get("children", []):
            depth[c] = depth[k] + 1
            if depth[c] >= MAX_MESH_NODE_DEPTH:
                raise SwatchError(f"{source}: node {c} is {depth[c] + 1} nodes deep; a glTF's node trees may be "
                                  f"at most {MAX_MESH_NODE_DEPTH} deep")
            reached += 1
            stack.append(c)
    if reached < len(nodes):
        cycle = next(k for k in range(len(nodes)) if parent[k] >= 0 and depth[k] == 0)
        for _ in range(len(nodes)):  # up its parents: after as many steps as nodes, a node on the cycle
            cycle = parent[cycle]
        raise SwatchError(f"{source}: node {cycle} is its own ancestor (a cycle); a glTF's nodes form trees")
    # the scene graph's frames: a node each, and each primitive of a mesh with several for each node placing
    # it; and the trimesh meshes of a mesh no node places (read all the same)
    frames = len(nodes) + sum(prims if n == 0 else n * prims if prims > 1 else 0
                              for n, (_, _, prims) in zip(instances, meshes, strict=True))
    placed = [max(n, 1) for n in instances]
    triangles = sum(n * size[0] for n, size in zip(placed, meshes, strict=True))
    vertices = sum(n * size[1] for n, size in zip(placed, meshes, strict=True))
    if frames > MAX_MESH_NODES:
        raise SwatchError(f"{source}: {frames} nodes and primitives (a node each, and each primitive of a mesh "
                          f"with several, for each node placing it); a glTF may have at most {MAX_MESH_NODES}")
    if triangles > MAX_MESH_TRIANGLES:
        raise SwatchError(f"{source}: its nodes place {triangles} triangles (each node a copy of its mesh); a mesh "
                          f"may have at most {MAX_MESH_TRIANGLES}")
    if vertices > MAX_MESH_VERTICES:
        raise SwatchError(f"{source}: its nodes place {vertices} vertices (each node a copy of its mesh); a mesh "
                          f"may have at most {MAX_MESH_VERTICES}")
