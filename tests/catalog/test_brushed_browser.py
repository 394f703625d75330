"""Brushed reads brushed in the live view too (issue 37): a brushed catalog's page embeds the hairline field's
constants (swatch.catalog.explorer.hairline_data, from swatch.physics.finishes) and its WebGL view tilts the facet
normals with it, so the plate shows lines along its grain (left to right) under the studio and the point light,
and the bent sheet lines up its axis; an isotropic catalog's page (the suite's small catalog, called "satin"
here) has no field and no lines."""
from __future__ import annotations

import json
import re
import shutil

import numpy as np
import pytest

from swatch.physics.finishes import HAIRLINE_OCTAVES, HAIRLINE_SLOPE, HAIRLINE_STRETCH
from tests.browser import open_catalog_page

SPEC = """
name = "brushed page"
[thickness]
list_nm = [50.8, 140]
[render]
size_px = 64
finish = "{finish}"
angular_map = false
[chips]
enabled = false
[presets]
enabled = false
"""

#: The green channel of the canvas's middle third (top row first) after showing q at 240 x 180: 80 x 60 values
#: (a whole buffer through the DevTools protocol took seconds).
_PIXELS_JS = """q => { const c = document.getElementById('view'), gl = c.getContext('webgl2');
  c.width = 240; c.height = 180; swatchCatalog.show(q);
  const p = new Uint8Array(240 * 180 * 4); gl.readPixels(0, 0, 240, 180, gl.RGBA, gl.UNSIGNED_BYTE, p);
  const out = [];
  for (let y = 60; y < 120; y++) for (let x = 80; x < 160; x++) out.push(p[((179 - y) * 240 + x) * 4 + 1]);
  return out; }"""


@pytest.fixture(scope="module")
def pages(tmp_path_factory, chromium, small_catalog):
    """A brushed catalog built here, and the suite's small catalog (isotropic GGX) to set it against."""
    from swatch.catalog.build import build_catalog

    root = tmp_path_factory.mktemp("brushed-page")
    spec = root / "brushed.toml"
    spec.write_text(SPEC.format(finish="brushed"), encoding="utf-8")
    build_catalog(spec, root / "brushed", jobs=1)
    yield {"brushed": root / "brushed", "satin": small_catalog}
    shutil.rmtree(root, ignore_errors=True)


def _texture(green: list[int]) -> tuple[float, float]:
    """Mean |second difference| of the green channel (80 x 60, :data:`_PIXELS_JS`) along x and along y."""
    c = np.asarray(green, dtype=np.float64).reshape(60, 80)
    return float(np.abs(np.diff(c, 2, axis=1)).mean()), float(np.abs(np.diff(c, 2, axis=0)).mean())


def test_the_page_embeds_the_field_only_for_brushed(pages):
    def table(finish):
        text = (pages[finish] / "index.html").read_text(encoding="utf-8")
        return json.loads(re.search(r'<script type="application/json" id="explorer-table">(.*?)</script>', text).group(1))
    h = table("brushed")["render"]["hairlines"]
    assert h == {"slope": HAIRLINE_SLOPE, "octaves": [list(o) for o in HAIRLINE_OCTAVES], "stretch": HAIRLINE_STRETCH}
    assert "hairlines" not in table("satin")["render"]


def test_live_view_draws_lines_along_the_grain(chromium, pages):
    """Under the studio and the point light (one page per catalog: a page load is most of the cost)."""
    got = {}
    for finish, path in pages.items():
        ctx, pg, events = open_catalog_page(chromium, path, fragment="lighting=point")
        try:
            for lighting in ("studio", "point"):
                q = {"lighting": lighting, "thickness_nm": 50.8, "view_azimuth_deg": 180}
                got[finish, lighting, "plate"] = _texture(pg.evaluate(_PIXELS_JS, {**q, "shape": "plate", "view_deg": 20}))
                got[finish, lighting, "bent sheet"] = _texture(pg.evaluate(_PIXELS_JS, {**q, "shape": "bent sheet",
                                                                                        "view_deg": 70}))
            assert events["errors"] == []
        finally:
            ctx.close()
    print(got)
    # the plate is brushed left to right: its texture is across the lines, along y; the sheet's up its axis: along x
    for lighting in ("studio", "point"):
        bx, by = got["brushed", lighting, "plate"]
        assert by > 3 * bx and by > 4 * got["satin", lighting, "plate"][1], (lighting, got)
        sx, sy = got["brushed", lighting, "bent sheet"]
        assert sx > 3 * sy and sx > 4 * got["satin", lighting, "bent sheet"][0], (lighting, got)


#: The canvas at 256 x 192: its central 192 x 192 square, one canvas pixel per pixel of a 192 px render (the page's
#: framing is swatch render's: tests/catalog/test_catalog_explorer_env_browser.py), green channel, top row first.
_SQUARE_JS = """q => { const c = document.getElementById('view'), gl = c.getContext('webgl2');
  c.width = 256; c.height = 192; swatchCatalog.show(q);
  const p = new Uint8Array(256 * 192 * 4); gl.readPixels(0, 0, 256, 192, gl.RGBA, gl.UNSIGNED_BYTE, p);
  const out = [];
  for (let y = 0; y < 192; y++) for (let x = 32; x < 224; x++) out.push(p[((191 - y) * 256 + x) * 4 + 1]);
  return out; }"""


def _profile(green: np.ndarray, axis: int) -> np.ndarray:
    """The lines' profile: the middle of the object averaged along the grain (``axis``), less its running mean
    over 9 pixels (the smooth shading), so what is left is the lines."""
    n = green.shape[0]
    mid = green[n // 4: 3 * n // 4, n // 4: 3 * n // 4].astype(np.float64)
    prof = mid.mean(axis=axis)
    return prof - np.convolve(prof, np.ones(9) / 9, mode="same")


@pytest.mark.parametrize("shape, page_shape, view_deg, axis", [("flat", "plate", 36.0, 1), ("cylinder", "bent sheet", 70.0, 0)])
def test_the_live_view_draws_the_same_lines_as_swatch_render(chromium, pages, tmp_path, shape, page_shape, view_deg, axis):
    """The same field at the same surface points: the page's GLSL hash and coordinates are the Python's, so its
    lines fall where `swatch render --finish brushed` draws them (the profiles across the grain correlate; the
    page's lobe is the isotropic one of the same area, so the lines' contrast differs, not their places)."""
    from PIL import Image

    from tests.cli_helpers import run_swatch

    r = run_swatch("render", "--thickness", "50.8", "--shape", shape, "--finish", "brushed", "--environment", "studio",
                   "--size", "192", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    want = np.asarray(Image.open(tmp_path / f"{shape}_050.8nm.png").convert("RGB"))[..., 1]
    ctx, pg, events = open_catalog_page(chromium, pages["brushed"], fragment="lighting=point")
    try:
        got = np.asarray(pg.evaluate(_SQUARE_JS, {"lighting": "studio", "shape": page_shape, "thickness_nm": 50.8,
                                                  "view_deg": view_deg, "view_azimuth_deg": 180}),
                         dtype=np.float64).reshape(192, 192)
        assert events["errors"] == []
    finally:
        ctx.close()
    a, b = _profile(want, axis), _profile(got, axis)
    corr = float(np.corrcoef(a, b)[0, 1])
    shifted = float(np.corrcoef(a[3:], b[:-3])[0, 1])  # the lines three pixels off: the check can fail
    print(shape, "correlation", round(corr, 3), "shifted", round(shifted, 3))
    assert corr > 0.6 and shifted < 0.5 * corr, (corr, shifted)
