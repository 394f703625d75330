"""Exports read the way designers' tools read them, checked with readers we did not write.

* ASE: parsed here from the format description (Adobe Swatch Exchange 1.0: big-endian ``ASEF``
  header, blocks of type/length, UTF-16BE names with a terminating NUL, a 4-byte colour model
  and 32-bit floats); its Lab compared with ``swatch color --illuminant D50 --observer 2`` run
  as a separate process (ΔE2000 ≤ 0.05).
* hex codes: colour-science's ``sd_to_XYZ`` with the CIE 1931 2° observer and ``XYZ_to_sRGB``
  on the same spectra (±1 code value).
"""
from __future__ import annotations

import json
import struct
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import swatch  # noqa: F401  (silences colour-science's plotting notice)
import colour  # noqa: F401
from swatch.catalog.exports import ase_bytes
from swatch.catalog.records import compute
from swatch.catalog.spec import parse_spec

SWATCH = str(Path(sys.executable).with_name("swatch"))
THICKNESSES = [20.0, 40.0, 75.5, 130.0, 172.5, 260.0]
SPEC = parse_spec({"name": "Designer exports", "thickness": {"list_nm": THICKNESSES}})


@pytest.fixture(scope="module")
def data():
    return compute(SPEC)


# -- Adobe Swatch Exchange ------------------------------------------------------------------------
ASE_MODEL_SIZES = {b"CMYK": 4, b"RGB ": 3, b"LAB ": 3, b"Gray": 1}


def parse_ase(blob: bytes) -> dict:
    """A reader written from the ASE description, independent of swatch's writer."""
    if blob[:4] != b"ASEF":
        raise ValueError("not an ASE file")
    version = struct.unpack_from(">HH", blob, 4)
    (count,) = struct.unpack_from(">I", blob, 8)
    pos, groups, colours, current = 12, [], [], None
    for _ in range(count):
        kind, length = struct.unpack_from(">HI", blob, pos)
        pos += 6
        body = blob[pos:pos + length]
        pos += length
        if kind == 0xC002:  # group end
            current = None
            continue
        (n_chars,) = struct.unpack_from(">H", body, 0)
        raw = body[2:2 + 2 * n_chars]
        if raw[-2:] != b"\0\0":
            raise ValueError("ASE name without its NUL terminator")
        name = raw[:-2].decode("utf-16-be")
        if kind == 0xC001:
            current = name
            groups.append(name)
            continue
        if kind != 0x0001:
            raise ValueError(f"unknown block type {kind:#x}")
        rest = body[2 + 2 * n_chars:]
        model = rest[:4]
        k = ASE_MODEL_SIZES[model]
        values = struct.unpack_from(f">{k}f", rest, 4)
        (ctype,) = struct.unpack_from(">H", rest, 4 + 4 * k)
        if len(rest) != 4 + 4 * k + 2:
            raise ValueError("trailing bytes in a colour block")
        colours.append({"group": current, "name": name, "model": model.decode().strip(), "values": values,
                        "type": ("global", "spot", "normal")[ctype]})
    if pos != len(blob):
        raise ValueError("trailing bytes after the last block")
    return {"version": version, "groups": groups, "colours": colours}


def swatch_color_json(*args) -> dict:
    run = subprocess.run([SWATCH, "color", *args, "--json"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_ase_lab_is_d50_2deg_at_the_reference_geometry(data):
    ase = parse_ase(ase_bytes(SPEC, data.records, "lab"))
    assert ase["version"] == (1, 0) and ase["groups"] == ["Designer exports"]
    assert [c["model"] for c in ase["colours"]] == ["LAB"] * len(THICKNESSES)
    ref = swatch_color_json("--thickness", ",".join(f"{t:g}" for t in THICKNESSES),
                            "--illuminant", "D50", "--observer", "2")
    assert ref["illuminant"] == "D50" and ref["observer"] == "2" and ref["light_deg"] == 45 and ref["view_deg"] == 0
    ours = np.array([[c["values"][0] * 100.0, c["values"][1], c["values"][2]] for c in ase["colours"]])
    theirs = np.array([r["Lab"] for r in ref["rows"]])
    dE = colour.delta_E(ours, theirs, method="CIE 2000")
    assert float(np.max(dE)) <= 0.05, dE
    # ... and it is not the catalog's own D65/10° Lab (the mistake this file used to make)
    d65 = np.array([r["Lab"] for r in data.records])
    assert float(np.max(colour.delta_E(ours, d65, method="CIE 2000"))) > 0.5


def test_ase_names_and_types(data):
    ase = parse_ase(ase_bytes(SPEC, data.records, "lab"))
    names = [c["name"] for c in ase["colours"]]
    assert names[0] == "S001 Ti 20 nm (9.8 V)"
    assert names[2] == "S003 Ti 75.5 nm (37.2 V)"
    assert all(c["type"] == "global" and c["group"] == "Designer exports" for c in ase["colours"])


def test_ase_srgb_variant_is_the_hex(data):
    ase = parse_ase(ase_bytes(SPEC, data.records, "srgb"))
    assert [c["model"] for c in ase["colours"]] == ["RGB"] * len(THICKNESSES)
    for c, rec in zip(ase["colours"], data.records):
        hexed = "#" + "".join(f"{round(v * 255):02x}" for v in c["values"])
        assert hexed == rec["srgb_hex"]
        assert all(0.0 <= v <= 1.0 for v in c["values"])


# -- hex codes from CIE 1931 2° colorimetry ---------------------------------------------------------
@pytest.mark.parametrize("illuminant, observer", [("D65", "10"), ("D50", "10"), ("D65", "2")])
def test_catalog_hex_is_2deg_srgb(illuminant, observer):
    spec = parse_spec({"name": "hex", "thickness": {"list_nm": THICKNESSES},
                       "colour": {"illuminant": illuminant, "observer": observer}})
    data = compute(spec)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS[illuminant]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(data.wavelength_nm.size), data.wavelength_nm),
                                 cmfs, ill) / 100.0
        for R, rec in zip(data.reflectance, data.records):
            XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(R, data.wavelength_nm), cmfs, ill) / 100.0
            rgb = colour.XYZ_to_sRGB(XYZ, illuminant=colour.XYZ_to_xy(white), chromatic_adaptation_transform="Bradford")
            want = np.round(np.clip(rgb, 0, 1) * 255).astype(int)
            got = np.array([int(rec["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5)])
            assert np.max(np.abs(got - want)) <= 1, (rec["thickness_nm"], got, want)
    # swatch color reports the same hex for the same spectra (one definition of hex everywhere)
    ref = swatch_color_json("--thickness", ",".join(f"{t:g}" for t in THICKNESSES),
                            "--illuminant", illuminant, "--observer", observer)
    assert [r["srgb_hex"] for r in ref["rows"]] == [r["srgb_hex"] for r in data.records]


# -- CxF3 -----------------------------------------------------------------------------------------
CXF_XSD = Path(__file__).parent / "data" / "cxf3" / "CxF3_Core.xsd"
NS = {"cc": "http://colorexchangeformat.com/CxF3-core"}


def cxf_schema():
    from lxml import etree

    return etree.XMLSchema(etree.parse(str(CXF_XSD)))


@pytest.mark.parametrize("illuminant, observer", [("D65", "10"), ("D50", "2"), ("A", "10")])
def test_cxf3_is_valid_against_the_official_schema(illuminant, observer):
    from lxml import etree

    from swatch.catalog.exports import cxf_bytes

    spec = parse_spec({"name": "schema", "thickness": {"list_nm": [40.0, 130.0]},
                       "colour": {"illuminant": illuminant, "observer": observer}})
    doc = etree.fromstring(cxf_bytes(spec, compute(spec)))
    schema = cxf_schema()
    assert schema.validate(doc), schema.error_log
    # The schema can fail: an unknown method is refused
    bad = etree.fromstring(cxf_bytes(spec, compute(spec)))
    bad.find(".//cc:Method", NS).text = "E308_Table7"
    assert not schema.validate(bad)


def test_cxf3_method_white_points_srgb_and_d50(data):
    import xml.etree.ElementTree as ET

    from swatch.catalog.exports import cxf_bytes

    root = ET.fromstring(cxf_bytes(SPEC, data))
    specs = {cs.get("Id"): cs for cs in root.findall(".//cc:ColorSpecification", NS)}
    for cs in specs.values():
        assert cs.find(".//cc:Method", NS).text == "E308_1nm"  # 5 nm data, ASTM E308 (colour.sd_to_XYZ)
        ill = cs.find(".//cc:Illuminant", NS)
        obs = cs.find(".//cc:Observer", NS).text
        cmfs = colour.MSDS_CMFS[{"2_Degree": "CIE 1931 2 Degree Standard Observer",
                                 "10_Degree": "CIE 1964 10 Degree Standard Observer"}[obs]]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(81), data.wavelength_nm), cmfs,
                                     colour.SDS_ILLUMINANTS[ill.text])
        assert [float(ill.get(k)) for k in "XYZ"] == pytest.approx(white, abs=1e-3)
    obj = root.findall(".//cc:Object", NS)[2]
    rec = data.records[2]
    srgb = obj.find("cc:ColorValues/cc:ColorSRGB", NS)
    cs_srgb = specs[srgb.get("ColorSpecification")]
    assert cs_srgb.find(".//cc:Observer", NS).text == "2_Degree"
    assert cs_srgb.find(".//cc:Illuminant", NS).text == "D65"
    assert "#" + "".join(f"{int(srgb.find(f'cc:{k}', NS).text):02x}" for k in "RGB") == rec["srgb_hex"]
    labs = {specs[e.get("ColorSpecification")].find(".//cc:Illuminant", NS).text
            + "/" + specs[e.get("ColorSpecification")].find(".//cc:Observer", NS).text: e
            for e in obj.findall("cc:ColorValues/cc:ColorCIELab", NS)
            if specs[e.get("ColorSpecification")].find(".//cc:SingleAngle", NS) is not None}
    assert set(labs) == {"D65/10_Degree", "D50/2_Degree"}
    d50 = [float(labs["D50/2_Degree"].find(f"cc:{k}", NS).text) for k in ("L", "A", "B")]
    ref = swatch_color_json("--thickness", "75.5", "--illuminant", "D50", "--observer", "2")["rows"][0]["Lab"]
    assert float(colour.delta_E(d50, ref, method="CIE 2000")) <= 0.05
