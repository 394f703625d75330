"""Catalog specs: the shipped specs, and rejection of bad ones with the file, the key and what is allowed."""
from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from swatch.catalog.spec import load_spec, parse_spec
from swatch.core.errors import SwatchError

ROOT = Path(__file__).resolve().parents[2]

# The paper's Table 2 (Fujii et al. 2019), typed in from the paper, not from the spec.
PAPER_TABLE_2_NM = [15.9, 50.8, 60.6, 87.5, 121.4, 138.4, 160.6, 173.9, 226.6, 264.4]


def test_titanium_spec_is_the_default_range():
    spec, _ = load_spec(ROOT / "catalog" / "titanium.toml")
    d = spec.thickness_nm
    assert d[0] == 20 and d[-1] == 300
    steps = {round(b - a, 9) for a, b in itertools.pairwise(d)}
    assert len(steps) == 1
    assert spec.reference.light_deg == 45 and spec.reference.view_deg == 0
    assert [g.aspecular_deg for g in spec.multi_angle] == [-15, 15, 25, 45, 75, 110]
    assert spec.illuminant == "D65" and spec.observer == "10"


def test_paper_spec_has_table_2():
    spec, _ = load_spec(ROOT / "catalog" / "paper-samples.toml")
    assert list(spec.thickness_nm) == PAPER_TABLE_2_NM


def test_multi_angle_view_directions():
    spec = parse_spec({"name": "x", "thickness": {"list_nm": [100]}})
    by = {g.aspecular_deg: g for g in spec.multi_angle}
    # -15°: past the specular direction, far side at 60°; 110°: on the light's side at 65°.
    assert (by[-15].view_deg, by[-15].view_side) == (60, "opposite")
    assert (by[110].view_deg, by[110].view_side) == (65, "light")
    assert by[110].theta_d_deg == pytest.approx(10.0)
    assert by[-15].theta_d_deg == pytest.approx(52.5)
    assert by[45].view_deg == 0
    assert [g.name for g in spec.multi_angle] == ["45as-15", "45as15", "45as25", "45as45", "45as75", "45as110"]


@pytest.mark.parametrize("key", ["nm_per_V", "growth_nm_per_V"])  # the old name stays an alias
def test_voltage_spec_uses_growth_rate(key):
    spec = parse_spec({"name": "v", key: 2.5, "voltage": {"start_V": 10, "stop_V": 30, "step_V": 10}})
    assert spec.voltage_V == (10, 20, 30)
    assert spec.thickness_nm == pytest.approx((25, 50, 75))
    assert spec.nm_per_V == 2.5 and spec.process == "titanium-fujii2019"
    assert "nm_per_V" in spec.process_origin


def test_spec_process_presets_and_files(tmp_path):
    ti = parse_spec({"name": "t", "process": "titanium-phosphate-ohtsuka1985", "voltage": {"list_V": [10]}})
    assert (ti.nm_per_V, ti.film, ti.substrate, ti.thickness_nm) == (2.8, "TiO2-Siefke", "Ti-Johnson", (28.0,))
    nb = parse_spec({"name": "n", "process": "niobium", "thickness": {"list_nm": [50]}})
    assert (nb.film, nb.substrate, nb.nm_per_V) == ("Nb2O5-Franta", "Nb-Weaver", None)
    with pytest.raises(SwatchError, match="no growth rate"):
        parse_spec({"name": "n", "process": "niobium", "voltage": {"list_V": [10]}})
    (tmp_path / "line.toml").write_text('name = "my line"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\n'
                                        'nm_per_V = 2.5\noffset_nm = 4.0\nfilm_index_scale = 0.95\n')
    (tmp_path / "spec.toml").write_text('name = "s"\nprocess = "line.toml"\n[voltage]\nlist_V = [10, 20]\n')
    spec, _ = load_spec(tmp_path / "spec.toml")
    assert spec.thickness_nm == pytest.approx((29.0, 54.0)) and spec.film_index_scale == 0.95
    assert spec.process == "my line" and spec.offset_nm == 4.0
    outside = tmp_path / "sub"
    outside.mkdir()
    (outside / "spec.toml").write_text('name = "s"\nprocess = "../line.toml"\n[thickness]\nlist_nm = [50]\n')
    with pytest.raises(SwatchError, match="inside the spec's folder"):
        load_spec(outside / "spec.toml")


def test_spec_tolerance_in_its_own_metric():
    spec = parse_spec({"name": "t", "thickness": {"list_nm": [50]}, "tolerance": {"metric": "dE00", "max": 2.0}})
    assert (spec.metric, spec.max_delta_E, spec.grade) == ("dE00", 2.0, None)
    assert spec.tolerance.label == "dE00 ≤ 2"
    c = parse_spec({"name": "t", "thickness": {"list_nm": [50]}})
    assert (c.metric, c.max_delta_E, c.grade, c.scheme) == ("dEab", 6.5, "C", "csaj")


def _write(tmp_path, text: str) -> Path:
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    return p


BASE = 'name = "x"\n[thickness]\nlist_nm = [50]\n'


@pytest.mark.parametrize(
    "text, needles",
    [
        ('name = "x"\n[thickness]\nstart_nm = 20\nstop_nm = 30\nstep_nm = "a"\n',
         ["key thickness.step_nm", "must be a number > 0", "'a'"]),
        ('name = "x"\n[thickness]\nstart_nm = 20\nstop_nm = 30\nstep_nm = 0\n', ["thickness.step_nm", "> 0"]),
        ('name = "x"\n[thickness]\nstart_nm = 40\nstop_nm = 30\nstep_nm = 5\n', ["thickness.stop_nm", ">= start_nm"]),
        ('name = "x"\n[thickness]\nlist_nm = [50, -1]\n', ["thickness.list_nm[1]", ">= 0"]),
        ('name = "x"\n[thickness]\nlist_nm = [5000]\n', ["thickness.list_nm[0]", "<= 1000"]),
        (BASE + "colour_space = 1\n", ["unknown key thickness.colour_space"]),
        ('name = "x"\ncolor = 1\n[thickness]\nlist_nm = [50]\n', ["unknown key color", "allowed", "colour"]),
        (BASE + '[render]\nsize = 100\n', ["unknown key render.size", "size_px"]),
        (BASE + '[render]\nsize_px = 10\n', ["render.size_px", "64 to 512"]),
        (BASE + '[render]\nsize_px = 100.5\n', ["render.size_px", "whole number"]),
        (BASE + '[render]\nshapes = ["cube"]\n', ["render.shapes[0]", "flat, cylinder, sphere"]),
        (BASE + '[render]\nmodel = "phong"\n', ["render.model", "paper, microfacet"]),
        (BASE + '[render]\nangular_map = "yes"\n', ["render.angular_map", "true or false"]),
        (BASE + '[tolerance]\ngrade = "Z"\n', ["tolerance.grade", "AAA", "E"]),
        (BASE + '[tolerance]\nscheme = "iso"\n', ["tolerance.scheme", "csaj", "nbs"]),
        (BASE + '[geometry]\nreference = { light_deg = 95 }\n', ["geometry.reference.light_deg", "< 90"]),
        (BASE + '[geometry]\nmulti_angle = { aspecular_deg = [-60] }\n',
         ["geometry.multi_angle.aspecular_deg[0]", "105"]),
        (BASE + '[colour]\nobserver = "5"\n', ["colour.observer", "10, 2"]),
        ('film = "Ti-Johnson"\n' + BASE, ["key film", "substrate table", "TiO2-Siefke"]),
        ('substrate = "Unobtainium"\n' + BASE, ["key substrate", "unknown substrate", "Ti-Johnson"]),
        ('growth_nm_per_V = true\n' + BASE, ["key growth_nm_per_V", "number"]),
        ('nm_per_V = 2.0\ngrowth_nm_per_V = 2.0\n' + BASE, ["nm_per_V", "not both"]),
        ('process = "zirconium"\n' + BASE, ["key process", "titanium-fujii2019"]),
        (BASE + '[tolerance]\nmetric = "dE76"\nmax = 2\n', ["tolerance.metric", "dEab, dE00"]),
        (BASE + '[tolerance]\nmetric = "dE00"\nmax = 0\n', ["tolerance.max", "> 0"]),
        (BASE + '[tolerance]\nmetric = "dE00"\n', ["tolerance", "both metric and max"]),
        (BASE + '[tolerance]\nmetric = "dE00"\nmax = 2\ngrade = "C"\n', ["tolerance", "not both"]),
        ('growth_nm_per_V = 50\n' + BASE, ["key growth_nm_per_V", "<= 10"]),
        ('[thickness]\nlist_nm = [50]\n', ["missing key name"]),
        ('name = "x"\n', ["[thickness]", "[voltage]"]),
        ('name = "x"\n[thickness]\nlist_nm = [50]\n[voltage]\nlist_V = [5]\n', ["exactly one"]),
        ('name = "x"\n[thickness]\nstart_nm = 20\nstop_nm = 30\nstep_nm = 5\nlist_nm = [1]\n', ["either"]),
        ('name = "x"\n[thickness]\nstart_nm = 0\nstop_nm = 1000\nstep_nm = 0.1\n', ["at most 400"]),
        ('name = "x"\n[thickness]\nlist_nm = [50, 50]\n', ["must not repeat"]),
        ('name = [1]\n', ["key name", "text"]),
        ('name = "x"\n[thickness\n', ["not valid TOML"]),
    ],
)
def test_bad_specs_are_rejected_with_file_key_and_allowed(tmp_path, text, needles):
    path = _write(tmp_path, text)
    with pytest.raises(SwatchError) as info:
        load_spec(path)
    msg = str(info.value)
    assert msg.startswith(str(path) + ":"), msg
    for needle in needles:
        assert needle in msg, (needle, msg)


def test_missing_and_unreadable_spec(tmp_path):
    with pytest.raises(SwatchError, match="does not exist"):
        load_spec(tmp_path / "nope.toml")
    with pytest.raises(SwatchError, match="is a folder"):
        load_spec(tmp_path)
    p = tmp_path / "bin.toml"
    p.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(SwatchError, match="UTF-8"):
        load_spec(p)
