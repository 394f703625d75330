"""CxF3 and ASE exports, read back with independent readers (xml.etree, colour-cxf, a small ASE parser)."""
from __future__ import annotations

import struct
import xml.etree.ElementTree as ET

import colour  # noqa: F401  (after swatch: its plotting notice stays silenced)
import numpy as np
import pytest

import swatch  # noqa: F401
from swatch.catalog.context import catalog_context
from swatch.catalog.exports import ase_bytes, cxf_bytes
from swatch.catalog.records import compute
from swatch.catalog.spec import parse_spec

NS = {"cc": "http://colorexchangeformat.com/CxF3-core"}
SPEC = parse_spec({"name": "Exports <test> & co", "thickness": {"list_nm": [40.0, 75.5, 130.0]}})


@pytest.fixture(scope="module")
def data():
    return compute(catalog_context(SPEC))


def read_ase(blob: bytes):
    """An independent reader of the Adobe Swatch Exchange format (big-endian)."""
    assert blob[:4] == b"ASEF"
    major, minor, count = struct.unpack(">HHI", blob[4:12])
    pos, blocks = 12, []
    for _ in range(count):
        kind, length = struct.unpack(">HI", blob[pos:pos + 6])
        body = blob[pos + 6:pos + 6 + length]
        pos += 6 + length
        entry = {"kind": kind}
        if kind in (0x0001, 0xC001):
            (n,) = struct.unpack(">H", body[:2])
            name = body[2:2 + 2 * n].decode("utf-16-be")
            assert name.endswith("\x00")
            entry["name"] = name[:-1]
            rest = body[2 + 2 * n:]
            if kind == 0x0001:
                entry["model"] = rest[:4]
                assert entry["model"] == b"LAB "
                entry["values"] = struct.unpack(">fff", rest[4:16])
                (entry["type"],) = struct.unpack(">H", rest[16:18])
                assert len(rest) == 18
        blocks.append(entry)
    assert pos == len(blob)
    return (major, minor), blocks


def test_ase_round_trip(data):
    version, blocks = read_ase(ase_bytes(SPEC, data.records))
    assert version == (1, 0)
    assert blocks[0] == {"kind": 0xC001, "name": "Exports <test> & co"}
    assert blocks[-1] == {"kind": 0xC002}
    colours = blocks[1:-1]
    assert len(colours) == 3
    for blk, rec in zip(colours, data.records, strict=True):
        L, a, b = blk["values"]
        assert [L * 100, a, b] == pytest.approx(rec["Lab_D50_2"], abs=1e-3)  # D50/2°: as Adobe reads ASE
        assert blk["type"] == 0  # global
        assert blk["name"].startswith(f"{rec['id']} Ti {rec['thickness_nm']:g} nm")


def test_cxf3_content(data):
    blob = cxf_bytes(SPEC, data)
    root = ET.fromstring(blob)
    assert root.tag == "{" + NS["cc"] + "}CxF"
    objs = root.findall(".//cc:Object", NS)
    assert len(objs) == 3
    specs = {cs.get("Id"): cs for cs in root.findall(".//cc:ColorSpecification", NS)}
    # reference (D65/10°), reference under D50/2° and under D65/2° (sRGB), the multi-angle geometries
    assert len(specs) == 3 + len(SPEC.multi_angle)
    ref_id = "CS-45-0"
    sa = specs[ref_id].find(".//cc:SingleAngle", NS)
    assert float(sa.find("cc:IlluminationAngle", NS).text) == 45 and float(sa.find("cc:MeasurementAngle", NS).text) == 0
    assert specs[ref_id].find(".//cc:Illuminant", NS).text == "D65"
    assert specs[ref_id].find(".//cc:Observer", NS).text == "10_Degree"
    wr = specs[ref_id].find(".//cc:WavelengthRange", NS)
    assert (wr.get("StartWL"), wr.get("Increment")) == ("380", "5")
    ma = specs["CS-45as110"].find(".//cc:BRDFAngle", NS)
    assert float(ma.find("cc:Aspecular", NS).text) == 110
    for obj, rec, R in zip(objs, data.records, data.reflectance, strict=True):
        labs = {e.get("ColorSpecification"): e for e in obj.findall(".//cc:ColorCIELab", NS)}
        lab = labs[ref_id]
        got = [float(lab.find(f"cc:{k}", NS).text) for k in ("L", "A", "B")]
        assert got == pytest.approx(rec["Lab"], abs=1e-4)
        m = labs["CS-45as-15"]
        assert [float(m.find(f"cc:{k}", NS).text) for k in "LAB"] == pytest.approx(rec["multi_angle"]["45as-15"], abs=1e-4)
        spectra = {e.get("ColorSpecification"): e for e in obj.findall(".//cc:ReflectanceSpectrum", NS)}
        values = np.array(spectra[ref_id].text.split(), dtype=float)
        assert values.size == 81 and np.allclose(values, R, atol=1e-5)


def test_cxf3_reads_with_colour_cxf_and_is_deterministic(data):
    import colour_cxf

    blob = cxf_bytes(SPEC, data)
    doc = colour_cxf.read_cxf(blob)
    names = [o.name for o in doc.resources.object_collection.object_value]
    assert len(names) == 3 and names[1].startswith("S002 Ti 75.5 nm")
    assert cxf_bytes(SPEC, data) == blob
