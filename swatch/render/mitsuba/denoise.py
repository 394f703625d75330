"""Denoising the Mitsuba engine's renders with Intel Open Image Denoise (issue 37).

A path-traced swatch at a few dozen samples per pixel is grainy; Intel Open Image Denoise (OIDN, its
``RT`` filter: a neural network trained on path-traced images) turns it into a clean picture for a
fraction of the render's time. It is guided by two buffers of the same scene and camera, rendered after
the image by Mitsuba's ``aov`` integrator alone (:func:`render_buffers`: first hits only, :data:`BUFFER_SPP` samples per pixel, ~2 %
of a 32-sample render; wrapping the path tracer in the ``aov`` integrator instead cost 1.6–2.5× the
render): the **albedo** of the first surface a camera ray meets (the ``anodic_film`` plugin reports its
film's directional reflectance colour, ``AnodicFilmBSDF.eval_diffuse_reflectance``; the studio's
cyclorama its diffuse albedo) and its shading **normal** (world space). With them the denoiser keeps
silhouettes, the film's colour boundaries, a mesh's creases and a brushed finish's hairlines, which
colour alone blurs. Both buffers are averaged over the pixel's samples (anti-aliased) and carry a little
spectral sampling noise in the albedo's colour (a spectral estimate of sRGB); the denoiser reads the
albedo's luminance, nearly free of it, and the normal (geometry) has none, so both are passed as clean
(``clean_aux = True``). Measured on the test cases: as good as OIDN's "best" mode (each buffer denoised
by OIDN first, then clean: block ΔE00 within 0.01) at a third of its time, and 5–15 % lower block error
and sharper silhouettes than passing them as noisy.

The denoiser is run through ``mitsuba-oidn`` (OIDN on Dr.Jit's own thread pool: the renderer and the
denoiser share the same threads instead of oversubscribing the cores; NumPy arrays in, NumPy arrays
out). On the ``cuda`` device (:data:`swatch.core.choices.DEVICES`) it runs on OIDN's CUDA device: the images are
copied to the GPU and back by the binding's ``denoise`` (:func:`device_unavailable` says when OIDN has none).
The tests (tests/mitsuba/test_mitsuba_denoise.py) check the denoised image against an undenoised
render of many samples: it must not move colour.
"""
from __future__ import annotations

import functools
import importlib.metadata

import mitsuba as mi
import mitsuba_oidn as oidn
import numpy as np

from swatch.core.choices import DENOISE_QUALITIES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_DENOISE_MEMORY_MB

__all__ = ["BUFFER_SPP", "QUALITIES", "render_buffers", "denoise_rgb", "describe", "oidn_version", "device_unavailable"]

#: Samples per pixel of the buffers (a power of 4, as the low-discrepancy sampler wants).
BUFFER_SPP = 16
#: OIDN's names of the filter qualities of :data:`swatch.core.choices.DENOISE_QUALITIES`.
QUALITIES = {q: q.capitalize() for q in DENOISE_QUALITIES}
#: Rec. 709 / sRGB luminance weights: the denoiser is guided by the albedo's luminance (see denoise_rgb).
_REC709_Y = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
_BUFFERS = {"type": "aov", "aovs": "albedo:albedo,normal:sh_normal"}


def render_buffers(scene, width: int, height: int, seed: int, max_lanes: int) -> tuple[np.ndarray, np.ndarray]:
    """The albedo and normal buffers of ``scene`` seen by its camera: Mitsuba's ``aov`` integrator alone,
    :data:`BUFFER_SPP` samples per pixel in passes of at most ``max_lanes`` samples.

    Parameters
    ----------
    scene : mitsuba.Scene
        The loaded scene of the render (its sensor and film).
    width, height : int
        The film's (crop window's) size in pixels.
    seed : int
        The render's seed (the same seed gives the same buffers).
    max_lanes : int
        Samples per pass at most (:data:`swatch.core.limits.MAX_PASS_LANES`).

    Returns
    -------
    albedo, normal : numpy.ndarray
        (H, W, 3) float32: albedo in [0, 1] (linear sRGB), the pixel's mean world-space normal in
        [-1, 1] (shorter than 1 on an edge, 0 where nothing was hit).
    """
    integrator = mi.load_dict(_BUFFERS)
    per = BUFFER_SPP
    while per > 1 and width * height * per > max_lanes:
        per //= 4
    passes = BUFFER_SPP // per
    acc = np.zeros((height, width, 6), dtype=np.float64 if passes > 1 else np.float32)
    for i in range(passes):
        pass_seed = int((seed * 7919 + 31 * i + 5) % 2**32)
        out = np.asarray(mi.render(scene, integrator=integrator, seed=pass_seed, spp=per))  # type: ignore[arg-type]
        if out.ndim != 3 or out.shape[2] < 6:
            raise SwatchError(f"the denoiser's buffers came back with shape {out.shape}")
        acc += out[..., -6:]
        del out
    acc /= passes
    return (np.clip(acc[..., :3], 0.0, 1.0).astype(np.float32), np.clip(acc[..., 3:], -1.0, 1.0).astype(np.float32))


def denoise_rgb(rgb: np.ndarray, albedo: np.ndarray | None = None, normal: np.ndarray | None = None,
                quality: str = "high", device: str = "cpu") -> np.ndarray:
    """OIDN's ``RT`` filter (HDR input) on a linear image, guided by the buffers (as
    clean auxiliaries: module documentation). The albedo guides by its luminance (grey): with the
    film's saturated colour as albedo OIDN shifted a yellow plate's colour by ΔE00 0.25 (Δa* −0.4, Δb*
    +0.35, mean of 4 seeds against the raw estimate), with its luminance by 0.08, and the block error fell
    too (0.400 → 0.385); edges and hairlines are in the luminance.

    Parameters
    ----------
    rgb : numpy.ndarray
        (H, W, 3) scene-referred linear RGB (≥ 0; any scale: OIDN measures the exposure itself).
    albedo, normal : numpy.ndarray, optional
        (H, W, 3) buffers of the same render (:func:`render_buffers`); albedo needs normal (OIDN's rule:
        normal is used only with albedo).
    quality : str
        OIDN's filter quality (:data:`QUALITIES`).
    device : str
        ``cpu`` or ``cuda``: OIDN's device (:data:`swatch.core.choices.DEVICES`; ``cuda``: see
        :func:`device_unavailable`).

    Returns
    -------
    numpy.ndarray
        (H, W, 3) float32, the denoised image (same units).

    Raises
    ------
    SwatchError
        When the buffers do not match the image.
    """
    color = np.ascontiguousarray(np.maximum(np.nan_to_num(rgb, nan=0.0, posinf=0.0), 0.0), dtype=np.float32)
    aux: list[np.ndarray | None] = []
    for name, buf in (("albedo", albedo), ("normal", normal)):
        if buf is not None:
            if buf.shape != color.shape:
                raise SwatchError(f"the {name} buffer is {buf.shape}, the image {color.shape}")
            aux.append(np.ascontiguousarray(buf, dtype=np.float32))
        else:
            aux.append(None)
    if aux[1] is not None and aux[0] is None:
        raise SwatchError("the denoiser takes a normal buffer only with an albedo buffer")
    images = {"color": color}
    if aux[0] is not None:
        grey = np.ascontiguousarray(np.repeat(aux[0] @ _REC709_Y, 3).reshape(aux[0].shape), dtype=np.float32)
        images["albedo"] = grey
        if aux[1] is not None:
            images["normal"] = aux[1]
    clean_aux = aux[0] is not None
    if device == "cpu":
        return np.maximum(_run(images, QUALITIES[quality], clean_aux=clean_aux), 0.0)
    return np.maximum(_run_staged(_device(device), images, QUALITIES[quality], clean_aux), 0.0)


@functools.lru_cache(maxsize=2)
def _device(kind: str = "cpu"):
    """The OIDN device of ``kind`` (``cpu``: the CPU, named: OIDN's default is the fastest device it finds, a GPU
    where there is one; ``cuda``: CUDA device 0, Dr.Jit's default), made once."""
    device = oidn.Device(oidn.DeviceType.CPU) if kind == "cpu" else oidn.Device.cuda(0)
    device.commit()
    return device


def device_unavailable(device: str) -> str | None:
    """Why OIDN cannot denoise on ``device`` here (one line), or None when it can.

    Parameters
    ----------
    device : str
        ``cpu`` or ``cuda`` (:data:`swatch.core.choices.DEVICES`).

    Returns
    -------
    str or None
        For ``cuda`` without a CUDA device among OIDN's physical devices: what it found and what to do.
    """
    if device == "cpu":
        return None
    found = oidn.physical_devices()
    if any(p.type == oidn.DeviceType.CUDA for p in found):
        return None
    seen = ", ".join(f"{p.type.name} {p.name}" for p in found) or "none"
    return (f"`device='cuda'`: Intel Open Image Denoise finds no CUDA device (it sees: {seen}); render on a machine "
            "with an NVIDIA GPU and driver, or give `denoise=False`")


def _run_staged(device, images: dict[str, np.ndarray], quality: str, clean_aux: bool) -> np.ndarray:
    """One OIDN ``RT`` filter (HDR) on ``device`` through the binding's ``denoise``, which copies host arrays to a
    device that cannot read them (a GPU's) and the result back (its filters kept per device, inputs and size)."""
    out = oidn.denoise(images["color"], images.get("albedo"), images.get("normal"), hdr=True, clean_aux=clean_aux,
                       quality=getattr(oidn.Quality, quality), device=device)
    return np.asarray(out, dtype=np.float32)


def _run(images: dict[str, np.ndarray], quality: str, clean_aux: bool = False) -> np.ndarray:
    """One OIDN ``RT`` filter on the CPU device (high quality; HDR when it filters a colour image). Filters are
    kept per set of inputs and image size: committing a new one (its network) took ~0.7 s, running it 0.02 s."""
    first = next(iter(images.values()))
    flt = _filter(tuple(images), first.shape[0], first.shape[1], quality, clean_aux)
    for name, img in images.items():
        flt.set_image(name, img)
    out = np.empty_like(first)
    flt.set_image("output", out)
    flt.execute()
    return out


@functools.lru_cache(maxsize=8)
def _filter(names: tuple[str, ...], height: int, width: int, quality: str, clean_aux: bool):
    """An OIDN ``RT`` filter for inputs ``names`` of one image size (its settings made once)."""
    flt = _device().new_filter("RT")
    if "color" in names:
        flt.hdr = True
        flt.clean_aux = clean_aux
    flt.quality = getattr(oidn.Quality, quality)
    flt.max_memory_mb = MAX_DENOISE_MEMORY_MB  # larger images are filtered in tiles (the same bytes for one that fits)
    return flt


def oidn_version() -> str:
    """``"OIDN <version>, mitsuba-oidn <version>"`` (the denoiser and its binding).

    Returns
    -------
    str
        The denoiser's and the binding's versions, for the image metadata.
    """
    return f"Intel Open Image Denoise {oidn.oidn_version()}, mitsuba-oidn {importlib.metadata.version('mitsuba-oidn')}"


def describe(quality: str | None, device: str = "cpu") -> str:
    """The metadata's ``denoise`` entry: whether and how the image was denoised.

    Parameters
    ----------
    quality : str or None
        The request's ``denoise`` (:func:`swatch.render.checks.check_denoise`; None: not denoised).
    device : str
        ``cpu`` or ``cuda``: where OIDN ran (said for ``cuda`` alone).

    Returns
    -------
    str
        ``"none (raw path-traced estimate)"``, or the filter, quality, versions and guide buffers in words.
    """
    if quality is None:
        return "none (raw path-traced estimate)"
    where = "" if device == "cpu" else f" on its {device.upper()} device"
    return (f"{oidn_version()}: RT filter{where}, {quality} quality, HDR input, guided by the first hit's "
            "albedo (film: its directional reflectance colour) and shading normal of the same scene and camera "
            f"(Mitsuba aov integrator, {BUFFER_SPP} spp; albedo as luminance; clean auxiliaries)")

