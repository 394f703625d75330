"""The live view against the path-traced heroes, and its frame times: measured in headless Chromium (SwiftShader
WebGL2) on a built catalog page, for the bench (bench_explorer) and the browser tests
(tests/catalog/test_live_studio_browser.py).

``live_vs_hero``: for each swatch with a hero, the live view is put at the hero's pose (its thickness, shape, finish,
camera and the studio) and size (the canvas made the hero's side in pixels, one device pixel a CSS pixel, so its
drawing buffer is the hero's raster), its drawing buffer read back and compared with the hero PNG pixel by pixel:
CIEDE2000 of the two sRGB pictures (colour-science, D65, the 2° observer of sRGB), the mean over the whole frame
and over the object (the pixels the object covers wholly, from the built-in engine's coverage of the same camera and
shape). ``frame_times``: the median time of one frame while the thickness slider moves (the page's shade pass: the
moments and the backdrop are kept; a read-back includes the GPU work), of a drag step (a coarse gather and backdrop
at half the resolution) and of the refined view after a turn, at the canvas's 640 × 480.
"""
from __future__ import annotations

import base64
import io
import json
from pathlib import Path

import colour
import numpy as np
from PIL import Image

__all__ = ["hero_records", "live_vs_hero", "frame_times", "SHAPE_NAMES"]

#: A hero's shape (catalog.json) as the live view names it.
SHAPE_NAMES = {"sphere": "sphere", "mesh": "part", "cylinder": "bent sheet", "flat": "plate"}

FRAMES_JS = """() => {
  const s = document.getElementById('thickness'), c = document.getElementById('view');
  const gl = c.getContext('webgl2'), px = new Uint8Array(4), times = [];
  const lo = Number(s.min), hi = Number(s.max);
  for (let i = -WARMUP; i < STEPS; i++) {
    const t0 = performance.now();
    s.value = lo + (hi - lo) * Math.abs(i) / (STEPS - 1);
    s.dispatchEvent(new Event('input', {bubbles: true}));
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    if (i >= 0) times.push(performance.now() - t0);
  }
  times.sort((a, b) => a - b);
  return [times[times.length >> 1], c.width, c.height];
}"""

DRAG_JS = """() => {
  const c = document.getElementById('view'), r = c.getBoundingClientRect(), times = [];
  const at = (x, y) => ({clientX: r.left + x, clientY: r.top + y, pointerId: 1, bubbles: true});
  c.dispatchEvent(new PointerEvent('pointerdown', at(300, 200)));
  for (let i = -WARMUP; i < STEPS; i++) {
    const t0 = performance.now();
    c.dispatchEvent(new PointerEvent('pointermove', at(300 + 3 * (i + WARMUP), 200)));
    swatchCatalog.pixel({x: 0, y: 0});
    if (i >= 0) times.push(performance.now() - t0);
  }
  const t0 = performance.now();
  c.dispatchEvent(new PointerEvent('pointerup', at(300, 200)));
  swatchCatalog.pixel({x: 0, y: 0});
  const refine = performance.now() - t0;
  times.sort((a, b) => a - b);
  return [times[times.length >> 1], refine];
}"""


def hero_records(out: Path) -> list[dict]:
    """The swatches of a built catalog that have a hero (catalog.json).

    Parameters
    ----------
    out : pathlib.Path
        The catalog folder.

    Returns
    -------
    list of dict
        Their records.
    """
    doc = json.loads((Path(out) / "catalog.json").read_text(encoding="utf-8"))
    return [r for r in doc["swatches"] if r.get("hero")]


def _lab(rgb8: np.ndarray) -> np.ndarray:
    return colour.XYZ_to_Lab(colour.sRGB_to_XYZ(rgb8.astype(np.float64) / 255.0), colour.CCS_ILLUMINANTS[
        "CIE 1931 2 Degree Standard Observer"]["D65"])


def _canvas(page) -> np.ndarray:
    url = page.evaluate("() => document.getElementById('view').toDataURL('image/png')")
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB"))


def live_vs_hero(page, out: Path, records: list[dict], mesh=None, save: Path | None = None) -> list[dict]:
    """The live view at each hero's pose and size against the hero (module doc).

    Parameters
    ----------
    page : playwright.sync_api.Page
        The catalog's page, loaded (``window.swatchCatalog`` there), one device pixel a CSS pixel.
    out : pathlib.Path
        The catalog folder.
    records : list of dict
        Swatches with heroes (:func:`hero_records`).
    mesh : swatch.render.mesh.MeshShape, optional
        The catalog's part, for heroes of shape ``mesh`` (the object's coverage).
    save : pathlib.Path, optional
        A folder: each pair side by side as ``live_vs_hero_<id>.png``, to look at.

    Returns
    -------
    list of dict
        Per swatch: ``id``, ``frame`` and ``object`` (mean CIEDE2000).
    """
    from swatch.render.dispatch import render_swatch
    from swatch.render.scene import DEFAULT_VIEW_DEG

    results = []
    for r in records:
        hero = np.asarray(Image.open(Path(out) / r["hero"]["png"]).convert("RGB"))
        n = hero.shape[0]
        page.evaluate(f"() => {{ const c = document.getElementById('view'); c.style.width = '{n}px'; "
                      f"c.style.height = '{n}px'; c.style.aspectRatio = 'auto'; }}")
        page.wait_for_timeout(200)
        shape = r["hero"].get("shape", "sphere")
        # the hero's camera: the shape's own (swatch.render.scene.DEFAULT_VIEW_DEG; a part's is the sphere's), from
        # the front
        view_deg = DEFAULT_VIEW_DEG["sphere" if shape == "mesh" else shape]
        query = {"thickness_nm": r["thickness_nm"], "shape": SHAPE_NAMES[shape], "lighting": "studio",
                 "model": "microfacet", "view_deg": view_deg, "view_azimuth_deg": 180}
        if r["hero"].get("finish"):
            query["finish"] = r["hero"]["finish"]
        page.evaluate("(q) => swatchCatalog.show(q)", query)
        live = _canvas(page)
        if live.shape != hero.shape:
            raise AssertionError(f"the canvas is {live.shape}, the hero {hero.shape}")
        cover = render_swatch(float(r["thickness_nm"]), shape, n, mesh=mesh, environment="point").coverage > 0.999
        de = colour.delta_E(_lab(live), _lab(hero), method="CIE 2000")
        results.append({"id": r["id"], "frame": float(de.mean()), "object": float(de[cover].mean())})
        if save is not None:
            Image.fromarray(np.concatenate([live, hero], axis=1)).save(Path(save) / f"live_vs_hero_{r['id']}.png")
    page.evaluate("() => { const c = document.getElementById('view'); c.style.width = c.style.height = "
                  "c.style.aspectRatio = ''; }")
    return results


def frame_times(page, warmup: int = 5, steps: int = 30) -> dict:
    """Median frame times of the live view as it is now (module doc), milliseconds.

    Parameters
    ----------
    page : playwright.sync_api.Page
        The catalog's page, the live view in the state to time.
    warmup, steps : int, optional
        Untimed and timed steps.

    Returns
    -------
    dict
        ``slider_ms`` (a thickness step), ``drag_ms`` (a drag step), ``refine_ms`` (the view refined after the
        turn) and the canvas's ``size`` [w, h].
    """
    slider, w, h = page.evaluate(FRAMES_JS.replace("WARMUP", str(warmup)).replace("STEPS", str(steps)))
    drag, refine = page.evaluate(DRAG_JS.replace("WARMUP", str(max(1, warmup // 2))).replace("STEPS", str(max(3, steps // 2))))
    return {"slider_ms": slider, "drag_ms": drag, "refine_ms": refine, "size": [w, h]}
