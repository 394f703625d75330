"""``swatch render --engine mitsuba`` (Mitsuba 3, llvm_ad_spectral, the anodic_film plugin).

* ``mitsuba_sphere_512_s``: one 512 × 512 sphere in the studio at 256 spp, 80 nm, raw (JIT kernels compiled
  by a small render of the same scene first; ``mitsuba_compile_s`` is that first render's time).
* ``mitsuba_clean_512_s`` (#37): a 512 × 512 sphere in the studio at 16 spp, denoised (the spp at which the
  denoised studio sphere meets the accuracy of tests/mitsuba/test_mitsuba_denoise.py at 256 px and above:
  mean block ΔE00 0.48, p95 1.26 against 2048 spp at 256 px; the tests' 96 px need 32), kernels warm;
  median of 3.
* ``mitsuba_equal_error_ratio`` (#37): on a 256 px studio sphere (80 nm, α 0.3), the time the raw render
  needs to reach the mean block ΔE00 (4 × 4 px, D65, CIE 1931 2°) of the denoised 16 spp render against a
  2048 spp reference (two 1024 spp renders of other seeds, averaged: one render is at most
  ``MAX_MITSUBA_SAMPLES``), over the denoised render's time (raw spp 16 … 1024, error and time interpolated in
  log-log between the two that bracket it, past 1024 along error ∝ spp^-1/2); ``mitsuba_denoised_dE00`` is
  that error.
  ``mitsuba_equal_error_ratio_px`` and ``mitsuba_denoised_dE00_px``: the same with the error of each pixel
  (the grain a viewer sees; the measure of equal-error comparisons of denoisers). The reference's own noise
  adds to both errors alike, so it hardly moves the ratio: against an 8192 spp reference the per-pixel
  ratio was 46.4, against 2048 spp 45.7 (the block ratio 3.50 and 3.58).
* ``mitsuba_bsdf_ratio``: the plugin's render time over Mitsuba's own ``roughconductor`` (Ti-Johnson's
  n, k) in the same scene (sphere, studio, 256², 64 spp, raw) in the same run, each after a warm-up render.
"""
from __future__ import annotations

import itertools
import math
import time

import numpy as np

from benchmarks.timing import pick


def _irregular(wl, values):
    keep = (wl > 300) & (wl < 900)
    return {"type": "irregular", "wavelengths": ", ".join(f"{x:.9g}" for x in wl[keep]),
            "values": ", ".join(f"{x:.9g}" for x in values[keep])}


def _timed(fn, repeat: int = 1):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, float(np.median(times))


def _block_dE00(a, b, block: int = 4) -> float:
    """Mean CIEDE2000 between the ``block`` × ``block`` px means of two linear sRGB images (1: per pixel)."""
    import colour

    cs = colour.RGB_COLOURSPACES["sRGB"]

    def lab(rgb):
        h, w, _ = rgb.shape
        m = rgb[:h // block * block, :w // block * block].reshape(h // block, block, w // block, block, 3)
        XYZ = colour.RGB_to_XYZ(m.mean(axis=(1, 3)).astype(np.float64), cs, apply_cctf_decoding=False)
        return colour.XYZ_to_Lab(XYZ, cs.whitepoint)

    return float(np.mean(colour.delta_E(lab(a), lab(b), method="CIE 2000")))


def _time_to_error(points: list[tuple[int, float, float]], target: float) -> float:
    """The raw render's time at error ``target`` from (spp, error, time) points of rising spp: log-log
    interpolation between the two that bracket it, or past the last along error ∝ spp^-1/2."""
    if points[0][1] <= target:
        return points[0][2]
    for (_, e0, t0), (_, e1, t1) in itertools.pairwise(points):
        if e1 <= target:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    _, e1, t1 = points[-1]
    return t1 * (e1 / target) ** 2


def equal_error_ratio(size: int = 256, spp: int = 16) -> dict[int, tuple[float, float]]:
    """Block size (4, 1) -> (ratio, denoised error): see the module documentation."""
    from swatch.core.limits import MAX_PASS_SPP
    from swatch.render.mitsuba.engine import mitsuba_lighting, render_swatch_mitsuba

    studio = mitsuba_lighting("studio")

    def render(n, denoise, seed=1):
        return render_swatch_mitsuba(80.0, "sphere", size, n, seed, studio, roughness_alpha=0.3, denoise=denoise)

    # the 2048 spp reference as two 1024 spp renders of other seeds, averaged (a render is at most MAX_MITSUBA_SAMPLES)
    ref = 0.5 * (render(pick(1024, 16), False, seed=77).linear_rgb + render(pick(1024, 16), False, seed=78).linear_rgb)
    render(spp, True)  # kernels
    den, t_den = _timed(lambda: render(spp, True), pick(3, 1))
    blocks = (4, 1)
    e_den = {b: _block_dE00(den.linear_rgb, ref, b) for b in blocks}
    points: dict[int, list[tuple[int, float, float]]] = {b: [] for b in blocks}
    for n in pick((16, 32, 64, 128, 256, 512, 1024), (4, 16)):  # (past 1024: extrapolated, error ∝ spp^-1/2)
        if n <= MAX_PASS_SPP:
            render(n, False)  # kernels of this pass size (larger spp: passes of MAX_PASS_SPP, compiled)
        img, t = _timed(lambda n=n: render(n, False))
        for b in blocks:
            points[b].append((n, _block_dE00(img.linear_rgb, ref, b), t))
        if all(points[b][-1][1] <= e_den[b] for b in blocks):
            break
    return {b: (_time_to_error(points[b], e_den[b]) / t_den, e_den[b]) for b in blocks}


def run() -> list[str]:
    from swatch.core.errors import SwatchError
    from swatch.physics.materials import load_material

    try:  # Mitsuba's LLVM variant needs a system libLLVM: without one the section says so and the bench goes on
        from swatch.render.mitsuba.engine import mitsuba_lighting, render_swatch_mitsuba

        studio = mitsuba_lighting("studio")
    except (ImportError, OSError, RuntimeError, SwatchError) as exc:
        return [f"mitsuba: skipped ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"]
    t0 = time.perf_counter()
    render_swatch_mitsuba(80.0, "sphere", pick(64, 16), pick(4, 1), lighting_name=studio)
    compile_s = time.perf_counter() - t0
    big, spp_raw = pick(512, 16), pick(256, 1)
    render_swatch_mitsuba(80.0, "sphere", big, pick(64, 1), lighting_name=studio, denoise=False)  # kernels of 512²
    _, sphere_s = _timed(lambda: render_swatch_mitsuba(80.0, "sphere", big, spp_raw, lighting_name=studio,
                                                        denoise=False))
    render_swatch_mitsuba(80.0, "sphere", big, pick(16, 1), lighting_name=studio)  # kernels of 512² in passes of 16
    _, clean_s = _timed(lambda: render_swatch_mitsuba(80.0, "sphere", big, pick(16, 1), lighting_name=studio),
                        pick(3, 1))
    ratios = equal_error_ratio(pick(256, 16), pick(16, 4))

    s = load_material("Ti-Johnson")
    bsdfs = {"plugin": {"type": "anodic_film", "thickness_nm": 80.0, "alpha": 0.3},
             "roughconductor": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3,
                                "eta": _irregular(s.wavelength_nm, s.n), "k": _irregular(s.wavelength_nm, s.k)}}
    times = {}
    for name, bsdf in bsdfs.items():
        size, spp = pick(256, 16), pick(64, 1)
        render_swatch_mitsuba(80.0, "sphere", size, spp, lighting_name=studio, bsdf_override=bsdf, denoise=False)
        _, times[name] = _timed(lambda bsdf=bsdf, size=size, spp=spp: render_swatch_mitsuba(
            80.0, "sphere", size, spp, lighting_name=studio, bsdf_override=bsdf, denoise=False))
    return [f"mitsuba_compile_s={compile_s:.2f}", f"mitsuba_sphere_512_s={sphere_s:.2f}",
            f"mitsuba_clean_512_s={clean_s:.2f}",
            f"mitsuba_equal_error_ratio={ratios[4][0]:.2f} mitsuba_denoised_dE00={ratios[4][1]:.2f}",
            f"mitsuba_equal_error_ratio_px={ratios[1][0]:.2f} mitsuba_denoised_dE00_px={ratios[1][1]:.2f}",
            f"mitsuba_plugin_256_64spp_s={times['plugin']:.2f} mitsuba_roughconductor_256_64spp_s="
            f"{times['roughconductor']:.2f}", f"mitsuba_bsdf_ratio={times['plugin'] / times['roughconductor']:.2f}"]
