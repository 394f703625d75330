"""Environment lighting against references we did not write.

* Furnace test: under the ``uniform`` environment (radiance 1 everywhere) a surface seen along
  its normal has radiance equal to the directional albedo ``∫ f cos θ_l dω_l`` of the thin-film
  GGX BRDF. The reference integrates it here, independently: the GGX ``D`` and height-correlated
  Smith ``G`` written out in this file, Byrnes' ``tmm.coh_tmm`` for the film's reflectance,
  ``scipy.integrate.quad_vec`` for the integral (along the normal the integrand is symmetric in
  azimuth and θ_d = θ_l / 2), ``colour.sd_to_XYZ`` for the colour (CIE 1931 2°: the RGB of
  renders comes from 2° colorimetry whatever observer the Lab numbers use).
* A constant user EXR normalises to ``uniform``; the fast path's error against the brute-force
  integration under the studio light box is bounded; bad maps are refused.
Renders through the renderer: tests/render/test_env_render.py.
"""
from __future__ import annotations

import colour
import numpy as np
import pytest
from scipy import integrate

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.errors import SwatchError
from swatch.render import environment, render_swatch, scene
from swatch.render.builtin import env_shading, shading
from tests.helpers import random_directions
from tests.render.env_reference import (
    ALPHA,
    CM,
    COATING,
    WL,
    albedo_normal_view,
    ggx_lambda,
    lab_2deg,
    lab_of_spectrum,
    tmm_R,
    write_equirect,
    xyz_of_srgb,
)


@pytest.mark.parametrize("d_nm", [30.0, 80.0, 160.0])
def test_furnace_integration_along_the_normal(d_nm):
    """The fast path itself (no renderer): a surface seen along its normal under ``uniform``."""
    env = environment.get_environment("uniform")
    ss = env_shading.sample_set(ALPHA)
    tab = shading.facet_colour_table(d_nm, COATING, CM, 257, (0.0, 1.0)).to_rgb(CM).values.astype(float)
    n = np.array([[0.0, 1.0, 0.0]])
    rgb = env_shading.shade(n, n, environment.levels(env), ss, env_shading.band_weights(ss, tab))[0]
    got = lab_2deg(xyz_of_srgb(rgb))
    ref = lab_of_spectrum(albedo_normal_view(d_nm))
    assert delta_E_00(got, ref) <= 1.0, (d_nm, got, ref)


def test_constant_exr_is_normalised_to_uniform(tmp_path):
    p = tmp_path / "grey.exr"
    write_equirect(p, np.full((32, 64, 3), 0.37, dtype=np.float32))
    env = environment.get_environment(str(p))
    assert env.is_constant and env.radiance[0, 0, 0] == pytest.approx(1.0, rel=1e-6)


def test_albedo_level_of_the_sample_sets():
    """The dense level set against the quadrature with F = 1 at several view angles."""
    ss = env_shading.sample_set(ALPHA)
    A = env_shading.directional_albedo(ss, np.ones((3, 3)))[:, 0]
    for j in (ss.bins - 1, ss.bins // 2, ss.bins // 8):
        cv = ss.cos_v[j]
        v = np.array([np.sqrt(1 - cv * cv), 0.0, cv])

        def f(phi, th, v=v, cv=cv):
            l = np.array([np.sin(th) * np.cos(phi), np.sin(th) * np.sin(phi), np.cos(th)])
            h = (l + v) / np.linalg.norm(l + v)
            den = (ALPHA ** 2 - 1.0) * h[2] ** 2 + 1.0
            D = ALPHA ** 2 / (np.pi * den * den)
            G = 1.0 / (1.0 + ggx_lambda(max(l[2], 1e-12), ALPHA) + ggx_lambda(cv, ALPHA))
            return D * G / (4.0 * cv) * np.sin(th)

        ref = integrate.dblquad(f, 0.0, np.pi / 2, 0.0, 2 * np.pi, epsabs=1e-7)[0]
        assert A[j] == pytest.approx(ref, abs=2e-4)


def test_equirect_orientation(tmp_path):
    """A map bright only near the zenith row lights a surface facing up, not one facing down."""
    img = np.zeros((64, 128, 3), dtype=np.float32)
    img[:8] = 5.0
    img[60:] = 0.01
    p = tmp_path / "sky.exr"
    write_equirect(p, img)
    env = environment.get_environment(str(p))
    up, down = env.radiance_at(np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]))
    assert up[0] > 100 * down[0]


def test_studio_error_against_brute_force():
    """#23: the fast path (128 samples, filtered map) against 2048 samples on the unfiltered map, over
    random normals and views (80 nm, α 0.3, CIE 1931 2°, D65): median ΔE00 ≤ 0.4, p95 ≤ 1 (measured 0.22 and
    0.78, max 1.28; with the earlier 24 samples the bound was median 1, p95 2.5)."""
    rng = np.random.default_rng(7)
    n = random_directions(rng, 300)
    v = random_directions(rng, 300)
    v *= np.sign((n * v).sum(1))[:, None]
    keep = (n * v).sum(1) > 0.1
    n, v = n[keep], v[keep]
    env = environment.get_environment("studio")
    ss = env_shading.sample_set(ALPHA)
    tab = shading.facet_colour_table(80.0, COATING, CM, 257, (0.0, 1.0)).to_rgb(CM).values.astype(float)
    fast = env_shading.shade(n, v, environment.levels(env), ss, env_shading.band_weights(ss, tab))
    ref = env_shading.shade_reference(n, v, env, ALPHA, tab, samples=2048)
    dE = delta_E_00(lab_2deg(xyz_of_srgb(fast)), lab_2deg(xyz_of_srgb(ref)))
    assert np.median(dE) <= 0.4 and np.percentile(dE, 95) <= 1.0, (np.median(dE), np.percentile(dE, 95))


@pytest.mark.parametrize("pixels,words", [
    (np.full((8, 8, 3), 1.0), "twice as wide"),
    (np.where(np.arange(16)[None, :, None] == 3, np.nan, 1.0) * np.ones((8, 16, 3)), "NaN"),
    (-np.ones((8, 16, 3)), "negative"),
    (np.concatenate([np.zeros((4, 16, 3)), np.ones((4, 16, 3))]), "no light"),
])
def test_bad_maps(tmp_path, pixels, words):
    p = tmp_path / "bad.exr"
    write_equirect(p, pixels.astype(np.float32))
    with pytest.raises(SwatchError, match=words):
        environment.get_environment(str(p))


def test_not_an_exr(tmp_path):
    p = tmp_path / "fake.exr"
    p.write_bytes(b"not an image at all")
    with pytest.raises(SwatchError):
        environment.get_environment(str(p))


def test_level_correction_is_finite_where_a_channel_changes_sign():
    """#23: at 170 nm the film's linear-sRGB red changes sign across the lobe (a saturated cyan),
    so a per-channel ratio to the dense level was singular in one view bin (23.7°: bright dots on
    the catalog's 170 nm plate). Every view bin from 10° to 40° under the studio, plate normal, is
    within ΔE2000 2.5 of the 4096-sample brute force (the bound of the studio test above), and
    neighbouring views 0.35° apart agree within 1."""
    a = 0.2
    th = np.radians(np.linspace(10.0, 40.0, 86))
    v = np.stack([np.zeros_like(th), np.cos(th), -np.sin(th)], -1)
    n = np.broadcast_to([0.0, 1.0, 0.0], v.shape)
    env = environment.get_environment("studio")
    ss = env_shading.sample_set(a)
    tab = shading.facet_colour_table(170.0, COATING, CM, 257, (0.0, 1.0)).to_rgb(CM).values.astype(float)
    fast = env_shading.shade(n, v, environment.levels(env), ss, env_shading.band_weights(ss, tab))
    ref = env_shading.shade_reference(n, v, env, a, tab, samples=4096)
    dE = delta_E_00(lab_2deg(xyz_of_srgb(fast)), lab_2deg(xyz_of_srgb(ref)))
    assert dE.max() <= 2.5, (np.degrees(th[np.argmax(dE)]), dE.max())
    lab = lab_2deg(xyz_of_srgb(fast))
    assert delta_E_00(lab[1:], lab[:-1]).max() <= 1.0, delta_E_00(lab[1:], lab[:-1]).max()


def _studio_quadrature(normal, view, d_nm: float, a: float = ALPHA, n_theta: int = 160, n_phi: int = 320):
    """Linear sRGB of one surface point under the built-in studio, by quadrature written here: the
    studio's own radiance function (``swatch.render.studio``, times the environment's normalisation)
    over the sphere (Gauss–Legendre in the polar angle, midpoints in azimuth), GGX ``D`` and
    height-correlated Smith, F from ``tmm.coh_tmm`` over θ_d, its colour by ``colour.sd_to_XYZ``
    (CIE 1931 2°, D65) and ``colour.XYZ_to_RGB`` (neutral light: RGB of F times the radiance)."""
    from scipy.special import roots_legendre

    from swatch.render.studio import studio_radiance

    x, w = roots_legendre(n_theta)
    th, wth = (x + 1) * np.pi / 2, w * np.pi / 2
    ph = (np.arange(n_phi) + 0.5) / n_phi * 2 * np.pi
    T, P = np.meshgrid(th, ph, indexing="ij")
    L = np.stack([np.sin(T) * np.cos(P), np.cos(T), np.sin(T) * np.sin(P)], -1)  # y up
    dw = np.sin(T) * wth[:, None] * (2 * np.pi / n_phi)
    rad = environment.get_environment("studio").scale * studio_radiance(L)[..., 1]
    tds = np.linspace(0.0, np.pi / 2, 46)
    shape = colour.SpectralShape(float(WL[0]), float(WL[-1]), float(WL[1] - WL[0]))
    F_rgb = np.array([colour.XYZ_to_RGB(colour.sd_to_XYZ(colour.SpectralDistribution(tmm_R(d_nm, t), WL),
                                                          colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"],
                                                          colour.SDS_ILLUMINANTS["D65"], shape=shape) / 100, "sRGB")
                      for t in tds])
    H = L + view
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    cl, cv, ch = L @ normal, float(view @ normal), H @ normal
    D = a * a / (np.pi * ((a * a - 1) * ch * ch + 1) ** 2)
    G = 1.0 / (1.0 + ggx_lambda(np.maximum(cl, 1e-9), a) + ggx_lambda(cv, a))
    wgt = np.where((cl > 0) & (ch > 0), D * G / (4 * cv) * dw * rad, 0.0).ravel()
    td = np.arccos(np.clip((L * H).sum(-1), -1, 1)).ravel()
    return np.array([wgt @ np.interp(td, tds, F_rgb[:, k]) for k in range(3)])


def _lab_of_rgb(rgb):
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    return colour.XYZ_to_Lab(colour.RGB_to_XYZ(np.asarray(rgb, dtype=float), "sRGB"), white)


@pytest.mark.slow
def test_studio_integral_equals_quadrature_and_the_fast_path_error_is_bounded():
    """#23: the built-in's map, its normalisation and solid angles and its BRDF are right: the brute force
    over the unfiltered map (8192 VNDF samples) equals an independent quadrature of BRDF × the studio's
    radiance function at the plate and the sphere centre within ΔE00 0.05 (measured ≤ 0.01; CIE 1931 2°,
    D65, 80 nm, α 0.3). The fast path (fixed VNDF samples on a per-sample blurred map, ``env_shading``) is
    within ΔE00 0.75 at the plate centre and 0.5 at the sphere centre (measured 0.51 and 0.26). With the
    earlier 24 samples it read +1.2 % at the plate centre (ΔE00 0.27) and +7.5 % at the sphere centre
    (ΔE00 1.5): the lobe's tails there reach the soft boxes beside a dark wall, and 24 samples with their
    wide blur picked them up (the built-in engine then read 8–12 % brighter than Mitsuba)."""
    size = 32
    for shape, fast_max in (("flat", 0.75), ("sphere", 0.5)):
        normals, _, views, _ = scene.scene_geometry(scene.make_scene(shape, 45.0), size)
        n = normals[16, 16] / np.linalg.norm(normals[16, 16])
        v = views[16, 16] / np.linalg.norm(views[16, 16])
        ref = _lab_of_rgb(_studio_quadrature(n, v, 80.0))
        tab = shading.facet_colour_table(80.0, COATING, CM, 257, (0.0, 1.0)).to_rgb(CM).values.astype(float)
        brute = env_shading.shade_reference(n[None], v[None], environment.get_environment("studio"), ALPHA, tab,
                                            samples=8192)[0]
        fast = render_swatch(80.0, shape, size, environment="studio", coating=COATING, colorimeter=CM).linear_rgb[16, 16]
        assert colour.delta_E(_lab_of_rgb(brute), ref, method="CIE 2000") <= 0.05, shape
        assert colour.delta_E(_lab_of_rgb(fast), ref, method="CIE 2000") <= fast_max, shape
