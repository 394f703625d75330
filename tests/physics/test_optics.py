"""The thin-film optics against Byrnes' tmm (coh_tmm), plus physical properties."""
from __future__ import annotations

import numpy as np
import pytest
import tmm
from hypothesis import example, given, settings
from hypothesis import strategies as st

from swatch.core.errors import SwatchError
from swatch.physics import multilayer, optics

TOL = 1e-10

index_re = st.floats(0.05, 5.0)
index_im = st.floats(0.0, 5.0)
angle = st.one_of(st.just(0.0), st.just(89.9), st.floats(0.0, 89.9))
thickness = st.one_of(st.just(0.0), st.floats(0.0, 1000.0))
wavelength = st.floats(300.0, 1000.0)


def reference(pol, n_list, d_list, theta_deg, wl):
    return tmm.coh_tmm(pol, n_list, d_list, np.radians(theta_deg), wl)


@settings(max_examples=400, deadline=None)
@given(nf=index_re, kf=index_im, ns=index_re, ks=index_im, d=thickness, th=angle, wl=wavelength)
def test_single_film_equals_coh_tmm(nf, kf, ns, ks, d, th, wl):
    n_film, n_sub = complex(max(nf, 1.0), kf), complex(ns, ks)
    res = optics.film_reflectance(d, th, [wl], n_film, n_sub, amplitudes=True)
    for pol, R, r in (("s", res.R_s, res.r_s), ("p", res.R_p, res.r_p)):
        ref = reference(pol, [1.0, n_film, n_sub], [np.inf, d, np.inf], th, wl)
        assert abs(R[0] - ref["R"]) <= TOL
        assert abs(r[0] - ref["r"]) <= TOL
    sweep = optics.film_reflectance_sweep(d, 0.0, 1, th, [wl], n_film, n_sub)
    for pol, R in (("s", sweep.R_s), ("p", sweep.R_p)):
        ref = reference(pol, [1.0, n_film, n_sub], [np.inf, d, np.inf], th, wl)
        assert abs(R[0, 0] - ref["R"]) <= TOL


@settings(max_examples=150, deadline=None)
@given(
    layers=st.lists(st.tuples(st.floats(1.0, 3.0), index_im, thickness), min_size=1, max_size=3),
    ns=index_re, ks=index_im, th=angle, wl=wavelength,
)
def test_stack_equals_coh_tmm(layers, ns, ks, th, wl):
    ns_c = complex(ns, ks)
    n_layers = [complex(n, k) for n, k, _ in layers]
    ds = [d for _, _, d in layers]
    res = multilayer.stack_reflectance(ds, n_layers, ns_c, th, [wl])
    for pol, R, r in (("s", res.R_s, res.r_s), ("p", res.R_p, res.r_p)):
        ref = reference(pol, [1.0, *n_layers, ns_c], [np.inf, *ds, np.inf], th, wl)
        assert abs(R[0] - ref["R"]) <= TOL
        assert abs(r[0] - ref["r"]) <= TOL


def test_vectorised_grid_equals_coh_tmm_pointwise():
    """Broadcasting over thickness x angle x wavelength gives the same numbers as point calls."""
    rng = np.random.default_rng(7)
    wl = np.linspace(380, 780, 9)
    n_film = 2.4 + 0.3j * rng.random(wl.size)
    n_sub = 2.0 + 3.0j + rng.random(wl.size)
    d = np.array([0.0, 37.5, 290.0])
    th = np.array([0.0, 45.0, 89.9])
    res = optics.film_reflectance(d[:, None], th[None, :], wl, n_film, n_sub)
    assert res.R_s.shape == (3, 3, 9)
    for i, di in enumerate(d):
        for j, tj in enumerate(th):
            for w, wv in enumerate(wl):
                ref_s = reference("s", [1.0, n_film[w], n_sub[w]], [np.inf, di, np.inf], tj, wv)["R"]
                ref_p = reference("p", [1.0, n_film[w], n_sub[w]], [np.inf, di, np.inf], tj, wv)["R"]
                assert abs(res.R_s[i, j, w] - ref_s) <= TOL
                assert abs(res.R_p[i, j, w] - ref_p) <= TOL


@settings(max_examples=60, deadline=None)
@given(start=st.floats(0.0, 300.0), step=st.floats(0.01, 3.0), count=st.integers(1, 400),
       kf=st.floats(0.0, 0.5))
def test_sweep_equals_general_path(start, step, count, kf):
    wl = np.arange(380.0, 781.0, 20.0)
    n_film = 2.4 + kf * 1j + 0.0 * wl
    n_sub = 2.5 + 3.4j + 0.0 * wl
    angles = np.array([0.0, 30.0, 75.0, 89.0])
    sweep = optics.film_reflectance_sweep(start, step, count, angles, wl, n_film, n_sub)
    d = start + step * np.arange(count)
    direct = optics.film_reflectance(d[:, None], angles[None, :], wl, n_film, n_sub)
    assert sweep.R_s.shape == direct.R_s.shape
    assert np.max(np.abs(sweep.R_s - direct.R_s)) <= 1e-12
    assert np.max(np.abs(sweep.R_p - direct.R_p)) <= 1e-12


@settings(max_examples=200, deadline=None)
@given(nf=st.floats(1.0, 4.0), kf=index_im, ns=index_re, ks=index_im, d=thickness, th=angle, wl=wavelength)
# Found by hypothesis (session 6): film and substrate of the ambient's index, the substrate's k
# subnormal-small, gave 0 * inf = NaN in the pole form (issue 17's suite ran into it).
@example(nf=1.0, kf=0.0, ns=1.0, ks=1.79e-161, d=0.0, th=0.0, wl=300.0)
def test_reflectance_in_unit_interval(nf, kf, ns, ks, d, th, wl):
    res = optics.film_reflectance(d, th, [wl], complex(nf, kf), complex(ns, ks))
    for R in (res.R_s, res.R_p, res.R):
        assert 0.0 <= R[0] <= 1.0 + 1e-12


@settings(max_examples=100, deadline=None)
@given(nf=st.floats(1.0, 4.0), kf=index_im, ns=index_re, ks=index_im, d=thickness, wl=wavelength)
def test_s_equals_p_at_normal_incidence(nf, kf, ns, ks, d, wl):
    res = optics.film_reflectance(d, 0.0, [wl], complex(nf, kf), complex(ns, ks))
    assert abs(res.R_s[0] - res.R_p[0]) <= 1e-12


@settings(max_examples=100, deadline=None)
@given(nf=st.floats(1.0, 4.0), kf=index_im, ns=index_re, ks=index_im, th=angle, wl=wavelength)
def test_zero_thickness_is_bare_substrate(nf, kf, ns, ks, th, wl):
    n_sub = complex(ns, ks)
    res = optics.film_reflectance(0.0, th, [wl], complex(nf, kf), n_sub)
    # Bare interface air/substrate, written out independently of the module (Fresnel equations).
    t = np.radians(th)
    c0 = np.cos(t)
    c2 = np.sqrt(1 - (np.sin(t) / n_sub) ** 2 + 0j)
    if c2.imag * n_sub.real + c2.real * n_sub.imag < 0:  # forward branch of n cos(theta)
        c2 = -c2
    rs = (c0 - n_sub * c2) / (c0 + n_sub * c2)
    rp = (n_sub * c0 - c2) / (n_sub * c0 + c2)
    assert abs(res.R_s[0] - abs(rs) ** 2) <= 1e-10
    assert abs(res.R_p[0] - abs(rp) ** 2) <= 1e-10


@settings(max_examples=100, deadline=None)
@given(nf=st.floats(1.2, 3.0), ns=index_re, ks=index_im, d=st.floats(0.0, 500.0), th=angle, wl=wavelength)
def test_lossless_film_is_periodic_in_thickness(nf, ns, ks, d, th, wl):
    cos1 = np.sqrt(1 - (np.sin(np.radians(th)) / nf) ** 2)
    period = wl / (2 * nf * cos1)
    a = optics.film_reflectance(d, th, [wl], nf, complex(ns, ks))
    b = optics.film_reflectance(d + period, th, [wl], nf, complex(ns, ks))
    assert abs(a.R_s[0] - b.R_s[0]) <= 1e-9
    assert abs(a.R_p[0] - b.R_p[0]) <= 1e-9


def test_colour_science_thin_film_tmm_discrepancy_is_documented():
    """colour.phenomena.thin_film_tmm (0.4.7) takes only Re(n) in Snell's law: on titanium at
    oblique incidence it is off by more than 0.1 somewhere on the default grid, while it agrees at
    normal incidence (where Snell's law plays no part). We use our own kernel, checked against tmm."""
    from colour.phenomena import thin_film_tmm

    from swatch.physics.model import get_coating

    c = get_coating()
    wl = c.wavelength_nm
    d = np.arange(0.0, 301.0, 10.0)
    angles = np.arange(0.0, 90.0, 5.0)
    R, _ = thin_film_tmm(np.stack([np.ones_like(wl), c.n_film, c.n_substrate]), d, wl, angles)
    theirs_s = np.transpose(R[..., 0], (2, 1, 0))  # (W, A, T) -> (T, A, W)
    ours = optics.film_reflectance(d[:, None], angles[None, :], wl, c.n_film, c.n_substrate)
    diff = np.abs(theirs_s - ours.R_s)
    assert diff[:, 0].max() < 1e-9, "normal incidence must agree"
    if diff.max() <= 0.1:
        pytest.skip("colour-science's thin_film_tmm now agrees with tmm: the documented trap is fixed")
    # Spot-check that it is colour-science, not us, that is off: tmm at the worst point.
    t, a, w = np.unravel_index(diff.argmax(), diff.shape)
    ref = reference("s", [1.0, c.n_film[w], c.n_substrate[w]], [np.inf, d[t], np.inf], angles[a], wl[w])["R"]
    assert abs(ours.R_s[t, a, w] - ref) <= TOL
    assert abs(theirs_s[t, a, w] - ref) > 0.1


def test_colour_science_thin_film_tmm_takes_every_angle_from_the_first_wavelength():
    """Issue 19: besides Re(n), colour.phenomena.thin_film_tmm (0.4.7) computes the refraction angles for
    all wavelengths from the first wavelength's index (``snell_law(n_0, n[:, 0], θ)``). A lossless,
    dispersive film (the real part of TiO2-Siefke: n 2.77 at 380 nm to 2.35 at 780 nm) on n = 1.5 glass,
    100 nm, at 60°: at 550 nm its R_s is
    0.3796 on the 380→780 nm grid, 0.3700 on the same grid reversed, and tmm's 0.3725 (ours equals
    tmm). The physics uses our kernel."""
    from colour.phenomena import thin_film_tmm

    from swatch.physics.materials import load_material

    wl = np.arange(380.0, 781.0, 5.0)
    j = int(np.flatnonzero(wl == 550.0)[0])
    nf = load_material("TiO2-Siefke").nk(wl).real + 0j  # lossless (k = 0) and dispersive: only the angle bug
    ns = np.full(wl.size, 1.5 + 0j)
    N = np.stack([np.ones_like(wl) + 0j, nf, ns])
    forward = thin_film_tmm(N, 100.0, wl, 60.0)[0][:, 0, 0, 0]
    backward = thin_film_tmm(N[:, ::-1], 100.0, wl[::-1], 60.0)[0][::-1, 0, 0, 0]
    ref = reference("s", [1.0, nf[j], ns[j]], [np.inf, 100.0, np.inf], 60.0, 550.0)["R"]
    ours = optics.film_reflectance(100.0, 60.0, wl, nf, ns).R_s[j]
    assert abs(ours - ref) <= TOL
    if abs(forward[j] - ref) < 1e-6 and abs(backward[j] - ref) < 1e-6:
        pytest.skip("colour-science's thin_film_tmm now refracts each wavelength by its own index: fixed")
    assert forward[j] == pytest.approx(0.3796, abs=5e-4) and backward[j] == pytest.approx(0.3700, abs=5e-4)
    assert ref == pytest.approx(0.3725, abs=5e-4)
    assert abs(forward[j] - backward[j]) > 0.005  # the order of the grid changes its answer
    # at the first wavelength of each grid it is right: the angle there is its own
    assert forward[0] == pytest.approx(reference("s", [1.0, nf[0], ns[0]], [np.inf, 100.0, np.inf], 60.0,
                                                 380.0)["R"], abs=1e-9)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"thickness_nm": -1.0}, "thickness"),
        ({"thickness_nm": np.nan}, "thickness"),
        ({"incidence_deg": 90.0}, "`incidence_deg` must be in"),
        ({"incidence_deg": -5.0}, "`incidence_deg` must be in"),
    ],
)
def test_bad_input_raises_swatch_error(kwargs, message):
    args = {"thickness_nm": 50.0, "incidence_deg": 10.0}
    args.update(kwargs)
    with pytest.raises(SwatchError, match=message):
        optics.film_reflectance(args["thickness_nm"], args["incidence_deg"], [500.0], 2.4, 2.5 + 3.4j)


def test_negative_k_rejected():
    with pytest.raises(SwatchError, match="k"):
        optics.film_reflectance(10.0, 0.0, [500.0], 2.4 - 0.1j, 2.5 + 3.4j)


def test_threaded_sweep_equals_general_path():
    """A sweep large enough to be split over threads gives the general path's numbers."""
    from swatch.physics.model import get_coating

    c = get_coating()
    angles = np.arange(0.0, 90.0, 3.0)
    sweep = optics.film_reflectance_sweep(5.0, 2.5, 121, angles, c.wavelength_nm, c.n_film, c.n_substrate)
    assert sweep.R_s.size >= optics._THREADED_MIN_SAMPLES
    d = 5.0 + 2.5 * np.arange(121)
    direct = c.reflectance(d[:, None], angles[None, :])
    assert np.max(np.abs(sweep.R_s - direct.R_s)) <= 1e-12
    assert np.max(np.abs(sweep.R_p - direct.R_p)) <= 1e-12


def test_threaded_sweep_points_equal_coh_tmm():
    """Random points of the benchmark-sized grid against tmm directly."""
    from swatch.physics.model import get_coating

    c = get_coating()
    wl = c.wavelength_nm
    angles = np.arange(0.0, 90.0)
    sweep = optics.film_reflectance_sweep(0.0, 1.0, 301, angles, wl, c.n_film, c.n_substrate)
    rng = np.random.default_rng(11)
    for _ in range(40):
        t, a, w = rng.integers(301), rng.integers(90), rng.integers(wl.size)
        for pol, R in (("s", sweep.R_s), ("p", sweep.R_p)):
            ref = reference(pol, [1.0, c.n_film[w], c.n_substrate[w]], [np.inf, float(t), np.inf], angles[a], wl[w])
            assert abs(R[t, a, w] - ref["R"]) <= TOL
