"""Issue 19: a catalog built from a two-slope (knee) profile: the explorer's voltage slider and its
find-by-colour voltages follow the same law as the records (real headless Chromium)."""
from __future__ import annotations

import json

import pytest

import swatch  # noqa: F401
from swatch.physics.process import load_process, process_toml
from tests.browser import POINT_LIGHT, SMALL_CATALOG_SPEC, open_catalog_page

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_voltage_slider_and_matches_follow_a_knee_law(chromium, tmp_path):
    from swatch.catalog.build import build_catalog

    base = process_toml(load_process("titanium-fujii2019"))
    (tmp_path / "line.toml").write_text(
        base.replace("offset_nm =", "knee_V = 40.0\nnm_per_V_above_knee = 3.0\noffset_nm =", 1), encoding="utf-8")
    # the records and the page are what this reads: one render shape, no angular maps (~0.5 CPU-s less),
    # no presets (their fits, ~1 CPU-s)
    spec = 'process = "line.toml"\n' + SMALL_CATALOG_SPEC.format(name="knee").replace(
        "size_px = 64", 'size_px = 64\nshapes = ["flat"]\nangular_map = false') + "\n[presets]\nenabled = false\n"
    (tmp_path / "spec.toml").write_text(spec, encoding="utf-8")
    build_catalog(tmp_path / "spec.toml", tmp_path / "out", jobs=1)
    records = json.loads((tmp_path / "out" / "catalog.json").read_text(encoding="utf-8"))
    assert records["catalog"]["process"]["knee_V"] == 40.0
    ctx, pg, events = open_catalog_page(chromium, tmp_path / "out", fragment=POINT_LIGHT)
    # 60 V grows 2.032 × 40 + 3.0 × 20 = 141.28 nm
    pg.eval_on_selector("#voltage-range", "e => { e.value = 60; e.dispatchEvent(new Event('input', {bubbles: true})); }")
    assert pg.locator("#t-out").text_content() == "141.3 nm"
    hits = pg.evaluate("swatchCatalog.match({Lab: swatchCatalog.colorAt({thickness_nm: 200, light_deg: 45, "
                       "view_deg: 0}).Lab}, 1)")
    assert hits[0]["thickness_nm"] == pytest.approx(200.0, abs=0.2)
    assert hits[0]["voltage_V"] == pytest.approx(40.0 + (200.0 - 2.032 * 40) / 3.0, abs=0.1)
    for s in records["swatches"]:
        if s["voltage_V"] is not None and s["thickness_nm"] > 2.032 * 40:
            assert s["voltage_V"] == pytest.approx(40.0 + (s["thickness_nm"] - 2.032 * 40) / 3.0, abs=1e-3)
    assert not events["errors"], events["errors"]
    ctx.close()
