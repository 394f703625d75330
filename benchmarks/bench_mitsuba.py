"""``swatch render --engine mitsuba`` (Mitsuba 3, llvm_ad_spectral, the anodic_film plugin).

* ``mitsuba_sphere_512_s``: one 512 × 512 sphere in the studio at 256 spp, 80 nm (JIT kernels compiled
  by a small render of the same scene first; ``mitsuba_compile_s`` is that first render's time).
* ``mitsuba_bsdf_ratio``: the plugin's render time over Mitsuba's own ``roughconductor`` (Ti-Johnson's
  n, k) in the same scene (sphere, studio, 256², 64 spp) in the same run, each after a warm-up render.
"""
from __future__ import annotations

import time

from benchmarks.timing import pick


def _irregular(wl, values):
    keep = (wl > 300) & (wl < 900)
    return {"type": "irregular", "wavelengths": ", ".join(f"{x:.9g}" for x in wl[keep]),
            "values": ", ".join(f"{x:.9g}" for x in values[keep])}


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
    t0 = time.perf_counter()
    render_swatch_mitsuba(80.0, "sphere", pick(512, 16), pick(256, 1), lighting_name=studio)
    sphere_s = time.perf_counter() - t0

    s = load_material("Ti-Johnson")
    bsdfs = {"plugin": {"type": "anodic_film", "thickness_nm": 80.0, "alpha": 0.3},
             "roughconductor": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3,
                                "eta": _irregular(s.wavelength_nm, s.n), "k": _irregular(s.wavelength_nm, s.k)}}
    times = {}
    for name, bsdf in bsdfs.items():
        size, spp = pick(256, 16), pick(64, 1)
        render_swatch_mitsuba(80.0, "sphere", size, spp, lighting_name=studio, bsdf_override=bsdf)  # compile
        t0 = time.perf_counter()
        render_swatch_mitsuba(80.0, "sphere", size, spp, lighting_name=studio, bsdf_override=bsdf)
        times[name] = time.perf_counter() - t0
    return [f"mitsuba_compile_s={compile_s:.2f}", f"mitsuba_sphere_512_s={sphere_s:.2f}",
            f"mitsuba_plugin_256_64spp_s={times['plugin']:.2f} mitsuba_roughconductor_256_64spp_s="
            f"{times['roughconductor']:.2f}", f"mitsuba_bsdf_ratio={times['plugin'] / times['roughconductor']:.2f}"]
