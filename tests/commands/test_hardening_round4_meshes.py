"""Hardening round 4, meshes (issue 49 item 2), from the user's side: the CLI in one capped subprocess.

* A mesh smaller than MIN_MESH_EXTENT (1e-300 ended in an OverflowError, exit 70: OBJ, glTF, ``--engine mitsuba``).
* A glTF whose nodes instance one mesh many times (20 000 nodes × 5 000 triangles in 1 MB reached 5–8 GB: the
  triangle cap was checked after trimesh flattened the scene): the triangles and vertices the nodes place, the
  nodes, the node trees' depth, cycles and nodes with two parents, all from the JSON before anything is built,
  fast; a JSON of a million empty objects, refused before it is parsed; accessors past their buffer view or
  holding more than the file cap together; a PLY header's counts.
* Sparse accessors (silently ignored: a sparse substitution rendered as the mesh without it) in the positions,
  the normals or the indices.

Each: one line ``error: FILE: …``, exit 2, nothing written, under a 2.5 GB address-space cap; an instanced
glTF within the caps renders as the same triangles written out flat."""
from __future__ import annotations

import numpy as np
import OpenImageIO as oiio
import pytest

from swatch.core.limits import (
    MAX_MESH_BYTES,
    MAX_MESH_JSON_ITEMS,
    MAX_MESH_NODE_DEPTH,
    MAX_MESH_NODES,
    MAX_MESH_TRIANGLES,
    MIN_MESH_EXTENT,
)
from tests.cli_helpers import run_capped_batch
from tests.mesh_files import glb, gltf_doc, gltf_text, instanced, obj_text, sparse

CAP = 2 * 1024**3 + 512 * 1024**2
TRI = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
IDX = np.array([0, 1, 2], np.uint32)
LIMIT = f"a mesh is at least {MIN_MESH_EXTENT:.0e} across"
SPARSE = "sparse accessors are not supported"


def _nodes_glb(nodes: list[dict]) -> bytes:
    return glb(*gltf_doc(TRI, IDX, nodes=nodes))


def _sparse_cases() -> dict[str, tuple[bytes, str]]:
    """A valid sparse substitution of one element in the positions, the normals and the indices."""
    quad = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    one = np.uint32([2]).tobytes()
    blobs = (one, np.float32([1, 1, 0]).tobytes(), one, np.float32([0, 0, -1]).tobytes(), np.uint32([0]).tobytes(),
             np.uint32([3]).tobytes())
    cases = {}
    for name, (accessor, first_view) in {"positions": (0, 3), "normals": (2, 5), "indices": (1, 7)}.items():
        doc, payload = gltf_doc(quad, IDX, normals=normals, blobs=blobs)
        cases[f"sparse_{name}.glb"] = (glb(sparse(doc, accessor, first_view, first_view + 1), payload), SPARSE)
    return cases


def _accessor_cases() -> dict[str, tuple[bytes, str]]:
    doc, payload = gltf_doc(TRI, IDX)
    doc["accessors"][1]["count"] = 4000
    past = glb(doc, payload)
    block = np.zeros((100_000, 3), np.float32)  # one 1.2 MB view read by 60 accessors: 72 MB together
    doc, payload = gltf_doc(block, IDX)
    doc["accessors"] += [dict(doc["accessors"][0]) for _ in range(59)]
    return {"accessor_past_view.glb": (past, "accessor 1 (4000 elements) reads past its bufferView"),
            "accessors_overlap.glb": (glb(doc, payload), f"at most {MAX_MESH_BYTES} bytes (the file cap)")}


def _cases() -> dict[str, tuple[bytes, str]]:
    """name -> (file bytes, what the one line says)."""
    far_apart = [{"mesh": 0, "translation": [2.0 * k, 0, 0]} for k in range(9000)]
    many_vertices = np.random.default_rng(1).random((700, 3)).astype(np.float32)
    chain = [{"mesh": 0, "children": [k + 1]} for k in range(MAX_MESH_NODE_DEPTH)] + [{"mesh": 0}]
    cases = {
        "tiny.obj": (obj_text(TRI.astype(np.float64) * 1e-300, [[0, 1, 2]]), LIMIT),
        "subnormal.obj": (obj_text(TRI.astype(np.float64) * 1e-320, [[0, 1, 2]]), LIMIT),
        "tiny.gltf": (gltf_text(*gltf_doc(TRI * np.float32(1e-35), IDX)), LIMIT),
        "tiny_mitsuba.obj": (obj_text(TRI.astype(np.float64) * 1e-300, [[0, 1, 2]]), LIMIT),
        "instanced.glb": (instanced(5000), f"its nodes place 25000000 triangles (each node a copy of its mesh); a "
                                           f"mesh may have at most {MAX_MESH_TRIANGLES}"),
        "instanced_20000.glb": (instanced(20_000), f"20000 nodes; a glTF may have at most {MAX_MESH_NODES}"),
        "instanced_vertices.glb": (glb(*gltf_doc(many_vertices, IDX, nodes=far_apart)), "its nodes place 6300000 "
                                   "vertices"),
        "deep.glb": (_nodes_glb(chain), f"is {MAX_MESH_NODE_DEPTH + 1} nodes deep; a glTF's node trees may be at "
                                        f"most {MAX_MESH_NODE_DEPTH} deep"),
        "cycle.glb": (_nodes_glb([{"mesh": 0}, {"mesh": 0, "children": [2]}, {"children": [1]}]),
                      "node 2 is its own ancestor (a cycle)"),
        "two_parents.glb": (_nodes_glb([{"children": [2]}, {"children": [2]}, {"mesh": 0}]), "node 2 has two parents"),
        "own_child.glb": (_nodes_glb([{"mesh": 0, "children": [0]}]), "node 0 has two parents or is its own child"),
        "huge_header.ply": (b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                            b"property float y\nproperty float z\nelement face 1\nproperty list uchar int "
                            b"vertex_indices\nend_header\n", "the PLY header declares 4000000000 vertices"),
        "superscript_count.ply": ("ply\nformat ascii 1.0\nelement vertex ²\nend_header\n".encode(),
                                  "element vertex count '²' is not a whole number"),  # (str.isdigit takes '²')
        "long_count.ply": (b"ply\nformat ascii 1.0\nelement face " + b"9" * 5000 + b"\nend_header\n",
                           "is not a whole number of at most"),  # (int() refuses over 4 300 digits)
        "json_items.gltf": (b'{"asset": {"version": "2.0"}, "nodes": [' + b"{}, " * MAX_MESH_JSON_ITEMS + b"{}]}",
                            f"a glTF's JSON may hold at most {MAX_MESH_JSON_ITEMS}"),
        **_sparse_cases(),
        **_accessor_cases(),
    }
    return cases


@pytest.fixture(scope="module")
def refused(tmp_path_factory):
    """Every case through the CLI in one capped subprocess: name -> (result, fragment), and the folder."""
    d = tmp_path_factory.mktemp("round4_meshes")
    names, argvs, fragments = [], [], []
    for name, (data, fragment) in _cases().items():
        (d / name).write_bytes(data)
        engine = ["--engine", "mitsuba"] if "mitsuba" in name else []
        names.append(name)
        fragments.append(fragment)
        argvs.append(["render", "--thickness", "100", "--mesh", d / name, "--size", "32", *engine,
                      "--environment", "point" if not engine else "uniform", "--out", d / f"out-{name}"])
    procs = run_capped_batch(argvs, CAP)
    return {n: (p, f) for n, p, f in zip(names, procs, fragments, strict=True)}, d


@pytest.mark.parametrize("name", list(_cases()))
def test_issue49_hostile_mesh_refused_in_one_line_with_nothing_written(refused, name):
    results, folder = refused
    proc, fragment = results[name]
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith(f"error: {name}: ") and proc.stderr.count("\n") == 1, proc.stderr
    assert "Traceback" not in proc.stderr and fragment in proc.stderr, proc.stderr
    assert not (folder / f"out-{name}").exists()
    if name.startswith(("instanced", "deep", "cycle", "json")):  # refused from the JSON, before anything is built
        assert proc.wall_s < 5.0, proc.wall_s  # type: ignore[attr-defined]


def test_issue49_instanced_nodes_within_the_caps_render_as_the_triangles_written_flat(tmp_path):
    """Instancing is still read: a root placing one triangle mesh at two nodes (one under the other, translated,
    one scaled) is the same picture as an OBJ of the two triangles where those nodes put them."""
    nodes = [{"children": [1, 2]}, {"mesh": 0, "translation": [-1.2, 0, 0]},
             {"mesh": 0, "translation": [0.2, -0.5, 0], "children": [3]}, {"mesh": 0, "translation": [0, 1, 0],
                                                                           "scale": [0.5, 0.5, 1]}]
    (tmp_path / "nodes.glb").write_bytes(_nodes_glb(nodes))
    flat = np.concatenate([TRI + np.array([-1.2, 0, 0]), TRI + np.array([0.2, -0.5, 0]),
                           TRI * np.array([0.5, 0.5, 1]) + np.array([0.2, 0.5, 0])])
    (tmp_path / "flat.obj").write_bytes(obj_text(flat.astype(np.float32), np.arange(9).reshape(3, 3)))
    procs = run_capped_batch([["render", "--thickness", "100", "--mesh", tmp_path / f, "--size", "48",
                               "--environment", "point", "--out", tmp_path / f"out-{f}"]
                              for f in ("nodes.glb", "flat.obj")], CAP)
    for proc in procs:
        assert proc.returncode == 0, proc.stderr
    a, b = (oiio.ImageBuf(str(next((tmp_path / f"out-{f}").glob("*.png")))).get_pixels(oiio.UINT8).astype(int)
            for f in ("nodes.glb", "flat.obj"))
    assert (np.abs(a - a[0, 0]).sum(axis=-1) > 0).sum() > 100  # (the triangles are in the picture)
    assert np.abs(a - b).max() <= 1
