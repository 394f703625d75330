"""The exact Mitsuba 3 presets (#18 item 4): the catalog's XML and JSON files loaded in real Mitsuba with the
``anodic_film`` plugin registered, the BSDF evaluated at 45:0, the catalog's multi-angle geometries and mirror
0–60°, its Fresnel factor taken out with a microfacet D·G written here in numpy, and the colour (colour-science,
the catalog's illuminant and observer) compared with the colour the catalog states: ΔE2000 ≈ 0."""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import colour
import numpy as np
import pytest

from swatch.catalog.presets_mitsuba import mitsuba_presets
from swatch.colorimetry.colorimeter import delta_E_00
from swatch.presets.files import single_mitsuba_preset
from tests.mitsuba_setup import jit_of, mitsuba_variant

MIRROR_DEG = (0.0, 15.0, 30.0, 45.0, 60.0)
#: ΔE2000 allowed between Mitsuba's BSDF (single precision) and the catalog's colour: "0 by construction".
EXACT_DE = 0.01

UNIFORM = """
name = "mitsuba preset test"
[thickness]
list_nm = [25, 120, 190, 285]
[render]
roughness = 0.2
"""
# a brushed (anisotropic) finish, CIE 1931 2°, and (set below) a thickness spread
BRUSHED = """
name = "mitsuba preset test, brushed, spread"
[thickness]
list_nm = [60, 140, 260]
[colour]
observer = "2"
[render]
finish = "brushed"
"""


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def _built(root: Path, text: str, spread: tuple[float, float] | None = None):
    from swatch.catalog.context import catalog_context
    from swatch.catalog.records import compute
    from swatch.catalog.spec import load_spec

    root.mkdir(parents=True, exist_ok=True)
    (root / "s.toml").write_text(text, encoding="utf-8")
    spec, _ = load_spec(root / "s.toml")
    if spread is not None:
        spec = dataclasses.replace(spec, spread_nm=spread[0], spread_fraction=spread[1])
    data = compute(catalog_context(spec))
    files, entries = mitsuba_presets(spec, data.records)
    records = [{**rec, "presets": entry} for rec, entry in zip(data.records, entries, strict=True)]
    for name, blob in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_bytes(blob)
    return spec, records, files


@pytest.fixture(scope="module")
def catalogs(tmp_path_factory):
    root = tmp_path_factory.mktemp("mitsuba_presets")
    return [_built(root / "uniform", UNIFORM), _built(root / "brushed", BRUSHED, (3.0, 0.02))]


def _ggx_DG_over_4cos(wi, wo, au, av):
    """D(h) G₂(i, o) / (4 cos θi): anisotropic GGX and height-correlated Smith, written out (Heitz 2014)."""
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    D = 1.0 / (math.pi * au * av * ((h[:, 0] / au) ** 2 + (h[:, 1] / av) ** 2 + h[:, 2] ** 2) ** 2)

    def lam(w):
        t2 = ((w[:, 0] * au) ** 2 + (w[:, 1] * av) ** 2) / w[:, 2] ** 2
        return 0.5 * (np.sqrt(1.0 + t2) - 1.0)

    return D / (1.0 + lam(wi) + lam(wo)) / (4.0 * wi[:, 2])


def _fresnel(mi, bsdf, wi, wo, wl, alphas):
    """The BSDF's Fresnel factor (G, W) at views ``wi`` / lights ``wo`` (G, 3) and wavelengths ``wl`` (W,):
    eval (which includes cos θo) divided by D G₂ / (4 cos θi)."""
    import drjit as dr

    W = wl.size
    wl4 = np.concatenate([wl, np.full(-W % 4, wl[-1])]).reshape(-1, 4)  # 4 wavelengths per lane
    L, G = wl4.shape[0], wi.shape[0]
    wi_l, wo_l = np.repeat(wi, L, axis=0), np.repeat(wo, L, axis=0)
    si = dr.zeros(mi.SurfaceInteraction3f, G * L)
    si.wi = jit_of(mi.Vector3f, wi_l.T)
    si.wavelengths = jit_of(mi.Spectrum, [np.tile(wl4[:, j], G) for j in range(4)])
    val = np.asarray(bsdf.eval(mi.BSDFContext(), si, jit_of(mi.Vector3f, wo_l.T)), dtype=np.float64)  # (4, G·L)
    au, av = (alphas[0], alphas[0]) if len(alphas) == 1 else alphas
    F = val / _ggx_DG_over_4cos(wi_l, wo_l, au, av)[None, :]
    return F.T.reshape(G, L * 4)[:, :W]


def _Lab(R, wl, illuminant, observer):
    """CIELAB of reflectance spectra (…, W) by colour.sd_to_XYZ (the reference colorimetry)."""
    cmfs = colour.MSDS_CMFS[{"2": "CIE 1931 2 Degree Standard Observer",
                             "10": "CIE 1964 10 Degree Standard Observer"}[observer]]
    ill = colour.SDS_ILLUMINANTS[illuminant]
    shape = colour.SpectralShape(float(wl[0]), float(wl[-1]), float(wl[1] - wl[0]))
    white = colour.sd_to_XYZ(colour.sd_ones(shape), cmfs, ill)
    out = [colour.XYZ_to_Lab(colour.sd_to_XYZ(colour.SpectralDistribution(dict(zip(wl, r, strict=True))), cmfs, ill)
                             / white[1], colour.XYZ_to_xy(white)) for r in np.reshape(R, (-1, wl.size))]
    return np.reshape(out, (*np.shape(R)[:-1], 3))


def _dirs(spec):
    """(names, views, lights): 45:0, the catalog's multi-angle geometries and mirror 0–60°, in plane."""
    names, views, lights = [], [], []
    for g in (spec.reference, *spec.multi_angle):
        side = -1.0 if g.view_side == "opposite" else 1.0
        names.append(g.name)
        lights.append([math.sin(math.radians(g.light_deg)), 0.0, math.cos(math.radians(g.light_deg))])
        views.append([side * math.sin(math.radians(g.view_deg)), 0.0, math.cos(math.radians(g.view_deg))])
    for t in MIRROR_DEG:
        names.append(f"mirror {t:g}")
        lights.append([math.sin(math.radians(t)), 0.0, math.cos(math.radians(t))])
        views.append([-math.sin(math.radians(t)), 0.0, math.cos(math.radians(t))])
    return names, np.array(views), np.array(lights)


def _stated(spec, rec, wl):
    """The colours to match: the record's Lab (45:0, multi-angle) and, at mirror angles, swatch's model
    (tmm-checked in test_optics/test_spread) through colour-science."""
    coating = spec.coating(wl)
    R = np.stack([coating.reflectance(rec["thickness_nm"], t).R for t in MIRROR_DEG])
    mirror = _Lab(R, wl, spec.illuminant, spec.observer)
    return np.array([rec["Lab"], *(rec["multi_angle"][g.name] for g in spec.multi_angle), *mirror])


@pytest.mark.slow
def test_mitsuba_presets_are_the_catalog_colour_in_mitsuba(mi, catalogs):
    """#18 item 4: each swatch's JSON (mi.load_dict) and XML (mi.load_file) BSDF, evaluated in Mitsuba 3.9 at 45:0,
    the catalog's multi-angle geometries and mirror 0–60°, shows the catalog's colour within ΔE2000 0.01
    (uniform film α 0.2 under D65/10°; brushed α 0.12 × 0.4 with a 3 nm + 2 % spread under D65/2°)."""
    from swatch.physics.materials import wavelength_grid

    worst = 0.0
    for spec, records, files in catalogs:
        wl = wavelength_grid(380.0, 780.0, spec.wavelength_step_nm)  # the catalog's grid
        names, wi, wo = _dirs(spec)
        alphas = ((spec.finish_spec.alpha_u, spec.finish_spec.alpha_v) if spec.finish_spec is not None
                  and spec.finish_spec.anisotropic else (spec.roughness,))
        for rec in records:
            doc = json.loads(files[rec["presets"]["mitsuba_json"]])
            from_dict = mi.load_dict(doc["bsdf"])
            from_xml = mi.load_string(files[rec["presets"]["mitsuba"]].decode("utf-8"))
            want = _stated(spec, rec, wl)
            for bsdf in (from_dict, from_xml):
                got = _Lab(_fresnel(mi, bsdf, wi, wo, wl, alphas), wl, spec.illuminant, spec.observer)
                dE = np.atleast_1d(delta_E_00(got, want))
                worst = max(worst, float(dE.max()))
                assert dE.max() < EXACT_DE, (rec["id"], dict(zip(names, np.round(dE, 4), strict=True)))
    print(f"mitsuba presets: max ΔE2000 {worst:.4f} over {sum(len(c[1]) for c in catalogs)} swatches")


@pytest.mark.slow
def test_mitsuba_xml_is_mitsubas_scene_format(mi, catalogs, tmp_path):
    """#18 item 4: the XML file parses with Mitsuba's own parser as a file and inside a scene (``<include>``,
    then ``<ref id>``), giving the BSDF the JSON gives (same values at a geometry), with the profile's spread."""
    import drjit as dr

    _spec, records, files = catalogs[1]
    rec = records[1]
    xml_name = rec["presets"]["mitsuba"]
    (tmp_path / xml_name).parent.mkdir(parents=True, exist_ok=True)
    (tmp_path / xml_name).write_bytes(files[xml_name])
    ident = json.loads(files[rec["presets"]["mitsuba_json"]])["bsdf"]["id"]
    scene = mi.load_string(f'<scene version="3.0.0"><include filename="{tmp_path / xml_name}"/>'
                           f'<shape type="rectangle"><ref id="{ident}"/></shape></scene>')
    included = scene.shapes()[0].bsdf()
    assert "AnodicFilmBSDF" in str(included) and "spread_nm=3, spread_fraction=0.02" in str(included)
    by_file = mi.load_file(str(tmp_path / xml_name))
    by_dict = mi.load_dict(json.loads(files[rec["presets"]["mitsuba_json"]])["bsdf"])
    si = dr.zeros(mi.SurfaceInteraction3f, 3)
    si.wi = mi.Vector3f([0.0, 0.3, -0.5], [0.0, 0.1, 0.2], [1.0, 0.95, 0.84])
    si.wi = dr.normalize(si.wi)
    si.wavelengths = mi.Spectrum(430.0, 520.0, 600.0, 690.0)
    wo = dr.normalize(mi.Vector3f([0.7, -0.2, 0.4], [0.0, 0.1, -0.3], [0.7, 0.97, 0.86]))
    values = [np.asarray(b.eval(mi.BSDFContext(), si, wo)) for b in (included, by_file, by_dict)]
    assert np.all(values[0] > 0)
    np.testing.assert_array_equal(values[0], values[1])
    np.testing.assert_array_equal(values[0], values[2])


def test_mitsuba_preset_files_say_how_to_register_and_are_deterministic(catalogs):
    """#18 item 4: both files name the plugin's registration; a rerun writes the same bytes; without a spread the
    BSDF is one anodic_film with the swatch's own parameters (nothing fitted)."""
    spec, records, files = catalogs[0]
    again, _ = mitsuba_presets(spec, [dict(r) for r in records])
    assert again == files
    for rec in records:
        xml = files[rec["presets"]["mitsuba"]].decode("utf-8")
        doc = json.loads(files[rec["presets"]["mitsuba_json"]])
        assert "swatch.mitsuba.register()" in xml and "swatch.mitsuba.register()" in doc["swatch"]["register"]
        assert doc["bsdf"] == {"id": f"swatch_{rec['id']}", "type": "anodic_film", "thickness_nm": rec["thickness_nm"],
                               "film": spec.film, "substrate": spec.substrate, "film_index_scale": 1.0,
                               "distribution": "ggx", "alpha": 0.2, "shadowing": "correlated"}


def test_single_mitsuba_preset_writes_both_files():
    """#18 item 4: ``swatch preset --format mitsuba``'s library call: an XML and a JSON named by thickness."""
    files, summary = single_mitsuba_preset(150.0, "TiO2-Siefke", "Ti-Johnson", 1.0, 0.3)
    assert sorted(files) == ["preset_150nm_mitsuba.json", "preset_150nm_mitsuba.xml"]
    assert json.loads(files["preset_150nm_mitsuba.json"])["bsdf"]["thickness_nm"] == 150.0
    assert "exact" in summary


def test_preset_command_writes_the_mitsuba_pair_and_refuses_to_overwrite(tmp_path):
    """#18 item 4: ``swatch preset --format mitsuba`` writes the XML and the JSON (brushed: alpha_u along the
    grain, alpha_v across); a second run without --force is refused in one line, exit 2, the files unchanged."""
    from tests.cli_helpers import run_swatch

    r = run_swatch("preset", "--thickness", "80", "--format", "mitsuba", "--finish", "brushed", "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["preset_80nm_mitsuba.json", "preset_80nm_mitsuba.xml"]
    bsdf = json.loads((tmp_path / "preset_80nm_mitsuba.json").read_text(encoding="utf-8"))["bsdf"]
    assert (bsdf["alpha_u"], bsdf["alpha_v"], bsdf["thickness_nm"]) == (0.12, 0.4, 80.0)
    before = (tmp_path / "preset_80nm_mitsuba.xml").read_bytes()
    again = run_swatch("preset", "--thickness", "80", "--format", "mitsuba", "--out", tmp_path)
    assert again.returncode == 2 and again.stderr.strip().startswith("error:") and "--force" in again.stderr
    assert (tmp_path / "preset_80nm_mitsuba.xml").read_bytes() == before
