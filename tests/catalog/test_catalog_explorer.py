"""The explorer's embedded colour table against the direct spectral computation."""
from __future__ import annotations

from pathlib import Path

import colour
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import swatch  # noqa: F401
from swatch.catalog.context import catalog_context
from swatch.catalog.explorer import decode, explorer_data, grid_lookup
from swatch.catalog.records import hue_family
from swatch.catalog.spec import load_spec
from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
from swatch.colorimetry.names import colour_name
from swatch.physics.materials import wavelength_grid
from swatch.physics.model import get_coating


@pytest.fixture(scope="module")
def table():
    spec, _ = load_spec("catalog/titanium.toml")
    wl = wavelength_grid(380.0, 780.0, spec.wavelength_step_nm)
    return spec, wl, explorer_data(catalog_context(spec))


def _direct(spec, wl, d, cos_d, observer):
    coating = get_coating(spec.film, spec.substrate, wl)
    cm = get_colorimeter(wl, spec.illuminant, observer)
    R = np.stack([coating.reflectance_cos(float(di), np.array([ci])).R[0] for di, ci in zip(d, cos_d, strict=True)])
    # colour.sd_to_XYZ-independent check of the weights happens in test_colorimetry; here the
    # reference is the engine's direct path per sample, not the table
    return cm, cm.XYZ(R)


def test_interpolated_table_within_half_a_delta_e(table):
    spec, wl, t = table
    rng = np.random.default_rng(7)
    d = rng.uniform(min(spec.thickness_nm), max(spec.thickness_nm), 400)
    c = np.concatenate([rng.uniform(0.0, 1.0, 300), rng.uniform(0.0, 0.05, 100)])  # and near grazing
    got = grid_lookup(t, d, c)
    for obs, sl in (("10", slice(0, 3)), ("2", slice(3, 6))):
        cm, XYZ = _direct(spec, wl, d, c, obs)
        dE = delta_E_00(cm.Lab(got[:, sl]), cm.Lab(XYZ))
        assert dE.max() <= 0.5, (obs, dE.max(), d[dE.argmax()], c[dE.argmax()])


def test_reference_column_is_the_reference_geometry(table):
    spec, wl, t = table
    ref = t["reference"]
    col = decode(ref["values"])
    n = ref["thickness_nm"]["count"]
    assert col.shape == (n, 6)
    d = ref["thickness_nm"]["start"] + ref["thickness_nm"]["step"] * np.arange(n)
    assert d[0] == pytest.approx(min(spec.thickness_nm)) and d[-1] == pytest.approx(max(spec.thickness_nm))
    idx = np.arange(0, n, 97)
    coating = get_coating(spec.film, spec.substrate, wl)
    cm = get_colorimeter(wl, spec.illuminant, spec.observer)
    # 45:0 -> theta_d = 22.5 deg: the reflectance through the engine's angle path (not cos)
    R = coating.reflectance(d[idx], 22.5).R
    dE = delta_E_00(cm.Lab(col[idx, :3]), cm.Lab(cm.XYZ(R)))
    assert dE.max() < 0.02


def test_matrices_match_colour_science(table):
    spec, wl, t = table
    cm2 = get_colorimeter(wl, spec.illuminant, "2")
    XYZ = np.array([[20.0, 30.0, 40.0], [50.0, 40.0, 10.0]])
    want = colour.XYZ_to_RGB(XYZ / 100, "sRGB", illuminant=cm2.white_xy, chromatic_adaptation_transform="Bradford")
    assert np.allclose(XYZ @ np.array(t["XYZ2_to_srgb_linear"]), want, atol=1e-9)
    want_p3 = colour.XYZ_to_RGB(XYZ / 100, "Display P3", illuminant=cm2.white_xy,
                                chromatic_adaptation_transform="Bradford")
    assert np.allclose(XYZ @ np.array(t["XYZ2_to_p3_linear"]), want_p3, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(st.floats(0, 100), st.floats(0, 150), st.floats(0, 360))
def test_hue_family_and_name_are_total(L, C, h):
    assert hue_family(C, h) in {"red", "orange", "yellow", "green", "cyan", "blue", "purple", "neutral"}
    assert isinstance(colour_name(L, C, h), str) and colour_name(L, C, h)


def test_families_fixed_where_designers_disagreed():
    spec, _ = load_spec("catalog/titanium.toml")
    from swatch.catalog.context import catalog_context
    from swatch.catalog.records import compute

    recs = {r["thickness_nm"]: r for r in compute(catalog_context(spec)).records}
    assert recs[80.0]["hue_family"] == "neutral"  # C* 7.6 is not "cyan"
    for d in (85.0, 90.0, 95.0, 100.0):  # pale straw, not "green"
        assert recs[d]["hue_family"] in ("neutral", "yellow"), (d, recs[d]["hue_family"])
    assert recs[200.0]["hue_family"] == "green"
    names = {d: r["colour_name"] for d, r in recs.items()}
    assert names[50.0] == "blue" and names[70.0] == "silver blue" and names[95.0] == "straw"
    assert names[30.0] == "bronze" and names[145.0] == "magenta" and names[180.0] == "teal"


def test_cards_flag_out_of_gamut_chips_and_carry_p3():
    from swatch.catalog.context import catalog_context
    from swatch.catalog.explorer import chip_colours
    from swatch.catalog.html import index_html
    from swatch.catalog.records import compute

    spec, _ = load_spec("catalog/titanium.toml")
    data = compute(catalog_context(spec))
    chips = chip_colours(data)
    recs = data.records
    from swatch.catalog.execute import catalog_header

    doc = {"catalog": catalog_header(spec, data, "titanium.toml"), "sheets": [], "swatches": recs}
    page = index_html(doc, chips=chips)
    out = [r for r in recs if not r["in_srgb_gamut"]]
    assert out, "the default catalog has colours outside sRGB (170–180 nm)"
    assert page.count('<span class="gamut">outside sRGB</span>') == len(out)
    # P3 from colour-science: the 2° XYZ of the reflectance, Bradford-adapted into Display P3
    cm2 = get_colorimeter(data.wavelength_nm, spec.illuminant, "2")
    rgb = colour.XYZ_to_RGB(cm2.XYZ(data.reflectance) / 100, "Display P3", illuminant=cm2.white_xy,
                            chromatic_adaptation_transform="Bradford")
    want = colour.RGB_COLOURSPACES["Display P3"].cctf_encoding(np.clip(rgb, 0, 1))
    assert np.allclose([c["p3"] for c in chips], want, atol=1e-4)
    n_multi_out = sum(not v for c in chips for v in c["multi_in_srgb_gamut"].values())
    assert page.count('<span class="out-of-gamut"') == n_multi_out


def test_table_follows_the_process_film_index_scale(tmp_path):
    """Regression: the table ignored the process profile's film index scale, so for a calibrated
    line the page's colours and matches differed from the cards (catalog.json records)."""
    from swatch.catalog.context import catalog_context
    from swatch.catalog.records import compute

    profile = (Path("tables/processes/titanium-fujii2019.toml").read_text(encoding="utf-8")
               .replace('name = "titanium-fujii2019"', 'name = "scaled-line"')
               .replace("film_index_scale = 1.0", "film_index_scale = 1.12"))
    (tmp_path / "line.toml").write_text(profile, encoding="utf-8")
    (tmp_path / "spec.toml").write_text('name = "scaled"\nprocess = "line.toml"\n[thickness]\nlist_nm = [60, 140]\n',
                                        encoding="utf-8")
    spec, _ = load_spec(tmp_path / "spec.toml")
    assert spec.film_index_scale == pytest.approx(1.12)
    wl = wavelength_grid(380.0, 780.0, spec.wavelength_step_nm)
    t = explorer_data(catalog_context(spec))
    ref = t["reference"]
    col = decode(ref["values"])
    d = ref["thickness_nm"]["start"] + ref["thickness_nm"]["step"] * np.arange(ref["thickness_nm"]["count"])
    cm = get_colorimeter(wl, spec.illuminant, spec.observer)
    for rec in compute(catalog_context(spec)).records:
        i = int(np.argmin(np.abs(d - rec["thickness_nm"])))
        assert d[i] == pytest.approx(rec["thickness_nm"])
        assert float(delta_E_00(cm.Lab(col[i, :3]), np.asarray(rec["Lab"]))) < 0.02
