"""Hardening round 3 (issue 38 items 4 and 5), from the user's side: the CLI in one subprocess per group.
A coupon file over the (lowered) coupon cap, a 2-channel environment map, glTF files that need what
swatch does not read (Draco, a buffer larger than the file, files outside it), a triangle far from the
origin within the documented coordinate cap, and `fit` of absurd wavelengths: one line `error: …`,
exit 2, no numpy warning; or, for the valid triangle, a render."""
from __future__ import annotations

import base64
import json
import struct

import numpy as np
import OpenImageIO as oiio
import pytest

from swatch.core.limits import MAX_COUPONS, MAX_MESH_BYTES
from tests.cli_helpers import run_capped_batch

CAP = 2 * 1024**3 + 512 * 1024**2

#: one triangle: 3 float32 positions, then 3 uint16 indices (padded to 4 bytes)
TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<3H", 0, 1, 2) + b"\0\0"


def gltf(**changes) -> dict:
    """A valid one-triangle glTF with its buffer embedded as a data: URI, with top-level ``changes``."""
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0],
                          "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                           {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
           "buffers": [{"byteLength": len(TRIANGLE),
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(TRIANGLE).decode()}]}
    doc.update(changes)
    return doc


def glb(doc: dict, payload: bytes) -> bytes:
    """A binary glTF: the JSON chunk (``doc``, its buffer 0 without a URI) and a BIN chunk."""
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    payload += b"\0" * (-len(payload) % 4)
    return (b"glTF" + struct.pack("<II", 2, 28 + len(js) + len(payload)) + struct.pack("<II", len(js), 0x4E4F534A)
            + js + struct.pack("<II", len(payload), 0x004E4942) + payload)


def _mesh_cases() -> dict[str, tuple[bytes, str]]:
    """name -> (file bytes, what the one line says)."""
    draco = gltf(extensionsUsed=["KHR_draco_mesh_compression"], extensionsRequired=["KHR_draco_mesh_compression"])
    huge = gltf()
    huge["buffers"][0]["byteLength"] = 10**12
    outside = gltf()
    outside["buffers"].append({"byteLength": 10, "uri": "../../etc/passwd"})
    image = gltf(images=[{"uri": "../../etc/passwd"}])
    in_extension = gltf(extensions={"EXT_example": {"uri": "/etc/hostname"}})
    bin_doc = gltf()
    del bin_doc["buffers"][0]["uri"]
    bin_doc["buffers"][0]["byteLength"] = 10**12
    view_past = gltf()
    view_past["bufferViews"][1]["byteLength"] = MAX_MESH_BYTES
    return {
        "draco.gltf": (json.dumps(draco).encode(), "requires the glTF extension 'KHR_draco_mesh_compression'"),
        "huge_buffer.gltf": (json.dumps(huge).encode(), "buffer 0 claims 1000000000000 bytes but holds 44"),
        "huge_buffer.glb": (glb(bin_doc, TRIANGLE), "buffer 0 claims 1000000000000 bytes but holds 44"),
        "view_past_the_buffer.gltf": (json.dumps(view_past).encode(), "bufferView 1 lies outside its buffer"),
        "outside_buffer.gltf": (json.dumps(outside).encode(), "external file '../../etc/passwd'"),
        "outside_image.gltf": (json.dumps(image).encode(), "external file '../../etc/passwd'"),
        "outside_in_an_extension.gltf": (json.dumps(in_extension).encode(), "external file '/etc/hostname'"),
    }


def _exr(path, channels: int) -> None:
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(64, 32, channels, "float"))
    assert out.write_image(np.full((32, 64, channels), 0.5, dtype=np.float32))
    out.close()


@pytest.fixture(scope="module")
def refused(tmp_path_factory):
    """Every refusal case through the CLI in one capped subprocess: name -> (result, fragment, folder)."""
    d = tmp_path_factory.mktemp("round3")
    cases: dict[str, tuple[list, str]] = {}
    for name, (data, fragment) in _mesh_cases().items():
        (d / name).write_bytes(data)
        cases[name] = (["render", "--thickness", "100", "--mesh", d / name, "--size", "32", "--environment", "point",
                        "--out", d / f"out-{name}"], fragment)
    _exr(d / "two.exr", 2)
    cases["two_channel_map"] = (["render", "--thickness", "100", "--size", "32", "--environment", d / "two.exr",
                                 "--out", d / "out-two"], "has 2 channels; give 1 (grey) or 3 to 64")
    rows = "".join(f"{10 + 0.25 * i:.2f},50,1,-20\n" for i in range(MAX_COUPONS + 1))  # within MAX_VOLTAGE_V
    (d / "coupons.csv").write_text("voltage_V,L,a,b\n" + rows, encoding="utf-8")
    cases["one_coupon_too_many"] = (["calibrate", d / "coupons.csv", "--out", d / "line.toml"],
                                    f"more than {MAX_COUPONS} coupons; a calibration takes at most {MAX_COUPONS}")
    for k, text in enumerate(["1e300,0.2\n2e300,0.3\n3e300,0.4\n", "400,0.2\n1e308,0.3\n"]):
        (d / f"huge_wl{k}.csv").write_text("wavelength_nm,reflectance\n" + text, encoding="utf-8")
        cases[f"huge_wavelengths_{k}"] = (["fit", d / f"huge_wl{k}.csv"], "nm is outside the measured range")
    names = list(cases)
    procs = run_capped_batch([cases[n][0] for n in names], CAP)
    return {n: (p, cases[n][1]) for n, p in zip(names, procs, strict=True)}, d


CASE_NAMES = [*_mesh_cases(), "two_channel_map", "one_coupon_too_many", "huge_wavelengths_0", "huge_wavelengths_1"]


@pytest.mark.parametrize("name", CASE_NAMES)
def test_issue38_refused_in_one_line_with_nothing_written(refused, name):
    results, folder = refused
    proc, fragment = results[name]
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("error: ") and proc.stderr.count("\n") == 1, proc.stderr  # (no numpy warning line)
    assert fragment in proc.stderr, proc.stderr
    assert not (folder / f"out-{name}").exists() and not (folder / "line.toml").exists()


def test_issue38_a_triangle_far_out_within_the_coordinate_cap_renders_as_at_unit_scale(tmp_path):
    """Issue 38: a valid triangle at ±1e11…1e15 (MAX_MESH_COORDINATE is 1e15) was refused "all vertices are at one
    point" (trimesh's vertex merge rounds to 1e-8 in int64, which overflowed). Placed in the unit sphere, it is
    the same picture as the triangle at unit scale."""
    argvs = []
    for scale in ("1", "1e11", "1e13", "1e15"):
        (tmp_path / f"tri_{scale}.obj").write_text(f"v -{scale} 0 0\nv {scale} 0 0\nv 0 {scale} 0\nf 1 2 3\n",
                                                   encoding="utf-8")
        argvs.append(["render", "--thickness", "100", "--mesh", tmp_path / f"tri_{scale}.obj", "--size", "32",
                      "--environment", "point", "--out", tmp_path / scale])
    for proc in run_capped_batch(argvs, CAP):
        assert proc.returncode == 0, proc.stderr
    images = {s: oiio.ImageBuf(str(next((tmp_path / s).glob("*.png")))).get_pixels(oiio.UINT8) for s in
              ("1", "1e11", "1e13", "1e15")}
    assert images["1"].max() > 0  # (the triangle is in the picture)
    for scale in ("1e11", "1e13", "1e15"):
        assert np.array_equal(images[scale], images["1"]), scale
