"""3-D material presets: the ported renderer models against exact references, the written files
against real readers (Khronos glTF validator, MaterialX, three.js in Chromium), and the errors the
catalog states against the exact colour."""
from __future__ import annotations

import ast
import functools
import json
import os
import shutil
import subprocess
from pathlib import Path

import colour
import numpy as np
import pytest

from swatch.catalog.presets import catalog_presets
from swatch.colorimetry.colorimeter import delta_E_00
from swatch.presets import cycles, gltf, openpbr, spectral
from swatch.presets.fit import FIT_ANGLES_DEG, exact_Lab, model_Lab
from tests.preset_reference import tmm_exact_Lab as _tmm_exact_Lab
from tests.preset_reference import write_catalog_presets
from tests.tmm_reference import unpolarised_R

pytestmark = pytest.mark.slow  # builds catalogs or runs processes (seconds per test)

HERE = Path(__file__).resolve().parents[1]  # tests/
VENDOR = HERE / "vendor"
WL = np.arange(360.0, 831.0, 1.0)


# -- the ports where their assumptions hold, against tmm -------------------------------------

@functools.lru_cache(maxsize=1)
def _rgb_cmfs():

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.asarray(cmfs[WL]) @ spectral.XYZ_TO_REC709.T


def _tmm_rgb(n_film, n_base, d_nm, theta_deg):
    """Unpolarised film reflectance from coh_tmm, integrated against the CIE 1931 CMFs in Rec.709
    (equal energy, each channel normalised: the spectral weighting the Fourier tables encode)."""
    R = unpolarised_R([1.0, n_film, n_base], [np.inf, d_nm, np.inf], np.radians(theta_deg), WL)
    w = _rgb_cmfs()
    return (R @ w) / w.sum(axis=0)


def _dE(rgb1, rgb2):
    return float(delta_E_00(spectral.rgb_to_Lab(rgb1), spectral.rgb_to_Lab(rgb2)))


@pytest.mark.parametrize("n_film,n_base,d,theta", [(2.0, 1.5, 300, 0), (2.0, 1.5, 300, 40), (1.4, 2.4, 500, 30),
                                                   (2.3, 1.5, 120, 60), (1.33, 1.0, 400, 20)])
def test_cycles_film_on_dielectric_equals_tmm(n_film, n_base, d, theta):
    """Cycles' Airy series (3 orders, tabulated CMF transform) on a dielectric: exact up to truncation."""
    model = cycles.film_on_dielectric_fresnel(np.cos(np.radians(theta)), d, n_film, n_base)
    assert _dE(model, _tmm_rgb(n_film, n_base, d, theta)) < 0.5


@pytest.mark.parametrize("n_film,n,k,d,theta", [(2.4, 2.0, 3.0, 100, 0), (2.4, 2.7, 3.7, 200, 30),
                                                 (1.5, 0.2, 3.0, 300, 45), (2.0, 1.5, 2.0, 150, 60)])
def test_openpbr_film_on_conductor_equals_tmm(n_film, n, k, d, theta, monkeypatch):
    """OpenPBR's metal branch (polarised conductor amplitudes and phases) on a metal of known n, k.

    The F82-tint → (n, k) mapping is replaced by the metal's true n, k, so the thin-film physics
    itself is checked: phases of the metal and the film, both polarisations, the series.
    """
    monkeypatch.setattr(openpbr, "gulbrandsen_nk", lambda r, g: (np.full(3, n), np.full(3, k)))
    model = openpbr.thin_film_metal_fresnel(np.cos(np.radians(theta)), d, n_film, np.full(3, 0.5))
    assert _dE(model, _tmm_rgb(n_film, n + 1j * k, d, theta)) < 0.5


@pytest.mark.parametrize("n_film,n_base,d", [(2.0, 1.5, 300), (1.4, 2.4, 500), (2.3, 1.5, 120), (1.8, 1.45, 250)])
def test_gltf_at_normal_incidence_on_dielectric_near_tmm(n_film, n_base, d):
    """At normal incidence on a dielectric, Schlick and the 0/π phases are exact: what remains is
    the extension's Gaussian fit of the CMF transforms (and its per-XYZ phase), a few ΔE2000.
    A sign or phase error would be tens of ΔE (the glTF-vs-exact gap on titanium is ~50)."""
    f0 = ((n_base - 1.0) / (n_base + 1.0)) ** 2 - 0.0001  # the README adds 1e-4 before Fresnel0ToIor
    model = gltf.iridescent_fresnel(1.0, d, n_film, np.full(3, f0))
    assert _dE(model, _tmm_rgb(n_film, n_base, d, 0.0)) < 6.0


def test_cycles_sensitivity_table_is_the_cmf_transform():
    """Cycles' table (the precompute recipe) against a direct quadrature of the CMFs' transform."""
    opd = np.array([0.0, 150.0, 600.0, 1400.0, 3000.0])
    w = _rgb_cmfs()
    direct = (np.exp(-2j * np.pi * opd[:, None] / WL[None, :]) @ w) / w.sum(axis=0)
    assert np.abs(spectral.cmf_sensitivity(opd) - direct).max() < 0.01


def test_cycles_f82_metal_without_film_is_its_f82_curve():
    """A 0 nm film leaves Cycles' F82-tint metal Fresnel (the film IOR blends to the ambient)."""
    base = np.array([0.6, 0.5, 0.4])
    c = np.linspace(0.2, 1.0, 5)
    got = cycles.principled_metal_fresnel(c, 0.0, 2.4, base)
    want = cycles.f82(c[:, None], base, cycles.f82tint_B(base, 1.0))
    assert np.abs(got - want).max() < 0.02


# -- presets of a small catalog: the stated errors hold for the files as written --------------

SPEC = """
name = "preset test"
[thickness]
list_nm = [25, 60, 120, 190, 260]
[render]
roughness = 0.3
"""


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    return write_catalog_presets(SPEC, tmp_path_factory.mktemp("presets"))


def _params_gltf(path):
    doc = json.loads(path.read_text(encoding="utf-8"))
    m = doc["materials"][0]
    ir = m["extensions"]["KHR_materials_iridescence"]
    return [ir["iridescenceThicknessMaximum"], ir["iridescenceIor"], *m["pbrMetallicRoughness"]["baseColorFactor"][:3]]


def _params_blender(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    node = next(n for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "INPUTS")
    inputs = ast.literal_eval(node.value)
    return [inputs["Thin Film Thickness"], inputs["Thin Film IOR"], *inputs["Base Color"][:3]]


def _params_materialx(path):
    import MaterialX as mx

    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    node = doc.getNodes()[0] if doc.getNodes()[0].getCategory() == "open_pbr_surface" else doc.getNodes()[1]
    v = {i.getName(): i.getValue() for i in node.getInputs()}
    assert v["base_metalness"] == 1.0 and v["thin_film_weight"] == 1.0
    return [v["thin_film_thickness"] * 1000.0, v["thin_film_ior"], *list(v["base_color"])]


@pytest.mark.parametrize("fmt,prefix,reader", [("gltf", "threejs", _params_gltf), ("gltf", "gltf", _params_gltf),
                                               ("blender", "blender", _params_blender),
                                               ("materialx", "materialx", _params_materialx),
                                               ("materialx", "openpbr", _params_materialx)])
def test_written_presets_hold_their_stated_error(written, fmt, prefix, reader):
    """Each figure in a record is the error of the file as written (rounded), under its model (#17 item 7: the
    error recomputed independently of the function that produced it: the exact colour from tmm and
    colour.sd_to_XYZ, ΔE2000 by colour.delta_E; the model is the port, itself checked against the real
    renderer by the tests of tests/preset_reference.py)."""
    from swatch.catalog.presets import FIGURE_MODELS

    _spec, records, root, _ = written
    for rec in records:
        params = np.asarray(reader(root / rec["presets"][fmt]), dtype=np.float64)
        rough = float(np.sqrt(0.3).round(4))
        model = model_Lab(FIGURE_MODELS[prefix], params[None], FIT_ANGLES_DEG, rough)[0]  # (A, 3)
        dE = np.asarray(colour.delta_E(model, _tmm_exact_Lab(float(rec["thickness_nm"])), method="CIE 2000"))
        stated, stated_45 = rec["presets"][f"{prefix}_max_delta_E_00"], rec["presets"][f"{prefix}_max_delta_E_00_45"]
        assert abs(dE.max() - stated) <= 0.06, (rec["id"], dE.max(), stated)
        assert abs(dE[FIT_ANGLES_DEG <= 45].max() - stated_45) <= 0.06, (rec["id"], dE, stated_45)
        if prefix == "blender":
            assert dE[FIT_ANGLES_DEG <= 45].max() <= 3.0, (rec["id"], dE)  # the issue's target


def test_exact_colour_is_colour_science_of_the_tmm_spectrum():
    """The fit target: the Airy spectrum (here from tmm) through colour.sd_to_XYZ, D65, 2°."""

    from swatch.physics.materials import load_material

    d, th = 140.0, 30.0
    wl = np.arange(380.0, 781.0, 5.0)
    nf, ns = load_material("TiO2-Siefke").nk(wl), load_material("Ti-Johnson").nk(wl)
    R = unpolarised_R([1.0, nf, ns], [np.inf, d, np.inf], np.radians(th), wl)
    sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
    XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], colour.SDS_ILLUMINANTS["D65"])
    white = colour.sd_to_XYZ(colour.sd_ones(colour.SpectralShape(380, 780, 5)),
                             colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], colour.SDS_ILLUMINANTS["D65"])
    Lab = colour.XYZ_to_Lab(XYZ / white[1], colour.XYZ_to_xy(white))
    assert float(delta_E_00(exact_Lab([d], [th])[0, 0], Lab)) < 0.05


def test_preset_files_are_deterministic(written, tmp_path):
    spec, records, _, files = written
    again, _ = catalog_presets(spec, [dict(r) for r in records], None)
    assert again == files


def test_materialx_documents_validate(written):
    import MaterialX as mx

    _, records, root, _ = written
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    for rec in records:
        doc = mx.createDocument()
        mx.readFromXmlFile(doc, str(root / rec["presets"]["materialx"]))
        doc.importLibrary(lib)
        ok, msg = doc.validate()
        assert ok, msg


def test_blender_script_refuses_blender_before_5(written):
    """Blender 4.2–4.5 ignore Thin Film on a metallic Principled BSDF (measured with bpy 4.5.15:
    the mirror colour is the bare Base Color at every film thickness), so the script refuses
    them; checked with a stand-in ``bpy`` reporting 4.5 (the real one is below)."""
    import sys
    import types

    _, records, root, _ = written
    made = []
    bpy = types.SimpleNamespace(app=types.SimpleNamespace(version=(4, 5, 15), version_string="4.5.15 LTS"),
                                data=types.SimpleNamespace(materials=types.SimpleNamespace(
                                    get=lambda n: None, new=made.append)))
    sys.modules["bpy"] = bpy
    try:
        src = (root / records[0]["presets"]["blender"]).read_text(encoding="utf-8")
        with pytest.raises(RuntimeError, match=r"needs Blender 5\.0 or later"):
            exec(compile(src, "preset", "exec"), {})
    finally:
        del sys.modules["bpy"]
    assert made == []  # nothing created


def _blender_commands() -> list[tuple[str, list[str]]]:
    """How to run a script in real Blender: ``$SWATCH_BLENDER_PYTHON``, one or more Pythons with
    ``bpy`` from PyPI separated by ``os.pathsep`` (bpy 5.0 needs numpy < 2 and 5.2 Python 3.13, so
    each lives in its own environment: .ci/run makes two), else a ``blender`` executable on PATH.
    Missing: skip, or fail with ``SWATCH_REQUIRE_BLENDER=1`` (CI)."""
    script = str(HERE / "presets_blender" / "mirror.py")
    pys = [p for p in os.environ.get("SWATCH_BLENDER_PYTHON", "").split(os.pathsep) if p and Path(p).exists()]
    out = [(Path(p).parent.parent.name, [p, script]) for p in pys]
    exe = shutil.which("blender")
    if exe:
        out.append(("blender", [exe, "-b", "--factory-startup", "--python", script, "--"]))
    return out


def _blender_ids() -> list[str]:
    return [name for name, _ in _blender_commands()] or ["none"]


#: Cycles measurements (tests/presets_blender/mirror.py): mirror (roughness 0) at facet angles, the
#: sun at 45° seen along the normal (45:0) and a white furnace seen at 0° and 45°, both at the
#: preset's own roughness and distribution.
BLENDER_MEASUREMENTS = ("mirror:0", "mirror:30", "mirror:45", "mirror:60", "sun:45", "furnace:0", "furnace:45")


@pytest.mark.slow
@pytest.mark.parametrize("blender", _blender_ids())
def test_blender_preset_in_real_blender(written, tmp_path, blender):
    """#18: the written script run in real Blender (``bpy`` 5.0 and 5.2 from PyPI, Cycles) builds and
    assigns the material with the stated inputs and the GGX distribution it was fitted for, and
    what Cycles renders — the mirror colour at 0–60°, the plate at 45:0 and in a white furnace at
    the preset's own roughness, each relative to a white metal plate in the same light — is within
    the error catalog.json states + 0.5 of the exact colour there (swatch.physics.model + colour-science,
    D65, 2°; the furnace by an independent quadrature over the GGX lobe). Where the geometry is a
    single facet angle (mirror, 45:0) the render also equals our numpy port of Cycles' thin film."""
    from tests.preset_reference import renderer_delta_E

    commands = dict(_blender_commands())
    if blender not in commands:
        if os.environ.get("SWATCH_REQUIRE_BLENDER") == "1":
            pytest.fail("SWATCH_REQUIRE_BLENDER=1 but neither SWATCH_BLENDER_PYTHON nor a blender executable is there")
        pytest.skip("no Blender: set SWATCH_BLENDER_PYTHON to a Python with bpy>=5.0 (see .ci/run) or put blender on PATH")
    _, records, root, _ = written
    chosen = (records[1], records[3])  # 60 and 190 nm
    presets = [str(root / rec["presets"]["blender"]) for rec in chosen]
    run = subprocess.run([*commands[blender], str(tmp_path), *BLENDER_MEASUREMENTS, "--", *presets],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    doc = json.loads(next(ln for ln in run.stdout.splitlines() if ln.startswith("SWATCH-JSON "))[12:])
    assert tuple(int(x) for x in doc["blender"].split()[0].split(".")[:2]) >= (5, 0)
    for rec, result in zip(chosen, doc["results"], strict=True):
        d, eta, *base = _params_blender(root / rec["presets"]["blender"])
        stated = rec["presets"]["blender_max_delta_E_00"]
        for m in result["measurements"]:
            assert m["assigned"] == f"{rec['id']} anodised {rec['thickness_nm']:g} nm"
            assert m["distribution"] == "GGX"
            got = m["inputs"]
            assert got["Metallic"] == 1.0 and got["Roughness"] == pytest.approx(np.sqrt(0.3), abs=1e-4)
            assert got["Thin Film Thickness"] == pytest.approx(d, rel=1e-6)
            assert got["Thin Film IOR"] == pytest.approx(eta, rel=1e-6)
            assert got["Base Color"][:3] == pytest.approx(base, rel=1e-6)
            rgb = np.asarray(m["rgb"]) / (np.asarray(m["white_rgb"]) if "white_rgb" in m else 1.0)
            facet = {"mirror": m["angle_deg"], "sun": m["angle_deg"] / 2.0}.get(m["kind"])
            if facet is not None:  # measured: equal to 4 decimals
                port = cycles.principled_metal_fresnel(np.cos(np.radians(facet)), d, eta, np.array(base))
                assert np.abs(rgb - port).max() < 2e-3, (m, port)
            dE = renderer_delta_E(rec["thickness_nm"], m["kind"], m["angle_deg"], rgb, 0.3)
            assert dE <= stated + 0.5, (rec["id"], m["kind"], m["angle_deg"], dE, stated)
            if m["kind"] == "sun" or (m["kind"] == "mirror" and m["angle_deg"] <= 45.0):
                assert dE <= rec["presets"]["blender_max_delta_E_00_45"] + 0.5, (m, dE)


# -- real readers: the Khronos validator, three.js in Chromium --------------------------------

def test_gltf_presets_pass_khronos_validator(written):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node not installed")
    _, records, root, _ = written
    script = ("const v=require(process.argv[1]);const fs=require('fs');"
              "Promise.all(process.argv.slice(2).map(f=>v.validateBytes(new Uint8Array(fs.readFileSync(f)),"
              "{writeTimestamp:false,maxIssues:0}))).then(r=>console.log(JSON.stringify(r.map(x=>x.issues))));")
    paths = [str(root / r["presets"]["gltf"]) for r in records]
    out = subprocess.run([node, "-e", script, str(VENDOR / "gltf-validator" / "index.js"), *paths],
                         capture_output=True, text=True, timeout=120, check=True)
    for issues in json.loads(out.stdout):
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0 and issues["numInfos"] == 0, issues


@pytest.mark.browser
def test_gltf_preset_in_threejs_matches(written, tmp_path, chromium):
    """#18: three.js r187 (the vendored copy: GLTFLoader, MeshPhysicalMaterial iridescence) renders
    each preset plate under a directional light at 45:0 and at mirror geometries 0–60°. Its colour
    relative to a white metal plate in the same light (float render target, linear) equals our port
    of what three.js computes (swatch.presets.threejs: the film at N·V, the direct-light multiscatter
    factor from its DFG LUT) and is within the figures catalog.json states for three.js + 0.5 of the
    exact colour (45:0: the facet angle 22.5°; mirror θ: θ)."""
    from swatch.presets import threejs
    from tests.preset_reference import render_in_threejs

    _, records, root, _ = written
    result = render_in_threejs([root / r["presets"]["gltf"] for r in records], tmp_path, browser=chromium)
    assert result["revision"] == threejs.REVISION.removeprefix("r")
    worst_port = 0.0
    for rec, got in zip(records, result["presets"], strict=True):
        info = got["info"]
        assert info["type"] == "MeshPhysicalMaterial" and info["iridescence"] == 1.0 and info["metalness"] == 1.0
        params = np.asarray(_params_gltf(root / rec["presets"]["gltf"]))
        assert info["iridescenceIOR"] == pytest.approx(params[1]) and info["thicknessRange"][1] == pytest.approx(params[0])
        assert info["roughness"] == pytest.approx(np.sqrt(0.3), abs=1e-4)
        stated = rec["presets"]
        for row in got["rows"]:
            ref = np.asarray(row["reference"])
            assert ref.min() > 0.01, row  # the white plate is lit
            shown = np.asarray(row["preset"]) / ref
            view, light = row["view"], row["light"]
            port = threejs.displayed_fresnel(np.cos(np.radians(view)), params[0], params[1], params[2:],
                                             info["roughness"])
            worst_port = max(worst_port, _dE(shown, port))
            assert _dE(shown, port) <= 0.3, (rec["id"], row, port)
            facet = (view + light) / 2.0
            dE = float(delta_E_00(spectral.rgb_to_Lab(shown), exact_Lab([rec["thickness_nm"]], [facet])[0, 0]))
            if view != light:  # 45:0
                assert dE <= stated["threejs_delta_E_00_45_0"] + 0.5, (rec["id"], row, dE)
            else:
                assert dE <= stated["threejs_max_delta_E_00"] + 0.5, (rec["id"], row, dE)
                if view <= 45.0:
                    assert dE <= stated["threejs_max_delta_E_00_45"] + 0.5, (rec["id"], row, dE)
    print(f"three.js vs port: max ΔE00 {worst_port:.3f}")
    shot = os.environ.get("SWATCH_PRESET_SCREENSHOT")
    if shot:
        shutil.copy(tmp_path / "threejs.png", shot)


@pytest.mark.slow
def test_materialx_preset_in_materialx_renderer(written, tmp_path, xvfb_display):
    """#18: MaterialX 1.39.5's own GLSL shader generator and renderer (Mesa under Xvfb) render each
    .mtlx preset (OpenPBR Surface, metal under a thin film) under a directional light at 45:0 and
    at mirror geometries 0–60°. Relative to a white metal in the same light it equals our port of
    that GLSL (swatch.presets.materialx: mx_fresnel_airy, its energy compensation) and is within
    the figures catalog.json states for MaterialX + 0.5 of the exact colour."""
    import MaterialX as mx

    from swatch.presets import materialx
    from tests.preset_reference import render_in_materialx

    assert mx.getVersionString() == materialx.VERSION
    _, records, root, _ = written
    result = render_in_materialx([root / r["presets"]["materialx"] for r in records], tmp_path)
    for rec, got in zip(records, result, strict=True):
        d, eta, *base = _params_materialx(root / rec["presets"]["materialx"])
        stated = rec["presets"]
        for row in got["rows"]:
            ref = np.asarray(row["reference"])
            assert ref.min() > 0.05, row  # the white plate is lit
            shown = np.asarray(row["preset"]) / ref
            view, light = row["view"], row["light"]
            facet = (view + light) / 2.0
            port = materialx.displayed_fresnel(np.cos(np.radians(facet)), d, eta, np.array(base), np.sqrt(0.3).round(4),
                                               cos_nv=np.cos(np.radians(view)))
            assert np.abs(shown - port).max() < 1e-3, (rec["id"], row, port)  # measured: 7 digits
            dE = float(delta_E_00(spectral.rgb_to_Lab(shown), exact_Lab([rec["thickness_nm"]], [facet])[0, 0]))
            if view != light:  # 45:0
                assert dE <= stated["materialx_delta_E_00_45_0"] + 0.5, (rec["id"], row, dE)
            else:
                assert dE <= stated["materialx_max_delta_E_00"] + 0.5, (rec["id"], row, dE)
                if view <= 45.0:
                    assert dE <= stated["materialx_max_delta_E_00_45"] + 0.5, (rec["id"], row, dE)


# -- the command ------------------------------------------------------------------------------

def test_preset_command(tmp_path):
    from tests.cli_helpers import assert_one_line_error, run_swatch

    r = run_swatch("preset", "--thickness", "150", "--format", "gltf", "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    path = tmp_path / "preset_150nm.gltf"
    assert path.is_file() and "max ΔE2000" in r.stdout
    first = path.read_bytes()
    assert_one_line_error(run_swatch("preset", "--thickness", "150", "--format", "gltf", "--out", tmp_path),
                          "already exists")
    r = run_swatch("preset", "--thickness", "150", "--format", "gltf", "--out", tmp_path,
                   "--force")
    assert r.returncode == 0 and path.read_bytes() == first
    bad = run_swatch("preset", "--thickness", "-5", "--format", "blender", "--out", tmp_path)
    assert_one_line_error(bad, "thickness")
    assert bad.returncode == 2 and not (tmp_path / "preset_-5nm_blender.py").exists()


def test_model_Lab_shapes():
    p = np.array([[150.0, 2.3, 0.6, 0.5, 0.4], [90.0, 2.1, 0.5, 0.5, 0.5]])
    for m in ("gltf", "threejs", "cycles", "openpbr", "materialx"):
        assert model_Lab(m, p, FIT_ANGLES_DEG).shape == (2, FIT_ANGLES_DEG.size, 3)


def test_default_catalog_meets_the_target():
    """The default catalog (20–300 nm): Blender presets within 3 ΔE2000 at facet angles 0–45° as Cycles
    renders them; glTF as three.js shows it within 3 at the catalog's 45:0 for most swatches (#18:
    three.js evaluates the film at N·V, so a colour that changes fast with angle cannot be met at
    both 0° and 45:0; the files and catalog.json state the figure per swatch)."""
    from swatch.catalog.context import catalog_context
    from swatch.catalog.records import compute
    from swatch.catalog.spec import load_spec

    spec, _ = load_spec(HERE.parent / "catalog" / "titanium.toml")
    records = compute(catalog_context(spec)).records
    _, entries = catalog_presets(spec, records, None)
    assert max(e["blender_max_delta_E_00_45"] for e in entries) <= 3.0
    at_45_0 = np.array([e["threejs_delta_E_00_45_0"] for e in entries])
    assert np.median(at_45_0) <= 2.0 and (at_45_0 <= 3.0).mean() >= 0.8, at_45_0  # measured: 1.47, 47 of 57


def test_a_damaged_fit_cache_is_refitted(written, tmp_path):
    spec, records, root, files = written
    caches = list(root.glob("presets-*.json"))
    assert len(caches) == 1
    cache = tmp_path / "cache"
    cache.mkdir()
    for junk in ('{"gltf": {"params": [[1, 2]]}}', "not json", '{"gltf": 3}'):
        (cache / caches[0].name).write_text(junk, encoding="utf-8")
        assert catalog_presets(spec, [dict(r) for r in records], cache)[0] == files
