"""The exact colour a preset should show at the geometries the real renderers are checked at (#18).

Exact: the Airy reflectance of the film on the substrate (``swatch.physics.model``) through the CIE 1931
2° observer under D65 (swatch's colorimeter, itself pinned to ``colour.sd_to_XYZ`` by
tests/presets/test_presets.py), CIELAB relative to the perfect white. A renderer's measured colour is its
linear Rec.709 ratio to a white metal plate rendered in the same light, converted with
colour-science's sRGB matrix. Geometries:

- ``mirror`` θ: the facet angle θ (roughness 0, or the specular direction);
- ``sun`` light L, view 0: the facet angle L/2 (single-scatter GGX: D and G cancel in the ratio);
- ``furnace`` view θ: the Fresnel averaged over the single-scatter GGX lobe (GGX D, height-
  correlated Smith G, as Cycles evaluates them) of a uniform white world — an independent
  Gauss–Legendre quadrature (scipy) over the reflected directions.
"""
from __future__ import annotations

import functools
import http.server
import shutil
import threading
from pathlib import Path

import colour
import numpy as np
from scipy.special import roots_legendre

from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, load_material, wavelength_grid
from swatch.physics.model import get_coating
from swatch.presets.fit import FIT_ANGLES_DEG
from tests.browser import CHROMIUM, WEBGL_ARGS, wait_until
from tests.tmm_reference import unpolarised_R

HERE = Path(__file__).resolve().parent
VENDOR = HERE / "vendor"
_SRGB = colour.RGB_COLOURSPACES["sRGB"]
_D65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]


def rgb_to_Lab(rgb) -> np.ndarray:
    """CIELAB (D65, 2°) of a linear Rec.709 reflectance (..., 3), 1 = perfect white."""
    return colour.XYZ_to_Lab(colour.RGB_to_XYZ(np.asarray(rgb, dtype=np.float64), _SRGB, illuminant=_D65), _D65)


@functools.lru_cache(maxsize=4)
def _setup(film: str, substrate: str, scale: float):
    wl = wavelength_grid(380.0, 780.0, 5.0)
    return get_coating(film, substrate, wl, scale), get_colorimeter(wl, "D65", "2")


def exact_XYZ(thickness_nm: float, theta_d_deg, film=DEFAULT_FILM, substrate=DEFAULT_SUBSTRATE,
              film_index_scale: float = 1.0) -> np.ndarray:
    """XYZ (A, 3), white Y = 100, of the exact reflectance at facet angles θ_d (degrees)."""
    coating, cm = _setup(film, substrate, float(film_index_scale))
    R = coating.reflectance(np.array([[float(thickness_nm)]]), np.asarray(theta_d_deg, dtype=np.float64)[None, :]).R[0]
    return cm.XYZ(R)


def exact_Lab(thickness_nm: float, theta_d_deg, **kw) -> np.ndarray:
    _, cm = _setup(kw.get("film", DEFAULT_FILM), kw.get("substrate", DEFAULT_SUBSTRATE),
                   float(kw.get("film_index_scale", 1.0)))
    return cm.Lab(exact_XYZ(thickness_nm, theta_d_deg, **kw))


@functools.cache
def tmm_exact_Lab(d_nm: float) -> np.ndarray:
    """The exact colour at FIT_ANGLES_DEG (A, 3), independently of swatch: tmm.coh_tmm spectra of the default
    film on its metal at facet angle θ_d, colour.sd_to_XYZ (D65, CIE 1931 2°, ASTM E308), colour.XYZ_to_Lab."""
    wl = np.arange(380.0, 781.0, 5.0)
    nf, ns = load_material(DEFAULT_FILM).nk(wl), load_material(DEFAULT_SUBSTRATE).nk(wl)
    cmfs, d65 = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], colour.SDS_ILLUMINANTS["D65"]
    white = colour.sd_to_XYZ(colour.sd_ones(colour.SpectralShape(380, 780, 5)), cmfs, d65)
    out = []
    for th in FIT_ANGLES_DEG:  # 13 angles x 81 wavelengths
        R = unpolarised_R([1.0, nf, ns], [np.inf, d_nm, np.inf], np.radians(th), wl)
        XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(dict(zip(wl, R, strict=True))), cmfs, d65)
        out.append(colour.XYZ_to_Lab(XYZ / white[1], colour.XYZ_to_xy(white)))
    return np.array(out)


def ggx_lobe_weights(view_deg: float, alpha: float, n: int = 256) -> tuple[np.ndarray, np.ndarray]:
    """Facet angles θ_d (M,) and weights (M,) of single-scatter GGX under a uniform world seen at
    ``view_deg``: ∫ D·G2/(4 cos θ_v) dω_l over the reflected directions (sum of weights = the white
    plate's albedo). Integrated over half vectors with the GGX mapping tan²θ_h = α²u/(1 − u)
    (D cos θ_h dω_h = du dφ/2π, dω_l = 4 (v·h) dω_h), Gauss–Legendre in u and φ."""
    x, w = roots_legendre(n)
    u, wu = 0.5 * (x + 1.0), 0.5 * w
    phi, wphi = np.pi * (x + 1.0), np.pi * w
    U, PHI = np.meshgrid(u, phi, indexing="ij")
    W = wu[:, None] * wphi[None, :] / (2.0 * np.pi)
    cos_h = 1.0 / np.sqrt(1.0 + alpha ** 2 * U / (1.0 - U))
    sin_h = np.sqrt(1.0 - cos_h ** 2)
    hx, hz = sin_h * np.cos(PHI), cos_h  # (hy does not enter: v lies in the x-z plane)
    tv = np.radians(view_deg)
    vx, vz = np.sin(tv), np.cos(tv)
    vh = hx * vx + hz * vz
    lz = 2.0 * vh * hz - vz  # l = 2 (v·h) h − v
    a2 = alpha ** 2

    def lam(c):
        c = np.clip(c, 1e-9, 1.0)
        return 0.5 * (-1.0 + np.sqrt(1.0 + a2 * (1.0 - c ** 2) / c ** 2))

    ok = (lz > 0.0) & (vh > 0.0)
    G2 = np.where(ok, 1.0 / (1.0 + lam(vz) + lam(lz)), 0.0)
    weight = W * G2 * np.clip(vh, 0.0, 1.0) / (vz * cos_h)
    return np.degrees(np.arccos(np.clip(vh, 0.0, 1.0))).ravel(), weight.ravel()


def furnace_Lab(thickness_nm: float, view_deg: float, alpha: float, **kw) -> np.ndarray:
    """The exact colour of a rough plate in a white furnace relative to a white plate (Lab, D65, 2°)."""
    theta, weight = ggx_lobe_weights(view_deg, alpha)
    bins = np.linspace(0.0, 90.0, 181)
    hist, _ = np.histogram(theta, bins=bins, weights=weight)
    centres = 0.5 * (bins[1:] + bins[:-1])
    XYZ = (hist[:, None] * exact_XYZ(thickness_nm, centres, **kw)).sum(axis=0) / hist.sum()
    _, cm = _setup(kw.get("film", DEFAULT_FILM), kw.get("substrate", DEFAULT_SUBSTRATE),
                   float(kw.get("film_index_scale", 1.0)))
    return cm.Lab(XYZ)


def renderer_delta_E(thickness_nm: float, kind: str, angle_deg: float, ratio_rgb, alpha: float, **kw) -> float:
    """ΔE2000 between a renderer's measured ratio (linear Rec.709) and the exact colour there."""
    if kind == "mirror":
        ref = exact_Lab(thickness_nm, [angle_deg], **kw)[0]
    elif kind == "sun":
        ref = exact_Lab(thickness_nm, [angle_deg / 2.0], **kw)[0]
    elif kind == "furnace":
        ref = furnace_Lab(thickness_nm, angle_deg, alpha, **kw)
    else:
        raise ValueError(kind)
    return float(delta_E_00(rgb_to_Lab(ratio_rgb), ref))


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


#: three.js geometries VIEW:LIGHT (degrees from the normal, opposite sides): 45:0 and mirror 0–60°.
THREEJS_GEOMETRIES = ((0.0, 45.0), (0.0, 0.0), (30.0, 30.0), (45.0, 45.0), (60.0, 60.0))


def render_in_threejs(gltf_paths, tmp_path, geometries=THREEJS_GEOMETRIES, browser=None) -> dict:
    """Render glTF files with the vendored three.js (GLTFLoader, MeshPhysicalMaterial) in headless
    Chromium (SwiftShader WebGL) through tests/presets_page/render.html; its ``window.result``.
    ``browser``: a running Playwright Chromium to open the page in (the suite's ``chromium``
    fixture); None launches one (the command line of :func:`main`)."""
    site = tmp_path / "site"
    site.mkdir()
    shutil.copy(HERE / "presets_page" / "render.html", site / "render.html")
    (site / "three").symlink_to(VENDOR / "three")
    names = []
    for i, path in enumerate(gltf_paths):
        shutil.copy(path, site / f"p{i}.gltf")
        names.append(f"p{i}.gltf")
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    geo = ",".join(f"{v:g}:{li:g}" for v, li in geometries)
    url = f"http://127.0.0.1:{server.server_address[1]}/render.html?gltf={','.join(names)}&geometries={geo}&intensity=1"
    try:
        if browser is None:
            from playwright.sync_api import sync_playwright

            with sync_playwright() as p:
                own = p.chromium.launch(executable_path=CHROMIUM, args=WEBGL_ARGS)
                result = _threejs_page(own, url, tmp_path)
                own.close()
        else:
            result = _threejs_page(browser, url, tmp_path)
    finally:
        server.shutdown()
    assert "error" not in result, result
    return result


def _threejs_page(browser, url: str, tmp_path) -> dict:
    page = browser.new_page()
    try:
        page.goto(url)
        wait_until(page, "() => window.result !== undefined", timeout_s=120.0)
        result = page.evaluate("window.result")
        page.screenshot(path=str(tmp_path / "threejs.png"))
    finally:
        page.close()
    return result


def _blender_rows(doc: dict, records: dict) -> list[tuple[str, str, float, float]]:
    import re

    rows = []
    for r in doc["results"]:
        rec = records[re.search(r"preset_(S\d+)_blender", r["preset"]).group(1)]
        for m in r["measurements"]:
            ratio = np.asarray(m["rgb"]) / (np.asarray(m["white_rgb"]) if "white_rgb" in m else 1.0)
            alpha = m["inputs"]["Roughness"] ** 2  # the preset's own (GGX α = roughness²)
            dE = renderer_delta_E(rec["thickness_nm"], m["kind"], m["angle_deg"], ratio, alpha)
            p = rec["presets"]
            single = m["kind"] == "sun" or (m["kind"] == "mirror" and m["angle_deg"] <= 45.0)
            stated = p["blender_max_delta_E_00_45"] if single else p["blender_max_delta_E_00"]
            rows.append((rec["id"], f"{m['kind']}:{m['angle_deg']:g} ({m['distribution']})", dE, stated))
    return rows


def _threejs_rows(result: dict, records: list[dict], prefix: str) -> list[tuple[str, str, float, float]]:
    """Rows (id, geometry, ΔE2000 to the exact colour, the stated figure) of a VIEW:LIGHT render."""
    old = {"threejs": "gltf", "materialx": "openpbr"}[prefix]  # the records' keys before #18
    rows = []
    for rec, got in zip(records, result["presets"], strict=True):
        p = rec["presets"]
        for row in got["rows"]:
            shown = np.asarray(row["preset"]) / np.asarray(row["reference"])
            facet = (row["view"] + row["light"]) / 2.0
            dE = float(delta_E_00(rgb_to_Lab(shown), exact_Lab(rec["thickness_nm"], [facet])[0]))
            if row["view"] != row["light"]:
                geo, stated = "45:0", p.get(f"{prefix}_delta_E_00_45_0", p.get(f"{old}_max_delta_E_00_45"))
            else:
                geo = f"mirror {row['view']:g}"
                key = "max_delta_E_00_45" if row["view"] <= 45.0 else "max_delta_E_00"
                stated = p.get(f"{prefix}_{key}", p.get(f"{old}_{key}"))
            rows.append((rec["id"], geo, dE, stated))
    return rows


def main(argv: list[str]) -> None:
    """``python -m tests.preset_reference threejs|materialx|blender CATALOG_DIR [PYTHON_WITH_BPY] [PRESET_DIR]``:
    every preset of a built catalog in the real renderer; per geometry the median / max ΔE2000
    against the exact colour and how many exceed the stated figure + 0.5 (#18's figures)."""
    import json
    import subprocess
    import tempfile

    what, folder = argv[0], Path(argv[1])
    records = json.loads((folder / "catalog.json").read_text(encoding="utf-8"))["swatches"]
    presets = Path(argv[3]) if len(argv) > 3 else folder
    with tempfile.TemporaryDirectory() as tmp:
        if what == "threejs":
            result = render_in_threejs([presets / r["presets"]["gltf"] for r in records], Path(tmp))
            rows = _threejs_rows(result, records, "threejs")
            print(f"three.js r{result['revision']}")
        elif what == "materialx":  # needs DISPLAY (an X server: Xvfb)
            import MaterialX

            result = {"presets": render_in_materialx([presets / r["presets"]["materialx"] for r in records], tmp)}
            rows = _threejs_rows(result, records, "materialx")
            print(f"MaterialX {MaterialX.getVersionString()} GLSL")
        else:
            files = [str(presets / r["presets"]["blender"]) for r in records]
            measure = ("mirror:0", "mirror:30", "mirror:45", "mirror:60", "sun:45", "furnace:0", "furnace:45")
            run = subprocess.run([argv[2], str(HERE / "presets_blender" / "mirror.py"), tmp, *measure, "--", *files],
                                 capture_output=True, text=True, check=True)
            doc = json.loads(next(ln for ln in run.stdout.splitlines() if ln.startswith("SWATCH-JSON "))[12:])
            rows = _blender_rows(doc, {r["id"]: r for r in records})
            print(f"Blender {doc['blender']}")
    for geo in sorted({g for _, g, _, _ in rows}):
        dE = np.array([d for _, g, d, _ in rows if g == geo])
        over = sum(d > s + 0.5 for _, g, d, s in rows if g == geo)
        print(f"{geo}: ΔE00 median {np.median(dE):.2f} max {dE.max():.2f}; over stated + 0.5: {over} of {dE.size}")



# -- MaterialX's own GLSL renderer (MaterialXRenderGlsl, Mesa under Xvfb) -----------------------

#: MaterialX geometries VIEW:LIGHT (degrees from the normal, opposite sides): 45:0 and mirror 0–60°.
MATERIALX_GEOMETRIES = THREEJS_GEOMETRIES


def render_in_materialx(mtlx_paths, tmp_path, geometries=MATERIALX_GEOMETRIES) -> list[dict]:
    """Render MaterialX documents with MaterialX's GLSL shader generator and renderer: a plane
    (+Z normal) under one directional light, orthographic camera 200 units away (a practically
    constant view direction), no environment, float read-back of the centre. Needs an OpenGL
    context (``DISPLAY``: the test starts Xvfb). For each document, per geometry: the mean linear
    RGB of the preset and of the same surface with a white metal (base_color 1, no thin film).

    One program for all documents (#17: each GLSL program costs Mesa's llvmpipe ~2.6 s to compile
    and ~1 s of draw variants on an empty shader cache, and the documents' sources differ only in
    their uniforms' default values): generated from the first document, then, per document, every
    input of its surface node as MaterialX reads it from the file (the node's own value, else its
    nodedef's default) is bound to the program's uniform for that input before it is drawn, so each
    picture is that of its file. Checked: a binding that did not take would draw every document
    like the first, and a document whose surface differs from the program's in anything but
    uniform values (another node, a connection) is refused."""
    import math

    import MaterialX as mx
    from MaterialX import PyMaterialXGenGlsl as mx_glsl
    from MaterialX import PyMaterialXGenShader as mx_gen
    from MaterialX import PyMaterialXRender as mx_render
    from MaterialX import PyMaterialXRenderGlsl as mx_render_glsl

    lib = mx.createDocument()
    search = mx.getDefaultDataSearchPath()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, lib)
    size = 16
    obj = Path(tmp_path) / "plane.obj"
    obj.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n", encoding="ascii")
    renderer = mx_render_glsl.GlslRenderer.create(size, size, mx_render.BaseType.FLOAT)
    renderer.initialize()
    geometry = mx_render.GeometryHandler.create()
    geometry.addLoader(mx_render.TinyObjLoader.create())
    geometry.loadGeometry(mx.FilePath(str(obj)), False)
    renderer.setGeometryHandler(geometry)
    renderer.setImageHandler(mx_render_glsl.GLTextureHandler.create(mx_render.StbImageLoader.create()))
    black = mx_render.createUniformImage(4, 4, 3, mx_render.BaseType.FLOAT, mx.Color4(0, 0, 0, 1))

    def lights(light_deg):
        doc = mx.createDocument()
        doc.importLibrary(lib)
        node = doc.addNode("directional_light", "sun", "lightshader")
        a = math.radians(light_deg)
        node.setInputValue("direction", mx.Vector3(math.sin(a), 0.0, -math.cos(a)), "vector3")  # from −x
        node.setInputValue("color", mx.Color3(1.0, 1.0, 1.0), "color3")
        node.setInputValue("intensity", 1.0, "float")
        return doc, [n for n in doc.getNodes() if n.getType() == "lightshader"]

    def surface(doc):
        return next(n for n in doc.getNodes() if n.getCategory() == "open_pbr_surface")

    def inputs(doc):
        """The surface's inputs as the document gives them: (nodedef name, {input: Value})."""
        node = surface(doc)
        nodedef = node.getNodeDef()
        assert not any(i.getConnectedNode() or i.hasInterfaceName() for i in node.getInputs()), node.getName()
        values = {}
        for i in nodedef.getActiveInputs():
            own = node.getInput(i.getName())
            given = own if own is not None and own.hasValueString() else i
            if given.hasValueString():
                values[i.getName()] = mx.Value.createValueFromStrings(given.getValueString(), given.getType())
        return nodedef.getName(), values

    def program(doc):
        """Generate and compile the document's shader once (the light's type registered; its
        direction is a uniform, bound at each render from the light handler); the uniform of each
        surface input by input name."""
        gen = mx_glsl.GlslShaderGenerator.create()
        ctx = mx_gen.GenContext(gen)
        ctx.registerSourceCodeSearchPath(search)
        opts = ctx.getOptions()
        opts.shaderInterfaceType = mx_gen.ShaderInterfaceType.SHADER_INTERFACE_COMPLETE  # inputs are uniforms
        opts.hwSpecularEnvironmentMethod = mx_gen.HwSpecularEnvironmentMethod.SPECULAR_ENVIRONMENT_PREFILTER
        opts.hwMaxActiveLightSources = 1
        opts.hwShadowMap = False
        opts.targetColorSpaceOverride = "lin_rec709"
        ldoc, sources = lights(45.0)
        handler = mx_render.LightHandler.create()
        handler.registerLights(ldoc, sources, ctx)
        shader = gen.generate("preset", mx_gen.findRenderableElements(doc)[0], ctx)
        renderer.createProgram(shader)
        prefix = surface(doc).getNamePath() + "/"
        block = shader.getStage(mx_gen.PIXEL_STAGE).getUniformBlock(mx_gen.HW_PUBLIC_UNIFORMS)
        ports = [block[i] for i in range(block.size())]
        uniforms = {p.getPath()[len(prefix):]: p.getVariable() for p in ports if p.getPath().startswith(prefix)}
        return handler, uniforms

    def draw(handler, view_deg, light_deg):
        _, sources = lights(light_deg)
        handler.setLightSources(sources)
        handler.setIndirectLighting(False)
        handler.setEnvRadianceMap(black)
        handler.setEnvIrradianceMap(black)
        renderer.setLightHandler(handler)
        camera = renderer.getCamera()
        v = math.radians(view_deg)
        eye = mx.Vector3(200.0 * math.sin(v), 0.0, 200.0 * math.cos(v))  # on +x: the mirror of the light
        camera.setViewMatrix(mx_render.Camera.createViewMatrix(eye, mx.Vector3(0, 0, 0), mx.Vector3(0, 1, 0)))
        camera.setProjectionMatrix(mx_render.Camera.createOrthographicMatrix(-0.1, 0.1, -0.1, 0.1, 100.0, 300.0))
        renderer.render()
        image = mx_render.Image.create(size, size, 4, mx_render.BaseType.FLOAT)
        image.createResourceBuffer()
        image = renderer.captureImage(image)
        px = [list(image.getTexelColor(x, y))[:3] for x in range(size // 2 - 2, size // 2 + 2)
              for y in range(size // 2 - 2, size // 2 + 2)]
        return np.mean(np.asarray(px), axis=0).tolist()

    def load(path, white=False):
        doc = mx.createDocument()
        mx.readFromXmlFile(doc, str(path))
        doc.importLibrary(lib)
        if white:
            node = surface(doc)
            node.setInputValue("base_color", mx.Color3(1.0, 1.0, 1.0), "color3")
            node.setInputValue("thin_film_weight", 0.0, "float")
        return doc

    first = load(mtlx_paths[0])
    handler, uniforms = program(first)
    nodedef, _ = inputs(first)
    assert {"base_color", "thin_film_thickness", "thin_film_ior", "thin_film_weight"} <= uniforms.keys(), uniforms

    def bind(doc):
        """The document's surface values into the program's uniforms (the render binds only the
        view, the lights and the textures, so they hold until the next bind)."""
        name, values = inputs(doc)
        assert name == nodedef, (name, nodedef)  # the same surface: only values differ
        gl = renderer.getProgram()
        assert gl.bind()  # glUniform sets the program in use
        for key, value in values.items():
            if key in uniforms:
                gl.bindUniform(uniforms[key], value, True)
        gl.unbind()

    bind(load(mtlx_paths[0], white=True))  # the white metal: the same for every preset
    reference = [draw(handler, v, li) for v, li in geometries]
    out = []
    for path in mtlx_paths:
        bind(load(path))
        rows = [{"view": v, "light": li, "preset": draw(handler, v, li), "reference": ref}
                for (v, li), ref in zip(geometries, reference, strict=True)]
        out.append({"file": str(path), "rows": rows})
    return out


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])


def write_catalog_presets(spec_text: str, root: Path):
    """The presets a catalog of ``spec_text`` writes (swatch.catalog.presets.catalog_presets), written under
    ``root``: (spec, records with their ``presets`` entries, root, {name: bytes})."""
    from swatch.catalog.context import catalog_context
    from swatch.catalog.presets import catalog_presets
    from swatch.catalog.records import compute
    from swatch.catalog.spec import load_spec

    (root / "s.toml").write_text(spec_text, encoding="utf-8")
    spec, _ = load_spec(root / "s.toml")
    data = compute(catalog_context(spec))
    files, entries = catalog_presets(spec, data.records, root)
    for name, blob in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_bytes(blob)
    return spec, [dict(r, presets=e) for r, e in zip(data.records, entries, strict=True)], root, files
