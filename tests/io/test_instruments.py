"""Instrument files in (issue 20): CxF3, CGATS.17 (i1Profiler, ArgyllCMS .ti3) and CSV with ';' or tab
separators and decimal commas, for fit, calibrate and check; hostile files refused in one line."""
from __future__ import annotations

from pathlib import Path

import colour
import numpy as np
import pytest
from lxml import etree

from swatch.core.errors import SwatchError
from swatch.io.coupons import read_coupons
from swatch.io.instrument_files import read_instrument_file
from swatch.io.instruments import Request
from swatch.io.measurement_csv import read_measurement
from tests.cli_helpers import assert_one_line_error, run_json, run_swatch

DATA = Path(__file__).resolve().parents[1] / "data" / "instruments"
CXF = DATA / "colour_cxf_sample_trimmed.cxf"
I1 = DATA / "i1profiler_coupons.txt"
TI3 = DATA / "argyll_parts.ti3"
NS = {"cc": "http://colorexchangeformat.com/CxF3-core"}
O2 = "CIE 1931 2 Degree Standard Observer"


def test_semicolon_coupon_file_with_decimal_commas_reads_like_the_comma_file(tmp_path):
    """Issue 21: a semicolon CSV gave "unknown column 'voltage_V;L;a;b'"."""
    a = tmp_path / "a.csv"
    a.write_text("voltage_V,L,a,b\n20,45.2,3.1,-20.5\n30,50,1,2\n", encoding="utf-8")
    b = tmp_path / "b.csv"
    b.write_text("voltage_V;L;a;b\n20;45,2;3,1;-20,5\n30;50;1;2\n", encoding="utf-8")
    ca, cb = read_coupons(a), read_coupons(b)
    np.testing.assert_array_equal(ca.Lab, cb.Lab)
    np.testing.assert_array_equal(ca.voltage_V, cb.voltage_V)


def test_tab_separated_spectrum_with_decimal_commas_reads(tmp_path):
    p = tmp_path / "s.tsv"
    p.write_text("wavelength_nm\treflectance\n" + "".join(f"{w}\t0,{w // 10}\n" for w in range(400, 700, 10)),
                 encoding="utf-8")
    m = read_measurement(p)
    assert m.reflectance[0, 0] == pytest.approx(0.40)


def test_comma_csv_with_decimal_commas_is_refused_with_a_hint(tmp_path):
    p = tmp_path / "c.csv"
    p.write_text("voltage_V,L,a,b\n20,45,2,3,1,-20,5\n", encoding="utf-8")
    assert_one_line_error(run_swatch("calibrate", p, "--out", tmp_path / "x.toml"), "decimal commas", "';' or tab")


def test_header_mixing_separators_is_refused(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("voltage_V;L,a;b\n20;45;2;3\n", encoding="utf-8")
    assert_one_line_error(run_swatch("calibrate", p, "--out", tmp_path / "x.toml"), "mixes ';' and ','")


def test_thousands_separator_is_refused(tmp_path):
    p = tmp_path / "t.csv"
    p.write_text("wavelength_nm;reflectance\n1.400,5;0,5\n500;0,4\n", encoding="utf-8")
    with pytest.raises(SwatchError, match="thousands separator"):
        read_measurement(p)


def test_colour_cxf_sample_spectra_agree_with_the_lab_x_rite_wrote():
    """The colour-cxf package's own test file (X-Rite ColorPort, D50/2°): the spectra we read, integrated
    by colour-science, give the CIELAB the file states (read independently with lxml)."""
    f = read_instrument_file(CXF)
    assert (f.format, f.illuminant, f.observer, f.kind) == ("cxf3", "D50", "2", "spectrum")
    tree = etree.parse(str(CXF))
    objs = tree.findall(".//cc:Object", NS)
    assert [s.id for s in f.samples] == [o.get("Name") for o in objs]
    for s, o in zip(f.samples, objs, strict=True):
        spec = [float(x) for x in o.find("cc:ColorValues/cc:ReflectanceSpectrum", NS).text.split()]
        np.testing.assert_array_equal(s.measurement.reflectance[0], spec)
        lab = [float(o.find(f"cc:ColorValues/cc:ColorCIELab/cc:{k}", NS).text) for k in "LAB"]
        sd = colour.SpectralDistribution(dict(zip(s.measurement.wavelength_nm, s.measurement.reflectance[0],
                                                  strict=True)))
        XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[O2], colour.SDS_ILLUMINANTS["D50"]) / 100
        ours = colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS[O2]["D50"])
        assert colour.delta_E(ours, lab, method="CIE 2000") < 0.3
        assert (s.measurement.light_deg[0], s.measurement.view_deg[0]) == (45.0, 0.0)


def _lab_only_cxf(tmp_path, white: bool) -> Path:
    text = CXF.read_text(encoding="utf-8")
    tree = etree.fromstring(text.encode())
    for el in tree.findall(".//cc:ReflectanceSpectrum", NS) + tree.findall(".//cc:ColorSRGB", NS):
        el.getparent().remove(el)
    if not white:
        for el in tree.findall(".//cc:TristimulusSpec", NS):
            el.getparent().remove(el)
    p = tmp_path / ("white.cxf" if white else "nowhite.cxf")
    p.write_bytes(etree.tostring(tree, xml_declaration=True, encoding="UTF-8"))
    return p


def test_cxf_lab_is_read_under_its_stated_white_and_refused_without_one(tmp_path):
    f = read_instrument_file(_lab_only_cxf(tmp_path, True))
    assert (f.kind, f.illuminant, f.observer) == ("colour", "D50", "2")
    assert f.samples[1].measurement.Lab[0] == pytest.approx([47.83558, 63.29078, 36.27213])
    proc = run_swatch("fit", _lab_only_cxf(tmp_path, False))
    assert_one_line_error(proc, "without a white point", "--illuminant")
    assert proc.returncode == 2
    given = read_instrument_file(tmp_path / "nowhite.cxf", Request(illuminant="D50", observer="2",
                                                                   given=frozenset({"illuminant", "observer"})))
    assert given.illuminant == "D50"


def test_i1profiler_cgats_states_its_colorimetry_and_geometry():
    f = read_instrument_file(I1)
    assert (f.format, f.illuminant, f.observer) == ("cgats", "D50", "2")
    assert f.stated["geometry"] == "45/0"
    assert [s.voltage_V for s in f.samples] == [10, 20, 30, 40, 50, 60]
    assert f.samples[0].measurement.wavelength_nm[[0, -1]].tolist() == [380.0, 730.0]


def test_a_file_contradicting_the_command_line_is_refused(tmp_path):
    assert_one_line_error(run_swatch("fit", I1, "--illuminant", "D65"), "states illuminant D50", "--illuminant D65")
    assert_one_line_error(run_swatch("fit", I1, "--light", "30"), "states geometry 45:0", "--light/--view")
    out = run_json("fit", TI3, "--illuminant", "D50", "--observer", "2")  # agreeing: accepted
    assert [s["thickness_nm"] for s in out["samples"]] == pytest.approx([118.0, 120.0, 123.0], abs=0.5)


def test_argyll_ti3_spectra_fit_the_thickness_they_were_made_at():
    """ArgyllCMS .ti3 layout (percent spectra, SPECTRAL_BANDS/START/END), made by tmm at 118/120/123 nm."""
    f = read_instrument_file(TI3)
    assert f.samples[0].measurement.percent
    from swatch.fit.spectral_fit import fit_measurement

    for s, d in zip(f.samples, (118.0, 120.0, 123.0), strict=True):
        r = fit_measurement(s.measurement, "TiO2-Siefke", "Ti-Johnson", illuminant=f.illuminant,
                            observer=f.observer, exclude_mirror_deg=0.0)
        assert r.thickness_nm == pytest.approx(d, abs=0.5)


def test_calibrate_reads_coupons_from_an_i1profiler_file(tmp_path):
    out = run_json("calibrate", I1, "--out", tmp_path / "line.toml", "--fixed-scale")
    assert out["nm_per_V"] == pytest.approx(2.032, abs=0.02)
    assert out["illuminant"] == "D50" and out["observer"] == "2"


HOSTILE = {
    "doctype.cxf": ('<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "aaaa">]><cc:CxF xmlns:cc="'
                    'http://colorexchangeformat.com/CxF3-core">&a;</cc:CxF>', "document type"),
    "wrong_schema.cxf": ('<?xml version="1.0"?><CxF xmlns="http://colorexchangeformat.com/CxF2">'
                         '<Object/></CxF>', "not a CxF3 document"),
    "broken.cxf": ('<?xml version="1.0"?><cc:CxF xmlns:cc="http://colorexchangeformat.com/CxF3-core">'
                   '<cc:Resources><cc:Bogus/></cc:Resources></cc:CxF>', "CxF3"),
    "nan.txt": ("CGATS.17\nMEASUREMENT_SOURCE \"Illumination=D50 ObserverAngle=2\"\nBEGIN_DATA_FORMAT\n"
                "SAMPLE_ID LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\nBEGIN_DATA\n1 50 nan 3\nEND_DATA\n", "finite"),
    "no_white.txt": ("CGATS.17\nBEGIN_DATA_FORMAT\nSAMPLE_ID LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\nBEGIN_DATA\n"
                     "1 50 2 3\nEND_DATA\n", "without a white point"),
    "sphere.txt": ("CGATS.17\nMEASUREMENT_GEOMETRY \"d/8\"\nBEGIN_DATA_FORMAT\nSAMPLE_ID nm400 nm500 nm600\n"
                   "END_DATA_FORMAT\nBEGIN_DATA\n1 0.2 0.3 0.4\nEND_DATA\n", "diffuse"),
    "two_tables.txt": ("CGATS.17\nBEGIN_DATA_FORMAT\nSAMPLE_ID nm400 nm500\nEND_DATA_FORMAT\nBEGIN_DATA\n1 0.2 0.3\n"
                       "END_DATA\nBEGIN_DATA_FORMAT\nSAMPLE_ID nm400 nm500\nEND_DATA_FORMAT\n", "second table"),
    "two_whites.txt": ("CGATS.17\nMEASUREMENT_SOURCE \"Illumination=D50 ObserverAngle=2\"\nWEIGHTING_FUNCTION "
                       "\"ILLUMINANT, D65\"\nBEGIN_DATA_FORMAT\nSAMPLE_ID LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\n"
                       "BEGIN_DATA\n1 50 2 3\nEND_DATA\n", "two illuminants"),
    "sets.txt": ("CGATS.17\nNUMBER_OF_SETS 3\nBEGIN_DATA_FORMAT\nSAMPLE_ID nm400 nm500\nEND_DATA_FORMAT\nBEGIN_DATA\n"
                 "1 0.2 0.3\nEND_DATA\n", "NUMBER_OF_SETS says 3"),
    "cut.txt": ("CGATS.17\nBEGIN_DATA_FORMAT\nSAMPLE_ID nm400 nm500\nEND_DATA_FORMAT\nBEGIN_DATA\n1 0.2 0.3\n",
                "cut short"),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_instrument_files_are_refused_in_one_line(tmp_path, name):
    text, fragment = HOSTILE[name]
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    proc = run_swatch("fit", p)
    assert_one_line_error(proc, fragment)
    assert proc.returncode == 2


def test_mixed_geometries_in_one_cxf_file_are_refused(tmp_path):
    tree = etree.parse(str(CXF))
    coll = tree.find(".//cc:ColorSpecificationCollection", NS)
    cs2 = etree.fromstring(etree.tostring(coll[0]))
    cs2.set("Id", "CS2")
    cs2.find(".//cc:IlluminationAngle", NS).text = "15.0"
    coll.append(cs2)
    for el in tree.findall(".//cc:Object", NS)[1].iter():
        if el.get("ColorSpecification") == "CS1":
            el.set("ColorSpecification", "CS2")
    p = tmp_path / "mixed.cxf"
    tree.write(str(p), xml_declaration=True, encoding="UTF-8")
    assert_one_line_error(run_swatch("fit", p), "different geometries")


def test_huge_instrument_file_is_refused_before_it_is_read(tmp_path):
    assert_one_line_error(run_swatch("fit", "/dev/zero"), "at most 16 MB")


def test_fit_report_names_each_sample_of_an_instrument_file(tmp_path):
    assert run_swatch("fit", TI3, "--report", tmp_path / "r").returncode == 0
    assert sorted(p.name for p in (tmp_path / "r").glob("delta_e_map_*.png")) == [
        "delta_e_map_argyll_parts_1.png", "delta_e_map_argyll_parts_2.png", "delta_e_map_argyll_parts_3.png"]
