"""``--device`` of the Mitsuba engine (#50 part 3): ``cpu`` (llvm_ad_spectral, OIDN on the CPU) or ``cuda``
(cuda_ad_spectral, OIDN's CUDA device). The CPU machines of the tests have no CUDA: there ``--device cuda`` is
refused in one line, exit 2, nothing written; where Dr.Jit and OIDN do find a CUDA device the same tests render
on it instead. The GPU path's denoiser call (the binding's ``denoise``, which copies host images to the device)
is checked on OIDN's CPU device against the CPU path's own filter: the same bytes.
"""
from __future__ import annotations

import functools
import time

import numpy as np
import pytest

from swatch.core.choices import DEVICES
from swatch.core.errors import SwatchError
from swatch.render.checks import check_device
from swatch.render.request import render_request
from tests.cli_helpers import run_swatch, run_swatch_process
from tests.mitsuba_setup import mitsuba_variant


@functools.lru_cache(maxsize=1)
def _cuda_here() -> bool:
    """Whether both Dr.Jit and OIDN find a CUDA device (their own answers, not ours)."""
    mitsuba_variant()  # (skips without libLLVM; loads Dr.Jit and OIDN the tests' way)
    import drjit as dr
    import mitsuba_oidn as oidn

    return bool(dr.has_backend(dr.JitBackend.CUDA)) and any(
        p.type == oidn.DeviceType.CUDA for p in oidn.physical_devices())


@pytest.mark.parametrize("given, device, variant", [
    ((None, None), "cpu", "llvm_ad_spectral"),
    (("cpu", None), "cpu", "llvm_ad_spectral"),
    ((" CUDA ", None), "cuda", "cuda_ad_spectral"),
    (("Cpu", "scalar_spectral"), "cpu", "scalar_spectral"),
    ((None, "cuda_ad_spectral"), "cuda", "cuda_ad_spectral"),
])
def test_a_device_names_its_variant_and_a_variant_its_device(given, device, variant):
    assert check_device(*given) == (device, variant)
    request = render_request(80.0, "sphere", 32, engine="mitsuba", spp=4,
                             **{k: v for k, v in zip(("device", "variant"), given, strict=True) if v is not None})
    assert (request.device, request.variant) == (device, variant)


@pytest.mark.parametrize("device, variant", [("cuda", "llvm_ad_spectral"), ("cuda", "scalar_spectral"),
                                             ("cpu", "cuda_ad_spectral")])
def test_a_variant_of_the_other_device_is_refused(device, variant):
    with pytest.raises(SwatchError, match=rf"'{variant}' renders on the .*not on `device='{device}'`"):
        render_request(80.0, "sphere", 32, engine="mitsuba", device=device, variant=variant)


def test_an_unknown_device_is_refused_with_the_choices():
    with pytest.raises(SwatchError, match=r"unknown render device 'gpu' for `device`; use one of cpu, cuda"):
        render_request(80.0, "sphere", 32, engine="mitsuba", device="gpu")
    assert DEVICES.names() == ("cpu", "cuda")


@pytest.mark.parametrize("device", ["cpu", "cuda"])
def test_the_builtin_engine_refuses_a_device(device, tmp_path):
    """It renders with NumPy on the CPU whatever is given: the option would change nothing (as ``spp``)."""
    with pytest.raises(SwatchError, match=r"^`device` is an option of the mitsuba engine; add `engine='mitsuba'`$"):
        render_request(80.0, "flat", 32, device=device)
    proc = run_swatch("render", "--thickness", "80", "--size", "32", "--device", device, "--out", tmp_path / "o")
    assert proc.returncode == 2 and proc.stderr == "error: --device is an option of the mitsuba engine; add --engine mitsuba\n"
    assert not (tmp_path / "o").exists()


def _render(out, *extra):
    return run_swatch("render", "--engine", "mitsuba", "--shape", "sphere", "--thickness", "80", "--size", "32",
                      "--spp", "4", "--out", out, *extra)


@pytest.mark.slow
def test_device_cpu_is_the_default_byte_for_byte(tmp_path):
    assert _render(tmp_path / "a").returncode == 0
    assert _render(tmp_path / "b", "--device", "CPU").returncode == 0
    for name in ("sphere_080.0nm.exr", "sphere_080.0nm.png"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


@pytest.mark.slow
def test_device_cuda_is_refused_in_one_line_where_there_is_no_cuda(tmp_path):
    if _cuda_here():
        pytest.skip("this machine has CUDA: test_device_cuda_renders_where_there_is_cuda runs instead")
    t0 = time.perf_counter()
    proc = run_swatch_process("render", "--engine", "mitsuba", "--device", "Cuda", "--thickness", "80",
                              "--size", "32", "--spp", "4", "--out", tmp_path / "o")
    wall_s = time.perf_counter() - t0
    assert proc.returncode == 2, proc.stderr  # (an aborted interpreter exits 134 or by a signal)
    assert proc.stdout == "" and len(proc.stderr.splitlines()) == 1, proc.stderr
    assert proc.stderr.startswith("error: --device cuda: Dr.Jit finds no CUDA GPU here")
    assert "or use --device cpu" in proc.stderr
    assert not (tmp_path / "o").exists()
    assert wall_s < 60  # interpreter start and Mitsuba's import; nothing is rendered (~1.5 s on an idle core)


@pytest.mark.slow
def test_use_variant_cuda_raises_rather_than_aborting():
    if _cuda_here():
        pytest.skip("this machine has CUDA")
    from swatch.render.mitsuba.engine import device_unavailable, use_variant

    with pytest.raises(SwatchError, match=r"^`device='cuda'`: Dr.Jit finds no CUDA GPU here"):
        use_variant("cuda_ad_spectral")
    assert device_unavailable("cuda", denoise=False) is not None and device_unavailable("cpu") is None
    mitsuba_variant()  # the CPU variant still renders in this process


@pytest.mark.slow
def test_oidn_without_cuda_says_what_it_sees(monkeypatch):
    from swatch.render.mitsuba import denoise, engine

    if _cuda_here():
        assert denoise.device_unavailable("cuda") is None
        return
    import mitsuba_oidn as oidn

    if any(p.type == oidn.DeviceType.CUDA for p in oidn.physical_devices()):
        pytest.skip("OIDN has a CUDA device here (Dr.Jit has none)")
    why = denoise.device_unavailable("cuda")
    assert why is not None and why.startswith("`device='cuda'`: Intel Open Image Denoise finds no CUDA device")
    assert "CPU" in why and "`denoise=False`" in why and denoise.device_unavailable("cpu") is None
    # a GPU that Dr.Jit sees and OIDN does not: a denoised render is refused with OIDN's line, a raw one is not
    monkeypatch.setattr(engine.dr, "has_backend", lambda backend: True)
    assert engine.device_unavailable("cuda", denoise=True) == why
    assert engine.device_unavailable("cuda", denoise=False) is None


@pytest.mark.slow
@pytest.mark.parametrize("quality", ["high", "balanced"])
def test_the_gpu_paths_denoiser_call_is_the_cpu_paths_filter(quality):
    """The ``cuda`` device's call (the binding's ``denoise``: images copied to a device buffer and back) run on
    OIDN's CPU device gives the bytes of the CPU path's own filter: the same inputs, HDR, clean auxiliaries and
    quality reach OIDN."""
    mitsuba_variant()
    import mitsuba_oidn as oidn

    from swatch.render.mitsuba import denoise

    rng = np.random.default_rng(7)
    colour_ = (rng.random((40, 48, 3)) * np.linspace(0.2, 1.5, 48)[None, :, None]).astype(np.float32)
    albedo = (0.5 + 0.1 * rng.random((40, 48, 3))).astype(np.float32)
    normal = np.zeros((40, 48, 3), dtype=np.float32)
    normal[..., 1] = 1.0
    cpu_path = denoise.denoise_rgb(colour_, albedo, normal, quality)
    grey = np.ascontiguousarray(np.repeat(albedo @ denoise._REC709_Y, 3).reshape(albedo.shape), dtype=np.float32)
    staged = np.maximum(denoise._run_staged(oidn.Device(oidn.DeviceType.CPU),
                                            {"color": colour_, "albedo": grey, "normal": normal},
                                            denoise.QUALITIES[quality], True), 0.0)
    assert staged.dtype == np.float32 and staged.shape == colour_.shape
    assert np.array_equal(staged, cpu_path)
    assert np.abs(cpu_path - colour_).max() > 0.1  # (it denoised)


@pytest.mark.slow
def test_device_cuda_renders_where_there_is_cuda(tmp_path):
    if not _cuda_here():
        pytest.skip("no CUDA here (Dr.Jit or OIDN): test_device_cuda_is_refused_in_one_line_where_there_is_no_cuda")
    from swatch.io import imageio

    for out in ("a", "b"):
        proc = _render(tmp_path / out, "--device", "cuda")
        assert proc.returncode == 0, proc.stderr
    exr = tmp_path / "a" / "sphere_080.0nm.exr"
    assert exr.read_bytes() == (tmp_path / "b" / "sphere_080.0nm.exr").read_bytes()
    meta = imageio.read_metadata(exr)
    assert "cuda_ad_spectral" in str(meta["engine"]) and "on its CUDA device" in str(meta["denoise"])
