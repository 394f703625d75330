"""Renders of designers' meshes (``swatch render --mesh``, issue #11 item 5).

References we did not write: the directional albedo of the thin-film GGX BRDF by tmm + scipy
quadrature (tests/render/test_environment.py) for a mesh plate seen along its normal under ``uniform``;
trimesh's pure-numpy ray/triangle intersector (``trimesh.ray.ray_triangle``, a separate
implementation from Embree) for hits and points; the analytic sphere of the renderer for a fine
icosphere. Untrusted files: one-line errors, nothing written.
"""
from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.errors import SwatchError
from swatch.render import mesh, render_swatch, scene
from tests.cli_helpers import assert_one_line_error, run_swatch
from tests.render.env_reference import CM, COATING, albedo_normal_view, lab_2deg, lab_of_spectrum, xyz_of_srgb


def _torus_on_plate():
    t = trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=48, minor_sections=24)
    t.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    box = trimesh.creation.box(extents=[2.6, 0.1, 2.6])
    box.apply_translation([0, -0.45, 0])
    return trimesh.util.concatenate([t, box])


@pytest.fixture(scope="module")
def torus_files(tmp_path_factory):
    root = tmp_path_factory.mktemp("mesh")
    obj = _torus_on_plate()
    for ext in ("glb", "obj", "stl", "ply"):
        obj.export(root / f"torus.{ext}")
    return root


def test_icosphere_renders_as_the_sphere():
    """A fine icosphere through the mesh path equals the analytic sphere (same camera and light)."""
    path_mesh = mesh.MeshShape(trimesh.creation.icosphere(subdivisions=5), "ico.ply", "0")
    for env in (None, "studio"):
        a = render_swatch(80.0, "mesh", 128, environment=env, mesh=path_mesh, coating=COATING, colorimeter=CM)
        b = render_swatch(80.0, "sphere", 128, environment=env, coating=COATING, colorimeter=CM)
        assert np.abs(a.coverage - b.coverage).mean() < 2e-3
        diff = np.abs(a.display_rgb.astype(int) - b.display_rgb.astype(int))
        assert np.percentile(diff, 99) <= 3 and diff.mean() < 0.5, (env, diff.mean())


def test_hits_agree_with_trimesh_pure_numpy_intersector(torus_files):
    """Embree's first hits equal trimesh's ray_triangle (an independent implementation)."""
    from trimesh.ray.ray_triangle import RayMeshIntersector

    shape = mesh.load_mesh(torus_files / "torus.glb")
    rng = np.random.default_rng(7)
    o = np.array([0.3, 2.5, 3.0])
    d = rng.normal(size=(3000, 3)) * 0.25 - o / np.linalg.norm(o)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    hit, _, _, point = shape._cast(o, d)
    _, ref_ray, ref_loc = RayMeshIntersector(shape._mesh).intersects_id(
        np.broadcast_to(o, d.shape), d, multiple_hits=False, return_locations=True)
    ref_hit = np.zeros(d.shape[0], dtype=bool)
    ref_hit[ref_ray] = True
    assert 500 < hit.sum() < 2900
    assert (hit != ref_hit).sum() <= 3  # rays grazing an edge may differ in single precision
    both = np.flatnonzero(hit & ref_hit)
    ref_point = np.zeros_like(d)
    ref_point[ref_ray] = ref_loc
    assert np.abs(point[both] - ref_point[both]).max() < 1e-4


@pytest.mark.parametrize("d_nm", [30.0, 160.0])
def test_mesh_plate_furnace_along_the_normal(tmp_path, d_nm):
    """A two-triangle plate under ``uniform``, seen along its normal: the centre pixel is the
    directional albedo of the thin-film GGX BRDF (tmm + quadrature), within ΔE2000 1."""
    path = tmp_path / "plate.obj"
    path.write_text("v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 4 3\n", encoding="utf-8")
    img = render_swatch(d_nm, "mesh", 32, environment="uniform", view_deg=0.0, mesh=mesh.load_mesh(path),
                               coating=COATING, colorimeter=CM)
    centre = img.linear_rgb[15:17, 15:17].reshape(-1, 3).mean(axis=0)
    assert delta_E_00(lab_2deg(xyz_of_srgb(centre)), lab_of_spectrum(albedo_normal_view(d_nm))) <= 1.0


def test_file_formats_render_alike_and_the_torus_shadows_the_plate(torus_files):
    shapes = {ext: mesh.load_mesh(torus_files / f"torus.{ext}") for ext in ("glb", "obj", "stl", "ply")}
    imgs = {ext: render_swatch(80.0, "mesh", 96, mesh=s, coating=COATING, colorimeter=CM, environment="point")
            for ext, s in shapes.items()}
    for ext in ("obj", "stl", "ply"):
        assert np.abs(imgs[ext].display_rgb.astype(int) - imgs["glb"].display_rgb.astype(int)).max() <= 2, ext
    # shadow rays: plate-top pixels (normal +y, facing the light) that the torus hides from it
    for obj, expect_shadow in ((shapes["glb"], True),
                               (mesh.MeshShape(trimesh.creation.box(extents=[2.6, 0.1, 2.6]), "plate.glb", "1"), False)):
        sc = scene.make_scene("sphere", 45.0, mesh=obj)
        c = np.arange(96, dtype=np.float32) + np.float32(0.5)
        hit, _, ny, _ = obj.intersect(sc.camera.position, *sc.camera.directions(c[None, :], c[:, None], 96))
        hit2, cos_l, _ = obj.trace(sc.camera, *sc.camera.window(c[None, :], c[:, None], 96), sc.light)
        assert (hit == hit2).all() and sc.light[1] > 0.3
        shadowed = hit & (ny > 0.99) & (cos_l == 0.0)
        assert (shadowed.sum() > 100) if expect_shadow else (shadowed.sum() == 0), shadowed.sum()
    img = imgs["glb"]
    assert ((img.coverage == 1.0) & (img.linear_rgb.max(axis=-1) == 0.0)).sum() > 100  # black in the render


def test_cli_mesh_render_writes_metadata(tmp_path, torus_files):
    proc = run_swatch("render", "--mesh", torus_files / "torus.glb", "--thickness", "50.8", "--size", "48",
                      "--environment", "studio", "--out", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
    from swatch.io import imageio

    meta = imageio.read_metadata(tmp_path / "out" / "mesh_050.8nm.png")
    assert meta["shape"] == "mesh" and meta["mesh"]["file"] == "torus.glb" and len(meta["mesh"]["sha256"]) == 64
    assert "torus.glb" in meta["geometry"] and "self-occlusion" in meta["lighting"]
    again = run_swatch("render", "--mesh", torus_files / "torus.glb", "--thickness", "50.8", "--size", "48",
                       "--environment", "studio", "--out", tmp_path / "out2")
    assert again.returncode == 0
    for suf in (".png", ".exr"):
        assert (tmp_path / "out" / f"mesh_050.8nm{suf}").read_bytes() == \
            (tmp_path / "out2" / f"mesh_050.8nm{suf}").read_bytes()


def _gltf_with_buffer(uri: str) -> str:
    return json.dumps({"asset": {"version": "2.0"}, "buffers": [{"uri": uri, "byteLength": 36}],
                       "meshes": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0})


BAD = [
    ("evil.gltf", _gltf_with_buffer("../secret.bin"), "external file"),
    ("evil.gltf", _gltf_with_buffer("/etc/passwd"), "external file"),
    ("empty.obj", "# nothing\n", "no triangles"),
    ("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "finite"),
    ("point.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n", "one point"),
    ("garbage.glb", "not a glb at all, just text", "binary gltf"),
    ("model.fbx", "x", "unknown mesh format"),
]


@pytest.mark.parametrize("name,text,fragment", BAD)
def test_bad_mesh_files_give_one_line(tmp_path, name, text, fragment):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    assert_one_line_error(run_swatch("render", "--mesh", path, "--thickness", "80", "--size", "16",
                                     "--out", tmp_path / "out"), fragment)
    assert not (tmp_path / "out").exists()


def test_oversized_mesh_is_refused_before_reading(tmp_path):
    path = tmp_path / "huge.stl"
    with open(path, "wb") as fh:  # sparse: 65 MB of nothing
        fh.truncate(65 * 1024 * 1024)
    with pytest.raises(SwatchError, match="at most 64 MB"):
        mesh.load_mesh(path)
    with pytest.raises(SwatchError, match="not a file"):
        mesh.load_mesh(tmp_path / "missing.obj")


def _torus_soup():
    t = trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=32, minor_sections=16)
    return t.vertices, t.faces


@pytest.mark.parametrize("scale", [1e-6, 1e-12, 1e-29, 3e-31])
def test_a_small_mesh_renders_as_at_unit_scale_down_to_the_extent_cap(tmp_path, scale):
    """Issue 49: a mesh under ~1e-290 ended in an OverflowError (exit 70), and one of 1e-9 was "all vertices at
    one point" (trimesh's merge to 10^-8) while one of 1e-6 lost its smooth normals (trimesh's are zero under
    ~1e-13 of area). Down to MIN_MESH_EXTENT (the torus is 2.7 across) a mesh is the picture, and the triangles
    Mitsuba is given, of the same mesh at unit scale; below it, one line naming the cap."""
    from swatch.core.limits import MIN_MESH_EXTENT
    from tests.mesh_files import obj_text

    v, f = _torus_soup()
    (tmp_path / "unit.obj").write_bytes(obj_text(v, f))
    (tmp_path / "small.obj").write_bytes(obj_text(v * scale, f))
    unit = mesh.load_mesh(tmp_path / "unit.obj")
    if 2.7 * scale < MIN_MESH_EXTENT:
        with pytest.raises(SwatchError, match=rf"small.obj: the mesh is 8.1e-31 across .*; a mesh is at least "
                                              rf"{MIN_MESH_EXTENT:.0e} across in the file's units"):
            mesh.load_mesh(tmp_path / "small.obj")
        return
    small = mesh.load_mesh(tmp_path / "small.obj")
    for got, want in zip(small.triangle_soup(), unit.triangle_soup(), strict=True):
        assert np.abs(got - want).max() < 1e-9
    a, b = (render_swatch(80.0, "mesh", 48, mesh=m, environment="point", coating=COATING, colorimeter=CM).display_rgb
            for m in (small, unit))
    assert np.array_equal(a, b)


def test_a_small_float32_gltf_renders_as_at_unit_scale(tmp_path):
    """The same for a .glb's float32 positions at 1e-20 (glTF, binary STL and PLY store float32)."""
    from tests.mesh_files import glb, gltf_doc

    v, f = _torus_soup()
    shapes = []
    for name, s in (("unit.glb", 1.0), ("small.glb", 1e-20)):
        (tmp_path / name).write_bytes(glb(*gltf_doc((v * s).astype(np.float32), f.reshape(-1))))
        shapes.append(mesh.load_mesh(tmp_path / name))
    for got, want in zip(shapes[1].triangle_soup(), shapes[0].triangle_soup(), strict=True):
        assert np.abs(got - want).max() < 1e-6
    a, b = (render_swatch(80.0, "mesh", 48, mesh=m, environment="point", coating=COATING, colorimeter=CM).display_rgb
            for m in shapes)
    assert np.abs(a.astype(int) - b.astype(int)).max() <= 1


def test_an_instanced_gltf_is_refused_from_its_json_before_anything_is_built(tmp_path, monkeypatch):
    """Issue 49: 5 000 nodes placing one 5 000-triangle mesh (a 0.3 MB file) is counted from the node tree and
    the accessors' counts, and refused without trimesh reading the file (it flattened 20 000 such nodes into
    5–8 GB before the triangle cap was checked)."""
    import time

    from tests.mesh_files import instanced

    def never(*args, **kwargs):
        raise AssertionError("trimesh.load was called")

    (tmp_path / "instanced.glb").write_bytes(instanced(5000))
    monkeypatch.setattr(mesh.trimesh, "load", never)
    start = time.perf_counter()
    with pytest.raises(SwatchError, match=r"instanced\.glb: its nodes place 25000000 triangles"):
        mesh.load_mesh(tmp_path / "instanced.glb")
    assert time.perf_counter() - start < 2.0
