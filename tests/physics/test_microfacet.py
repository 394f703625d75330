"""Microfacet distributions and Smith shadowing: normalisation, furnace tests, closed forms.

References are properties, not outputs of the code: ∫ D cos θh dω = 1 (Walter et al. 2007),
the weak white furnace ∫ G1(v) D(h) max(0, v·h) dω_h = cos θ_v (Heitz 2014, eq. 18) and energy
conservation (directional albedo ≤ 1 with F = 1), each integrated by independent quadrature.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from swatch.core.errors import SwatchError
from swatch.physics import microfacet as mf

DISTS = ["ggx", "beckmann"]


def _hemisphere_grid(alpha, n_theta=32, n_phi=96):
    """Gauss–Legendre nodes/weights over the upper hemisphere (dω = sin θ dθ dφ) for integrands
    peaked at the pole with width ``alpha`` and mirror-symmetric about the xz plane.

    θ: Gauss–Legendre panels broken at α/4, α, 3α (the lobe) and 45° (where the light leaves the
    hemisphere at normal view); φ: midpoints over [0, π], doubled by the symmetry. Against a
    200 × 1024-node reference of the same rule this is within 1.3e-4 of every albedo the tests
    take (the tests allow 2e-3), at 1/10 of the nodes of a uniform 600 × 256 grid.
    """
    breaks = sorted({b for b in (alpha / 4, alpha, 3 * alpha, np.pi / 4) if b < np.pi / 2})
    edges = np.array([0.0, *breaks, np.pi / 2])
    x, w = np.polynomial.legendre.leggauss(n_theta)
    half = 0.5 * np.diff(edges)[:, None]
    theta = (half * (x + 1.0) + edges[:-1, None]).ravel()
    wt = (half * w).ravel()
    phi = (np.arange(n_phi) + 0.5) * np.pi / n_phi
    wp = np.full(n_phi, 2 * np.pi / n_phi)  # each φ in [0, π] stands for ±φ
    T, P = np.meshgrid(theta, phi, indexing="ij")
    W = np.outer(wt, wp) * np.sin(T)
    dirs = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    return dirs, W


def _uniform_hemisphere_grid(n_theta, n_phi):
    """Gauss–Legendre in θ over [0, π/2] and midpoints in φ over [0, 2π] (no assumptions)."""
    x, w = np.polynomial.legendre.leggauss(n_theta)
    theta = 0.25 * np.pi * (x + 1.0)
    wt = 0.25 * np.pi * w
    phi = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    wp = np.full(n_phi, 2 * np.pi / n_phi)
    T, P = np.meshgrid(theta, phi, indexing="ij")
    W = np.outer(wt, wp) * np.sin(T)
    dirs = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    return dirs, W


@pytest.mark.parametrize("dist", DISTS)
@pytest.mark.parametrize("alpha", [0.05, 0.1, 0.3, 0.6, 1.0])
def test_D_is_normalised(dist, alpha):
    # ∫ D(θh) cos θh sin θh dθh dφ over the hemisphere = 1, by adaptive quadrature (scipy.quad).
    def f(t):
        return float(mf.D(np.cos(t), alpha, dist)) * np.cos(t) * np.sin(t) * 2 * np.pi

    val, _err = integrate.quad(f, 0.0, np.pi / 2, points=[alpha / 4, alpha, 2 * alpha], limit=400)
    assert val == pytest.approx(1.0, abs=2e-5)


def test_ggx_matches_the_tan_form():
    # D = α² / (π cos⁴θ (α² + tan²θ)²): the published form, written out independently here.
    t = np.linspace(0.0, 1.5, 50)
    for a in (0.1, 0.3, 0.9):
        ref = a**2 / (np.pi * np.cos(t) ** 4 * (a**2 + np.tan(t) ** 2) ** 2)
        np.testing.assert_allclose(mf.D_ggx(np.cos(t), a), ref, rtol=1e-10)
        ref_b = np.exp(-np.tan(t) ** 2 / a**2) / (np.pi * a**2 * np.cos(t) ** 4)
        np.testing.assert_allclose(mf.D_beckmann(np.cos(t), a), ref_b, rtol=1e-10, atol=1e-300)


@pytest.mark.parametrize("dist", DISTS)
@pytest.mark.parametrize("alpha", [0.1, 0.3, 0.7, 1.0])
@pytest.mark.parametrize("theta_v", [0.0, 30.0, 60.0, 80.0])
def test_weak_white_furnace(dist, alpha, theta_v):
    # Heitz 2014: ∫ G1(v, h) D(h) max(0, v·h) dω_h = cos θ_v — the G1 matches its D.
    h, W = _hemisphere_grid(alpha)
    tv = np.radians(theta_v)
    v = np.array([np.sin(tv), 0.0, np.cos(tv)])
    vh = h @ v
    g1 = mf.G1(np.cos(tv), vh, alpha, dist)
    integrand = g1 * mf.D(h[..., 2], alpha, dist) * np.maximum(vh, 0.0)
    assert float((integrand * W).sum()) == pytest.approx(np.cos(tv), rel=2e-3, abs=1e-4)


def _albedo(theta_v, alpha, dist, correlated):
    """∫ f cos θ_l dω_l with F = 1, integrated over the half vector: dω_l = 4 (v·h) dω_h."""
    h, W = _hemisphere_grid(alpha)
    tv = np.radians(theta_v)
    v = np.array([np.sin(tv), 0.0, np.cos(tv)])
    vh = h @ v
    l = 2.0 * vh[..., None] * h - v
    cl = l[..., 2]
    cv = np.cos(tv)
    g = mf.G(cl, cv, vh, vh, alpha, dist, correlated)
    integrand = np.where((cl > 0) & (vh > 0), mf.D(h[..., 2], alpha, dist) * g * vh / cv, 0.0)
    return float((integrand * W).sum())


@pytest.mark.parametrize("correlated", [True, False])
@pytest.mark.parametrize("dist", DISTS)
@pytest.mark.parametrize("alpha", [0.05, 0.2, 0.5, 1.0])
def test_furnace_albedo_at_most_one(dist, alpha, correlated):
    for theta_v in (0.0, 20.0, 45.0, 70.0, 85.0, 89.0):
        a = _albedo(theta_v, alpha, dist, correlated)
        assert 0.0 < a <= 1.0 + 2e-3, (theta_v, a)
    # Smooth surfaces lose almost nothing at normal incidence.
    if alpha <= 0.05:
        assert _albedo(0.0, alpha, dist, correlated) > 0.98


def test_albedo_by_direct_light_integration():
    # The same albedo integrated over light directions directly (no change of variables, no
    # adapted nodes: a uniform grid; the lobe is broad at α = 0.5 and the rule converges fast).
    l, W = _uniform_hemisphere_grid(120, 96)  # converged: 800 × 512 nodes agree to 1e-10
    for theta_v in (10.0, 60.0):
        tv = np.radians(theta_v)
        v = np.array([np.sin(tv), 0.0, np.cos(tv)])
        hv = l + v
        hv /= np.linalg.norm(hv, axis=-1, keepdims=True)
        f = mf.brdf_scale(l[..., 2], v[2], hv[..., 2], (l * hv).sum(-1), 0.5, "ggx")
        direct = float((f * l[..., 2] * W).sum())
        assert direct == pytest.approx(_albedo(theta_v, 0.5, "ggx", True), rel=3e-3)
        assert direct <= 1.0


@settings(max_examples=40, deadline=None)
@given(alpha=st.floats(0.02, 1.0), cl=st.floats(0.01, 1.0), cv=st.floats(0.01, 1.0), ch=st.floats(0.05, 1.0))
def test_fast_forms_equal_the_definition(alpha, cl, cv, ch):
    ref = mf.D(ch, alpha, "ggx") * mf.G(cl, cv, 0.5, 0.5, alpha, "ggx") / (4 * cl * cv)
    assert float(mf.brdf_scale(cl, cv, ch, 0.5, alpha, "ggx")) == pytest.approx(float(ref), rel=1e-9)
    def lam(c):  # GGX Λ, written out
        return 0.5 * (np.sqrt(1 + alpha**2 * (1 - c * c) / (c * c)) - 1)

    assert float(mf.G(cl, cv, 0.5, 0.5, alpha)) == pytest.approx(1 / (1 + lam(cl) + lam(cv)), rel=1e-9)
    fast = mf.ggx_reflectance_factor_cos(np.float32(cl), np.float32(cv), np.float32(ch), alpha)
    # float32 near a sharp peak: D's denominator (α² − 1) cos²θh + 1 is a difference of numbers near
    # 1, so its rounding error (a few float32 ulps of 1) is relative to its own, small, size.
    den = (alpha**2 - 1.0) * ch * ch + 1.0
    assert float(fast) == pytest.approx(np.pi * float(ref) * cl, rel=2e-5 + 2e-7 / den)


def test_masking_and_dtype():
    assert float(mf.brdf_scale(-0.1, 0.5, 0.7, 0.5, 0.3)) == 0.0
    assert float(mf.brdf_scale(0.5, -0.1, 0.7, 0.5, 0.3, "beckmann")) == 0.0
    x = np.linspace(0.1, 1, 5, dtype=np.float32)
    assert mf.brdf_scale(x, x, x, x, 0.3).dtype == np.float32
    # 1/(1 + Λl + Λv) >= 1/((1 + Λl)(1 + Λv)): the correlated G is never below the separable one.
    c = np.linspace(0.05, 1, 20)
    assert np.all(mf.G(c[:, None], c[None, :], 1, 1, 0.4) >= mf.G(c[:, None], c[None, :], 1, 1, 0.4, correlated=False) - 1e-12)


@pytest.mark.parametrize("bad", [0, -0.1, 1.0001, float("nan"), "x"])
def test_bad_roughness(bad):
    with pytest.raises(SwatchError):
        mf.check_roughness_alpha(bad)


def test_bad_distribution():
    with pytest.raises(SwatchError):
        mf.D(0.5, 0.3, "phong")


@pytest.mark.parametrize("alpha_u, alpha_v", [(0.3, 0.3), (0.15, 0.5)])
@pytest.mark.parametrize("theta_v_deg, phi_v_deg", [(0.0, 0.0), (50.0, 30.0), (75.0, 100.0)])
def test_vndf_sampler_draws_the_visible_normal_density(alpha_u, alpha_v, theta_v_deg, phi_v_deg):
    """#23: the renderer's one GGX sampler (``sample_vndf_ggx``, isotropic and anisotropic) draws half vectors
    with the density of visible normals ``D_v(h) = G1(v) max(0, v·h) D(h) / cos θ_v`` (Heitz 2014, eq. 2),
    with ``D`` and ``Λ`` of anisotropic GGX written out here (Heitz 2014, eqs. 85–86): 200 000 random points,
    histogram over 8 × 12 cells of (cos θ_h, φ_h) against the density integrated over each cell (16 × 16
    midpoints), Pearson χ² (p > 1e-3); its returned pdf equals ``D_v(h) / (4 v·h)`` at the samples."""
    from scipy.stats import chisquare

    def D(h):
        den = (h[..., 0] / alpha_u) ** 2 + (h[..., 1] / alpha_v) ** 2 + h[..., 2] ** 2
        return 1.0 / (np.pi * alpha_u * alpha_v * den * den)

    tv, pv = np.radians(theta_v_deg), np.radians(phi_v_deg)
    v = np.array([np.sin(tv) * np.cos(pv), np.sin(tv) * np.sin(pv), np.cos(tv)])
    g1 = 1.0 / (1.0 + 0.5 * (np.sqrt(1.0 + ((alpha_u * v[0]) ** 2 + (alpha_v * v[1]) ** 2) / v[2] ** 2) - 1.0))

    def d_vis(h):
        return g1 * np.maximum(h @ v, 0.0) * D(h) / v[2]

    rng = np.random.default_rng(23)
    u1, u2 = rng.random(200_000), rng.random(200_000)
    l, _, cos_d, pdf = mf.sample_vndf_ggx(v[None], alpha_u, alpha_v, u1, u2)
    h = l[0] + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    np.testing.assert_allclose(pdf[0], d_vis(h) / (4.0 * cos_d[0]), rtol=1e-6)
    # cells: 8 bands uniform in θ_h up to atan(4 α) (the last one open to 90°), 12 sectors in φ_h
    nt, nph, sub = 8, 12, 16
    th_edges = np.linspace(0.0, np.arctan(4.0 * max(alpha_u, alpha_v)), nt + 1)
    th_edges[-1] = np.pi / 2
    ph_edges = np.linspace(-np.pi, np.pi, nph + 1)
    th_h = np.arccos(np.clip(h[:, 2], -1, 1))
    counts, _, _ = np.histogram2d(th_h, np.arctan2(h[:, 1], h[:, 0]), bins=[th_edges, ph_edges])
    expected = np.empty((nt, nph))
    for i in range(nt):
        t = th_edges[i] + (np.arange(sub) + 0.5) / sub * (th_edges[i + 1] - th_edges[i])
        for k in range(nph):
            p = ph_edges[k] + (np.arange(sub) + 0.5) / sub * (ph_edges[k + 1] - ph_edges[k])
            T, P = np.meshgrid(t, p, indexing="ij")
            hh = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
            dw = np.sin(T) * (th_edges[i + 1] - th_edges[i]) / sub * (ph_edges[k + 1] - ph_edges[k]) / sub
            expected[i, k] = (d_vis(hh) * dw).sum()
    assert expected.sum() == pytest.approx(1.0, abs=5e-3)  # the density is normalised (weak furnace)
    ok = expected.ravel() * u1.size >= 5
    obs, exp = counts.ravel()[ok], expected.ravel()[ok] * u1.size
    assert chisquare(obs, exp * obs.sum() / exp.sum()).pvalue > 1e-3
