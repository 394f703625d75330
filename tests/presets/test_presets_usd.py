"""USD/USDZ presets (Pixar's usd-core reads and validates them; MaterialX renders their OpenPBR network) and the
physicallybased.info documents (validated against the database's own v2 schema, vendored)."""
from __future__ import annotations

import json
import struct
import zipfile
from pathlib import Path

import colour
import numpy as np
import pytest
from pxr import Sdf, Usd, UsdGeom, UsdShade, UsdValidation

from swatch.presets.fit import FIT_ANGLES_DEG
from tests.preset_reference import tmm_exact_Lab, write_catalog_presets

pytestmark = pytest.mark.slow  # fits presets, runs processes and MaterialX's renderer (seconds per test)

VENDOR = Path(__file__).resolve().parents[1] / "vendor" / "physicallybased"
SPEC = """
name = "usd test"
[thickness]
list_nm = [25, 60, 120, 190, 260]
[render]
roughness = 0.3
[presets]
usd = true
physicallybased = true
"""


@pytest.fixture(scope="module")
def usd_written(tmp_path_factory):
    return write_catalog_presets(SPEC, tmp_path_factory.mktemp("usd"))


def _materialx_nodedefs() -> set[str]:
    import MaterialX as mx

    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    return {nd.getName() for nd in lib.getNodeDefs()}


def _validation_errors(stage) -> list:
    """Every validator usd-core ships, run on the stage: the errors (warnings are not failures)."""
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    assert len(validators) >= 25, len(validators)  # they loaded (usd-core 26.x: 30)
    errors = UsdValidation.ValidationContext(validators).Validate(stage)
    return [e for e in errors if e.GetType() == UsdValidation.ValidationErrorType.Error]


def _assert_valid(stage) -> None:
    """No error but usd-core's shader-registry check on the MaterialX nodes (usd-core is built without
    MaterialX, so its registry cannot know them): each of those must name a node definition of MaterialX's
    own libraries (and the network is rendered in MaterialX below)."""
    known = _materialx_nodedefs()
    for err in _validation_errors(stage):
        assert err.GetName() == "MissingShaderIdInRegistry", (err.GetName(), err.GetMessage())
        shader_id = err.GetMessage().split("'")[1]
        assert shader_id.startswith("ND_") and shader_id in known, err.GetMessage()


def _material_and_shaders(stage):
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/preset/part"))
    assert mesh
    material, _ = UsdShade.MaterialBindingAPI(mesh.GetPrim()).ComputeBoundMaterial()
    assert material, "the part has no bound material"
    pbr = material.ComputeSurfaceSource("mtlx")[0]
    preview = material.ComputeSurfaceSource()[0]
    return mesh, material, pbr, preview


def test_usdz_presets_validate_and_read_back(usd_written):
    """#47: each .usdz opens in usd-core, passes every validator it ships (the ND_ shaders aside, above), has
    Y up, metres, a default prim, and its mesh is bound to the material whose two surfaces are connected."""
    _spec, records, root, _ = usd_written
    for rec in records:
        path = root / rec["presets"]["usdz"]
        assert rec["presets"]["usdz"] == f"presets/preset_{rec['id']}.usdz"  # the page's AR control relies on it
        stage = Usd.Stage.Open(str(path))
        assert stage is not None
        _assert_valid(stage)
        assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
        assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
        assert stage.GetDefaultPrim().GetPath() == Sdf.Path("/preset")
        mesh, material, pbr, preview = _material_and_shaders(stage)
        assert pbr.GetShaderId() == "ND_open_pbr_surface_surfaceshader"
        assert preview.GetShaderId() == "UsdPreviewSurface"
        assert preview.GetInput("metallic").Get() == 1.0
        assert "cannot shift with angle" in material.GetPrim().GetDocumentation()
        assert "cannot shift with angle" in stage.GetRootLayer().documentation
        extent = np.array(mesh.GetExtentAttr().Get())
        assert np.allclose(np.abs(extent), 0.05, atol=1e-6)  # a 10 cm sphere
        with zipfile.ZipFile(path) as z:  # usdz: stored, one layer, no timestamps of the day
            info = z.infolist()
            assert [i.compress_type for i in info] == [zipfile.ZIP_STORED]
            assert info[0].filename == f"preset_{rec['id']}.usdc" and info[0].date_time == (1980, 1, 1, 0, 0, 0)
        blob = path.read_bytes()  # usdz: each file's data starts on a multiple of 64 bytes
        names, extra = struct.unpack_from("<HH", blob, info[0].header_offset + 26)
        assert (info[0].header_offset + 30 + names + extra) % 64 == 0


def _pbr_inputs(pbr) -> dict:
    return {i.GetBaseName(): i.Get() for i in pbr.GetInputs() if i.Get() is not None}


def test_usd_network_is_the_materialx_preset(usd_written):
    """The USD's OpenPBR inputs are those of the swatch's .mtlx preset (read by MaterialX from that file)."""
    import MaterialX as mx

    _spec, records, root, _ = usd_written
    for rec in records:
        stage = Usd.Stage.Open(str(root / rec["presets"]["usdz"]))
        values = _pbr_inputs(_material_and_shaders(stage)[2])
        doc = mx.createDocument()
        mx.readFromXmlFile(doc, str(root / rec["presets"]["materialx"]))
        node = next(n for n in doc.getNodes() if n.getCategory() == "open_pbr_surface")
        for inp in node.getInputs():
            want = inp.getValue()
            got = values[inp.getName()]
            assert np.allclose(np.asarray(list(want) if isinstance(want, mx.Color3) else want, dtype=float),
                               np.asarray(got, dtype=float), atol=1e-6), (rec["id"], inp.getName(), want, got)


def test_usd_preview_holds_its_stated_error(usd_written):
    """The fallback's stated ΔE2000 is that of its diffuseColor as written, under the Schlick metal of the
    UsdPreviewSurface specification (written out here), against the exact colour from tmm and colour-science."""
    _spec, records, root, _ = usd_written
    for rec in records:
        stage = Usd.Stage.Open(str(root / rec["presets"]["usdz"]))
        f0 = np.array(_material_and_shaders(stage)[3].GetInput("diffuseColor").Get(), dtype=float)
        c = np.cos(np.radians(FIT_ANGLES_DEG))[:, None]
        rgb = f0 + (1.0 - f0) * (1.0 - c) ** 5
        srgb = colour.RGB_COLOURSPACES["sRGB"]
        Lab = colour.XYZ_to_Lab(colour.RGB_to_XYZ(rgb, srgb, srgb.whitepoint, None), srgb.whitepoint)
        dE = np.asarray(colour.delta_E(Lab, tmm_exact_Lab(float(rec["thickness_nm"])), method="CIE 2000"))
        stated = rec["presets"]
        assert abs(dE.max() - stated["usd_preview_max_delta_E_00"]) <= 0.06, (rec["id"], dE, stated)
        assert abs(dE[FIT_ANGLES_DEG <= 45].max() - stated["usd_preview_max_delta_E_00_45"]) <= 0.06
        assert dE[np.isclose(FIT_ANGLES_DEG, 20.0) | np.isclose(FIT_ANGLES_DEG, 25.0)].max() < 1.5  # fitted at 22.5°
        assert f"{stated['usd_preview_max_delta_E_00']:.2f}" in stage.GetRootLayer().documentation


@pytest.mark.slow
def test_usd_network_in_materialx_renderer(usd_written, tmp_path, xvfb_display):
    """The USD's OpenPBR network, turned back into a MaterialX document node for node (its ``info:id`` the
    node definition, its inputs as typed), rendered by MaterialX's own GLSL renderer as the .mtlx presets are:
    equal to the port and within the MaterialX error the record states (+0.5, the .mtlx test's margin)."""
    import MaterialX as mx

    from swatch.colorimetry.colorimeter import delta_E_00
    from swatch.presets import materialx, spectral
    from swatch.presets.fit import exact_Lab
    from tests.preset_reference import render_in_materialx

    _spec, records, root, _ = usd_written
    paths = []
    for rec in records:
        stage = Usd.Stage.Open(str(root / rec["presets"]["usdz"]))
        pbr = _material_and_shaders(stage)[2]
        doc = mx.createDocument()
        doc.setColorSpace("lin_rec709")
        doc.importLibrary(_library())
        nodedef = doc.getNodeDef(pbr.GetShaderId())
        assert nodedef is not None, pbr.GetShaderId()
        node = doc.addNodeInstance(nodedef, "surface")
        for name, value in _pbr_inputs(pbr).items():
            kind = nodedef.getActiveInput(name).getType()
            node.setInputValue(name, mx.Color3(*value) if kind == "color3" else float(value), kind)
        doc.addMaterialNode("usd_material", node)
        ok, message = doc.validate()
        assert ok, message
        out = tmp_path / f"{rec['id']}.mtlx"
        mx.writeToXmlFile(doc, str(out), _no_library())
        paths.append(out)
    result = render_in_materialx(paths, tmp_path)
    for rec, got in zip(records, result, strict=True):
        stage = Usd.Stage.Open(str(root / rec["presets"]["usdz"]))  # held while its prims are read
        values = _pbr_inputs(_material_and_shaders(stage)[2])
        for row in got["rows"]:
            shown = np.asarray(row["preset"]) / np.asarray(row["reference"])
            facet = (row["view"] + row["light"]) / 2.0
            port = materialx.displayed_fresnel(np.cos(np.radians(facet)), values["thin_film_thickness"] * 1000.0,
                                               values["thin_film_ior"], np.array(values["base_color"]),
                                               values["specular_roughness"], cos_nv=np.cos(np.radians(row["view"])))
            assert np.abs(shown - port).max() < 1e-3, (rec["id"], row, port)
            if row["view"] == row["light"]:
                dE = float(delta_E_00(spectral.rgb_to_Lab(shown), exact_Lab([rec["thickness_nm"]], [facet])[0, 0]))
                assert dE <= rec["presets"]["materialx_max_delta_E_00"] + 0.5, (rec["id"], row, dE)


def _library():
    import MaterialX as mx

    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    return lib


def _no_library():
    import MaterialX as mx

    options = mx.XmlWriteOptions()
    options.elementPredicate = lambda elem: not elem.hasSourceUri()  # the document's own nodes, not the library
    return options


# -- the command ------------------------------------------------------------------------------

def test_preset_command_usd_and_usdz(tmp_path):
    """usd and usdz on the default sphere and on a designer's mesh: valid, bound, byte-identical on rerun
    (--force); --mesh with another format, or a bad mesh, is one line, exit 2, nothing written."""
    import trimesh

    from tests.cli_helpers import assert_one_line_error, run_swatch
    from tests.mesh_files import obj_text

    box = trimesh.creation.box(extents=[2.0, 1.0, 3.0])  # 12 triangles, sharp edges
    v, f = box.vertices, box.faces
    (tmp_path / "part.obj").write_bytes(obj_text(v, f))
    out = tmp_path / "out"
    r = run_swatch("preset", "--thickness", "150", "--format", "usdz", "--mesh", tmp_path / "part.obj", "--out", out)
    assert r.returncode == 0, r.stderr
    assert "UsdPreviewSurface" in r.stdout and "max ΔE2000" in r.stdout
    path = out / "preset_150nm.usdz"
    first = path.read_bytes()
    stage = Usd.Stage.Open(str(path))
    _assert_valid(stage)
    mesh = _material_and_shaders(stage)[0]
    assert len(mesh.GetFaceVertexCountsAttr().Get()) == len(f)
    pts = np.array(mesh.GetPointsAttr().Get())
    assert np.isclose(np.linalg.norm(pts, axis=1).max(), 0.05, rtol=1e-3)
    assert_one_line_error(run_swatch("preset", "--thickness", "150", "--format", "usdz", "--mesh",
                                     tmp_path / "part.obj", "--out", out), "already exists")
    r = run_swatch("preset", "--thickness", "150", "--format", "usdz", "--mesh", tmp_path / "part.obj", "--out", out,
                   "--force")
    assert r.returncode == 0 and path.read_bytes() == first  # byte-identical (another second: zip times fixed)
    r = run_swatch("preset", "--thickness", "150", "--format", "usd", "--out", out)
    assert r.returncode == 0, r.stderr
    text = (out / "preset_150nm.usda").read_text(encoding="utf-8")
    assert text.startswith("#usda 1.0") and str(tmp_path) not in text
    _assert_valid(Usd.Stage.Open(str(out / "preset_150nm.usda")))
    (tmp_path / "bad.obj").write_bytes(b"this is not a mesh\n")
    bad_out = tmp_path / "bad_out"
    bad = run_swatch("preset", "--thickness", "150", "--format", "usdz", "--mesh", tmp_path / "bad.obj", "--out",
                     bad_out)
    assert_one_line_error(bad, "bad.obj")
    assert bad.returncode == 2 and not bad_out.exists()
    wrong = run_swatch("preset", "--thickness", "150", "--format", "gltf", "--mesh", tmp_path / "part.obj", "--out",
                       bad_out)
    assert_one_line_error(wrong, "--mesh")
    assert wrong.returncode == 2 and not bad_out.exists()


# -- physicallybased.info ---------------------------------------------------------------------

def _schema_validator(formats: bool = True):
    """The vendored v2 schema; ``formats``: with ``format`` asserted (jsonschema's FormatChecker: ``uri`` through
    rfc3986-validator), else as JSON Schema 2020-12 has it by default (an annotation)."""
    import jsonschema
    from referencing import Registry, Resource
    from referencing.jsonschema import DRAFT202012

    resources = []
    for path in VENDOR.glob("*.json"):
        if path.name != "titanium-anodized.json":
            resource = Resource.from_contents(json.loads(path.read_text(encoding="utf-8")), default_specification=DRAFT202012)
            resources.append((f"https://physicallybased.test/{path.name}", resource))
    registry = Registry().with_resources(resources)
    schema = {"$ref": "https://physicallybased.test/Material.json"}
    return jsonschema.Draft202012Validator(schema, registry=registry,
                                           format_checker=jsonschema.FormatChecker() if formats else None)


def _errors(doc, formats: bool = True) -> list[str]:
    return sorted(f"{list(e.absolute_path)}: {e.message}" for e in _schema_validator(formats).iter_errors(doc))


def test_brushed_fallback_is_the_lobe_of_the_same_area(tmp_path):
    """A brushed finish: OpenPBR gets its anisotropic roughness (specular_roughness with an anisotropy), the isotropic
    UsdPreviewSurface the √α of the lobe of the same area, sqrt(sqrt(α_u α_v)) (not OpenPBR's roughness)."""
    from swatch.physics.finishes import get_finish
    from swatch.presets.usd import sphere_part
    from swatch.presets.usd_files import single_usd_preset

    finish = get_finish("brushed")
    data, _ = single_usd_preset(150.0, "usd", "TiO2-Siefke", "Ti-Johnson", 1.0, finish.roughness_alpha,
                                finish=finish, part=sphere_part())
    (tmp_path / "brushed.usda").write_bytes(data)
    stage = Usd.Stage.Open(str(tmp_path / "brushed.usda"))
    shaders = {prim.GetName(): UsdShade.Shader(prim) for prim in stage.Traverse() if prim.IsA(UsdShade.Shader)}
    pbr, preview = shaders["OpenPBR"], shaders["PreviewSurface"]
    lobe = float(np.sqrt(np.sqrt(finish.alpha_u * finish.alpha_v)))
    assert preview.GetInput("roughness").Get() == pytest.approx(lobe, abs=5e-5)  # (written to 4 decimals)
    assert pbr.GetInput("specular_roughness_anisotropy").Get() > 0
    assert abs(pbr.GetInput("specular_roughness").Get() - lobe) > 1e-3  # (the two differ: the test can tell)


def test_physicallybased_names_the_metal():
    """A niobium film is published as anodised niobium (name words, group, tag), without titanium's anatase index."""
    from swatch.presets.physicallybased import material_entry

    nb = material_entry("Niobium (Anodized, 80 nm)", 80.0, "Nb2O5-Franta", "Nb-Weaver", 1.0, 0.3)
    ti = material_entry("Titanium (Anodized, 80 nm)", 80.0, "TiO2-Siefke", "Ti-Johnson", 1.0, 0.3)
    assert nb["group"] == "Niobium (Anodized)" and nb["tags"][0] == "anodised niobium"
    assert nb["description"].startswith("Anodised niobium") and "anatase" not in nb["description"]
    assert ti["group"] == "Titanium (Anodized)" and "anatase's 2.488" in ti["description"]


def test_uri_format_is_asserted():
    """The FormatChecker really checks ``format: uri`` here (jsonschema skips it silently without a URI library)."""
    import jsonschema

    checker = jsonschema.FormatChecker()
    assert "uri" in checker.checkers
    assert checker.conforms("https://example.com/p/a.png", "uri") and not checker.conforms("p/a.png", "uri")


def test_physicallybased_schema_check_can_fail():
    """The vendored schema accepts the database's own "Titanium (Anodized)" entry and refuses it broken."""
    own = json.loads((VENDOR / "titanium-anodized.json").read_text(encoding="utf-8"))
    assert own["data"][0]["thinFilmIor"] == 2.488
    assert _errors(own) == []
    broken = json.loads(json.dumps(own))
    broken["data"][0]["thinFilmThickness"] = "20 nm"
    del broken["header"]["license"]
    assert len(_errors(broken)) == 2


def _pictures_beside(doc: dict, folder: Path) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each material's two pictures, read by Pillow from the files its relative ``images`` name (300, 600 px)."""
    from PIL import Image

    out = []
    for m in doc["data"]:
        (entry,) = m["images"]
        assert entry["format"] == "png"
        pair = []
        for size in ("300", "600"):
            path = folder / entry[size]
            assert path.parent == folder and path.is_file(), entry[size]
            with Image.open(path) as im:
                assert im.format == "PNG" and im.mode == "RGB" and im.size == (int(size), int(size))
                pair.append(np.asarray(im, dtype=float))
        out.append((pair[0], pair[1]))
    return out


def _check_pictures(pictures, thickness_nm) -> None:
    """The pictures show a sphere (a lit disc on the grey ground, the corners that ground), the 600 px one the 300 px
    one at twice the size, and each swatch in its own colour (the disc's mean differs between thicknesses)."""
    means = []
    for small, large in pictures:
        corner = large[:20, :20].reshape(-1, 3)
        assert np.ptp(corner, axis=0).max() == 0 and np.ptp(corner[0]) == 0  # flat neutral grey ground
        disc = np.abs(large - corner[0]).sum(axis=2) > 6
        yy, xx = np.nonzero(disc)
        assert 0.3 < disc.mean() < 0.785 and abs(xx.mean() - 299.5) < 15 and abs(yy.mean() - 299.5) < 15
        halved = large.reshape(300, 2, 300, 2, 3).mean(axis=(1, 3))
        assert np.abs(halved - small).mean() < 4.0  # the same picture at the other size
        means.append(large[disc].mean(axis=0))
    for i in range(len(means)):
        for j in range(i):
            if abs(thickness_nm[i] - thickness_nm[j]) >= 30:
                assert np.abs(means[i] - means[j]).max() > 5, (thickness_nm[i], thickness_nm[j])


def test_physicallybased_documents_validate(usd_written, tmp_path):
    """#47: the catalog's one document (a material per swatch) and swatch preset's are valid v2 documents (no
    error at all), their ``images`` the pictures beside them (relative references, the files there); with
    --base-url the URLs are absolute and valid with ``format: uri`` asserted too. Byte-identical on rerun."""
    from swatch.physics.materials import load_material
    from tests.cli_helpers import assert_one_line_error, run_swatch

    spec, records, root, files = usd_written
    doc = json.loads((root / "presets" / "physicallybased.json").read_text(encoding="utf-8"))
    assert _errors(doc, formats=False) == []
    assert _errors(doc) == sorted(f"{['data', i, 'images', 0, s]}: {m['images'][0][s]!r} is not a 'uri'"
                                  for i, m in enumerate(doc["data"]) for s in ("300", "600"))  # relative: not URIs
    n550 = float(load_material(spec.film).nk(np.array([550.0]))[0].real)
    for rec, m in zip(records, doc["data"], strict=True):
        assert m["thinFilmThickness"] == [rec["thickness_nm"]] and m["metalness"] == 1
        assert m["thinFilmIor"] == pytest.approx(n550, abs=5e-4)
        assert "2.488" in m["description"] and len(m["description"]) <= 500
        assert "built-in engine" in m["description"] and "sphere" in m["description"]
        assert m["images"][0]["300"] == f"preset_{rec['id']}_physicallybased_300.png"
    assert {f"presets/preset_{r['id']}_physicallybased_{s}.png" for r in records for s in (300, 600)} <= set(files)
    _check_pictures(_pictures_beside(doc, root / "presets"), [r["thickness_nm"] for r in records])

    out = tmp_path / "out"
    r = run_swatch("preset", "--thickness", "150", "--format", "physicallybased", "--out", out)
    assert r.returncode == 0, r.stderr
    single = out / "preset_150nm_physicallybased.json"
    one = json.loads(single.read_text(encoding="utf-8"))
    assert _errors(one, formats=False) == []
    _check_pictures(_pictures_beside(one, out), [150.0])
    first = {p.name: p.read_bytes() for p in out.iterdir()}
    assert sorted(first) == ["preset_150nm_physicallybased.json", "preset_150nm_physicallybased_300.png",
                             "preset_150nm_physicallybased_600.png"]
    assert_one_line_error(run_swatch("preset", "--thickness", "150", "--format", "physicallybased", "--out", out),
                          "already exists")
    assert run_swatch("preset", "--thickness", "150", "--format", "physicallybased", "--out", out,
                      "--force").returncode == 0
    assert {p.name: p.read_bytes() for p in out.iterdir()} == first

    hosted = tmp_path / "hosted"
    r = run_swatch("preset", "--thickness", "150", "--format", "physicallybased", "--out", hosted, "--base-url",
                   "https://example.com/titanium/")
    assert r.returncode == 0, r.stderr
    absolute = json.loads((hosted / "preset_150nm_physicallybased.json").read_text(encoding="utf-8"))
    assert _errors(absolute) == [] and _errors(absolute, formats=False) == []
    assert absolute["data"][0]["images"] == [{"format": "png",
                                              "300": "https://example.com/titanium/preset_150nm_physicallybased_300.png",
                                              "600": "https://example.com/titanium/preset_150nm_physicallybased_600.png"}]
    assert (hosted / "preset_150nm_physicallybased_600.png").read_bytes() == first["preset_150nm_physicallybased_600.png"]
    for url in ("ftp://example.com/x", "https://example.com/a b", "example.com/x", "https://example.com/?q=1"):
        bad = tmp_path / "bad"
        r = run_swatch("preset", "--thickness", "150", "--format", "physicallybased", "--out", bad, "--base-url", url)
        assert_one_line_error(r, "--base-url")
        assert r.returncode == 2 and not bad.exists()
    r = run_swatch("preset", "--thickness", "150", "--format", "gltf", "--out", tmp_path / "bad", "--base-url",
                   "https://example.com")
    assert_one_line_error(r, "--base-url")
    assert not (tmp_path / "bad").exists()


def test_catalog_physicallybased_base_url(tmp_path):
    """``[presets] physicallybased_base_url``: the catalog document's picture URLs are absolute under it and valid
    with ``format: uri`` asserted."""
    from swatch.catalog.presets_usd import physicallybased_files
    from swatch.catalog.spec import load_spec

    (tmp_path / "s.toml").write_text(SPEC + 'physicallybased_base_url = "https://example.com/cat/presets"\n',
                                     encoding="utf-8")
    spec, _ = load_spec(tmp_path / "s.toml")
    files = physicallybased_files(spec, [{"id": "S001", "thickness_nm": 60.0}])
    doc = json.loads(files["presets/physicallybased.json"])
    assert _errors(doc) == []
    assert doc["data"][0]["images"][0]["600"] == "https://example.com/cat/presets/preset_S001_physicallybased_600.png"
    assert sorted(files) == ["presets/physicallybased.json", "presets/preset_S001_physicallybased_300.png",
                             "presets/preset_S001_physicallybased_600.png"]


# -- the spec's options -----------------------------------------------------------------------

def test_spec_options_default_off_fingerprinted_and_checked(tmp_path):
    """``[presets] usd`` and ``physicallybased`` default to off and then leave the canonical spec (the build's
    fingerprint) as it is without them; on, they are in it (toggling rebuilds); without the presets, refused."""
    from swatch.catalog.spec import load_spec
    from swatch.core.errors import SwatchError

    base = 'name = "t"\n[thickness]\nlist_nm = [100]\n'
    (tmp_path / "off.toml").write_text(base, encoding="utf-8")
    (tmp_path / "explicit.toml").write_text(base + "[presets]\nusd = false\nphysicallybased = false\n", encoding="utf-8")
    (tmp_path / "on.toml").write_text(base + "[presets]\nusd = true\n", encoding="utf-8")
    (tmp_path / "pb.toml").write_text(base + "[presets]\nphysicallybased = true\n", encoding="utf-8")
    off, explicit, on, pb = (load_spec(tmp_path / f"{n}.toml")[0] for n in ("off", "explicit", "on", "pb"))
    assert not off.presets_usd and not off.presets_physicallybased
    assert "presets_usd" not in off.canonical() and "presets_physicallybased" not in off.canonical()
    assert explicit.canonical() == off.canonical()
    assert on.canonical() != off.canonical() and on.canonical()["presets_usd"] is True
    assert pb.canonical() != off.canonical() and pb.canonical() != on.canonical()
    for key in ("usd", "physicallybased"):
        (tmp_path / "bad.toml").write_text(base + f"[presets]\nenabled = false\nar = false\n{key} = true\n",
                                           encoding="utf-8")
        with pytest.raises(SwatchError, match=f"presets.{key}"):
            load_spec(tmp_path / "bad.toml")
        (tmp_path / "bad.toml").write_text(base + f'[presets]\n{key} = "yes"\n', encoding="utf-8")
        with pytest.raises(SwatchError, match=f"presets.{key}"):
            load_spec(tmp_path / "bad.toml")
    key = "presets.physicallybased_base_url"
    for extra in ('physicallybased = true\nphysicallybased_base_url = "ftp://example.com"\n',
                  'physicallybased = true\nphysicallybased_base_url = 3\n',
                  'physicallybased_base_url = "https://example.com"\n'):
        (tmp_path / "bad.toml").write_text(base + "[presets]\n" + extra, encoding="utf-8")
        with pytest.raises(SwatchError, match=key):
            load_spec(tmp_path / "bad.toml")
    (tmp_path / "url.toml").write_text(base + '[presets]\nphysicallybased = true\nphysicallybased_base_url = '
                                       '"https://example.com/p/"\n', encoding="utf-8")
    url = load_spec(tmp_path / "url.toml")[0]
    assert url.presets_physicallybased_base_url == "https://example.com/p"
    assert url.canonical() != pb.canonical() and "presets_physicallybased_base_url" not in pb.canonical()


def test_a_part_over_the_cap_is_refused_before_it_is_copied(monkeypatch):
    from swatch.core.errors import SwatchError
    from swatch.presets import usd

    corners = np.zeros((5, 3, 3))
    assert usd.triangle_part(corners + np.eye(3), corners + 1.0, "part.obj").triangles.shape == (5, 3)
    monkeypatch.setattr(usd, "MAX_USD_PART_TRIANGLES", 4)
    with pytest.raises(SwatchError, match=r"part.obj: 5 triangles; a USD preset's part has at most 4"):
        usd.triangle_part(corners, corners, "part.obj")
