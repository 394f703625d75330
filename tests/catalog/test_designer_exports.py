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
import warnings
from pathlib import Path

import colour
import numpy as np
import pytest

import swatch  # noqa: F401  (silences colour-science's plotting notice)
from swatch.catalog.context import catalog_context
from swatch.catalog.exports import ase_bytes
from swatch.catalog.records import compute
from swatch.catalog.spec import parse_spec
from swatch.io.pngmeta import SWATCH_XMP_NS
from tests.cli_helpers import run_json, run_swatch

pytestmark = pytest.mark.slow  # builds catalogs or runs processes (seconds per test)

THICKNESSES = [20.0, 40.0, 75.5, 130.0, 172.5, 260.0]
SPEC = parse_spec({"name": "Designer exports", "thickness": {"list_nm": THICKNESSES}})


@pytest.fixture(scope="module")
def data():
    return compute(catalog_context(SPEC))


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
    """``swatch color ARGS --json`` through the CLI's entry point, in this process (tests/cli_helpers.py)."""
    return run_json("color", *args)


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
    assert names[0] == "S001 Ti 20 nm (9.8 V) straw"  # the colour name of the sheets and the page (issue 21)
    assert names[2].startswith("S003 Ti 75.5 nm (37.2 V) ")
    assert all(c["type"] == "global" and c["group"] == "Designer exports" for c in ase["colours"])


def test_ase_srgb_variant_is_the_hex(data):
    ase = parse_ase(ase_bytes(SPEC, data.records, "srgb"))
    assert [c["model"] for c in ase["colours"]] == ["RGB"] * len(THICKNESSES)
    for c, rec in zip(ase["colours"], data.records, strict=True):
        hexed = "#" + "".join(f"{round(v * 255):02x}" for v in c["values"])
        assert hexed == rec["srgb_hex"]
        assert all(0.0 <= v <= 1.0 for v in c["values"])


# -- hex codes from CIE 1931 2° colorimetry ---------------------------------------------------------
@pytest.mark.parametrize("illuminant, observer", [("D65", "10"), ("D50", "10"), ("D65", "2")])
def test_catalog_hex_is_2deg_srgb(illuminant, observer):
    spec = parse_spec({"name": "hex", "thickness": {"list_nm": THICKNESSES},
                       "colour": {"illuminant": illuminant, "observer": observer}})
    data = compute(catalog_context(spec))
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS[illuminant]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(data.wavelength_nm.size), data.wavelength_nm),
                                 cmfs, ill) / 100.0
        for R, rec in zip(data.reflectance, data.records, strict=True):
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
CXF_XSD = Path(__file__).resolve().parents[1] / "data" / "cxf3" / "CxF3_Core.xsd"
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
    doc = etree.fromstring(cxf_bytes(spec, compute(catalog_context(spec))))
    schema = cxf_schema()
    assert schema.validate(doc), schema.error_log
    # The schema can fail: an unknown method is refused
    bad = etree.fromstring(cxf_bytes(spec, compute(catalog_context(spec))))
    bad.find(".//cc:Method", NS).text = "E308_Table7"
    assert not schema.validate(bad)


def test_cxf3_method_white_points_srgb_and_d50(data):
    import xml.etree.ElementTree as ET

    from swatch.catalog.exports import cxf_bytes

    root = ET.fromstring(cxf_bytes(SPEC, data))
    specs = {cs.get("Id"): cs for cs in root.findall(".//cc:ColorSpecification", NS)}
    for cs in specs.values():
        # 5 nm data: ASTM E308's practice weights them with the 1 nm table's values at every fifth
        # wavelength (colour.sd_to_XYZ's 5 nm omission method), which is what E308_1nm names; the
        # grid itself is the WavelengthRange (Increment 5) — checked below against that table (#18)
        assert cs.find(".//cc:Method", NS).text == "E308_1nm"
        assert cs.find(".//cc:WavelengthRange", NS).get("Increment") == "5"
        ill = cs.find(".//cc:Illuminant", NS)
        obs = cs.find(".//cc:Observer", NS).text
        cmfs = colour.MSDS_CMFS[{"2_Degree": "CIE 1931 2 Degree Standard Observer",
                                 "10_Degree": "CIE 1964 10 Degree Standard Observer"}[obs]]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(81), data.wavelength_nm), cmfs,
                                     colour.SDS_ILLUMINANTS[ill.text])
        assert [float(ill.get(k)) for k in "XYZ"] == pytest.approx(white, abs=1e-3)
        # E308_1nm as done: the 1 nm tables' values every 5 nm over the practice range 360–830 nm
        # (the data extended to it, as colour.sd_to_XYZ does), summed (#18)
        wl5 = np.arange(360.0, 831.0, 5.0)
        S = colour.SDS_ILLUMINANTS[ill.text][wl5]
        xyz5 = cmfs[wl5]
        direct = 100.0 * (S[:, None] * xyz5).sum(axis=0) / (S * xyz5[:, 1]).sum()
        assert [float(ill.get(k)) for k in "XYZ"] == pytest.approx(direct, abs=1e-3)
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


# -- PNG text, XMP, intent and DPI (read with Pillow) ---------------------------------------------
TINY_SPEC = """
name = "Tiny – 10° catalog"
[thickness]
list_nm = [40, 75.5, 130]
[render]
size_px = 64
[sheet]
columns = 2
rows = 2
[presets]
enabled = false
"""


@pytest.fixture(scope="module")
def tiny_catalog(tmp_path_factory):
    from swatch.catalog.build import build_catalog

    root = tmp_path_factory.mktemp("tiny")
    spec = root / "tiny.toml"
    spec.write_text(TINY_SPEC, encoding="utf-8")
    build_catalog(spec, root / "out", jobs=1)
    return root / "out"


def png_chunk_types(path: Path) -> list[bytes]:
    blob = path.read_bytes()
    pos, kinds = 8, []
    while pos < len(blob):
        (n,) = struct.unpack_from(">I", blob, pos)
        kinds.append(blob[pos + 4:pos + 8])
        pos += 12 + n
    return kinds


def xmp_fields(xmp: str) -> dict:
    import xml.etree.ElementTree as ET

    root = ET.fromstring(xmp[xmp.index("<x:xmpmeta"):xmp.index("</x:xmpmeta>") + len("</x:xmpmeta>")])
    rdf, dc = "{http://www.w3.org/1999/02/22-rdf-syntax-ns#}", "{http://purl.org/dc/elements/1.1/}"
    desc = root.find(f"{rdf}RDF/{rdf}Description")
    out = {k: desc.find(f"{dc}{k}/{rdf}Alt/{rdf}li").text for k in ("title", "description")}
    for el in desc:
        if el.tag.startswith("{" + SWATCH_XMP_NS + "}"):
            out[el.tag.split("}")[1]] = el.text
    return out


def test_sheet_png_text_is_utf8_itxt_with_xmp_intent_and_dpi(tiny_catalog):
    from PIL import Image

    doc = json.loads((tiny_catalog / "catalog.json").read_text(encoding="utf-8"))
    png = tiny_catalog / "sheets/sheet_01.png"
    kinds = png_chunk_types(png)
    assert b"tEXt" not in kinds and b"iTXt" in kinds
    assert kinds.index(b"pHYs") < kinds.index(b"IDAT")
    with Image.open(png) as im:
        text = dict(im.text)
        info = dict(im.info)
    # exact text: the UTF-8 characters survive (no "10Â°", no "â€“")
    assert json.loads(text["swatch:catalog"]) == doc["catalog"]
    assert "CIE 1964 10°" not in text["swatch:catalog"] and "1964 10°" in text["swatch:catalog"]
    assert json.loads(text["swatch:catalog"])["name"] == "Tiny – 10° catalog"
    assert json.loads(text["swatch:S002"]) == doc["swatches"][1]
    assert info["srgb"] in (0, 1)  # perceptual or relative colorimetric, not absolute (3)
    assert info["dpi"] == pytest.approx((150, 150), abs=0.05)  # pHYs holds whole pixels per metre
    xmp = xmp_fields(info["XML:com.adobe.xmp"])
    assert xmp["title"] == "Tiny – 10° catalog — sheet 1 of 1"
    assert "D65" in xmp["description"] and "1931 2°" in xmp["description"]
    rec = doc["swatches"][1]
    assert f"S002 Ti 75.5 nm ({rec['voltage_V']:.1f} V) {rec['colour_name']}: L*a*b* (D65/10°) " + " ".join(
        f"{x:.2f}" for x in rec["Lab"]) in xmp["swatches"]
    assert xmp["thickness_nm"] == "40 75.5 130"


def test_render_png_xmp_and_text(tmp_path):
    from PIL import Image

    run = run_swatch("render", "--thickness", "50.8", "--size", "32", "--out", tmp_path)
    assert run.returncode == 0, run.stderr
    with Image.open(tmp_path / "flat_050.8nm.png") as im:
        info = dict(im.info)
        text = dict(im.text)
    assert text["swatch:observer"] == "CIE 1964 10 deg" and float(text["swatch:thickness_nm"]) == 50.8
    xmp = xmp_fields(info["XML:com.adobe.xmp"])
    assert xmp["title"] == "flat swatch, 50.8 nm" and xmp["thickness_nm"] == "50.8"
    lab = [float(x) for x in xmp["Lab_reference"].split()]
    ref = swatch_color_json("--thickness", "50.8")["rows"][0]["Lab"]
    assert lab == pytest.approx(ref, abs=0.006)
    assert info["srgb"] == 0


# -- spectral EXR (read with the OpenEXR library) and one orientation -----------------------------
def test_spectral_exr_has_an_rgb_preview_and_float32_and_the_png_orientation(tmp_path):
    import OpenEXR

    run = run_swatch("angular", "--thickness", "50.8", "--light-range", "0:80:10", "--view-range", "0:60:20",
                     "--model", "paper", "--out", tmp_path)
    assert run.returncode == 0, run.stderr
    with OpenEXR.File(str(tmp_path / "angular_050.8nm_spectral.exr"), separate_channels=True) as f:
        ch = {k: v.pixels for k, v in f.channels().items()}
    assert {"R", "G", "B"} <= set(ch)
    spectral = sorted((k for k in ch if k.startswith("T.")), key=lambda k: float(k[2:-2].replace(",", ".")))
    assert len(spectral) == 81 and all(ch[k].dtype == np.float32 for k in [*spectral, "R", "G", "B"])
    cube = np.stack([ch[k] for k in spectral], -1).astype(np.float64)  # (rows, cols, W)
    assert cube.shape[:2] == (9, 4)
    wl = np.arange(380.0, 781.0, 5.0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for r, c in ((0, 0), (8, 0), (3, 2)):
            XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(cube[r, c], wl), cmfs, colour.SDS_ILLUMINANTS["D65"])
            want = colour.XYZ_to_RGB(XYZ / 100.0, "sRGB", illuminant=colour.CCS_ILLUMINANTS[
                "CIE 1931 2 Degree Standard Observer"]["D65"], chromatic_adaptation_transform="Bradford")
            got = [ch[k][r, c] for k in "RGB"]
            assert got == pytest.approx(want, abs=2e-3)
    # Orientation: the bottom row is light 0° (θd = view/2), the top row light 80°, as in the PNG.
    from swatch.physics.model import get_coating

    coating = get_coating()
    assert cube[-1, 2] == pytest.approx(coating.reflectance(50.8, 20.0).R, abs=1e-6)  # light 0, view 40
    assert cube[0, 0] == pytest.approx(coating.reflectance(50.8, 40.0).R, abs=1e-6)  # light 80, view 0
    with OpenEXR.File(str(tmp_path / "angular_050.8nm.exr"), separate_channels=True) as f:
        rgb = np.stack([f.channels()[k].pixels for k in "RGB"], -1).astype(np.float64)
    assert np.allclose(rgb, np.stack([ch[k] for k in "RGB"], -1), atol=2e-3)  # same rows, same order


# -- print chips (read with Pillow and tifffile) ----------------------------------------------------
def test_print_chips_png_and_tiff(tiny_catalog):
    import tifffile
    from PIL import Image, ImageCms

    doc = json.loads((tiny_catalog / "catalog.json").read_text(encoding="utf-8"))
    rec = doc["swatches"][1]
    assert rec["print_chip"] == {"png": "chips/chip_S002.png", "tiff": "chips/chip_S002.tif", "size_mm": 50.0, "dpi": 300}
    side = round(50 / 25.4 * 300)  # 591 px
    want8 = np.array([int(rec["srgb_hex"][i:i + 2], 16) for i in (1, 3, 5)])
    # PNG: 16-bit RGB (IHDR bit depth), tagged sRGB, 300 dpi, the record in UTF-8 text, XMP
    png = tiny_catalog / "chips/chip_S002.png"
    ihdr = png.read_bytes()[16:29]
    width, height, depth, ctype = struct.unpack(">IIBB", ihdr[:10])
    assert (width, height, depth, ctype) == (side, side, 16, 2)
    with Image.open(png) as im:  # #18: relative colorimetric, the convention for colour chips
        assert im.info["srgb"] == 1 and im.info["dpi"] == pytest.approx((300, 300), abs=0.05)
        assert json.loads(im.text["swatch:record"]) == dict(rec)
        xmp = xmp_fields(im.info["XML:com.adobe.xmp"])
    assert xmp["title"].startswith("S002 Ti 75.5 nm") and xmp["Lab_D50_2"] == " ".join(
        f"{x:.2f}" for x in rec["Lab_D50_2"])
    # TIFF: 16-bit, flat, the same colour, 300 dpi, an embedded sRGB ICC profile LittleCMS reads;
    # #18: LZW (what exiftool -validate accepts), a valid fixed DateTime (an empty one is an invalid date)
    with tifffile.TiffFile(tiny_catalog / "chips/chip_S002.tif") as tf:
        page = tf.pages[0]
        px = page.asarray()
        assert px.dtype == np.uint16 and px.shape == (side, side, 3)
        assert page.compression == tifffile.COMPRESSION.LZW
        assert page.tags["DateTime"].value == "1970:01:01 00:00:00"
        assert page.tags["XResolution"].value == (300, 1) and page.tags["ResolutionUnit"].value == 2
        icc = page.iccprofile
        assert "S002 Ti 75.5 nm" in page.tags["ImageDescription"].value
    assert (px == px[0, 0]).all()
    assert np.max(np.abs(np.round(px[0, 0] / 257.0) - want8)) <= 1  # the hex code's colour, in 16 bits
    profile = ImageCms.ImageCmsProfile(__import__("io").BytesIO(icc))
    assert "sRGB" in ImageCms.getProfileDescription(profile)
    assert ImageCms.getDefaultIntent(profile) == ImageCms.Intent.RELATIVE_COLORIMETRIC
    # libtiff (OpenImageIO's TIFF reader) reads the same pixels
    import OpenImageIO as oiio

    lib = oiio.ImageBuf(str(tiny_catalog / "chips/chip_S002.tif"))
    assert lib.spec().get_string_attribute("compression") == "lzw"
    assert (np.asarray(lib.get_pixels(oiio.UINT16)) == px).all()
    assert (tiny_catalog / "chips/chip_S002.png").stat().st_size < 64_000  # flat: small files


def test_chip_spec_limits():
    from swatch.core.errors import SwatchError

    base = {"name": "x", "thickness": {"list_nm": [50.0]}}
    assert parse_spec(dict(base, chips={"size_mm": 25, "dpi": 600})).chip_size_mm == 25
    assert not parse_spec(dict(base, chips={"enabled": False})).chips
    with pytest.raises(SwatchError, match=r"at most 4096 pixels"):
        parse_spec(dict(base, chips={"size_mm": 300, "dpi": 1200}))
    with pytest.raises(SwatchError, match=r"chips\.dpi"):
        parse_spec(dict(base, chips={"dpi": 10}))


# -- the files as other tools read them: exiftool (what Bridge/Lightroom-style XMP readers see) and
# pngcheck (the PNG chunk checker); Debian packages, installed by .ci/run ---------------------------

def _require_tool(name: str) -> str:
    import os
    import shutil

    exe = shutil.which(name)
    if exe:
        return exe
    if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
        pytest.fail(f"{name} is missing and SWATCH_REQUIRE_TOOLS=1 (.ci/run installs it)")
    pytest.skip(f"{name} not installed (Debian: pngcheck, libimage-exiftool-perl)")


def test_exiftool_and_pngcheck_read_the_exports(tiny_catalog):
    exiftool, pngcheck = _require_tool("exiftool"), _require_tool("pngcheck")
    doc = json.loads((tiny_catalog / "catalog.json").read_text(encoding="utf-8"))
    rec = doc["swatches"][1]
    sheet, chip_png, chip_tif = (tiny_catalog / n for n in ("sheets/sheet_01.png", "chips/chip_S002.png", "chips/chip_S002.tif"))
    for png in (sheet, chip_png):
        check = subprocess.run([pngcheck, "-v", str(png)], capture_output=True, text=True, timeout=60)
        assert check.returncode == 0 and "No errors detected" in check.stdout, check.stdout[-500:]
    run = subprocess.run([exiftool, "-j", "-G1", "-a", "-charset", "utf8", str(sheet), str(chip_png), str(chip_tif)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    s, p, t = json.loads(run.stdout)
    # the sheet: UTF-8 text and XMP read exactly, perceptual intent, 150 dpi
    assert s["XMP-dc:Title"] == "Tiny – 10° catalog — sheet 1 of 1"
    assert json.loads(s["PNG:Swatchcatalog"]) == doc["catalog"]
    assert s["PNG:SRGBRendering"] == "Perceptual"
    assert s["PNG-pHYs:PixelsPerUnitX"] == round(150 / 0.0254) and s["PNG-pHYs:PixelUnits"] == "meters"
    # the print chip PNG: 16 bits, 300 dpi, the swatch's numbers in XMP
    assert p["PNG:BitDepth"] == 16 and p["PNG-pHYs:PixelsPerUnitX"] == round(300 / 0.0254)
    assert p["XMP-dc:Title"] == f"S002 Ti 75.5 nm ({rec['voltage_V']:.1f} V) {rec['colour_name']}"
    assert p["XMP-anodic:Lab"] == " ".join(f"{x:.2f}" for x in rec["Lab"])
    assert p["XMP-anodic:Lab_D50_2"] == " ".join(f"{x:.2f}" for x in rec["Lab_D50_2"])
    assert p["XMP-anodic:Srgb_hex"] == rec["srgb_hex"] and json.loads(p["PNG:Swatchrecord"]) == rec
    # the print chip PNG's intent (#18: relative colorimetric for colour chips)
    assert p["PNG:SRGBRendering"] == "Relative Colorimetric"
    # the print chip TIFF: 16 bits, 300 dpi, an embedded sRGB profile
    assert t["IFD0:BitsPerSample"] == "16 16 16" and t["IFD0:XResolution"] == 300
    assert t["IFD0:ResolutionUnit"] == "inches" and "sRGB" in t["ICC_Profile:ProfileDescription"]
    assert t["IFD0:ImageDescription"].startswith("S002 Ti 75.5 nm")
    assert t["ICC-header:RenderingIntent"] == "Media-Relative Colorimetric"
    # #18: exiftool's validator finds nothing in either chip (it flagged Deflate and an empty DateTime)
    check = subprocess.run([exiftool, "-validate", "-warning", "-error", "-a", "-s", str(chip_tif), str(chip_png)],
                           capture_output=True, text=True, timeout=60)
    assert check.returncode == 0 and check.stdout.count(": OK") == 2, check.stdout


def test_cards_link_their_print_chips(tiny_catalog):
    """Each card links its print chip (PNG and TIFF), and the links name files in the catalog."""
    import html.parser

    class Links(html.parser.HTMLParser):
        def __init__(self):
            super().__init__()
            self.hrefs = []

        def handle_starttag(self, tag, attrs):
            if tag == "a":
                self.hrefs.append(dict(attrs).get("href"))

    doc = json.loads((tiny_catalog / "catalog.json").read_text(encoding="utf-8"))
    parser = Links()
    parser.feed((tiny_catalog / "index.html").read_text(encoding="utf-8"))
    for rec in doc["swatches"]:
        for key in ("png", "tiff"):
            name = rec["print_chip"][key]
            assert name in parser.hrefs and (tiny_catalog / name).is_file()


def test_presets_left_out_are_neither_fitted_nor_written_nor_named(tiny_catalog):
    """``[presets] enabled = false`` (TINY_SPEC): the build fits nothing (no cached fits), writes no
    ``presets/`` file, and neither the records nor the page name a preset; the CSV keeps its columns,
    empty (a reader's column layout does not depend on the spec). Issue 17."""
    import csv

    assert not (tiny_catalog / "presets").exists()
    manifest = json.loads((tiny_catalog / ".swatch-catalog" / "manifest.json").read_text(encoding="utf-8"))
    assert not [f for f in manifest["files"] if f.startswith("presets/")]
    assert not list((tiny_catalog / ".swatch-catalog" / "cache").glob("presets-*.json"))
    doc = json.loads((tiny_catalog / "catalog.json").read_text(encoding="utf-8"))
    assert len(doc["swatches"]) == 3 and all("presets" not in r for r in doc["swatches"])
    assert "3-D material presets" not in (tiny_catalog / "index.html").read_text(encoding="utf-8")
    (csv_name,) = [f for f in manifest["files"] if f.endswith(".csv")]
    with open(tiny_catalog / csv_name, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 3
    for col in ("preset_gltf", "preset_blender", "preset_materialx", "preset_mitsuba", "preset_mitsuba_json"):
        assert [r[col] for r in rows] == ["", "", ""], col


def test_presets_spec_option():
    """``[presets] enabled``: on by default and then left out of the build's hashes (the hashes of
    before stay); a non-boolean or an unknown key is refused naming the key; ``catalog validate``'s
    summary counts no ``presets/`` files without them. Issue 17."""
    from swatch.catalog.layout import layout_summary
    from swatch.core.errors import SwatchError

    base = {"name": "p", "thickness": {"list_nm": [50]}}
    on, off = parse_spec(base), parse_spec(base | {"presets": {"enabled": False}})
    assert on.presets is True and off.presets is False
    assert "presets" not in on.canonical() and off.canonical()["presets"] is False
    assert parse_spec(base | {"presets": {"enabled": True}}).canonical() == on.canonical()
    with pytest.raises(SwatchError, match=r"presets\.enabled"):
        parse_spec(base | {"presets": {"enabled": "no"}})
    with pytest.raises(SwatchError, match="presets"):
        parse_spec(base | {"presets": {"formats": ["gltf"]}})
    assert "presets/" in layout_summary(3, 1, True, False)
    assert "presets/" not in layout_summary(3, 1, True, False, presets=False)
