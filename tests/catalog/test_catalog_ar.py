"""#47: AR on the catalog page — ``[presets] ar``, the ``<model-viewer>`` files, what the vendored
``<model-viewer>`` really shows of them (headless Chromium), and the card's control offline."""
from __future__ import annotations

import functools
import hashlib
import http.server
import json
import re
import shutil
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest

from swatch.catalog import ar
from swatch.catalog.build import build_catalog
from swatch.catalog.spec import parse_spec
from swatch.core.errors import SwatchError
from swatch.presets import modelviewer
from swatch.presets.spectral import rgb_to_Lab
from tests.browser import SMALL_CATALOG_SPEC, open_catalog_page, wait_until
from tests.preset_reference import VENDOR, exact_Lab

pytestmark = pytest.mark.slow

MV = Path(__file__).resolve().parents[2] / "swatch" / "catalog" / "web" / "model-viewer"
#: The bench's ``presets_modelviewer_*`` (the default catalog as the vendored <model-viewer> shows it; ΔE00, D65,
#: CIE 1931 2°) are held to these (measured 2026-12-07: 1.23, 2.79, 8.81).
BOUNDS = {"dE00_45_median": 1.5, "dE00_45_max": 3.5, "dE00_60_max": 10.0}


def _spec(extra: str = ""):
    return parse_spec(__import__("tomllib").loads(SMALL_CATALOG_SPEC.format(name="ar") + extra), "ar.toml")


def test_ar_is_on_by_default_off_on_request_and_hashed():
    on, off = _spec(), _spec("[presets]\nar = false\n")
    assert on.ar and not off.ar
    assert not _spec("[presets]\nenabled = false\n").ar  # no presets: no viewer
    assert "ar" not in on.canonical() and off.canonical()["ar"] is False  # the fingerprint tells them apart
    with pytest.raises(SwatchError, match=r"presets\.ar"):
        _spec("[presets]\nenabled = false\nar = true\n")
    with pytest.raises(SwatchError, match=r"presets\.ar"):
        _spec("[presets]\nar = 1\n")


def test_vendored_model_viewer_is_the_ported_release():
    """The vendored script is @google/model-viewer 4.4.0 (npm, unmodified) and bundles the three.js the port is of:
    r183, with the DFG LUT of tables/renderers/threejs_dfg_lut.csv (its half floats decoded here)."""
    text = (MV / "model-viewer.min.js").read_text(encoding="utf-8")
    assert hashlib.sha256((MV / "model-viewer.min.js").read_bytes()).hexdigest() == (
        "18b2e711035aa4705ee281530a55dc2338ff05eed3d70ae16d54105282a75ed5")
    assert f'"{modelviewer.THREE_REVISION.removeprefix("r")}"' in text and "Apache License" in (MV / "LICENSE").read_text()
    assert "computeMultiscatteringIridescence" in text and "material.iridescenceFresnelMetallic" in text
    assert "max( roughnessFactor, 0.0525 )" in text


def test_control_names_the_usdz_and_says_quick_look_shows_no_flop():
    p = {"viewer": "presets/preset_S001_viewer.gltf", "modelviewer_max_delta_E_00": 3.86,
         "modelviewer_max_delta_E_00_45": 1.14}
    plain = ar.ar_control_html({"id": "S<1>", "presets": p})
    assert 'data-src="presets/preset_S001_viewer.gltf"' in plain and "S&lt;1&gt;" in plain
    assert "ΔE00 ≤ 1.1 at 0–45°, ≤ 3.9 at 0–60°" in plain and "ios-src" not in plain and "Quick Look" not in plain
    ios = ar.ar_control_html({"id": "S001", "presets": p | {"usdz": "presets/preset_S001.usdz",
                                                            "usd_preview_max_delta_E_00": 7.3}})
    assert 'data-ios-src="presets/preset_S001.usdz"' in ios
    assert "(Quick Look) show a fixed colour that does not change with the angle, ΔE00 ≤ 7.3" in ios
    assert ar.ar_control_html({"id": "S001", "presets": p | {"viewer": "../x.gltf"}}) == ""
    assert "ios-src" not in ar.ar_control_html({"id": "S001", "presets": p | {"usdz": "https://x/y.usdz"}})


@pytest.fixture(scope="module")
def ar_catalog(tmp_path_factory):
    root = tmp_path_factory.mktemp("ar")
    spec = root / "spec.toml"
    spec.write_text(SMALL_CATALOG_SPEC.format(name="ar test"), encoding="utf-8")
    build_catalog(spec, root / "out", jobs=1)
    return root / "out"


def test_viewer_files_pass_khronos_validator(ar_catalog):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node not installed")
    records = json.loads((ar_catalog / "catalog.json").read_text())["swatches"]
    paths = [str(ar_catalog / r["presets"]["viewer"]) for r in records]
    script = ("const v=require(process.argv[1]);const fs=require('fs');const path=require('path');"
              "Promise.all(process.argv.slice(2).map(f=>v.validateBytes(new Uint8Array(fs.readFileSync(f)),"
              "{uri:f,writeTimestamp:false,maxIssues:0,externalResourceFunction:u=>Promise.resolve("
              "new Uint8Array(fs.readFileSync(path.join(path.dirname(f),decodeURIComponent(u)))))})))"
              ".then(r=>console.log(JSON.stringify(r.map(x=>[x.issues,x.info.resources]))));")
    out = subprocess.run([node, "-e", script, str(VENDOR / "gltf-validator" / "index.js"), *paths],
                         capture_output=True, text=True, timeout=120, check=True)
    for issues, resources in json.loads(out.stdout):
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0 and issues["numInfos"] == 0, issues
        assert any(r.get("uri") == "viewer_part.bin" for r in resources), resources
    assert (ar_catalog / ar.SCRIPT).read_bytes() == (MV / "model-viewer.min.js").read_bytes()


@pytest.mark.browser
def test_model_viewer_shows_the_port_and_the_stated_figures(ar_catalog, tmp_path, chromium):
    """The vendored <model-viewer> renders each swatch's viewer material on a plate in an even white surround (tone
    mapping off) at views 0–60° from the normal: relative to a white metal plate it shows our port
    (swatch.presets.modelviewer) within 0.5 ΔE00 (8-bit readback), and the exact colour at that facet angle within
    the figures catalog.json states + 0.5 and within BOUND_45 / BOUND_60."""
    from benchmarks.modelviewer_view import material_params, render_in_model_viewer, shown_ratio

    records = json.loads((ar_catalog / "catalog.json").read_text())["swatches"]
    mats = [material_params(ar_catalog / r["presets"]["viewer"]) for r in records]
    rough = mats[0][1]
    result = render_in_model_viewer([p for p, _ in mats], rough, tmp_path, browser=chromium)
    worst_port, worst45, worst60 = 0.0, 0.0, 0.0
    for rec, (params, _), got in zip(records, mats, result["presets"], strict=True):
        stated = rec["presets"]
        for row, white in zip(got["rows"], result["white"], strict=True):
            assert row["alpha"] == 1.0 and 0.5 < white["rgb"][0] < 0.99, (row, white)  # on the plate, unclipped
            shown = shown_ratio(row, white)
            view = row["view"]
            port = modelviewer.surround_fresnel(np.cos(np.radians(view)), params[0], params[1], params[2:], rough)
            d_port = float(np.asarray(__import__("colour").delta_E(rgb_to_Lab(shown), rgb_to_Lab(port), method="CIE 2000")))
            worst_port = max(worst_port, d_port)
            dE = float(__import__("colour").delta_E(rgb_to_Lab(shown), exact_Lab(rec["thickness_nm"], [view])[0],
                                                    method="CIE 2000"))
            assert dE <= stated["modelviewer_max_delta_E_00"] + 0.5, (rec["id"], view, dE)
            if view <= 45.0:
                assert dE <= stated["modelviewer_max_delta_E_00_45"] + 0.5, (rec["id"], view, dE)
                worst45 = max(worst45, dE)
            worst60 = max(worst60, dE)
    assert worst_port <= 0.5, worst_port
    print(f"model-viewer vs port: max ΔE00 {worst_port:.3f}; vs exact: 0-45° {worst45:.2f}, 0-60° {worst60:.2f}")


@pytest.mark.browser
def test_bench_figures_within_bounds(chromium):
    """The bench's figures, measured as the bench measures them (benchmarks/modelviewer_view.py), on the default
    catalog's 57 swatches."""
    from benchmarks.modelviewer_view import modelviewer_figures
    from benchmarks.timing import DEFAULT_SPEC
    from swatch.catalog.spec import load_spec

    figures = modelviewer_figures(load_spec(DEFAULT_SPEC)[0], browser=chromium)
    print(figures)
    assert all(figures[k] <= bound for k, bound in BOUNDS.items()), figures


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.mark.browser
def test_ar_control_loads_offline(ar_catalog, tmp_path, chromium):
    """Served over http (as AR needs), a card's "see it in your room" loads the vendored <model-viewer> and the
    swatch's viewer file: every request stays inside the catalog folder (no network), no page error; the note beside
    the control states the measured error. Opened from a file, the control says it needs http(s)."""
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(ar_catalog)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    ctx = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = ctx.new_page()
    requests, errors = [], []
    page.on("request", lambda r: requests.append(r.url))
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.goto(base + "index.html")
        wait_until(page, "() => window.swatchCatalog !== undefined")
        note = page.locator(".ar-note").first.inner_text()
        rec = json.loads((ar_catalog / "catalog.json").read_text())["swatches"][0]
        assert f"ΔE00 ≤ {rec['presets']['modelviewer_max_delta_E_00_45']:.1f} at 0–45°" in note, note
        page.locator("button.ar-open").first.click()
        wait_until(page, "() => { const v = document.querySelector('.ar model-viewer'); return v && v.loaded; }", 120)
        shot = tmp_path / "ar.png"
        page.locator(".ar").first.screenshot(path=str(shot))
    finally:
        ctx.close()
        server.shutdown()
        server.server_close()
    assert errors == []
    outside = [u for u in requests if not u.startswith(base) and not u.startswith(("data:", "blob:"))]
    assert outside == [], outside
    assert any(u.endswith(ar.SCRIPT) for u in requests) and any(u.endswith("viewer_part.bin") for u in requests)

    ctx, page, events = open_catalog_page(chromium, ar_catalog)
    try:
        page.locator("button.ar-open").first.click()
        wait_until(page, "() => document.querySelector('.ar-error') !== null", 30)
    finally:
        ctx.close()
    assert all(u.startswith(("file:", "data:", "blob:")) for u in events["requests"]), events["requests"]


def test_ar_off_writes_no_viewer_and_no_control(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(SMALL_CATALOG_SPEC.format(name="no ar") + "[presets]\nar = false\n", encoding="utf-8")
    build_catalog(spec, tmp_path / "out", jobs=1)
    page = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert "ar-open" not in page and "model-viewer" not in page and "script-src 'self'" not in page.replace("&#x27;", "'")
    assert not (tmp_path / "out" / ar.SCRIPT).exists() and not list((tmp_path / "out" / "presets").glob("*viewer*"))
    records = json.loads((tmp_path / "out" / "catalog.json").read_text())["swatches"]
    assert all("viewer" not in r["presets"] and not any(re.match("modelviewer", k) for k in r["presets"])
               for r in records)
