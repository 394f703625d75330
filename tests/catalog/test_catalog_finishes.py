"""The finishes a catalog offers (issue 46 item 3): ``[render] finishes = [...]``, the first shown first (the sheets',
the chips' and every swatch's hero), the cover swatch's hero and cover in every other one, and the header's lobes.

The spec checks and the header run without Mitsuba; the heroes per finish are path-traced (slow, skipped without a
usable Mitsuba, as tests/catalog/test_catalog_hero.py)."""
from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from swatch.catalog import hero
from swatch.catalog.build import build_catalog
from swatch.catalog.execute import finish_params
from swatch.catalog.layout import extra_hero_files
from swatch.catalog.spec import load_spec, parse_spec, spec_summary
from swatch.core.choices import FINISHES
from swatch.core.errors import SwatchError
from swatch.physics.finishes import get_finish
from tests.mitsuba_setup import mitsuba_variant

ROOT = Path(__file__).resolve().parents[2]
BASE = {"name": "f", "thickness": {"list_nm": [50]}}


def _render(**render):
    return parse_spec(BASE | {"render": render})


def test_finishes_are_offered_in_the_spec_order_the_first_shown_first():
    s = _render(finishes=["satin", "Polished", "brushed"])
    assert s.finishes == ("satin", "polished", "brushed")  # each finish's own spelling
    assert s.finish == "satin" and s.roughness == get_finish("satin").roughness_alpha
    assert s.finish_spec.name == "satin"  # the sheets', the chips' and the heroes' first finish
    assert _render(finish="brushed").finishes == ("brushed",)  # one finish alone
    assert _render().finishes == () and _render(roughness=0.25).finishes == ()  # a bare roughness: none
    assert _render(finish="satin", finishes=["satin", "polished"]).finishes == ("satin", "polished")
    assert _render(finishes=list(FINISHES)).finishes == FINISHES


@pytest.mark.parametrize(("render", "words"), [
    ({"finishes": ["satin", "satin"]}, r"render\.finishes: must not repeat a finish"),
    ({"finishes": ["satin", "shiny"]}, r"render\.finishes\[1\]: must be one of polished, satin"),
    ({"finishes": []}, r"render\.finishes: must be a list of one to 4"),
    ({"finishes": "satin"}, r"render\.finishes: must be a list"),
    ({"finishes": ["satin", 3]}, r"render\.finishes\[1\]"),
    ({"finish": "polished", "finishes": ["satin", "polished"]},
     r"render\.finish: must be the first of render\.finishes.*'satin'"),
    ({"finishes": ["satin"], "roughness": 0.2}, r"render\.finishes: give either finish or roughness"),
    ({"finishes": ["satin", "brushed"], "model": "paper"}, r"render\.finishes: brushed is anisotropic"),
])
def test_bad_finishes_are_refused_in_one_line(render, words):
    with pytest.raises(SwatchError, match=words) as err:
        _render(**render)
    assert "\n" not in str(err.value) and str(err.value).startswith("<spec>: key render.finish")


def test_one_finish_keeps_the_hashes_of_before():
    """``finishes = [X]`` is ``finish = X``: the same canonical spec (the build's fingerprint and cache keys)."""
    assert _render(finishes=["satin"]).canonical() == _render(finish="satin").canonical()
    assert "finishes" not in _render(finish="satin").canonical()
    two = _render(finishes=["satin", "polished"]).canonical()
    assert two["finishes"] == ("satin", "polished") and two["finish"] == "satin"


def test_default_catalog_opens_polished_and_offers_the_others():
    """Both copies of the default spec (the package's and the repository's) offer all four, polished first (its sharp
    reflections of the soft boxes sell the metal)."""
    for path in (ROOT / "catalog" / "titanium.toml", ROOT / "swatch" / "catalog" / "specs" / "titanium.toml"):
        spec, _ = load_spec(path)
        assert spec.finishes == ("polished", "satin", "brushed", "bead-blasted")
        assert spec.finish == "polished" and spec.hero and spec.hero_cover_px
        assert "finishes polished, satin, brushed, bead-blasted" in spec_summary(spec)
    assert extra_hero_files(True, 4) == 7  # the cover, and the cover swatch's hero and cover in three more finishes


def test_finish_params_are_each_finishs_lobe():
    params = finish_params(["polished", "brushed"])
    assert list(params) == ["polished", "brushed"]
    assert params["polished"]["roughness_alpha"] == 0.04 and params["polished"]["anisotropic"] is False
    assert "alpha_u" not in params["polished"]
    b = params["brushed"]
    assert (b["alpha_u"], b["alpha_v"], b["anisotropic"]) == (0.12, 0.4, True)
    assert b["roughness_alpha"] == pytest.approx(np.sqrt(0.12 * 0.4), abs=1e-6)


def test_hero_names_per_finish():
    rec = {"id": "S004"}
    assert hero.hero_name(rec) == "heroes/hero_S004.png" and hero.cover_name(rec) == "heroes/cover_S004.png"
    assert hero.hero_name(rec, "satin") == "heroes/hero_S004_satin.png"
    assert hero.cover_name(rec, "bead-blasted") == "heroes/cover_S004_bead-blasted.png"


SPEC = """
name = "finish test"
[thickness]
list_nm = [50.8, 120]
[render]
shapes = ["flat"]
finishes = ["polished", "satin", "brushed"]
hero = {hero}
hero_size_px = 32
hero_spp = 4
hero_cover_px = {cover}
size_px = 64
angular_map = false
[chips]
enabled = false
[presets]
enabled = false
"""


@pytest.mark.slow
def test_the_header_names_the_finishes_and_the_sheets_show_the_first(tmp_path):
    spec = tmp_path / "f.toml"
    spec.write_text(SPEC.format(hero="false", cover=0), encoding="utf-8")
    build_catalog(spec, tmp_path / "c", jobs=1)
    doc = json.loads((tmp_path / "c" / "catalog.json").read_text(encoding="utf-8"))
    render = doc["catalog"]["render"]
    assert render["finishes"] == ["polished", "satin", "brushed"]
    assert list(render["finish_params"]) == render["finishes"] and render["finish"]["name"] == "polished"
    assert render["roughness"] == 0.04  # the tiles' lobe: the first finish
    assert all("hero" not in r and "hero_finishes" not in r for r in doc["swatches"])
    from swatch.io import imageio

    meta = imageio.read_metadata(tmp_path / "c" / "sheets" / "sheet_01.png")
    assert meta["catalog"]["render"]["finishes"] == render["finishes"]


@pytest.mark.slow
def test_every_swatch_has_its_hero_in_the_first_finish_and_the_cover_swatch_in_each(tmp_path):
    mitsuba_variant()
    spec = tmp_path / "f.toml"
    spec.write_text(SPEC.format(hero="true", cover=48), encoding="utf-8")
    out = tmp_path / "c"
    build_catalog(spec, out, jobs=1)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    recs = doc["swatches"]
    k = hero.cover_index(recs)
    for i, r in enumerate(recs):
        assert r["hero"]["finish"] == "polished" and r["hero"]["png"] == hero.hero_name(r)
        want = ["polished", "satin", "brushed"] if i == k else ["polished"]
        assert list(r["hero_finishes"]) == want
        assert r["hero_finishes"]["polished"] == r["hero"]  # the first finish's entry is the hero entry
        for name, entry in r["hero_finishes"].items():
            assert set(entry) == set(r["hero"]) and entry["finish"] == name
            assert entry["shape"] == "sphere" and entry["size_px"] == 32
            assert (out / entry["png"]).is_file()
            if i == k:
                side = 48 if name == "polished" else min(48, hero.OTHER_FINISH_COVER_PX)
                assert entry["cover"]["size_px"] == side
                assert Image.open(out / entry["cover"]["png"]).size == (side, side)
    rk = recs[k]
    assert rk["hero_finishes"]["satin"]["png"] == hero.hero_name(rk, "satin")
    assert rk["hero_finishes"]["satin"]["cover"]["png"] == hero.cover_name(rk, "satin")
    heroes = sorted(p.name for p in (out / "heroes").iterdir())
    assert len(heroes) == len(recs) + extra_hero_files(True, 3)
    # the finishes differ where they should: the polished sphere mirrors the studio sharply, the satin one blurs
    # it (more fine detail in the polished picture, the same scene otherwise)
    def detail(name):
        with Image.open(io.BytesIO((out / name).read_bytes())) as im:
            g = np.asarray(im.convert("L"), dtype=float)
        return float(np.abs(np.diff(g, axis=1)).mean())
    assert detail(rk["hero_finishes"]["polished"]["cover"]["png"]) > detail(rk["hero_finishes"]["satin"]["cover"]["png"])
    cache = {p.name for p in (out / ".swatch-catalog" / "cache").glob("hero-*.png")}
    assert len(cache) == len(heroes)  # one cache entry a picture: the key has the finish
    # an unchanged rebuild with one finish fewer keeps the others' cache entries and retires the dropped ones
    spec.write_text(SPEC.format(hero="true", cover=48).replace(', "brushed"', ""), encoding="utf-8")
    build_catalog(spec, out, jobs=1)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    assert list(doc["swatches"][k]["hero_finishes"]) == ["polished", "satin"]
    assert not list((out / "heroes").glob("*brushed*"))
    left = {p.name for p in (out / ".swatch-catalog" / "cache").glob("hero-*.png")}
    assert left < cache and len(left) == len(recs) + extra_hero_files(True, 2)
