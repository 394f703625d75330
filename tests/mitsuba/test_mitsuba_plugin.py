"""The anodic_film BSDF plugin for Mitsuba 3 (#23): its Airy formula against tmm, its eval against an
independent numpy microfacet formula with tmm's Fresnel, no NaN below the horizon, anisotropic = isotropic
at alpha_u = alpha_v, and the one-line setup error."""
from __future__ import annotations

import math

import numpy as np
import pytest
import tmm

from swatch.physics.materials import load_material
from tests.helpers import random_directions, unit
from tests.mitsuba_setup import jit_float, jit_of, mitsuba_variant


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def _tmm_R(d_nm, theta_rad, wl_nm, n_film, n_sub):
    """Unpolarised Airy reflectance by Byrnes' transfer-matrix package (the reference)."""
    stack, ds = [1.0, n_film, n_sub], [np.inf, d_nm, np.inf]
    return 0.5 * (tmm.coh_tmm("s", stack, ds, theta_rad, wl_nm)["R"] + tmm.coh_tmm("p", stack, ds, theta_rad, wl_nm)["R"])


def test_drjit_airy_matches_tmm(mi):
    """#23: the plugin's Dr.Jit Airy formula equals tmm.coh_tmm (s, p averaged) to 2e-6 over angles,
    wavelengths and thicknesses (single precision against double)."""
    from swatch.render.mitsuba.film import airy_reflectance

    f, s = load_material("TiO2-Siefke"), load_material("Ti-Johnson")
    rng = np.random.default_rng(23)
    wl = rng.uniform(380, 780, 200)
    c = rng.uniform(0.02, 1.0, 200)
    d = rng.uniform(0, 400, 200)
    nf, ns = f.nk(wl), s.nk(wl)
    got = np.asarray(airy_reflectance(*(jit_float(a) for a in (c, wl, nf.real, nf.imag, ns.real, ns.imag, d))))
    ref = np.array([_tmm_R(d[i], math.acos(c[i]), wl[i], nf[i], ns[i]) for i in range(wl.size)])
    assert np.max(np.abs(got - ref)) < 2e-6


def _si(mi, wi, wavelengths):
    """A SurfaceInteraction3f at ``wi`` (rows) and the four ``wavelengths`` (nm), opaque to Dr.Jit: the tests'
    kernels do not bake their wavelengths in, so tests differing only in them share compiled kernels (#17)."""
    import drjit as dr

    n = wi.shape[0]
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = jit_of(mi.Vector3f, wi.T)
    si.wavelengths = mi.Spectrum(*(dr.opaque(mi.Float, float(w)) for w in wavelengths))
    return si


def test_eval_equals_independent_microfacet_formula(mi):
    """#23: eval = F_tmm(θd) D G₂ / (4 cos θi) with GGX D and height-correlated Smith G₂ written here in numpy
    (anisotropic α 0.15 × 0.4, 120 nm); pdf = D G₁(i) / (4 cos θi) (visible normals)."""
    ax, ay, d = 0.15, 0.4, 120.0
    bsdf = mi.load_dict({"type": "anodic_film", "thickness_nm": d, "alpha_u": ax, "alpha_v": ay})
    rng = np.random.default_rng(5)
    wi = unit(rng.normal(size=(64, 3)) * [1, 1, 0.3] + np.array([0, 0, 1.2]))
    wo = unit(rng.normal(size=(64, 3)) * [1, 1, 0.3] + np.array([0, 0, 1.2]))
    wls = (420.0, 510.0, 580.0, 690.0)
    val = np.asarray(bsdf.eval(mi.BSDFContext(), _si(mi, wi, wls), jit_of(mi.Vector3f, wo.T)))
    pdf = np.asarray(bsdf.pdf(mi.BSDFContext(), _si(mi, wi, wls), jit_of(mi.Vector3f, wo.T)))

    h = unit(wi + wo)
    D = 1.0 / (math.pi * ax * ay * ((h[:, 0] / ax) ** 2 + (h[:, 1] / ay) ** 2 + h[:, 2] ** 2) ** 2)

    def lam(w):
        t2 = ((w[:, 0] * ax) ** 2 + (w[:, 1] * ay) ** 2) / w[:, 2] ** 2
        return 0.5 * (np.sqrt(1 + t2) - 1)

    G2 = 1 / (1 + lam(wi) + lam(wo))
    f, s = load_material("TiO2-Siefke"), load_material("Ti-Johnson")
    cos_d = np.einsum("ij,ij->i", wi, h)
    for j, wl in enumerate(wls):
        F = np.array([_tmm_R(d, math.acos(c), wl, f.nk(wl), s.nk(wl)) for c in cos_d])
        ref = F * D * G2 / (4 * wi[:, 2])
        np.testing.assert_allclose(val[j], ref, rtol=2e-4, atol=1e-7)
    np.testing.assert_allclose(pdf, D / (1 + lam(wi)) / (4 * wi[:, 2]), rtol=2e-4)


@pytest.mark.slow
def test_below_horizon_gives_zero_not_nan(mi):
    """#23: directions below the horizon (incoming, outgoing, grazing, the pole) give 0 value, 0 pdf and a
    finite zero sample weight; no NaN anywhere."""
    bsdf = mi.load_dict({"type": "anodic_film", "thickness_nm": 80.0, "alpha": 0.5})
    wi = np.array([[0, 0, 1.0], [0.6, 0, -0.8], [1, 0, 0], [0, 0.8, 0.6], [0, 0, -1.0], [0.3, 0.3, 1e-7]])
    wo = np.array([[0.6, 0, -0.8], [0, 0, 1.0], [0, 0, 1.0], [0, -1.0, 0], [0, 0, 1.0], [0, 0, 1.0]])
    si = _si(mi, unit(wi), (400.0, 500.0, 600.0, 700.0))
    ctx = mi.BSDFContext()
    val, pdf = bsdf.eval_pdf(ctx, si, jit_of(mi.Vector3f, unit(wo).T))
    val, pdf = np.asarray(val), np.asarray(pdf)
    assert np.all(np.isfinite(val)) and np.all(np.isfinite(pdf))
    assert np.all(val[:, :5] == 0) and np.all(pdf[:5] == 0)
    rng = np.random.default_rng(1)
    n = 4096
    wi_r = random_directions(rng, n)  # half of them below the horizon
    bs, w = bsdf.sample(ctx, _si(mi, wi_r, (400.0, 500.0, 600.0, 700.0)), jit_float(rng.random(n)),
                        jit_of(mi.Point2f, rng.random((2, n))))
    w, p, wo_s = np.asarray(w), np.asarray(bs.pdf), np.asarray(bs.wo)
    assert np.all(np.isfinite(w)) and np.all(np.isfinite(p))
    below = wi_r[:, 2] <= 0
    assert np.all(w[:, below] == 0) and np.all(p[below] == 0)
    assert np.all(w[:, wo_s[2] <= 0] == 0)


@pytest.mark.slow
def test_alpha_u_equal_alpha_v_is_isotropic(mi):
    """#23: alpha_u = alpha_v = 0.25 gives the isotropic alpha = 0.25 value, pdf and samples (GGX and Beckmann)."""
    rng = np.random.default_rng(9)
    n = 512
    wi, wo = unit(rng.normal(size=(n, 3)) + np.array([0, 0, 1.5])), unit(rng.normal(size=(n, 3)) + np.array([0, 0, 1.5]))
    u1, u2 = rng.random(n), rng.random((n, 2))
    for dist in ("ggx", "beckmann"):
        out = []
        for extra in ({"alpha": 0.25}, {"alpha_u": 0.25, "alpha_v": 0.25}):
            b = mi.load_dict({"type": "anodic_film", "thickness_nm": 60.0, "distribution": dist, **extra})
            si = _si(mi, wi, (450.0, 520.0, 610.0, 700.0))
            v, p = b.eval_pdf(mi.BSDFContext(), si, jit_of(mi.Vector3f, wo.T))
            bs, w = b.sample(mi.BSDFContext(), si, jit_float(u1), jit_of(mi.Point2f, u2.T))
            out.append([np.asarray(v), np.asarray(p), np.asarray(bs.wo), np.asarray(w)])
        for a, b in zip(*out, strict=True):
            np.testing.assert_array_equal(a, b)


def test_bad_parameters_are_refused(mi):
    """#23: an unknown table, a negative thickness, a scale outside 0.5-1.5, a roughness of 0 are refused by
    load_dict with the plugin's message."""
    for bad, words in (({"film": "Nope"}, "Nope"), ({"thickness_nm": -1.0}, "thickness_nm"),
                       ({"film_index_scale": 3.0}, "film_index_scale"), ({"alpha": 0.0}, "alpha"),
                       ({"film": "Ti-Johnson"}, "not a film"), ({"distribution": "phong"}, "distribution")):
        with pytest.raises(Exception, match=words):
            mi.load_dict({"type": "anodic_film", **bad})


def test_missing_libllvm_is_one_line(monkeypatch):
    """#23: without DRJIT_LIBLLVM_PATH (none found) the engine says in one line what to install."""
    from swatch.core.errors import SwatchError
    from swatch.render.mitsuba import engine

    monkeypatch.delenv("DRJIT_LIBLLVM_PATH", raising=False)
    with pytest.raises(SwatchError, match="apt-get install libllvm19") as exc:
        engine.use_variant("llvm_ad_spectral")
    assert "\n" not in str(exc.value)
    monkeypatch.setenv("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1")
    with pytest.raises(SwatchError, match="libLLVM 15 fails"):
        engine.use_variant("llvm_ad_spectral")


@pytest.mark.slow
def test_spread_averages_the_film_as_the_builtin_model_and_tmm(mi):
    """#19: with ``spread_nm`` 4 and ``spread_fraction`` 0.02 at 300 nm (σ 10 nm) the plugin's value is the uniform
    film's with F replaced by the thickness-averaged F: its ratio to the uniform value equals the built-in
    model's spread average over its uniform reflectance (``Coating.reflectance_cos``) to 2e-3, and the averaged
    F equals tmm integrated over the normal distribution by scipy.integrate.quad to 2e-3; spread 0 is the
    uniform film bit for bit."""
    from scipy import integrate
    from scipy.stats import norm

    from swatch.physics.model import get_coating
    from swatch.physics.spread import ThicknessSpread

    d, spread = 300.0, ThicknessSpread(4.0, 0.02)
    sigma = 4.0 + 0.02 * d
    base = {"type": "anodic_film", "thickness_nm": d, "alpha": 0.3}
    uniform = mi.load_dict(base)
    spread_bsdf = mi.load_dict({**base, "spread_nm": spread.spread_nm, "spread_fraction": spread.spread_fraction})
    zero = mi.load_dict({**base, "spread_nm": 0.0, "spread_fraction": 0.0})
    rng = np.random.default_rng(19)
    wi = unit(rng.normal(size=(12, 3)) * [1, 1, 0.3] + np.array([0, 0, 1.2]))
    wo = unit(rng.normal(size=(12, 3)) * [1, 1, 0.3] + np.array([0, 0, 1.2]))
    wls = (420.0, 510.0, 580.0, 690.0)
    ctx, wo_m = mi.BSDFContext(), jit_of(mi.Vector3f, wo.T)
    val_u = np.asarray(uniform.eval(ctx, _si(mi, wi, wls), wo_m), dtype=np.float64)
    val_s = np.asarray(spread_bsdf.eval(ctx, _si(mi, wi, wls), wo_m), dtype=np.float64)
    assert np.array_equal(np.asarray(zero.eval(ctx, _si(mi, wi, wls), wo_m)), val_u)
    cos_d = np.einsum("ij,ij->i", wi, unit(wi + wo))
    grid = np.array(wls)
    R_u = get_coating(wavelength_nm=grid).reflectance_cos(d, cos_d).R  # (12, 4)
    R_s = get_coating(wavelength_nm=grid, spread=spread).reflectance_cos(d, cos_d).R
    np.testing.assert_allclose(val_s / val_u, (R_s / R_u).T, rtol=2e-3)
    f, s = load_material("TiO2-Siefke"), load_material("Ti-Johnson")
    for i in (0, 7):
        for j in (0, 2):
            wl = wls[j]
            theta = math.acos(cos_d[i])

            def local(t, wl=wl, theta=theta):
                return _tmm_R(max(t, 0.0), theta, wl, f.nk(wl), s.nk(wl)) * norm.pdf(t, d, sigma)

            ref = integrate.quad(local, d - 8 * sigma, d + 8 * sigma, limit=200)[0]
            F_u = _tmm_R(d, theta, wl, f.nk(wl), s.nk(wl))
            np.testing.assert_allclose(val_s[j, i] / val_u[j, i] * F_u, ref, rtol=2e-3)
    assert "spread_nm=4" in str(spread_bsdf)


def test_brush_axis_sets_the_anisotropic_lobe_whatever_the_surface_frame(mi):
    """#23: with ``brush_axis`` (world y) an anisotropic lobe's α_u follows y projected onto the tangent plane, as
    the built-in engine's ``brush_tangent``, whatever tangent the shading frame has (here Mitsuba's
    ``Frame3f(n)``, arbitrary): eval = F_tmm D G₂ / (4 cos θi) with D and Smith written in numpy in that
    brushing frame (α 0.1 along, 0.4 across, 90 nm), and the sampled directions reflect about normals
    drawn in that frame (their eval is finite and positive)."""
    from swatch.physics.finishes import brush_tangent

    au, av, d = 0.1, 0.4, 90.0
    bsdf = mi.load_dict({"type": "anodic_film", "thickness_nm": d, "alpha_u": au, "alpha_v": av,
                         "brush_axis": [0.0, 1.0, 0.0]})
    rng = np.random.default_rng(8)
    n = random_directions(rng, 48)
    n[np.abs(n[:, 1]) > 0.95] = unit(np.array([0.3, 0.5, 0.8]))
    wi_w = unit(n * 1.3 + rng.normal(size=(48, 3)) * 0.5)
    wo_w = unit(n * 1.3 + rng.normal(size=(48, 3)) * 0.5)
    frame = mi.Frame3f(jit_of(mi.Vector3f, n.T))
    wls = (430.0, 520.0, 600.0, 680.0)
    si = _si(mi, np.zeros((48, 3)), wls)
    si.sh_frame = frame
    si.wi = frame.to_local(jit_of(mi.Vector3f, wi_w.T))
    val = np.asarray(bsdf.eval(mi.BSDFContext(), si, frame.to_local(jit_of(mi.Vector3f, wo_w.T))))
    t = brush_tangent("sphere", n).astype(np.float64)
    b = np.cross(n, t)

    def local(w):
        return np.stack([(w * t).sum(1), (w * b).sum(1), (w * n).sum(1)], -1)

    wi, wo = local(wi_w), local(wo_w)
    keep = (wi[:, 2] > 0.05) & (wo[:, 2] > 0.05)
    h = unit(wi + wo)
    D = 1.0 / (math.pi * au * av * ((h[:, 0] / au) ** 2 + (h[:, 1] / av) ** 2 + h[:, 2] ** 2) ** 2)

    def lam(w):
        return 0.5 * (np.sqrt(1 + ((w[:, 0] * au) ** 2 + (w[:, 1] * av) ** 2) / w[:, 2] ** 2) - 1)

    G2 = 1 / (1 + lam(wi) + lam(wo))
    f, s = load_material("TiO2-Siefke"), load_material("Ti-Johnson")
    cos_d = np.einsum("ij,ij->i", wi, h)
    for j, wl in enumerate(wls):
        F = np.array([_tmm_R(d, math.acos(min(c, 1.0)), wl, f.nk(wl), s.nk(wl)) for c in cos_d])
        np.testing.assert_allclose(val[j][keep], (F * D * G2 / (4 * wi[:, 2]))[keep], rtol=3e-4, atol=1e-7)
    assert keep.sum() > 20
    plain = mi.load_dict({"type": "anodic_film", "thickness_nm": d, "alpha_u": au, "alpha_v": av})
    other = np.asarray(plain.eval(mi.BSDFContext(), si, frame.to_local(jit_of(mi.Vector3f, wo_w.T))))
    assert np.max(np.abs(other - val)) > 0.1 * np.max(val)  # without the axis the lobe follows the frame's own s
