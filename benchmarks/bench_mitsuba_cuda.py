"""The Mitsuba engine on an NVIDIA GPU (``device="cuda"``: cuda_ad_spectral, OIDN's CUDA device), beside the CPU
(``device="cpu"``) in the same run on the same machine. Where Dr.Jit or OIDN finds no CUDA device the section
prints one line, ``cuda: not available here (<why>)``, and no figure. Run it alone on a GPU machine:
``python -m benchmarks.bench mitsuba_cuda`` (docs/performance.md).

* ``cuda_hero_s`` / ``cpu_hero_s``: one catalog hero (sphere, studio, 80 nm, α 0.3, ``HERO_SIZE_PX``²,
  ``HERO_SPP`` spp, denoised at ``HERO_DENOISE`` quality), kernels warm, median of 3.
* ``cuda_clean_512_s`` / ``cpu_clean_512_s``: a 512² studio sphere at 16 spp, denoised (``high``), kernels warm,
  median of 3 (``mitsuba_clean_512_s`` of the mitsuba section).
* ``cuda_sphere_512_s`` / ``cpu_sphere_512_s``: a 512² studio sphere at 256 spp, raw, kernels warm
  (``mitsuba_sphere_512_s``).
* ``cuda_compile_s``: the first CUDA render's time (a 64² sphere at 4 spp: Mitsuba's kernels for the GPU).
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks.timing import pick


def _median_s(fn, repeat: int) -> float:
    fn()  # kernels of this size and pass size
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _figures(render, device: str) -> list[str]:
    from swatch.catalog.hero import HERO_DENOISE, HERO_SIZE_PX, HERO_SPP

    big, repeat = pick(512, 16), pick(3, 1)
    hero = _median_s(lambda: render(pick(HERO_SIZE_PX, 16), pick(HERO_SPP, 1), HERO_DENOISE, device), repeat)
    clean = _median_s(lambda: render(big, pick(16, 1), "high", device), repeat)
    raw = _median_s(lambda: render(big, pick(256, 1), False, device), 1)
    return [f"{device}_hero_s={hero:.3f} {device}_clean_512_s={clean:.3f} {device}_sphere_512_s={raw:.3f}"]


def run() -> list[str]:
    from swatch.core.errors import SwatchError
    from swatch.core.procguard import signals_held

    try:
        with signals_held():  # (nanobind modules load here: docs/DEVNOTES.md)
            from swatch.render.mitsuba.engine import device_unavailable, mitsuba_lighting, render_swatch_mitsuba
        why = device_unavailable("cuda")
    except (ImportError, OSError, RuntimeError, SwatchError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    if why is not None:
        return [f"cuda: not available here ({why})"]
    import mitsuba_oidn as oidn

    studio = mitsuba_lighting("studio")

    def render(size: int, spp: int, denoise, device: str):
        return render_swatch_mitsuba(80.0, "sphere", size, spp, lighting_name=studio, roughness_alpha=0.3,
                                     denoise=denoise, device=device)

    gpu = next(p.name for p in oidn.physical_devices() if p.type == oidn.DeviceType.CUDA)
    t0 = time.perf_counter()
    render(pick(64, 16), pick(4, 1), False, "cuda")
    lines = [f"cuda_device: {gpu}", f"cuda_compile_s={time.perf_counter() - t0:.2f}", *_figures(render, "cuda")]
    try:
        lines += _figures(render, "cpu")
    except SwatchError as exc:  # (no libLLVM for the CPU variant)
        lines.append(f"cpu: not available here ({exc})")
    return lines
