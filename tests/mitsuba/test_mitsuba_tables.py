"""The plugin's table lookups and its two-sided option (#17: the render kernels' size and compile time).

The four optical tables are looked up in one shared grid through a bucket table
(:mod:`swatch.render.mitsuba.tables`) instead of Mitsuba's ``irregular`` spectra: it must be ``np.interp`` of
the raw tables, for every table shipped and for node sets clustered closer than a bucket. ``two_sided`` must
be Mitsuba's own ``twosided`` wrapper around the one-sided plugin (eval, pdf and samples)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.physics.materials import list_materials
from tests.helpers import random_directions, unit
from tests.mitsuba_setup import jit_float, jit_of, mitsuba_variant


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


#: Wavelengths a lookup is probed at: one array size for every call, and every table evaluated in one
#: ``dr.eval``, so that every pair of tables needing the same steps runs one compiled kernel (#17).
PROBES = 4096


def _lookup(mi, tables, lo, hi, wavelengths_nm, rng):
    """SpectralTables.eval at ``wavelengths_nm`` (topped up with random ones to :data:`PROBES`; each spectral
    lane a shifted copy): (tables, lanes, PROBES)."""
    import drjit as dr

    from swatch.render.mitsuba.tables import SpectralTables

    wl = np.asarray(wavelengths_nm, dtype=np.float32)
    assert wl.size <= PROBES
    wl = np.concatenate([wl, rng.uniform(lo, hi, PROBES - wl.size).astype(np.float32)])
    lanes = [np.roll(wl, 7 * k) for k in range(4)]
    got = SpectralTables(tables, lo, hi).eval(mi.UnpolarizedSpectrum(*(jit_float(x) for x in lanes)))
    dr.eval(got)
    return np.stack([np.asarray(g) for g in got]), np.stack(lanes)


def _probe_points(nodes, lo, hi, rng, n=600):
    """Every node, the midpoints, points just either side of each node, the span's ends, random points,
    and points outside the span (which clamp)."""
    inside = nodes[(nodes >= lo) & (nodes <= hi)]
    mids = 0.5 * (inside[1:] + inside[:-1])
    near = np.concatenate([np.nextafter(inside.astype(np.float32), np.float32(-np.inf)),
                           np.nextafter(inside.astype(np.float32), np.float32(np.inf))])
    return np.concatenate([inside, mids, near, [lo, hi, lo - 25.0, hi + 40.0], rng.uniform(lo, hi, n)])


def test_lookup_is_np_interp_of_every_shipped_table(mi):
    """Each film table paired with a substrate table (every table of ``swatch materials list`` at least
    once): the four looked-up spectra equal ``np.interp`` of the raw float64 tables at float32 wavelengths,
    clamped into the span, to float32 precision, at every node, between nodes, beside them and at random."""
    films = list_materials("film")
    subs = list_materials("substrate")
    rng = np.random.default_rng(17)
    for i in range(max(len(films), len(subs))):
        f, s = films[i % len(films)], subs[i % len(subs)]
        lo = max(f.wavelength_range_nm[0], s.wavelength_range_nm[0], 300.0)
        hi = min(f.wavelength_range_nm[1], s.wavelength_range_nm[1], 900.0)
        tables = [(f.wavelength_nm, f.n), (f.wavelength_nm, f.k), (s.wavelength_nm, s.n), (s.wavelength_nm, s.k)]
        probe = _probe_points(np.concatenate([f.wavelength_nm, s.wavelength_nm]), lo, hi, rng)
        got, lanes = _lookup(mi, tables, lo, hi, probe, rng)
        at = np.clip(lanes.astype(np.float64), lo, hi)
        for t, (wl, v) in enumerate(tables):
            want = np.interp(at, wl, v)
            np.testing.assert_allclose(got[t], want, rtol=3e-6, atol=3e-7 * np.max(np.abs(v)),
                                       err_msg=f"{f.name} / {s.name}, table {t}")


@settings(max_examples=10, deadline=None)
@given(st.lists(st.floats(400.0, 700.0), min_size=2, max_size=40, unique=True),
       st.lists(st.floats(-1e-3, 1e-3), min_size=0, max_size=12), st.integers(0, 2 ** 32 - 1))
def test_lookup_finds_the_segment_however_the_nodes_cluster(mi, spread_out, cluster, seed):
    """Random node sets with clusters far tighter than a bucket (nodes 1e-3 nm apart around 550 nm) and two
    tables on different nodes: the lookup is still ``np.interp`` of both, everywhere in the span, to what
    float32 wavelengths can resolve (2 ulp at 720 nm, 1.2e-4 nm, times the table's steepest slope: a cluster's
    random values make slopes of ~1000 per nm; a wrong segment would be off by its slope times the distance
    to it, ~1 nm at a midpoint)."""
    rng = np.random.default_rng(seed)
    a = np.sort(np.array(spread_out))
    b = np.sort(np.unique(np.concatenate([[380.0, 720.0], 550.0 + np.array(cluster)])))
    tables = [(a, rng.normal(size=a.size)), (b, rng.normal(size=b.size))]
    lo, hi = 380.0, 720.0
    probe = _probe_points(np.concatenate([a, b]), lo, hi, rng, n=300)
    got, lanes = _lookup(mi, tables, lo, hi, probe, rng)
    at = np.clip(lanes.astype(np.float64), lo, hi)
    for t, (wl, v) in enumerate(tables):
        steepest = np.max(np.abs(np.diff(v) / np.diff(wl)))
        np.testing.assert_allclose(got[t], np.interp(at, wl, v), rtol=1e-5, atol=2e-5 + 1.2e-4 * steepest)


def test_two_sided_is_mitsubas_twosided_wrapper(mi):
    """``two_sided = true`` evaluates, weighs and samples as Mitsuba's ``twosided`` around the one-sided plugin,
    on both faces (directions on either side, an anisotropic brushed lobe); the one-sided plugin is black
    from the back, and the flags say which faces reflect."""
    import drjit as dr

    base = {"type": "anodic_film", "thickness_nm": 140.0, "alpha_u": 0.12, "alpha_v": 0.35,
            "brush_axis": [0.0, 1.0, 0.0]}
    native = mi.load_dict({**base, "two_sided": True})
    wrapped = mi.load_dict({"type": "twosided", "material": base})
    one_sided = mi.load_dict(base)
    rng = np.random.default_rng(3)
    n = 512
    wi = random_directions(rng, n)
    wo = random_directions(rng, n)
    wo[: n // 2, 2] = np.abs(wo[: n // 2, 2]) * np.sign(wi[: n // 2, 2])  # half on the side of wi

    def si():
        s = dr.zeros(mi.SurfaceInteraction3f, n)
        s.sh_frame = mi.Frame3f(jit_of(mi.Vector3f, unit(rng_frame).T))
        s.wi = jit_of(mi.Vector3f, wi.T)
        s.wavelengths = mi.Spectrum(430.0, 520.0, 600.0, 680.0)
        return s

    rng_frame = np.random.default_rng(4).normal(size=(n, 3))
    ctx = mi.BSDFContext()
    u1, u2 = jit_float(rng.random(n)), jit_of(mi.Point2f, rng.random((2, n)))
    out = {}
    for name, b in (("native", native), ("wrapped", wrapped)):
        v, p = b.eval_pdf(ctx, si(), jit_of(mi.Vector3f, wo.T))
        bs, w = b.sample(ctx, si(), u1, u2)
        out[name] = [np.asarray(v), np.asarray(p), np.asarray(bs.wo), np.asarray(bs.pdf), np.asarray(w)]
    for a, b, what in zip(out["native"], out["wrapped"], ("eval", "pdf", "sampled wo", "sample pdf", "weight"),
                          strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-7, err_msg=what)
    lit_back = (wi[:, 2] < 0) & (wo[:, 2] < 0)
    assert lit_back.sum() > 50 and np.all(out["native"][0][:, lit_back].max(0) > 0)
    back_value = np.asarray(one_sided.eval(ctx, si(), jit_of(mi.Vector3f, wo.T)))
    assert np.all(back_value[:, lit_back] == 0)
    assert mi.has_flag(native.flags(), mi.BSDFFlags.BackSide) and mi.has_flag(native.flags(), mi.BSDFFlags.FrontSide)
    assert not mi.has_flag(one_sided.flags(), mi.BSDFFlags.BackSide)
    with pytest.raises(Exception, match="two_sided"):
        mi.load_dict({**base, "two_sided": 1.0})


def test_module_examples_run(mi):
    """The numpydoc examples of :mod:`swatch.render.mitsuba.tables` (not in tests/test_doctests.py: the module
    imports Mitsuba, which needs the libLLVM this file's fixture checks for)."""
    import doctest

    from swatch.render.mitsuba import tables

    result = doctest.testmod(tables)
    assert result.attempted >= 2 and result.failed == 0


def test_scalar_variant_looks_the_tables_up_as_the_jit_one(mi):
    """In ``scalar_spectral`` (no JIT: the tables are looked up with ``np.interp``) the plugin's eval at one
    direction pair equals the ``llvm_ad_spectral`` one at the same wavelengths (float32 arithmetic both)."""
    import drjit as dr

    from swatch.render.mitsuba.engine import use_variant

    wi, wo = unit(np.array([0.3, -0.2, 0.9])), unit(np.array([-0.25, 0.3, 0.8]))
    wls = (430.0, 520.0, 600.0, 680.0)
    bsdf = {"type": "anodic_film", "thickness_nm": 95.0, "alpha": 0.2, "two_sided": True}
    values = {}
    try:
        for variant in ("llvm_ad_spectral", "scalar_spectral"):
            use_variant(variant)
            import mitsuba

            si = dr.zeros(mitsuba.SurfaceInteraction3f)
            si.wi = mitsuba.Vector3f(*map(float, wi))
            si.wavelengths = mitsuba.Spectrum(*wls)
            val = mitsuba.load_dict(bsdf).eval(mitsuba.BSDFContext(), si, mitsuba.Vector3f(*map(float, wo)))
            values[variant] = np.asarray(val, dtype=np.float64).reshape(-1)
    finally:
        use_variant("llvm_ad_spectral")
    assert np.all(values["scalar_spectral"] > 0)
    np.testing.assert_allclose(values["scalar_spectral"], values["llvm_ad_spectral"], rtol=2e-5)
