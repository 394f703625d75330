"""What the vendored ``<model-viewer>`` (swatch/catalog/web/model-viewer) shows of a preset, measured in headless
Chromium (SwiftShader WebGL), for the bench (bench_presets: ``presets_modelviewer_*``) and
tests/catalog/test_catalog_ar.py (#47).

:func:`render_in_model_viewer` serves tests/presets_page/modelviewer.html with the vendored script, an even white
environment image (``white.png``, sRGB 230/255: linear 0.79, so nothing clips), a white metal plate (``white.gltf``: colour 1, no
iridescence) and the given preset plates; the page sets tone mapping off and reads the 8-bit sRGB centre of the
canvas at each view angle (``camera-orbit``'s polar angle from the plate normal). :func:`shown_ratio` decodes
that to linear Rec.709 relative to the white plate (colour-science's sRGB decoding); :func:`plate_gltf` writes a
viewer file's material onto the 10 cm plate (its geometry is not what is measured: its material is).
"""
from __future__ import annotations

import functools
import http.server
import json
import shutil
import threading
from pathlib import Path

import colour
import numpy as np
from PIL import Image

from swatch.presets.write import gltf_bytes

ROOT = Path(__file__).resolve().parents[1]
MODEL_VIEWER = ROOT / "swatch" / "catalog" / "web" / "model-viewer"
PAGE = ROOT / "tests" / "presets_page" / "modelviewer.html"
#: Debian's Chromium builds, preferred first (as tests/browser.py), and the flags for SwiftShader WebGL.
CHROMIUM_BUILDS = ("/usr/bin/chromium-headless-shell", "/usr/bin/chromium")
WEBGL_ARGS = ["--headless", "--no-sandbox", "--no-first-run", "--disable-background-networking",
              "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-compositing",
              "--disable-gpu-rasterization"]
#: View angles (degrees from the plate normal) the measurement takes: 0–60° every 5° (as FIT_ANGLES_DEG).
VIEWS_DEG = tuple(float(v) for v in range(0, 61, 5))
#: The environment image's sRGB value: linear 0.79, so the white plate stays below 1 (no tone mapping, no clipping).
SURROUND_SRGB8 = 230


def material_params(gltf_path) -> tuple[np.ndarray, float]:
    """``(thickness_nm, IOR, base R, G, B)`` and roughness of a preset or viewer file's first material."""
    m = json.loads(Path(gltf_path).read_text(encoding="utf-8"))["materials"][0]
    ir = m["extensions"]["KHR_materials_iridescence"]
    pbr = m["pbrMetallicRoughness"]
    return (np.array([ir["iridescenceThicknessMaximum"], ir["iridescenceIor"], *pbr["baseColorFactor"][:3]]),
            float(pbr["roughnessFactor"]))


def plate_gltf(params, roughness: float, white: bool = False) -> bytes:
    """The 10 cm plate with the preset's material (``white``: colour 1 without the iridescence extension)."""
    if not white:
        return gltf_bytes("preset", params, roughness)
    doc = json.loads(gltf_bytes("white", [100.0, 1.5, 1.0, 1.0, 1.0], roughness))
    doc.pop("extensionsUsed")
    doc["materials"][0].pop("extensions")
    return json.dumps(doc).encode()


def shown_ratio(row, white_row) -> np.ndarray:
    """Linear Rec.709 of a preset's centre relative to the white plate's at the same view."""
    lin = colour.models.eotf_sRGB(np.asarray(row["rgb"], dtype=np.float64))
    ref = colour.models.eotf_sRGB(np.asarray(white_row["rgb"], dtype=np.float64))
    return lin / ref


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def render_in_model_viewer(plates, roughness: float, tmp_path, views_deg=VIEWS_DEG, browser=None) -> dict:
    """Render preset plates (parameter rows) in the vendored ``<model-viewer>``; the page's ``window.result``
    (``white``: the white plate's rows; ``presets``: each plate's rows ``{view, rgb, alpha}``).
    ``browser``: a running Playwright Chromium (None: one is launched)."""
    site = tmp_path / "mv-site"
    site.mkdir()
    shutil.copy(PAGE, site / "index.html")
    (site / "model-viewer").symlink_to(MODEL_VIEWER)
    Image.new("RGB", (64, 32), (SURROUND_SRGB8,) * 3).save(site / "white.png")
    (site / "white.gltf").write_bytes(plate_gltf(None, roughness, white=True))
    names = []
    for i, p in enumerate(plates):
        (site / f"p{i}.gltf").write_bytes(plate_gltf(p, roughness))
        names.append(f"p{i}.gltf")
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    url = (f"http://127.0.0.1:{server.server_address[1]}/index.html?gltf={','.join(names)}"
           f"&views={','.join(f'{v:g}' for v in views_deg)}")
    try:
        if browser is None:
            from playwright.sync_api import sync_playwright

            with sync_playwright() as p:
                exe = next((c for c in CHROMIUM_BUILDS if Path(c).exists()), CHROMIUM_BUILDS[-1])
                own = p.chromium.launch(executable_path=exe, args=WEBGL_ARGS)
                try:
                    return _run(own, url)
                finally:
                    own.close()
        return _run(browser, url)
    finally:
        server.shutdown()
        server.server_close()


def _run(browser, url: str) -> dict:
    page = browser.new_page(viewport={"width": 160, "height": 160}, device_scale_factor=1)
    try:
        page.goto(url)
        page.wait_for_function("() => window.result !== undefined", timeout=300_000, polling=100)
        result = page.evaluate("() => window.result")
    finally:
        page.close()
    if "error" in result:
        raise AssertionError(result["error"])
    return result


def modelviewer_figures(spec, browser=None) -> dict[str, float]:
    """The bench's ``presets_modelviewer_*``: the catalog's ``<model-viewer>`` presets of ``spec``
    (:func:`swatch.catalog.ar.viewer_fit`) as the vendored ``<model-viewer>`` shows them, ΔE2000 (D65, CIE 1931 2°)
    against the exact colour at the view angle: ``dE00_45_median`` / ``dE00_45_max`` of each swatch's largest error
    over 0–45°, ``dE00_60_max`` over 0–60°."""
    import tempfile

    from swatch.catalog.ar import viewer_fit
    from swatch.colorimetry.colorimeter import delta_E_00
    from swatch.presets.files import roughness_factor
    from swatch.presets.fit import exact_Lab
    from swatch.presets.spectral import rgb_to_Lab

    params, _, _ = viewer_fit(spec)
    with tempfile.TemporaryDirectory(prefix="swatch-mv-") as tmp:
        result = render_in_model_viewer(params, roughness_factor(spec.roughness), Path(tmp), browser=browser)
    shown = np.array([[shown_ratio(row, white) for row, white in zip(got["rows"], result["white"], strict=True)]
                      for got in result["presets"]])  # (N, A, 3) linear Rec.709
    views = np.asarray(VIEWS_DEG)
    dE = delta_E_00(rgb_to_Lab(shown), exact_Lab(spec.thickness_nm, views, spec.film, spec.substrate,
                                                   spec.film_index_scale, spec.spread))
    e45 = dE[:, views <= 45.0].max(axis=1)
    return {"dE00_45_median": float(np.median(e45)), "dE00_45_max": float(e45.max()), "dE00_60_max": float(dE.max())}
