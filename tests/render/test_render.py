"""Renders, angular maps and image files.

References: the direct spectral path (full Airy spectrum at every pixel's own θ_d, integrated
with colour-science weights) for the table path; colour.sd_to_XYZ for the angular map's colour;
OpenImageIO (an independent reader) for the files' metadata and channel names.
"""
from __future__ import annotations

import colour
import numpy as np
import OpenImageIO as oiio
import pytest

from swatch.cli import main
from swatch.colorimetry.colorimeter import Lab_to_LCh, delta_E_00, get_colorimeter
from swatch.core.errors import SwatchError
from swatch.io import drawing, imageio, spectral_exr
from swatch.physics import microfacet
from swatch.physics.model import get_coating
from swatch.render import angular, display, metadata, render_swatch
from swatch.render import scene as scenes
from swatch.render.builtin import shading
from tests.cli_helpers import run_swatch
from tests.synthetic import tmm_half_vector_reflectance

COATING = get_coating()
CM = get_colorimeter(COATING.wavelength_nm)
CM2 = get_colorimeter(COATING.wavelength_nm, "D65", "2")  # RGB pixels are CIE 1931 2° colorimetry
BLUE_NM = 50.8  # the paper's blue sample (25 V)


def _rgb_to_XYZ(rgb, space="srgb"):
    name = {"srgb": "sRGB", "acescg": "ACEScg"}[space]
    return colour.RGB_to_XYZ(np.asarray(rgb, dtype=np.float64), name, illuminant=CM2.white_xy,
                             chromatic_adaptation_transform="Bradford") * 100.0


def _attrs(path) -> dict:
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    try:
        return {a.name: a.value for a in inp.spec().extra_attribs}
    finally:
        inp.close()


# -- the table path against the direct spectral path -------------------------------------------
@pytest.mark.parametrize("shape", scenes.SHAPES)
@pytest.mark.parametrize("thickness", [BLUE_NM, 240.0, 900.0])
def test_table_matches_direct_spectral(shape, thickness):
    scene = scenes.make_scene(shape, 45.0)
    n, l, v, hit = scenes.scene_geometry(scene, 64)
    n, v = n[hit], v[hit]
    table = shading.facet_colour_table(thickness, COATING, CM)  # default: full [0, 1] range, 1025 nodes
    for model in ("microfacet", "paper"):
        fast = shading.shade(n, l, v, table, model, 0.3)
        direct = shading.shade_direct(n, l, v, thickness, COATING, CM, model, 0.3)
        assert np.all(np.isfinite(direct)) and direct[:, 1].max() > 0
        dE = delta_E_00(CM.Lab(fast), CM.Lab(direct))
        assert float(np.max(dE)) <= 0.05


@pytest.mark.parametrize("shape", scenes.SHAPES)
def test_render_pixels_match_direct_spectral(shape):
    # The real render path (scene-range table, float32, trace without normals) against the
    # direct spectrum at the same pixel centres (normals from the explicit intersection).
    size = 96
    for thickness in (BLUE_NM, 600.0):
        img = render_swatch(thickness, shape, size, environment="point")
        scene = scenes.make_scene(shape, 45.0)
        n, l, v, hit = scenes.scene_geometry(scene, size)
        # Pixels shaded at their centre: away from the silhouette (edge pixels are supersampled).
        inside = (img.coverage == 1.0) & hit
        for _ in range(2):
            inside[1:-1, 1:-1] &= inside[:-2, 1:-1] & inside[2:, 1:-1] & inside[1:-1, :-2] & inside[1:-1, 2:]
        inside[[0, -1], :] = False
        inside[:, [0, -1]] = False
        # The pixels are RGB of CIE 1931 2° XYZ (whatever the colorimeter's observer): compare there.
        direct = shading.shade_direct(n[inside], l, v[inside], thickness, COATING, CM2, "microfacet", 0.3)
        got = _rgb_to_XYZ(img.linear_rgb[inside])
        lit = direct[:, 1] > 1e-3  # skip the unlit side (both ~0; ΔE of black is meaningless)
        dE = delta_E_00(CM2.Lab(got[lit]), CM2.Lab(direct[lit]))
        assert lit.sum() > 100
        assert float(np.max(dE)) <= 0.05, float(np.max(dE))


def test_acescg_render_is_the_same_colour():
    a = render_swatch(BLUE_NM, "sphere", 48, environment="point")
    b = render_swatch(BLUE_NM, "sphere", 48, space="acescg", environment="point")
    m = a.coverage == 1
    dE = delta_E_00(CM2.Lab(_rgb_to_XYZ(a.linear_rgb[m])), CM2.Lab(_rgb_to_XYZ(b.linear_rgb[m], "acescg")))
    assert float(np.max(dE)) < 0.05
    assert np.array_equal(a.display_rgb, b.display_rgb) or np.abs(a.display_rgb.astype(int) - b.display_rgb).max() <= 1


# -- appearance ----------------------------------------------------------------------------------
def test_blue_sample_is_blue_off_mirror():
    # Off-mirror pixels (outside the half maximum of the lobe) of the blue sample: hue 220–300°.
    for shape in ("flat", "cylinder", "sphere"):
        img = render_swatch(BLUE_NM, shape, 96, environment="point")
        scene = scenes.make_scene(shape, 45.0)
        n, l, v, hit = scenes.scene_geometry(scene, 96)
        h = (l + v) / np.linalg.norm(l + v, axis=-1, keepdims=True)
        cos_h = (n * h).sum(-1)
        off = hit & (img.coverage == 1) & (microfacet.D_ratio(np.clip(cos_h, 0, 1), 0.3) < 0.5) & ((n @ l) > 0.1)
        assert off.sum() > 20, shape
        lch = Lab_to_LCh(CM2.Lab(_rgb_to_XYZ(img.linear_rgb[off])))
        assert 220 <= np.median(lch[:, 2]) <= 300, (shape, np.median(lch[:, 2]))
        assert np.median(lch[:, 1]) > 15  # clearly coloured, not grey
    lab = metadata.reference_Lab(BLUE_NM, COATING, CM)
    assert 220 <= Lab_to_LCh(lab)[2] <= 300


def test_highlight_brighter_and_edges_antialiased():
    img = render_swatch(BLUE_NM, "sphere", 128, environment="point")
    a = img.coverage
    assert a.min() == 0.0 and a.max() == 1.0
    partial = (a > 0) & (a < 1)
    assert 100 < partial.sum() < 4 * 128 * 4  # a thin anti-aliased rim
    Y = _rgb_to_XYZ(img.linear_rgb)[..., 1]
    assert Y.max() > 3 * np.median(Y[a == 1])  # a highlight
    assert img.display_rgb.dtype == np.uint8 and img.display_rgb.shape == (128, 128, 3)
    bg = img.display_rgb[0, 0]
    assert bg[0] == bg[1] == bg[2]  # neutral background


def test_any_size_and_paper_model():
    for size in (1, 7, 33):
        img = render_swatch(BLUE_NM, "cylinder", size, model="paper")
        assert img.linear_rgb.shape == (size, size, 3) and img.linear_rgb.dtype == np.float32
    img = render_swatch(BLUE_NM, "flat", 64, model="paper")
    assert img.exposure == 1.0
    img = render_swatch(BLUE_NM, "flat", 64, distribution="beckmann", roughness_alpha=0.2)
    assert np.isfinite(img.linear_rgb).all()


@pytest.mark.parametrize("kwargs", [dict(size_px=0), dict(size_px=10**6), dict(roughness_alpha=0.0), dict(roughness_alpha=1.5),
                                    dict(shape="cube"), dict(model="phong"), dict(light_deg=95.0),
                                    dict(space="xyz"), dict(thickness_nm=-5.0)])
def test_render_api_rejects_bad_input(kwargs):
    args = dict(thickness_nm=BLUE_NM, shape="flat", size_px=16, environment="point")
    args.update(kwargs)
    with pytest.raises(SwatchError):
        render_swatch(**args)


# -- angular maps --------------------------------------------------------------------------------
def test_angular_map_colour_matches_colour_science():
    m = angular.angular_map(BLUE_NM, np.array([0.0, 45.0, 70.0]), np.array([0.0, 30.0]))
    assert m.XYZ.shape == (3, 2, 3) and m.spectral.shape == (3, 2, COATING.wavelength_nm.size)
    sd = colour.SpectralDistribution(dict(zip(COATING.wavelength_nm, m.spectral[1, 0], strict=True)))
    ref = colour.sd_to_XYZ(sd, CM.cmfs, CM.illuminant_sd)
    np.testing.assert_allclose(m.XYZ[1, 0], ref, rtol=1e-6)
    # Paper model: the reflectance at θ_d = (45 + 0)/2, by tmm.coh_tmm (not the engine's optics; #17).
    ref = tmm_half_vector_reflectance(BLUE_NM, 45.0, 0.0, COATING.wavelength_nm)[0]
    np.testing.assert_allclose(m.spectral[1, 0], ref, rtol=1e-6, atol=1e-9)
    assert m.theta_d_deg[2, 1] == pytest.approx(50.0)


def test_angular_microfacet_mirror_is_brightest():
    ang = np.arange(0, 86, 5.0)
    m = angular.angular_map(BLUE_NM, ang, ang, model="microfacet")
    Y = m.XYZ[..., 1]
    # Up to 60° (beyond, 1/cos θ_v lifts grazing off-mirror views): the mirror cell beats every
    # cell of its row at least 30° away from it.
    k = ang <= 60
    Yk = Y[np.ix_(k, k)]
    far = np.abs(ang[k][:, None] - ang[k][None, :]) >= 30
    assert np.all(np.diag(Yk)[:, None] > np.where(far, Yk, -np.inf))
    assert 0 < m.exposure < 50 and "off-mirror" in m.metadata["exposure_rule"]


# -- files and the command line ------------------------------------------------------------------
def _run(args, capsys):
    rc = main(args)
    out, err = capsys.readouterr()
    return rc, out, err


def test_render_files_metadata_and_determinism(tmp_path, capsys):
    out = tmp_path / "a"
    rc, _stdout, err = _run(["render", "--voltage", "25", "--shape", "cylinder", "--size", "64", "--out", str(out)], capsys)
    assert rc == 0, err
    exr, png = out / "cylinder_050.8nm.exr", out / "cylinder_050.8nm.png"
    assert exr.is_file() and png.is_file() and err == ""
    a = _attrs(exr)
    assert a["swatch:thickness_nm"] == pytest.approx(50.8, rel=1e-6)
    assert a["swatch:voltage_V"] == pytest.approx(25.0)
    for key in ("film", "substrate", "illuminant", "observer", "model", "roughness", "geometry", "Lab_reference"):
        assert f"swatch:{key}" in a, key
    assert a["swatch:film"] == COATING.film and a["swatch:illuminant"] == "D65"
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    expect = list(np.asarray(srgb.primaries).ravel()) + list(srgb.whitepoint)
    np.testing.assert_allclose(a["chromaticities"], expect, atol=1e-6)
    assert "DateTime" not in a
    spec = oiio.ImageInput.open(str(exr))
    assert list(spec.spec().channelnames) == ["R", "G", "B", "A"] and spec.spec().format == oiio.HALF
    spec.close()
    lab = imageio.read_metadata(exr)["Lab_reference"]
    np.testing.assert_allclose(lab, metadata.reference_Lab(50.8, COATING, CM), atol=1e-3)
    p = _attrs(png)
    assert p["swatch:film"] == COATING.film and float(p["swatch:thickness_nm"]) == pytest.approx(50.8)
    assert imageio.read_metadata(png)["roughness"] == pytest.approx(0.3)

    # Same inputs -> byte-identical files (another folder, and a forced rewrite in place).
    out2 = tmp_path / "b"
    assert _run(["render", "--voltage", "25", "--shape", "cylinder", "--size", "64", "--out", str(out2)], capsys)[0] == 0
    assert (out2 / exr.name).read_bytes() == exr.read_bytes()
    assert (out2 / png.name).read_bytes() == png.read_bytes()
    before = exr.read_bytes()
    rc, _, err = _run(["render", "--voltage", "25", "--shape", "cylinder", "--size", "64", "--out", str(out)], capsys)
    assert rc != 0 and "--force" in err and len(err.strip().splitlines()) == 1
    assert exr.read_bytes() == before
    assert _run(["render", "--voltage", "25", "--shape", "cylinder", "--size", "64", "--out", str(out), "--force"], capsys)[0] == 0
    assert exr.read_bytes() == before
    assert sorted(x.name for x in out.iterdir()) == sorted([exr.name, png.name])  # no temp files left


def test_acescg_chromaticities(tmp_path, capsys):
    rc, _, err = _run(["render", "--thickness", "80", "--shape", "flat", "--size", "32", "--space", "acescg",
                       "--out", str(tmp_path)], capsys)
    assert rc == 0, err
    aces = colour.RGB_COLOURSPACES["ACEScg"]
    expect = list(np.asarray(aces.primaries).ravel()) + list(aces.whitepoint)
    np.testing.assert_allclose(_attrs(tmp_path / "flat_080.0nm.exr")["chromaticities"], expect, atol=1e-6)


def test_angular_files(tmp_path, capsys):
    rc, _stdout, err = _run(["angular", "--thickness", "50.8", "--light-range", "0:85:5", "--view-range", "0:85:5",
                            "--model", "paper", "--out", str(tmp_path)], capsys)
    assert rc == 0, err
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == sorted(["angular_050.8nm" + s for s in (".exr", ".png", "_spectral.exr", ".csv", ".json")])
    # Spectral EXR: channel names (Fichet et al. 2021) parse back to the wavelength grid.
    chans = imageio.read_channel_names(tmp_path / "angular_050.8nm_spectral.exr")
    assert chans[:3] == ["R", "G", "B"]  # the preview ordinary viewers show
    chans = chans[3:]
    assert all(c.startswith("T.") and c.endswith("nm") and "," in c for c in chans)
    parsed = sorted(spectral_exr.parse_spectral_channel(c)[1] for c in chans)
    np.testing.assert_allclose(parsed, COATING.wavelength_nm)
    assert _attrs(tmp_path / "angular_050.8nm_spectral.exr")["spectralLayoutVersion"] == "1.0"
    buf = oiio.ImageBuf(str(tmp_path / "angular_050.8nm_spectral.exr"))
    assert buf.spec().format == oiio.FLOAT
    # Read back by colour-science's Fichet et al. 2021 reader (not our parser; #17): the reflective
    # component "T" holds the spectra (rows = light, growing upwards; columns = view).
    components = colour.io.read_spectral_image_Fichet2021(tmp_path / "angular_050.8nm_spectral.exr")
    wl_read, values = components["T"]
    np.testing.assert_allclose(wl_read, COATING.wavelength_nm)
    ref = tmm_half_vector_reflectance(50.8, 45.0, 0.0, COATING.wavelength_nm)[0]  # θ_d = 22.5°, by tmm
    np.testing.assert_allclose(values[17 - 9, 0], ref, rtol=1e-5, atol=1e-7)  # light 45°, view 0°
    # CSV: one row per cell, Lab of 45:0 equals the reference Lab in the metadata.
    rows = (tmp_path / "angular_050.8nm.csv").read_text().splitlines()
    assert len(rows) == 1 + 18 * 18
    row = next(r.split(",") for r in rows[1:] if r.startswith("45,0,"))
    meta = imageio.read_metadata(tmp_path / "angular_050.8nm.exr")
    np.testing.assert_allclose([float(x) for x in row[6:9]], meta["Lab_reference"], atol=2e-3)
    assert "exposure_rule" in meta and meta["model"] == "paper"


def test_angular_default_shows_the_mirror_diagonal(tmp_path, capsys):
    """By default the map carries the microfacet intensity: the mirror diagonal (light = view) is
    far brighter than the off-mirror cells, and the metadata says how it was exposed."""
    rc, _, err = _run(["angular", "--thickness", "50.8", "--light-range", "0:80:10", "--view-range", "0:80:10",
                       "--out", str(tmp_path)], capsys)
    assert rc == 0, err
    meta = imageio.read_metadata(tmp_path / "angular_050.8nm.exr")
    assert meta["model"] == "microfacet" and "exposure_rule" in meta
    rows = [r.split(",") for r in (tmp_path / "angular_050.8nm.csv").read_text().splitlines()[1:]]
    Y = {(float(r[0]), float(r[1])): float(r[4]) for r in rows}
    for a in (30.0, 40.0, 50.0):
        assert Y[(a, a)] > 2.0 * Y[(a, a - 30.0)]  # toward the normal the lobe falls off fast


BAD = [
    ["--size", "0"], ["--size", "100000"], ["--roughness", "0"], ["--roughness", "1.5"], ["--roughness", "-1"],
    ["--shape", "cube"], ["--model", "phong"], ["--light", "90"], ["--space", "xyz"], ["--thickness", "abc"],
]


@pytest.mark.parametrize("extra", BAD)
def test_bad_cli_input(tmp_path, extra, capsys):
    out = tmp_path / "out"
    args = ["render", "--shape", "flat", "--out", str(out)]
    if "--thickness" not in extra:
        args += ["--thickness", "50"]
    rc, _stdout, err = _run(args + extra, capsys)
    assert rc != 0
    assert len(err.strip().splitlines()) == 1 and err.startswith("error:")
    assert not out.exists() or not any(out.iterdir())


def test_unwritable_output_folder(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    for cmd in (["render", "--thickness", "50"], ["angular", "--thickness", "50"]):
        rc, _, err = _run([*cmd, "--out", str(blocker / "sub")], capsys)
        assert rc != 0 and len(err.strip().splitlines()) == 1
        rc, _, err = _run([*cmd, "--out", str(blocker)], capsys)
        assert rc != 0 and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_range_is_quiet_when_piped(tmp_path):
    r = run_swatch("render", "--thickness", "40:60:20", "--shape", "sphere", "--size", "24", "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    assert len(r.stdout.splitlines()) == 4 and len(list(tmp_path.iterdir())) == 4


def test_imageio_general(tmp_path):
    px = np.random.default_rng(1).random((5, 7, 5)).astype(np.float32)
    meta = {"n": 3, "x": 1.25, "flag": True, "list": [1, 2, {"a": "b"}], "text": "héllo"}
    p = imageio.write_exr(tmp_path / "five.exr", px, meta, channel_names=("a", "b", "c", "d", "e"), space=None, half=False)
    back = imageio.read_metadata(p)
    assert back == {"n": 3, "x": 1.25, "flag": True, "list": [1, 2, {"a": "b"}], "text": "héllo"}
    got = oiio.ImageBuf(str(p)).get_pixels(oiio.FLOAT)
    names = list(oiio.ImageInput.open(str(p)).spec().channelnames)
    np.testing.assert_array_equal(got[..., [names.index(c) for c in "abcde"]], px)
    img = drawing.draw_text(np.full((40, 120, 3), 255, np.uint8), "50.8 nm", 5, 30, 20, (0, 0, 0))
    assert img.min() < 100  # ink was drawn
    with pytest.raises(SwatchError):
        imageio.write_png(tmp_path / "x.png", px)  # not uint8
    with pytest.raises(SwatchError):
        imageio.write_exr(tmp_path / "y.exr", px, channel_names=("R", "G", "B"))
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "y.exr").exists()
    assert spectral_exr.reflective_channel_name(550) == "T.550,000000nm"
    assert spectral_exr.parse_spectral_channel("S0.1,5um") == ("S0", pytest.approx(1500.0))
    assert spectral_exr.parse_spectral_channel("R") is None


def test_display_encoding_matches_srgb():
    # Below the shoulder the LUT equals colour-science's sRGB encoding to within rounding.
    x = np.concatenate([np.linspace(0, display.KNEE, 50001), np.geomspace(1e-7, display.KNEE, 5000)]).astype(np.float32)
    got = display.display_encode(x[:, None]).astype(float).ravel()
    exact = colour.RGB_COLOURSPACES["sRGB"].cctf_encoding(x.astype(np.float64)) * 255
    assert np.max(np.abs(got - exact)) <= 0.6
    assert display.display_encode(np.array([[0.0, 100.0, -1.0]], np.float32)).tolist() == [[0, 255, 0]]


def test_render_metadata_leaves_the_voltage_to_the_caller_that_knows_the_process():
    """Issue #17: the library wrote the voltage at the *default* growth rate and the CLI overwrote it;
    now only the caller that knows the process writes it, once (right after the thickness)."""
    img = render_swatch(80.0, "flat", 8, coating=COATING, colorimeter=CM, environment="point")
    assert "voltage_V" not in img.metadata and "voltage_note" not in img.metadata
    from swatch.physics.process import load_process

    proc = load_process("titanium-fujii2019")
    meta = metadata.with_voltage(img.metadata, 40.0, "given", proc)
    keys = list(meta)
    assert keys[keys.index("thickness_nm") + 1:keys.index("thickness_nm") + 3] == ["voltage_V", "voltage_note"]
    assert meta["voltage_V"] == 40.0
