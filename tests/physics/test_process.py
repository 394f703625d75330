"""Process profiles: presets with sources, the growth law, the film index scale (against tmm), untrusted files."""
from __future__ import annotations

import tomllib

import numpy as np
import pytest
import tmm

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_PROFILE_BYTES
from swatch.physics.materials import load_material, tables_dir
from swatch.physics.process import DEFAULT_PROCESS, list_processes, load_process, process_toml
from tests.cli_helpers import assert_one_line_error, run_json, run_swatch

NUMBERS = ("nm_per_V", "offset_nm", "film_index_scale", "roughness")


def test_every_shipped_number_has_a_source():
    names = {p.name for p in list_processes()}
    assert DEFAULT_PROCESS in names and {"niobium", "tantalum"} <= names
    for path in sorted((tables_dir() / "processes").glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        sources = data.get("sources", {})
        for key in (*NUMBERS, "film", "substrate"):
            if key in data:
                assert len(sources.get(key, "")) > 20, (path.name, key)
        if "nm_per_V" not in data:  # a rate not shipped says why
            assert "not shipped" in sources["nm_per_V"], path.name
        else:
            assert "doi:" in sources["nm_per_V"], path.name


def test_default_preset_is_the_papers_blue_sample():
    p = load_process(DEFAULT_PROCESS)
    assert p.thickness_nm(25.0) == pytest.approx(50.8)  # Fujii et al. 2019, Table 2
    assert p.voltage_V(50.8) == pytest.approx(25.0)


def test_growth_law_with_offset(tmp_path):
    f = tmp_path / "line.toml"
    f.write_text('name = "l"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\nnm_per_V = 2.5\noffset_nm = 6\n')
    p = load_process(str(f))
    v = np.array([0.0, 10.0, 40.0])
    assert p.thickness_nm(v) == pytest.approx([6.0, 31.0, 106.0])
    assert p.voltage_V(p.thickness_nm(v)) == pytest.approx(v)
    assert p.origin == "line.toml"


def test_film_index_scale_against_tmm(tmp_path):
    """The scale multiplies the real part of the film's index; reflectance checked with tmm.coh_tmm."""
    f = tmp_path / "dense.toml"
    f.write_text('name = "d"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\nfilm_index_scale = 0.9\n')
    p = load_process(str(f))
    wl = np.arange(400.0, 701.0, 50.0)
    coat = p.coating(wl)
    nf = load_material("TiO2-Siefke").nk(wl)
    ns = load_material("Ti-Johnson").nk(wl)
    ours = coat.reflectance(80.0, 20.0).R
    ref = []
    for i, w in enumerate(wl):
        n_list = [1.0, 0.9 * nf[i].real + 1j * nf[i].imag, ns[i]]
        rs = tmm.coh_tmm("s", n_list, [np.inf, 80.0, np.inf], np.radians(20.0), w)["R"]
        rp = tmm.coh_tmm("p", n_list, [np.inf, 80.0, np.inf], np.radians(20.0), w)["R"]
        ref.append(0.5 * (rs + rp))
    assert ours == pytest.approx(ref, abs=1e-10)


def test_profile_round_trip(tmp_path):
    p = load_process("titanium-sulfuric-ohtsuka1985")
    f = tmp_path / "copy.toml"
    f.write_text(process_toml(p, header="a copy"), encoding="utf-8")
    q = load_process(str(f))
    assert (q.name, q.nm_per_V, q.offset_nm, q.film_index_scale, q.sources) == \
        (p.name, p.nm_per_V, p.offset_nm, p.film_index_scale, p.sources)
    assert process_toml(q, header="a copy") == f.read_text(encoding="utf-8")


BASE = 'name = "x"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\n'


@pytest.mark.parametrize("text, needles", [
    (BASE + "colour = 1\n", ["unknown key 'colour'", "nm_per_V"]),
    (BASE + "nm_per_V = 40\n", ["nm_per_V = 40", "0.1 to 10"]),
    (BASE + 'nm_per_V = "2"\n', ["nm_per_V must be a number"]),
    (BASE + "film_index_scale = 3\n", ["film_index_scale", "0.5 to 1.5"]),
    (BASE + "offset_nm = nan\n", ["offset_nm must be a number"]),
    ('name = "x"\nfilm = "Ti-Johnson"\nsubstrate = "Ti-Johnson"\n', ["not a film table", "TiO2-Siefke"]),
    ('name = "x"\nfilm = "TiO2-Siefke"\n', ["missing key 'substrate'"]),
    (BASE + "[sources]\nvoltage = 'x'\n", ["unknown key 'voltage' in [sources]"]),
    (BASE + "nm_per_V = \n", ["not valid TOML", "line 4"]),
])
def test_bad_profiles_one_line(tmp_path, text, needles):
    f = tmp_path / "bad.toml"
    f.write_text(text, encoding="utf-8")
    with pytest.raises(SwatchError) as info:
        load_process(str(f))
    msg = str(info.value)
    assert msg.startswith(str(f) + ":") and "\n" not in msg, msg
    for needle in needles:
        assert needle in msg, (needle, msg)


def test_oversized_and_unknown_profiles(tmp_path):
    big = tmp_path / "big.toml"
    big.write_text(BASE + "# " + "x" * MAX_PROFILE_BYTES + "\n")
    with pytest.raises(SwatchError, match="at most 64 kB"):
        load_process(str(big))
    with pytest.raises(SwatchError, match=r"unknown process 'zirconium'.*titanium-fujii2019"):
        load_process("zirconium")


def test_cli_process_option_and_metadata(tmp_path):
    out = run_json("color", "--voltage", "25", "--process", "titanium-phosphate-ohtsuka1985")
    assert out["rows"][0]["thickness_nm"] == pytest.approx(70.0)
    assert out["process"]["process"] == "titanium-phosphate-ohtsuka1985" and out["process"]["nm_per_V"] == 2.8
    over = run_json("color", "--voltage", "25", "--process", "titanium-phosphate-ohtsuka1985", "--nm-per-volt", "2")
    assert over["rows"][0]["thickness_nm"] == pytest.approx(50.0)
    assert "overridden: nm_per_V" in over["process"]["process_origin"]
    nb = run_json("spectrum", "--thickness", "60", "--process", "niobium")
    assert (nb["film"], nb["substrate"], nb["process"]["nm_per_V"]) == ("Nb2O5-Franta", "Nb-Weaver", None)
    assert_one_line_error(run_swatch("color", "--voltage", "20", "--process", "niobium"), "no growth rate",
                          "swatch calibrate")
    bad = tmp_path / "bad.toml"
    bad.write_text(BASE + "nm_per_V = 99\n")
    assert_one_line_error(run_swatch("color", "--voltage", "20", "--process", str(bad)), "bad.toml", "nm_per_V")
    m = run_json("match", "--hex", "257ab8", "--process", "titanium-sulfuric-ohtsuka1985", "--top", "2")
    assert m["process"]["nm_per_V"] == 2.4
    for c in m["candidates"]:
        assert c["voltage_V"] == pytest.approx(c["thickness_nm"] / 2.4, abs=1e-6)


def test_match_judges_each_tolerance_in_its_own_metric():
    e00 = run_json("match", "--hex", "257ab8", "--tolerance", "dE00:2", "--top", "3")
    assert e00["tolerance"]["metric"] == "dE00" and e00["tolerance"]["max"] == 2.0
    for c in e00["candidates"]:
        assert c["within_grade"] == (c["delta_E_00"] <= 2.0)
    csaj = run_json("match", "--hex", "257ab8", "--grade", "B", "--top", "3")
    assert csaj["tolerance"]["metric"] == "dEab" and csaj["tolerance"]["max"] == 3.2
    for c in csaj["candidates"]:
        assert c["within_grade"] == (c["delta_E_ab"] <= 3.2)
    assert_one_line_error(run_swatch("match", "--hex", "257ab8", "--tolerance", "dE76:2"), "dE76", "dE00")


def test_thickness_only_catalog_builds(tmp_path):
    """A profile without a growth rate (niobium) gives a whole catalog labelled by thickness."""
    spec = tmp_path / "nb.toml"
    spec.write_text('name = "Nb"\nprocess = "niobium"\n[thickness]\nlist_nm = [60, 120]\n'
                    '[render]\nshapes = ["flat"]\nsize_px = 64\nangular_map = false\n[presets]\nenabled = false\n',
                    encoding="utf-8")
    proc = run_swatch("catalog", "build", spec, "--out", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
    import json

    cat = json.loads((tmp_path / "out" / "catalog.json").read_text(encoding="utf-8"))
    assert cat["catalog"]["process"]["name"] == "niobium" and cat["catalog"]["process"]["nm_per_V"] is None
    for rec in cat["swatches"]:
        assert rec["voltage_V"] is None and rec["process_window"]["voltage_minus_V"] is None
        assert rec["process_window"]["thickness_minus_nm"] > 0


def test_fit_uses_the_profiles_film_index_scale(tmp_path):
    """fit with a scaled film finds the thickness of coupons made with that film (tmm-free: the scale
    is checked against tmm in test_film_index_scale_against_tmm)."""
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.fit.lab_fit import fit_lab
    from swatch.io.measurements import LabMeasurement
    from swatch.physics.model import get_coating

    wl = np.arange(380.0, 781.0, 5.0)
    coat = get_coating("TiO2-Siefke", "Ti-Johnson", wl, 0.9)
    cm = get_colorimeter(wl)
    light, view = np.array([45.0, 30.0, 60.0]), np.array([0.0, 10.0, 20.0])
    R, _ = coat.half_vector(120.0, light, view)
    m = LabMeasurement("x", light, view, np.zeros(3), np.full(3, 180.0), cm.Lab(cm.XYZ(R.R)))
    scaled = fit_lab(m, get_coating("TiO2-Siefke", "Ti-Johnson", wl, film_index_scale=0.9), scale="none")
    plain = fit_lab(m, get_coating("TiO2-Siefke", "Ti-Johnson", wl), scale="none")
    assert scaled.thickness_nm == pytest.approx(120.0, abs=0.2)
    assert abs(plain.thickness_nm - 120.0) > 5.0
