"""Per-swatch hero renders through Mitsuba in a catalog (#23 item 4): a spec option, cached like
the tiles (a rebuild reuses the bytes), skipped in one line without Mitsuba. (A cold rebuild is
not byte-identical: the Mitsuba engine's renders vary between processes, see docs/catalog.md.)"""
from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from swatch.catalog import hero
from swatch.catalog.build import build_catalog
from swatch.catalog.spec import parse_spec
from swatch.core.errors import SwatchError
from tests.mitsuba_setup import mitsuba_variant

HERO_PX = 64  # the test's small heroes (the spec's hero_size_px below; the default is hero.HERO_SIZE_PX)
SPEC = """
name = "hero test"
[thickness]
list_nm = [50.8, 210]
[render]
finish = "brushed"
hero = true
hero_size_px = 64
hero_spp = 8
size_px = 64
angular_map = false
[chips]
enabled = false
[presets]
enabled = false
"""


def test_hero_is_a_spec_option():
    base = {"name": "h", "thickness": {"list_nm": [50]}}
    assert parse_spec(base).hero is False
    assert parse_spec(base | {"render": {"hero": True}}).hero is True
    with pytest.raises(SwatchError, match="microfacet"):
        parse_spec(base | {"render": {"hero": True, "model": "paper"}})
    spec = parse_spec(base)
    assert (spec.hero_size_px, spec.hero_spp, spec.denoise) == (hero.HERO_SIZE_PX, hero.HERO_SPP, True)
    spec = parse_spec(base | {"render": {"hero_size_px": 96, "hero_spp": 32, "denoise": False}})
    assert (spec.hero_size_px, spec.hero_spp, spec.denoise) == (96, 32, False)
    for key, bad in (("hero_size_px", 4096), ("hero_spp", 0), ("denoise", "yes")):
        with pytest.raises(SwatchError, match=f"render.{key}"):
            parse_spec(base | {"render": {key: bad}})


def test_default_catalog_has_denoised_heroes():
    """#37: the default catalog shows a path-traced, denoised hero per swatch."""
    from pathlib import Path

    from swatch.catalog.spec import load_spec

    spec, _ = load_spec(Path(__file__).resolve().parents[2] / "catalog" / "titanium.toml")
    assert spec.hero and spec.denoise and spec.hero_size_px >= 256


@pytest.mark.slow
def test_hero_renders_are_written_cached_and_deterministic(tmp_path):
    mitsuba_variant()
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text(SPEC)
    build_catalog(spec_path, tmp_path / "a", jobs=1)
    out = tmp_path / "a"
    doc = json.loads((out / "catalog.json").read_text())
    names = [r["hero"]["png"] for r in doc["swatches"]]
    assert names == ["heroes/hero_S001.png", "heroes/hero_S002.png"]
    assert all(r["hero"]["denoised"] is True and r["hero"]["size_px"] == HERO_PX for r in doc["swatches"])
    first = [(out / n).read_bytes() for n in names]
    for n in names:
        im = np.asarray(Image.open(out / n).convert("RGB"), dtype=float)
        assert im.shape == (HERO_PX, HERO_PX, 3) and 10 < im.mean() < 245
    blue, green = (np.asarray(Image.open(out / n).convert("RGB"), dtype=float) for n in names)
    c = slice(HERO_PX // 2 - 8, HERO_PX // 2 + 8)
    assert blue[c, c, 2].mean() > blue[c, c, 0].mean() and green[c, c, 1].mean() > green[c, c, 2].mean()
    cached = sorted(p.name for p in (out / ".swatch-catalog" / "cache").glob("hero-*.png"))
    assert len(cached) == 2
    # a full rebuild (another name) reads the cache: the same bytes; and the cache is untrusted: a damaged
    # entry is rendered again (the same seed: the same bytes), not copied out. (#17: one rebuild for both, it
    # was two: a catalog build less.)
    (out / ".swatch-catalog" / "cache" / cached[0]).write_bytes(b"not a png")
    spec_path.write_text(SPEC.replace('name = "hero test"', 'name = "hero test 2"'))
    build_catalog(spec_path, out, jobs=1)
    for n in names:
        assert Image.open(out / n).size == (HERO_PX, HERO_PX)
    assert [(out / n).read_bytes() for n in names] == first
    assert (out / ".swatch-catalog" / "cache" / cached[0]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_without_mitsuba_the_build_skips_heroes_in_one_line(tmp_path, monkeypatch):
    monkeypatch.setattr(hero, "hero_unavailable", lambda spec: "hero renders skipped: Mitsuba is not installed")
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text(SPEC)
    said: list[str] = []
    build_catalog(spec_path, tmp_path / "c", jobs=1, log=said.append)
    assert said.count("hero renders skipped: Mitsuba is not installed") == 1
    assert not list((tmp_path / "c").glob("hero_*.png"))
    assert all("hero" not in r for r in json.loads((tmp_path / "c" / "catalog.json").read_text())["swatches"])
