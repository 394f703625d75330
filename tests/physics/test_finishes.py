"""Named finishes (#23 item 3): the table, the anisotropic GGX lobe of ``brushed`` against
independent quadrature (scipy) and against the isotropic lobe at ``α_u = α_v``, and the finish
through ``swatch render``, ``swatch preset`` and a catalog spec.

References written here, not taken from the code under test: the anisotropic GGX ``D`` and
Smith ``Λ`` (Heitz 2014, eqs. 85–86) and ``scipy.integrate`` for the integrals; the presets'
anisotropy read back through each format's own documented formula.
"""
from __future__ import annotations

import json
import math

import MaterialX as mx
import numpy as np
import OpenImageIO as oiio
import pytest
from scipy import integrate

from swatch.catalog.spec import parse_spec
from swatch.core.choices import FINISHES
from swatch.core.errors import SwatchError
from swatch.physics import microfacet
from swatch.physics.finishes import brush_tangent, get_finish, highlight_half_width_deg
from swatch.render import environment
from swatch.render.builtin import env_aniso, env_shading
from tests.cli_helpers import run_swatch
from tests.helpers import random_directions


def _D(h, au, av):
    """Anisotropic GGX, written out (Heitz 2014, eq. 85)."""
    x, y, z = h
    return 1.0 / (math.pi * au * av * (x * x / au ** 2 + y * y / av ** 2 + z * z) ** 2)


def _lam(w, au, av):
    """Smith Λ of anisotropic GGX, written out (Heitz 2014, eq. 86)."""
    x, y, z = w
    return 0.5 * (math.sqrt(1.0 + (au * au * x * x + av * av * y * y) / (z * z)) - 1.0)


def _dir(theta, phi):
    return (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))


def test_every_finish_has_a_documented_lobe():
    """Each named finish is in the table with roughness in (0, 1]; the half width of its
    highlight is where GGX's D falls to half its peak."""
    assert FINISHES == ("polished", "satin", "bead-blasted", "brushed")
    for name in FINISHES:
        f = get_finish(name)
        assert 0 < f.alpha_u <= f.alpha_v <= 1 and f.description and "Rdq" in f.metadata()["basis"]
        half = math.radians(float(highlight_half_width_deg(f.alpha_u))) / 2  # the half-vector angle
        assert microfacet.D_ggx(math.cos(half), f.alpha_u) == pytest.approx(0.5 * microfacet.D_ggx(1.0, f.alpha_u))
    assert get_finish("brushed").anisotropic and not get_finish("satin").anisotropic
    assert get_finish(" Satin ").name == "satin"
    with pytest.raises(SwatchError, match="polished, satin, bead-blasted, brushed"):
        get_finish("mirror")


def test_anisotropic_lobe_with_equal_alphas_is_the_isotropic_one():
    rng = np.random.default_rng(3)
    w = rng.normal(size=(200, 3))
    w[:, 2] = np.abs(w[:, 2]) + 0.05
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    for a in (0.05, 0.3, 0.8):
        np.testing.assert_allclose(microfacet.D_ggx_aniso(w, a, a), microfacet.D_ggx(w[:, 2], a), rtol=1e-12)
        np.testing.assert_allclose(microfacet.smith_lambda_ggx_aniso(w, a, a), microfacet.smith_lambda(w[:, 2], a),
                                   rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("au, av", [(0.12, 0.4), (0.4, 0.12), (0.05, 0.6)])
def test_anisotropic_D_is_normalised(au, av):
    """∫ D(h) cos θh dω_h = 1 over the hemisphere (scipy dblquad of the written-out D)."""
    val, _ = integrate.dblquad(lambda th, ph: _D(_dir(th, ph), au, av) * math.cos(th) * math.sin(th),
                               0.0, 2 * math.pi, 0.0, math.pi / 2, epsabs=1e-7, epsrel=1e-7)
    assert val == pytest.approx(1.0, abs=2e-4)
    h = np.array([_dir(0.3, 1.0), _dir(0.6, 2.5)])
    np.testing.assert_allclose(microfacet.D_ggx_aniso(h, au, av), [_D(x, au, av) for x in h], rtol=1e-12)


def _albedo_quad(v, au, av) -> float:
    """``∫ D G2 / (4 cos θ_v) dω_l`` (F = 1; height-correlated G2), by scipy over the light's
    hemisphere, with the half vector of each light direction."""
    vz = v[2]
    lv = _lam(v, au, av)

    def f(th, ph):
        l = _dir(th, ph)
        h = np.add(l, v)
        h /= np.linalg.norm(h)
        return _D(h, au, av) / (1.0 + lv + _lam(l, au, av)) / (4.0 * vz) * math.sin(th)

    val, _ = integrate.dblquad(f, 0.0, 2 * math.pi, 0.0, math.pi / 2 - 1e-9, epsabs=1e-6, epsrel=1e-6)
    return val


@pytest.mark.slow
def test_anisotropic_sample_set_level_is_the_lobe_integral():
    """The dense level of the anisotropic sample set (F = 1: the directional albedo per view bin)
    against scipy quadrature of the written-out lobe, at bins across θ_v and φ_v."""
    au, av = 0.12, 0.4
    ss = env_aniso.aniso_sample_set(au, av)
    level = env_shading.directional_albedo(ss, np.ones((2, 3)))[:, 0]
    for it in (5, 30, 55):
        for ip in (0, 6, 11):
            th = (it + 0.5) / env_aniso.THETA_BINS * math.pi / 2
            ph = (ip + 0.5) / env_aniso.PHI_BINS * math.pi / 2
            want = _albedo_quad(_dir(th, ph), au, av)
            assert level[it * env_aniso.PHI_BINS + ip] == pytest.approx(want, rel=0.01, abs=2e-3), (it, ip)


def _xyz(rgb):
    return np.asarray(rgb, dtype=float) @ np.array([[0.4124, 0.2126, 0.0193], [0.3576, 0.7152, 0.1192],
                                                    [0.1805, 0.0722, 0.9505]])


def _dE(a, b):
    import colour

    from swatch.colorimetry.colorimeter import delta_E_00

    return delta_E_00(colour.XYZ_to_Lab(_xyz(np.maximum(a, 1e-6))), colour.XYZ_to_Lab(_xyz(np.maximum(b, 1e-6))))


def test_anisotropic_path_with_equal_alphas_renders_as_the_isotropic_one():
    """α_u = α_v through the anisotropic bins and frames equals the isotropic set: under uniform
    light (the level) and in the studio (the sample directions), random normals and views."""
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.physics.model import get_coating
    from swatch.render.builtin import shading
    coating = get_coating()
    cm = get_colorimeter(coating.wavelength_nm)
    tab = shading.facet_colour_table(80.0, coating, cm, 257, (0.0, 1.0)).to_rgb(cm).values.astype(float)
    rng = np.random.default_rng(7)
    n = random_directions(rng, 300)
    v = random_directions(rng, 300)
    v *= np.sign((n * v).sum(1))[:, None]
    keep = (n * v).sum(1) > 0.1
    n, v = n[keep], v[keep]
    iso = env_shading.sample_set(0.3)
    an = env_aniso.aniso_sample_set(0.3, 0.3)
    tangent = brush_tangent("sphere", n)
    for name, med, top in (("uniform", 0.1, 0.3), ("studio", 0.3, 3.5)):  # studio: each is ≤ 2.5 (p95) off brute force
        maps = environment.levels(environment.get_environment(name))
        a = env_shading.shade(n, v, maps, iso, env_shading.band_weights(iso, tab))
        b = env_aniso.shade_aniso(n, v, maps, an, env_shading.band_weights(an, tab), tangent)
        dE = _dE(a, b)
        assert np.median(dE) <= med and dE.max() <= top, (name, np.median(dE), dE.max())


def test_brush_tangent_is_a_unit_tangent():
    rng = np.random.default_rng(1)
    n = random_directions(rng, 500)
    n[0] = (0.0, 1.0, 0.0)  # the sphere's pole: the fallback axis
    for shape in ("flat", "cylinder", "sphere", "mesh"):
        t = brush_tangent(shape, n)
        np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, atol=1e-5)
        assert np.abs((t * n).sum(1)).max() < 1e-5
    np.testing.assert_allclose(brush_tangent("flat", [[0.0, 1.0, 0.0]]), [[1.0, 0.0, 0.0]])
    np.testing.assert_allclose(brush_tangent("cylinder", [[0.0, 0.0, 1.0]]), [[0.0, 1.0, 0.0]])


def _attrs(path) -> dict:
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    out = {a.name: a.value for a in spec.extra_attribs}
    inp.close()
    return out


def test_render_finish_names_itself_and_refuses_what_it_cannot_do(tmp_path):
    r = run_swatch("render", "--thickness", "50.8", "--shape", "cylinder", "--finish", "brushed", "--size", "64",
                   "--out", tmp_path / "b")
    assert r.returncode == 0, r.stderr
    finish = json.loads(_attrs(tmp_path / "b" / "cylinder_050.8nm.exr")["swatch:finish"])
    assert (finish["name"], finish["alpha_along"], finish["alpha_across"]) == ("brushed", 0.12, 0.4)
    r = run_swatch("render", "--thickness", "50.8", "--finish", "polished", "--size", "32", "--environment", "point",
                   "--out", tmp_path / "p")
    assert r.returncode == 0, r.stderr
    assert float(_attrs(tmp_path / "p" / "flat_050.8nm.exr")["swatch:roughness"]) == pytest.approx(0.04)
    for args, words in ((["--finish", "brushed", "--environment", "point"], "anisotropic"),
                        (["--finish", "satin", "--roughness", "0.2"], "either a finish or a roughness"),
                        (["--finish", "brushed", "--size", "2000"], "at most 1024")):
        r = run_swatch("render", "--thickness", "50.8", *args, "--out", tmp_path / "no")
        assert r.returncode == 2 and words in r.stderr and r.stderr.startswith("error:"), r.stderr
        assert not (tmp_path / "no").exists()


def test_brushed_differs_from_its_isotropic_equivalent(tmp_path):
    """The brushed cylinder (grain along the axis) is not the isotropic GGX of the same mean
    roughness: the highlight is drawn out across the grain."""
    from swatch.physics.finishes import Finish, isotropic_finish
    from swatch.render import render_swatch

    f = get_finish("brushed")
    a = render_swatch(120.0, "cylinder", 96, environment="studio", finish=f).linear_rgb
    b = render_swatch(120.0, "cylinder", 96, environment="studio", finish=isotropic_finish(f.roughness_alpha)).linear_rgb
    c = render_swatch(120.0, "cylinder", 96, environment="studio",
                      finish=Finish("across", f.alpha_v, f.alpha_u, "grain around the axis")).linear_rgb
    assert np.abs(a - b).max() > 0.05 and np.abs(a - c).max() > 0.05
    assert np.isfinite(a).all() and (a >= 0).all()


def _preset(tmp_path, fmt: str, *extra):
    r = run_swatch("preset", "--thickness", "80", "--format", fmt, *extra, "--out", tmp_path, "--force")
    assert r.returncode == 0, r.stderr
    return next(p for p in tmp_path.iterdir() if p.suffix in (".gltf", ".py", ".mtlx"))


def test_preset_brushed_writes_each_formats_anisotropy(tmp_path):
    """Read back by each format's documented mapping, the presets give α 0.12 along the grain
    and 0.4 across it."""
    g = json.loads(_preset(tmp_path / "g", "gltf", "--finish", "brushed").read_text())
    m = g["materials"][0]
    ar = m["pbrMetallicRoughness"]["roughnessFactor"] ** 2
    ext = m["extensions"]["KHR_materials_anisotropy"]
    at = ar + (1 - ar) * ext["anisotropyStrength"] ** 2  # mix(α, 1, s²) along the anisotropy direction
    assert (ar, at) == (pytest.approx(0.12, abs=1e-4), pytest.approx(0.4, abs=1e-4))
    assert ext["anisotropyRotation"] == pytest.approx(math.pi / 2, abs=1e-5)
    assert "KHR_materials_anisotropy" in g["extensionsUsed"]
    assert "TANGENT" in g["meshes"][0]["primitives"][0]["attributes"]
    text = _preset(tmp_path / "b", "blender", "--finish", "brushed").read_text()
    ns: dict = {}
    exec(text[text.index("INPUTS = {"):text.index("\n}\n") + 3], ns)
    r, an = ns["INPUTS"]["Roughness"], ns["INPUTS"]["Anisotropic"]
    aspect = math.sqrt(1 - 0.9 * an)  # Cycles: α_x = r²/aspect, α_y = r² aspect
    assert (r * r / aspect, r * r * aspect) == (pytest.approx(0.4, abs=1e-4), pytest.approx(0.12, abs=1e-4))
    doc = mx.createDocument()
    mx.readFromXmlString(doc, _preset(tmp_path / "m", "materialx", "--finish", "brushed").read_text())
    sh = doc.getNodes("open_pbr_surface")[0] if doc.getNodes("open_pbr_surface") else doc.getNodes()[0]
    r = sh.getInputValue("specular_roughness")
    a = sh.getInputValue("specular_roughness_anisotropy")
    at = r * r * math.sqrt(2 / (1 + (1 - a) ** 2))  # OpenPBR
    assert (at, (1 - a) * at) == (pytest.approx(0.4, abs=1e-4), pytest.approx(0.12, abs=1e-4))
    iso = json.loads(_preset(tmp_path / "s", "gltf", "--finish", "satin").read_text())["materials"][0]
    assert iso["pbrMetallicRoughness"]["roughnessFactor"] ** 2 == pytest.approx(0.2, abs=1e-4)
    assert "KHR_materials_anisotropy" not in iso["extensions"]
    r = run_swatch("preset", "--thickness", "80", "--format", "gltf", "--finish", "satin", "--roughness", "0.2",
                   "--out", tmp_path / "x")
    assert r.returncode == 2 and "either a finish or a roughness" in r.stderr


def test_spec_finish():
    base = {"name": "f", "thickness": {"list_nm": [50]}}
    s = parse_spec(base | {"render": {"finish": "brushed"}})
    assert s.finish == "brushed" and s.roughness == pytest.approx(math.sqrt(0.12 * 0.4), abs=1e-6)
    assert s.finish_spec.label() == "brushed (GGX 0.12 along, 0.4 across the grain)"
    assert parse_spec(base).finish is None
    for render, words in (({"finish": "satin", "roughness": 0.2}, "either finish or roughness"),
                          ({"finish": "shiny"}, "polished"),
                          ({"finish": "brushed", "model": "paper"}, "anisotropic")):
        with pytest.raises(SwatchError, match=words):
            parse_spec(base | {"render": render})
