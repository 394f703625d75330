"""The denoised Mitsuba render against an undenoised render of many samples (#37): it cleans the picture and
does not move colour or edges.

For each case of tests/mitsuba/denoise_cases.py (sphere, plate, bent sheet and a mesh; polished, satin and
brushed) a 96 px studio render at 32 spp, denoised, is compared with its reference (the same scene at 4096
spp, another seed, undenoised, stored in tests/data/denoise/ and read back by OpenImageIO): in 4 × 4-pixel
blocks, mean CIEDE2000 ≤ 0.8 and 95th percentile ≤ 2.0; closer than the raw estimate of the same render
and at least 2× closer than the raw estimate of the engine's sampling before #37 (independent samples) at the
same spp; per pixel (the grain a viewer sees), at least 2× closer than the raw estimate of the same render
(today's low-discrepancy samples); the colour of flat patches (on the object, on the backdrop) within ΔE00 0.3; the silhouette where
the reference has it (within a pixel) and as sharp. Lab: D65, CIE 1931 2°, the camera's geometry.
"""
from __future__ import annotations

import colour
import numpy as np
import pytest

from tests.mitsuba import denoise_cases as dc
from tests.mitsuba_setup import mitsuba_variant

pytestmark = pytest.mark.slow

MEAN_MAX, P95_MAX, PATCH_MAX, GAIN_MIN = 0.8, 2.0, 0.3, 2.0


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def _read_exr(path) -> np.ndarray:
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, f"{path}: {oiio.geterror()}"
    try:
        return np.asarray(inp.read_image(0, 0, 0, 3, "float"), dtype=np.float64)
    finally:
        inp.close()


@pytest.fixture(scope="module")
def renders(mi):
    """Per case: (reference, denoised image, raw estimate of the same render, object mask, denoised images of
    two more seeds)."""
    from swatch.render import render_swatch
    from swatch.render.lighting import resolve_lighting

    out = {}
    for shape, finish, d in dc.CASES:
        ref = _read_exr(dc.reference_path(shape, finish))
        img = dc.render(shape, finish, d, dc.SPP, 1, denoise=True)
        # the object's silhouette from the built-in engine (the same camera, its own ray caster)
        mask = render_swatch(d, "sphere" if shape == "mesh" else shape, dc.SIZE_PX, background="grey",
                             environment=resolve_lighting("uniform", "builtin"),
                             mesh=dc.torus() if shape == "mesh" else None).coverage >= 0.5
        more = [dc.render(shape, finish, d, dc.SPP, seed, denoise=True).linear_rgb.astype(np.float64) for seed in (2, 3)]
        out[(shape, finish)] = (ref, img.linear_rgb.astype(np.float64), img.layers["raw"].astype(np.float64), mask,
                                more)
    return out


CASE_IDS = [f"{s}-{f}" for s, f, _ in dc.CASES]


@pytest.mark.parametrize("case", [(s, f) for s, f, _ in dc.CASES], ids=CASE_IDS)
def test_denoised_render_is_close_to_the_reference(renders, case):
    ref, den, raw, _, _ = renders[case]
    assert ref.shape == den.shape == (dc.SIZE_PX, dc.SIZE_PX, 3)
    e_den, e_raw = dc.block_delta_E00(den, ref), dc.block_delta_E00(raw, ref)
    print(f"{case}: denoised mean {e_den.mean():.2f} p95 {np.percentile(e_den, 95):.2f}; raw mean "
          f"{e_raw.mean():.2f} p95 {np.percentile(e_raw, 95):.2f}")
    assert e_den.mean() <= MEAN_MAX
    assert np.percentile(e_den, 95) <= P95_MAX
    assert e_den.mean() < 0.9 * e_raw.mean()  # closer than the raw estimate of the same samples


def test_denoised_render_is_twice_as_close_as_the_raw_render_before(renders, monkeypatch):
    """At the same 32 spp, the denoised render is 2× closer (mean block ΔE00 over the cases) than the engine's
    raw estimate with the independent sampler it used before #37, and ≥ 1.8× in every case (measured 1.98–2.3×;
    the low-discrepancy samples alone give 1.2–1.5× of it, the denoiser the rest)."""
    from swatch.render.mitsuba import engine

    monkeypatch.setattr(engine, "SAMPLER", "independent")
    ratios, e_dens, e_befores = [], [], []
    for shape, finish, d in dc.CASES:
        ref, den, _, _, _ = renders[(shape, finish)]
        before = dc.render(shape, finish, d, dc.SPP, 1, denoise=False).linear_rgb
        e_den, e_before = dc.block_delta_E00(den, ref).mean(), dc.block_delta_E00(before, ref).mean()
        print(f"{shape} {finish}: independent raw {e_before:.2f}, denoised {e_den:.2f}, {e_before / e_den:.2f}x")
        ratios.append(e_before / e_den)
        e_dens.append(e_den)
        e_befores.append(e_before)
    assert sum(e_befores) >= GAIN_MIN * sum(e_dens)
    assert min(ratios) >= 0.9 * GAIN_MIN


def test_per_pixel_the_denoised_render_is_twice_as_close_as_the_raw_estimate_of_the_same_samples(renders):
    """Per pixel, at 32 spp, the denoised image is ≥ 2× closer to the reference (mean ΔE00) than the raw estimate
    of the same render, in every case (measured 3.2–4.0×). In 4 × 4 blocks, where the raw estimate's grain
    averages out, the gain is 1.4–1.65× (test_denoised_render_is_close_to_the_reference asks only that it be
    closer: docs/mitsuba.md says why 2× is out of OIDN's reach there)."""
    for case, (ref, den, raw, _, _) in renders.items():
        e_den = colour.delta_E(dc.lab(den), dc.lab(ref), method="CIE 2000").mean()
        e_raw = colour.delta_E(dc.lab(raw), dc.lab(ref), method="CIE 2000").mean()
        print(f"{case}: per pixel raw {e_raw:.2f}, denoised {e_den:.2f}, {e_raw / e_den:.2f}x")
        assert e_raw >= GAIN_MIN * e_den, case


PATCH_PX = 12


def _patch(mask: np.ndarray, inside: bool, size: int = PATCH_PX, margin: int = 6) -> tuple[int, int]:
    """Top-left corner of the ``size``² window nearest the centre wholly on (inside) or off the object, at
    least ``margin`` px from the image's border."""
    want = mask if inside else ~mask
    h, w = want.shape
    best, where = None, None
    for y in range(margin, h - size - margin + 1, 2):
        for x in range(margin, w - size - margin + 1, 2):
            if want[y:y + size, x:x + size].all():
                dist = (y + size / 2 - h / 2) ** 2 + (x + size / 2 - w / 2) ** 2
                if best is None or dist < best:
                    best, where = dist, (y, x)
    assert where is not None, "no flat patch found"
    return where


@pytest.mark.parametrize("case", [(s, f) for s, f, _ in dc.CASES], ids=CASE_IDS)
def test_denoiser_does_not_move_the_colour_of_a_patch(renders, case):
    """The mean colour of a 12 × 12 patch on the object and one on the backdrop, over three denoised renders
    (seeds 1–3: the patch's own sampling noise at 32 spp, 0.1–0.6 ΔE00 in one render, is then ~0.6× that;
    a shift by the denoiser would stay): within ΔE00 0.3 of the reference's."""
    ref, den, _, mask, more = renders[case]
    mean = (den + more[0] + more[1]) / 3.0
    for inside in (True, False):
        y, x = _patch(mask, inside)
        a, b = (dc.lab(img[y:y + PATCH_PX, x:x + PATCH_PX].mean(axis=(0, 1))) for img in (mean, ref))
        de = float(colour.delta_E(a, b, method="CIE 2000"))
        print(f"{case} {'object' if inside else 'backdrop'} patch at {(y, x)}: ΔE00 {de:.3f}")
        assert de <= PATCH_MAX


def _edges(L: np.ndarray, mask: np.ndarray, reach: int = 3):
    """For each row crossing the silhouette: the column of the largest step of L* within ``reach`` px of the
    mask's edge, and that step; the same over columns (the image transposed)."""
    out = []
    for img, m in ((L, mask), (L.T, mask.T)):
        ys, xs = np.nonzero(m[:, 1:] != m[:, :-1])
        for y, x in zip(ys, xs, strict=True):
            lo, hi = max(x - reach, 0), min(x + reach + 1, img.shape[1] - 1)
            steps = np.abs(np.diff(img[y, lo:hi + 1]))
            out.append((lo + int(np.argmax(steps)), float(steps.max())))
    return np.array(out)


@pytest.mark.parametrize("case", [(s, f) for s, f, _ in dc.CASES], ids=CASE_IDS)
def test_silhouettes_stay_within_a_pixel_and_sharp(renders, case):
    """Where the reference steps by ≥ 8 L* across the silhouette, the denoised image steps at the same place
    (within a pixel) for ≥ 90 % of the crossings, by at least 70 % as much (median)."""
    ref, den, _, mask, _ = renders[case]
    e_ref, e_den = _edges(dc.lab(ref)[..., 0], mask), _edges(dc.lab(den)[..., 0], mask)
    strong = e_ref[:, 1] >= 8.0
    assert strong.sum() >= 20, "too few contrasted silhouette crossings to judge"
    within = np.abs(e_den[strong, 0] - e_ref[strong, 0]) <= 1
    sharp = float(np.median(e_den[strong, 1] / e_ref[strong, 1]))
    print(f"{case}: {strong.sum()} crossings, {within.mean():.0%} within a pixel, step ratio {sharp:.2f}")
    assert within.mean() >= 0.9
    assert sharp >= 0.7


def test_denoise_metadata_and_layers(renders, mi):
    """#37: the metadata says how the image was denoised; the raw estimate and the buffers come with it; a raw
    render says so."""
    from swatch.render.mitsuba.engine import render_swatch_mitsuba

    img = render_swatch_mitsuba(80.0, "sphere", dc.SIZE_PX, 4, 1, "studio")
    assert "Open Image Denoise" in img.metadata["denoise"] and "albedo" in img.metadata["denoise"]
    assert set(img.layers) == {"raw", "albedo", "normal"}
    assert all(v.shape == (dc.SIZE_PX, dc.SIZE_PX, 3) for v in img.layers.values())
    assert not np.array_equal(img.layers["raw"], img.linear_rgb)
    normal = img.layers["normal"]
    assert np.all(np.abs(normal) <= 1.0) and np.linalg.norm(normal[dc.SIZE_PX // 2, dc.SIZE_PX // 2]) > 0.95
    fast = render_swatch_mitsuba(80.0, "sphere", dc.SIZE_PX, 4, 1, "studio", denoise="balanced")
    assert "balanced quality" in fast.metadata["denoise"] and "high quality" in img.metadata["denoise"]
    np.testing.assert_array_equal(fast.layers["raw"], img.layers["raw"])
    from swatch.core.errors import SwatchError

    with pytest.raises(SwatchError, match="`denoise`"):
        render_swatch_mitsuba(80.0, "sphere", dc.SIZE_PX, 4, 1, "studio", denoise="best")
    raw = render_swatch_mitsuba(80.0, "sphere", dc.SIZE_PX, 4, 1, "studio", denoise=False)
    assert raw.metadata["denoise"].startswith("none") and raw.layers == {}
    np.testing.assert_array_equal(raw.linear_rgb, img.layers["raw"])


def test_film_albedo_is_its_directional_reflectance(mi):
    """The plugin's albedo (what the denoiser's buffer reads) is the Airy reflectance of the film at the
    incidence angle, against tmm (coh_tmm, s and p averaged) at one wavelength."""
    import drjit as dr

    from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, load_material
    from tests.mitsuba_setup import jit_float
    from tests.tmm_reference import unpolarised_R

    bsdf = mi.load_dict({"type": "anodic_film", "thickness_nm": 120.0, "alpha": 0.2})
    cos = np.array([1.0, 0.8, 0.5, 0.2])
    wl = np.array([450.0, 520.0, 600.0, 680.0])
    si = dr.zeros(mi.SurfaceInteraction3f, cos.size)
    si.wi = mi.Vector3f(jit_float(np.sqrt(1 - cos**2)), jit_float(0 * cos), jit_float(cos))
    si.wavelengths = mi.Spectrum(*(jit_float(np.full(cos.size, w)) for w in wl))
    got = np.asarray(bsdf.eval_diffuse_reflectance(si))  # (wavelength, direction)
    n_film, n_sub = load_material(DEFAULT_FILM).nk(wl), load_material(DEFAULT_SUBSTRATE).nk(wl)
    for j, c in enumerate(cos):
        want = unpolarised_R([1.0, n_film, n_sub], [np.inf, 120.0, np.inf], float(np.arccos(c)), wl)
        np.testing.assert_allclose(got[:, j], want, atol=3e-3)
