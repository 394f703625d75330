"""A designer's own part in a catalog (issue 46 item 4): ``[render] mesh = "part.glb"``, a path relative to the spec,
checked before any work (the mesh reader's formats and caps, the spec folder's bounds), hashed into the build's
fingerprint (an edited part rebuilds), rendered on every sheet tile (the built-in engine, the studio, the part hiding
the environment from itself) and path-traced in the heroes instead of the sphere."""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from swatch.catalog.build import build_catalog
from swatch.catalog.spec import load_spec, parse_spec, spec_summary
from swatch.core.errors import SwatchError
from swatch.io import imageio
from tests.cli_helpers import run_swatch
from tests.mesh_files import instanced
from tests.mitsuba_setup import mitsuba_variant

ROOT = Path(__file__).resolve().parents[2]
PART = ROOT / "examples" / "part.glb"

SPEC = """
name = "part test"
[thickness]
list_nm = [50.8, 140]
[render]
shapes = ["flat"]
mesh = "{mesh}"
finish = "polished"
hero = {hero}
hero_size_px = 32
hero_spp = 4
size_px = 64
angular_map = false
[chips]
enabled = false
[presets]
enabled = false
"""


def _spec(folder: Path, mesh: str = "part.glb", hero: bool = False) -> Path:
    path = folder / "spec.toml"
    path.write_text(SPEC.format(mesh=mesh, hero="true" if hero else "false"), encoding="utf-8")
    return path


def _obj(path: Path, mesh: trimesh.Trimesh) -> None:
    path.write_bytes(mesh.export(file_type="obj").encode("utf-8"))


def test_the_part_is_a_path_relative_to_the_spec(tmp_path, monkeypatch):
    (tmp_path / "parts").mkdir()
    shutil.copy(PART, tmp_path / "parts" / "knob.glb")
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text(SPEC.format(mesh="parts/knob.glb", hero="false"), encoding="utf-8")
    monkeypatch.chdir(ROOT)  # not the spec's folder: the path is the spec's
    spec, _ = load_spec(spec_path)
    assert spec.mesh == "parts/knob.glb" and Path(spec.mesh_path) == (tmp_path / "parts" / "knob.glb").resolve()
    assert spec.mesh_sha256 == hashlib.sha256(PART.read_bytes()).hexdigest()
    assert spec.tile_renders == ("flat", "mesh")
    assert "part parts/knob.glb" in spec_summary(spec)
    canon = spec.canonical()
    assert canon["mesh_sha256"] == spec.mesh_sha256 and "mesh_path" not in canon  # a moved folder is the same spec
    assert "mesh" not in parse_spec({"name": "n", "thickness": {"list_nm": [50]}}).canonical()  # the hashes of before
    example, _ = load_spec(ROOT / "examples" / "part-catalog.toml")
    assert example.mesh == "part.glb" and Path(example.mesh_path) == PART.resolve() and example.hero


@pytest.mark.parametrize(("mesh", "words"), [
    ("missing.glb", "no such file next to the spec"),
    ("part.txt", r"must name a mesh file \(\.obj, \.ply, \.stl, \.glb, \.gltf\)"),
    ("../outside.glb", "must lie inside the spec's folder"),
    ("link.glb", "must lie inside the spec's folder"),  # a link inside that leads out
    ("sub", r"must name a mesh file"),
])
def test_a_part_outside_the_spec_folder_or_missing_is_refused(tmp_path, mesh, words):
    folder = tmp_path / "specs"
    folder.mkdir()
    (folder / "sub").mkdir()
    shutil.copy(PART, tmp_path / "outside.glb")
    (folder / "part.txt").write_text("not a mesh", encoding="utf-8")
    os.symlink(tmp_path / "outside.glb", folder / "link.glb")
    with pytest.raises(SwatchError, match=rf"spec\.toml: key render\.mesh: {words}") as err:
        load_spec(_spec(folder, mesh))
    assert "\n" not in str(err.value)
    abs_outside = str(tmp_path / "outside.glb")
    with pytest.raises(SwatchError, match="must lie inside the spec's folder"):
        load_spec(_spec(folder, abs_outside))
    with pytest.raises(SwatchError, match="not read from a file"):  # a spec without a folder names no part
        parse_spec({"name": "n", "thickness": {"list_nm": [50]}, "render": {"mesh": "part.glb"}})


@pytest.mark.slow
@pytest.mark.parametrize(("name", "content", "words"), [
    ("part.glb", b"glTF not really", "not a binary glTF"),
    ("part.obj", b"# no faces\nv 0 0 0\n", "no triangles"),
    ("part.obj", b"v 0 0 0\nv 1e-300 0 0\nv 0 1e-300 0\nf 1 2 3\n", "a mesh is at least 1e-30 across"),  # issue 49
    ("part.glb", instanced(5000), "its nodes place 25000000 triangles"),
])
def test_a_bad_part_is_one_line_before_any_work(tmp_path, name, content, words):
    (tmp_path / name).write_bytes(content)
    spec = _spec(tmp_path, name)
    for args in (("validate", str(spec)), ("build", str(spec), "--out", str(tmp_path / "out"))):
        r = run_swatch("catalog", *args)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert r.stderr.startswith(f"error: {spec}: key render.mesh: {name}: ") and words in r.stderr
        assert "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()  # nothing half-written


@pytest.mark.slow
def test_the_part_is_on_every_tile_and_an_edited_part_rebuilds(tmp_path):
    _obj(tmp_path / "part.obj", trimesh.creation.annulus(r_min=0.4, r_max=1.0, height=0.5, sections=32))
    spec = _spec(tmp_path, "part.obj")
    out = tmp_path / "c"
    res = build_catalog(spec, out, jobs=1)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    mesh = doc["catalog"]["render"]["mesh"]
    assert mesh == {"file": "part.obj", "sha256": hashlib.sha256((tmp_path / "part.obj").read_bytes()).hexdigest(),
                    "triangles": mesh["triangles"]} and mesh["triangles"] > 100
    meta = imageio.read_metadata(out / "sheets" / "sheet_01.png")
    sheet = np.asarray(Image.open(out / "sheets" / "sheet_01.png").convert("RGB"))
    for tile in meta["sheet"]["tiles"]:
        shapes = [r["shape"] for r in tile["renders"]]
        assert shapes == ["flat", "mesh"] and tile["renders"][1]["mesh"] == "part.obj"
        x, y, w, h = tile["renders"][1]["rect_px"]
        part = sheet[y:y + h, x:x + w].astype(float)
        grey = np.abs(part - part[0, 0]).sum(axis=-1) > 6  # the part over the render's grey background
        assert 0.2 < grey.mean() < 0.9
        assert part[grey].std() > 10  # shaded, not a flat silhouette
    before = (out / "sheets" / "sheet_01.png").read_bytes()
    # an unchanged part: a no-op, in a fresh process, within 2 s
    t0 = time.perf_counter()
    r = run_swatch("catalog", "build", str(spec), "--out", str(out))
    assert r.returncode == 0 and "up to date" in r.stdout, r.stderr
    assert time.perf_counter() - t0 <= 2.0
    # the same name, other bytes: the tiles are rendered again and the record says the new part
    _obj(tmp_path / "part.obj", trimesh.creation.box(extents=(1.0, 0.6, 1.4)))
    res = build_catalog(spec, out, jobs=1)
    assert not res.noop and res.rendered == 2
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    assert doc["catalog"]["render"]["mesh"]["triangles"] == 12
    assert (out / "sheets" / "sheet_01.png").read_bytes() != before


def test_the_part_hides_the_environment_from_itself(monkeypatch):
    """The built-in engine under an environment: a direction the part blocks is dark (self-occlusion). Under the
    furnace light the part with occlusion is nowhere brighter than without it, and much darker where it sees itself
    (the flange's top beside the grip, the flutes); the sphere, convex, has nothing to hide."""
    from swatch.render import render_swatch
    from swatch.render.builtin import env_render
    from swatch.render.mesh import MeshShape, load_mesh

    part = load_mesh(PART)
    hit, pts, geo = part.surface(np.array([0.0, 0.3, 3.0]), np.array([[0.0, -0.1, -1.0]]) / np.hypot(0.1, 1.0))
    assert hit[0]
    into_and_back = np.array([[[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]])  # into the part, and back towards the camera
    assert part.blocked(pts, geo, into_and_back).tolist() == [[True, False]]
    occluded = render_swatch(140.0, "sphere", 64, mesh=part, environment="uniform")
    assert "self-occlusion" in occluded.metadata["lighting"]
    assert "self-occlusion" not in render_swatch(140.0, "sphere", 64, environment="uniform").metadata["lighting"]
    monkeypatch.setattr(env_render, "_CACHE", {})  # (the prepared scene is cached per scene)
    monkeypatch.setattr(MeshShape, "blocked", lambda self, p, n, d: np.zeros(np.shape(d)[:2], dtype=bool))
    open_ = render_swatch(140.0, "sphere", 64, mesh=part, environment="uniform")
    on = np.asarray(occluded.coverage) == 1.0
    a, b = (np.asarray(im.linear_rgb).mean(axis=-1)[on] for im in (occluded, open_))
    assert (a <= b + 1e-6).all()
    assert ((b - a) > 0.25 * b).mean() > 0.05, ((b - a) / b).max()


@pytest.mark.slow
def test_the_heroes_show_the_part(tmp_path):
    mitsuba_variant()
    shutil.copy(PART, tmp_path / "part.glb")
    out = tmp_path / "c"
    build_catalog(_spec(tmp_path, hero=True), out, jobs=1)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    for r in doc["swatches"]:
        assert r["hero"]["shape"] == "mesh" and r["hero_finishes"]["polished"]["shape"] == "mesh"
        meta = imageio.read_metadata(out / r["hero"]["png"])
        assert meta["mesh"]["file"] == "part.glb"


def test_a_part_too_large_for_the_page_is_refused_before_any_work(tmp_path, monkeypatch):
    """The page's live view draws the part's triangles: a part over MAX_PAGE_MESH_TRIANGLES (lowered here, the
    check's own constant) is refused when the build checks its inputs, in one line naming the limit."""
    import swatch.catalog.context as context
    from swatch.catalog.spec import load_spec

    mesh = trimesh.creation.annulus(r_min=0.4, r_max=1.0, height=0.5, sections=32)
    _obj(tmp_path / "part.obj", mesh)
    spec, _ = load_spec(_spec(tmp_path, "part.obj"))
    assert context.catalog_mesh(spec) is not None
    monkeypatch.setattr(context, "MAX_PAGE_MESH_TRIANGLES", len(mesh.faces) - 1)
    with pytest.raises(SwatchError, match=rf"key render\.mesh: part\.obj has {len(mesh.faces)} triangles; the catalog "
                                          rf"page draws at most {len(mesh.faces) - 1} \(MAX_PAGE_MESH_TRIANGLES\)"):
        context.catalog_mesh(spec)
