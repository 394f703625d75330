"""Environment-lit renders: the furnace test through the renderer (plate and sphere), a constant
user EXR equals ``uniform``, the camera along the normal, no black crescent, the CLI options and
one-line errors. References (tmm + scipy quadrature + colour.sd_to_XYZ) in tests/render/test_environment.py."""
from __future__ import annotations

import numpy as np
import pytest

from swatch.cli import main
from swatch.colorimetry.colorimeter import delta_E_00
from swatch.render import environment, render_swatch, scene
from tests.render.env_reference import (
    CM,
    COATING,
    albedo_normal_view,
    lab_2deg,
    lab_of_spectrum,
    write_equirect,
    xyz_of_srgb,
)


@pytest.mark.parametrize("d_nm", [30.0, 80.0, 160.0])
def test_furnace_plate_along_the_normal(d_nm):
    img = render_swatch(d_nm, "flat", 32, environment="uniform", view_deg=0.0, coating=COATING, colorimeter=CM)
    centre = img.linear_rgb[15:17, 15:17].reshape(-1, 3).mean(axis=0)
    got = lab_2deg(xyz_of_srgb(centre))
    ref = lab_of_spectrum(albedo_normal_view(d_nm))
    assert delta_E_00(got, ref) <= 1.0, (d_nm, got, ref)
    assert img.metadata["environment"] == "uniform" and img.exposure == 1.0


@pytest.mark.parametrize("d_nm", [50.8, 250.0])
def test_furnace_sphere_centre_pixel(d_nm):
    size = 33
    sc = scene.make_scene("sphere", 45.0, 0.0)
    n, _, v, hit = scene.scene_geometry(sc, size)
    cv = np.where(hit, (n * v).sum(-1), -1.0)
    i, j = np.unravel_index(np.argmax(cv), cv.shape)
    assert cv[i, j] > 0.999
    img = render_swatch(d_nm, "sphere", size, environment="uniform", view_deg=0.0, coating=COATING,
                               colorimeter=CM)
    got = lab_2deg(xyz_of_srgb(img.linear_rgb[i, j]))
    ref = lab_of_spectrum(albedo_normal_view(d_nm))
    assert delta_E_00(got, ref) <= 1.0, (d_nm, got, ref)


def test_constant_exr_equals_uniform(tmp_path):
    p = tmp_path / "grey.exr"
    write_equirect(p, np.full((32, 64, 3), 0.37, dtype=np.float32))
    env = environment.get_environment(str(p))
    assert env.is_constant and env.radiance[0, 0, 0] == pytest.approx(1.0, rel=1e-6)
    for shape in ("flat", "sphere"):
        a = render_swatch(80.0, shape, 40, environment="uniform", coating=COATING, colorimeter=CM)
        b = render_swatch(80.0, shape, 40, environment=env, coating=COATING, colorimeter=CM)
        np.testing.assert_allclose(b.linear_rgb, a.linear_rgb, rtol=1e-5, atol=1e-6)


def test_view_along_the_normal_is_symmetric():
    img = render_swatch(120.0, "flat", 48, environment="uniform", view_deg=0.0, coating=COATING, colorimeter=CM)
    rgb = img.linear_rgb
    np.testing.assert_allclose(rgb, rgb[:, ::-1], atol=2e-3)
    np.testing.assert_allclose(rgb, rgb[::-1, :], atol=2e-3)


def test_no_black_crescent():
    kw = dict(coating=COATING, colorimeter=CM)
    lit = render_swatch(80.0, "sphere", 64, environment="studio", **kw)
    point = render_swatch(80.0, "sphere", 64, environment="point", **kw)
    inside = lit.coverage == 1.0
    assert point.linear_rgb[inside].sum(-1).min() == 0.0  # the point light leaves a dark side
    assert lit.linear_rgb[inside].sum(-1).min() > 0.02


def _run(args, capsys):
    rc = main(args)
    out, err = capsys.readouterr()
    return rc, out, err


def test_cli_environment_options(tmp_path, capsys):
    rc, _, err = _run(["render", "--thickness", "60", "--shape", "flat", "--size", "24", "--view", "0",
                       "--background", "environment", "--out", str(tmp_path / "a")], capsys)
    assert rc == 0, err
    from swatch.io import imageio

    meta = imageio.read_metadata(tmp_path / "a" / "flat_060.0nm.png")
    assert meta["environment"] == "studio" and "k = 1" in meta["exposure_rule"] and "environment" in meta["display"]


BAD = [
    (["--environment", "nowhere.exr"], "not a file"),
    (["--environment", "sunset"], "unknown environment"),
    (["--environment", "point", "--background", "environment"], "needs an environment"),
    (["--model", "paper", "--environment", "studio"], "microfacet"),
    (["--view", "95"], "--view must be in [0, 90)"),
    (["--size", "4096"], "at most 2048"),
]


@pytest.mark.parametrize("extra,words", BAD)
def test_cli_bad_environment_input(tmp_path, capsys, extra, words):
    out = tmp_path / "out"
    rc, _, err = _run(["render", "--thickness", "60", "--size", "16", "--out", str(out), *extra], capsys)
    assert rc == 2 and err.startswith("error:") and len(err.strip().splitlines()) == 1 and words in err, err
    assert not out.exists()




@pytest.mark.parametrize("shape", ["flat", "sphere"])
def test_environment_render_geometry_names_no_point_light(shape):
    """An environment-lit render's ``geometry`` describes the object and camera only: the point
    light of the point-light render plays no part in it (it used to be described there)."""
    img = render_swatch(80.0, shape, 16, environment="uniform", view_deg=10.0, coating=COATING, colorimeter=CM)
    point = render_swatch(80.0, shape, 16, view_deg=10.0, coating=COATING, colorimeter=CM, environment="point")
    assert "light" not in img.metadata["geometry"] and "light_deg" not in img.metadata
    assert "camera 10 deg" in img.metadata["geometry"]
    assert "light 45 deg" in point.metadata["geometry"] and point.metadata["light_deg"] == 45.0
