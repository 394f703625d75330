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


def test_cover_is_the_most_vivid_swatch_inside_srgb():
    """The page's cover: the largest chroma at the reference geometry among the swatches inside sRGB (the first of
    equals), else the first swatch; none without swatches."""
    recs = [{"LCh": [50, 40, 10], "in_srgb_gamut": True}, {"LCh": [50, 90, 10], "in_srgb_gamut": False},
            {"LCh": [50, 60, 200], "in_srgb_gamut": True}, {"LCh": [40, 60, 20], "in_srgb_gamut": True}]
    assert hero.cover_index(recs) == 2
    assert hero.cover_index([dict(r, in_srgb_gamut=False) for r in recs]) == 0
    assert hero.cover_index([]) is None
    assert hero.cover_name({"id": "S027"}) == "heroes/cover_S027.png"
    base = {"name": "h", "thickness": {"list_nm": [50]}}
    assert parse_spec(base).hero_cover_px == 0
    assert parse_spec(base | {"render": {"hero": True, "hero_cover_px": 960}}).hero_cover_px == 960
    with pytest.raises(SwatchError, match=r"render\.hero_cover_px"):
        parse_spec(base | {"render": {"hero": True, "hero_cover_px": 4096}})
    # a denoised cover is at most MAX_DENOISE_PX (1024) a side, an undenoised one MAX_MITSUBA_PX (2048)
    with pytest.raises(SwatchError, match=r"render\.hero_cover_px.*1024"):
        parse_spec(base | {"render": {"hero": True, "hero_cover_px": 1100}})
    assert parse_spec(base | {"render": {"hero": True, "hero_cover_px": 1100, "denoise": False}}).hero_cover_px == 1100
    with pytest.raises(SwatchError, match=r"render\.hero_cover_px.*set hero = true"):  # a cover is a hero: not silently none
        parse_spec(base | {"render": {"hero_cover_px": 960}})
    assert parse_spec(base | {"render": {"hero_cover_px": 0}}).hero_cover_px == 0


def test_edge_colours_are_the_mean_of_each_band_of_the_outer_columns():
    """Each of the bands (rows split as evenly as they go) is the rounded mean of the outermost max(2, w // 64)
    columns: a picture whose left and right columns are known, checked band by band."""
    import io

    h, w = 40, 128  # two columns a side (128 // 64), five rows a band at 8 bands
    rgb = np.zeros((h, w, 3), dtype=np.uint8)
    rgb[:, :2] = np.arange(h, dtype=np.uint8)[:, None, None] * 3  # left: rows 0, 3, 6, ...
    rgb[:, -2:, 0] = 200
    rgb[:, 2:-2] = 255  # the middle does not count
    buf = io.BytesIO()
    Image.fromarray(rgb, "RGB").save(buf, format="PNG")
    edges = hero.edge_colours(buf.getvalue(), bands=8)
    want_left = ["#{0:02x}{0:02x}{0:02x}".format(round(3 * (5 * b + 2))) for b in range(8)]  # rows 5b..5b+4: mean 5b+2
    assert edges == {"left": want_left, "right": ["#c80000"] * 8}


@pytest.mark.slow
def test_cover_is_the_hero_larger(tmp_path):
    """``hero_cover_px``: the most vivid swatch's hero again at that side (the same scene: its mean colour matches
    the hero's), cached, named in that swatch's entry only."""
    mitsuba_variant()
    spec_path = tmp_path / "spec.toml"
    spec_path.write_text(SPEC.replace("hero_size_px = 64", "hero_size_px = 64\nhero_cover_px = 128"))
    out = tmp_path / "a"
    build_catalog(spec_path, out, jobs=1)
    doc = json.loads((out / "catalog.json").read_text())
    recs = doc["swatches"]
    k = hero.cover_index(recs)
    assert [("cover" in r["hero"]) for r in recs] == [i == k for i in range(len(recs))]
    cover = recs[k]["hero"]["cover"]
    assert cover == {"png": f"heroes/cover_{recs[k]['id']}.png", "size_px": 128}
    big = np.asarray(Image.open(out / cover["png"]).convert("RGB"), dtype=float)
    small = np.asarray(Image.open(out / recs[k]["hero"]["png"]).convert("RGB"), dtype=float)
    assert big.shape == (128, 128, 3)
    assert np.abs(big.reshape(64, 2, 64, 2, 3).mean(axis=(1, 3)).mean(axis=(0, 1)) - small.mean(axis=(0, 1))).max() < 3
    assert len(list((out / ".swatch-catalog" / "cache").glob("hero-*.png"))) == 3
    for r in recs:
        assert set(r["hero"]["edges"]) == {"left", "right"} and len(r["hero"]["edges"]["left"]) == 16
