"""Checks of a path-traced render's sampling options (size, samples per pixel, seed, film window, display
exposure): plain arithmetic on :mod:`swatch.core.limits`, made by :func:`swatch.render.request.render_request`
before Mitsuba is loaded.
"""
from __future__ import annotations

import math

from swatch.core.choices import DEFAULT_VARIANT, DENOISE_QUALITIES, DEVICES, SPECTRAL_VARIANTS
from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_DENOISE_PX,
    MAX_DISPLAY_EXPOSURE,
    MAX_MITSUBA_PX,
    MAX_MITSUBA_SAMPLES,
    MAX_SEED,
    MAX_SPP,
)

__all__ = ["check_spp", "check_seed", "check_mitsuba_request", "check_window_px", "check_exposure", "check_variant",
           "check_denoise", "check_denoise_size", "variant_device", "check_device"]


def _whole_number(value, what: str, low: int, high: int) -> int:
    """``value`` as an int when it is a whole number from ``low`` to ``high``; else a SwatchError."""
    try:
        ok = float(value) == int(value)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not low <= int(value) <= high:
        raise SwatchError(f"{what} must be a whole number from {low} to {high}, got {value!r}")
    return int(value)


def check_spp(spp) -> int:
    """Samples per pixel, checked: a whole number from 1 to ``MAX_SPP``.

    Parameters
    ----------
    spp : int
        Samples per pixel of a Mitsuba render.

    Returns
    -------
    int
        ``spp`` as an int.

    Raises
    ------
    SwatchError
        Otherwise.
    """
    return _whole_number(spp, "samples per pixel", 1, MAX_SPP)


def check_seed(seed) -> int:
    """The sampler's seed, checked: a whole number from 0 to ``MAX_SEED``.

    Parameters
    ----------
    seed : int
        The Mitsuba sampler's seed (equal seeds give equal images).

    Returns
    -------
    int
        ``seed`` as an int.

    Raises
    ------
    SwatchError
        Otherwise.
    """
    return _whole_number(seed, "seed", 0, MAX_SEED)


def check_mitsuba_request(size_px, spp, seed) -> tuple[int, int, int]:
    """A Mitsuba render's size, samples and seed, checked before anything is loaded.

    Parameters
    ----------
    size_px : int
        Pixels per side, at most :data:`swatch.core.limits.MAX_MITSUBA_PX`.
    spp : int
        Samples per pixel (:func:`check_spp`).
    seed : int
        The sampler's seed (:func:`check_seed`).

    Returns
    -------
    tuple of int
        ``(size, spp, seed)``.

    Raises
    ------
    SwatchError
        One line, for a value out of range or size² × spp above ``MAX_MITSUBA_SAMPLES``.
    """
    try:
        size = int(size_px)
        ok = float(size_px) == size and 1 <= size <= MAX_MITSUBA_PX
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise SwatchError(f"image size must be a whole number of pixels from 1 to {MAX_MITSUBA_PX}, got {size_px!r}")
    spp = check_spp(spp)
    seed = check_seed(seed)
    if size * size * spp > MAX_MITSUBA_SAMPLES:
        raise SwatchError(f"{size}x{size} at {spp} spp is {size * size * spp:.3g} samples; a Mitsuba render is at "
                          f"most {MAX_MITSUBA_SAMPLES:.3g} (lower `spp` or `size_px`)")
    return size, spp, seed


def check_window_px(window_px, size: int) -> tuple[int, int, int, int] | None:
    """A film window, checked: four whole numbers inside the ``size``² image, or None.

    Parameters
    ----------
    window_px : (int, int, int, int) or None
        ``(x, y, width, height)`` in pixels from the image's top-left corner.
    size : int
        The image's side, pixels.

    Returns
    -------
    tuple of int or None
        The window as ints.

    Raises
    ------
    SwatchError
        Not four whole numbers with the window inside the image (naming ```window_px```).
    """
    if window_px is None:
        return None
    try:
        x, y, w, h = (int(v) for v in window_px)
        ok = [float(v) for v in window_px] == [x, y, w, h] and x >= 0 and y >= 0 and w >= 1 and h >= 1
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or x + w > size or y + h > size:
        raise SwatchError(f"window_px must be (x, y, width, height) in whole pixels inside the {size}x{size} "
                          f"image, got {window_px!r}")
    return x, y, w, h


def check_exposure(exposure) -> float:
    """A display exposure, checked: a finite factor from 1/``MAX_DISPLAY_EXPOSURE`` to ``MAX_DISPLAY_EXPOSURE``.

    Parameters
    ----------
    exposure : float
        Factor on the linear image before display encoding (1: the white diffuser is display white).

    Returns
    -------
    float
        ``exposure`` as a float.

    Raises
    ------
    SwatchError
        Out of range.
    """
    k = float(exposure)
    if not (math.isfinite(k) and 1.0 / MAX_DISPLAY_EXPOSURE <= k <= MAX_DISPLAY_EXPOSURE):
        raise SwatchError(f"display exposure must be from {1.0 / MAX_DISPLAY_EXPOSURE:g} to "
                          f"{MAX_DISPLAY_EXPOSURE:g}, got {exposure!r}")
    return k


def check_variant(variant: str) -> str:
    """A Mitsuba variant the plugin can run in (a spectral one).

    Parameters
    ----------
    variant : str
        A Mitsuba variant name (:data:`swatch.core.choices.SPECTRAL_VARIANTS`).

    Returns
    -------
    str
        ``variant`` (stripped).

    Raises
    ------
    SwatchError
        Naming the choices, for another variant.
    """
    key = str(variant).strip()
    if key not in SPECTRAL_VARIANTS:
        raise SwatchError(f"Mitsuba variant {variant!r} is not supported; the thin-film plugin needs a spectral "
                          f"variant: {', '.join(SPECTRAL_VARIANTS)}")
    return key


def variant_device(variant: str) -> str:
    """The device (:data:`swatch.core.choices.DEVICES`) a spectral variant renders on.

    Parameters
    ----------
    variant : str
        A checked variant (:func:`check_variant`).

    Returns
    -------
    str
        ``cuda`` for a ``cuda_*`` variant, else ``cpu``.

    Examples
    --------
    >>> variant_device("cuda_ad_spectral"), variant_device("scalar_spectral")
    ('cuda', 'cpu')
    """
    return "cuda" if variant.startswith("cuda_") else "cpu"


def check_device(device: str | None, variant: str | None) -> tuple[str, str]:
    """The device and the variant of a Mitsuba render: a device names its variant (``cpu``:
    :data:`swatch.core.choices.DEFAULT_VARIANT`, ``cuda``: ``cuda_ad_spectral``), a variant its device; a
    variant of another device than the one given is refused. Whether the device is here is the engine's
    check (:func:`swatch.render.mitsuba.engine.device_unavailable`).

    Parameters
    ----------
    device : str or None
        ``cpu`` or ``cuda`` in any case (:data:`swatch.core.choices.DEVICES`), or None: the variant's.
    variant : str or None
        A spectral variant (:func:`check_variant`), or None: the device's.

    Returns
    -------
    device, variant : str
        Both, checked.

    Raises
    ------
    SwatchError
        For an unknown device or variant, or a variant of another device.

    Examples
    --------
    >>> check_device(None, None), check_device("CUDA", None), check_device(None, "scalar_spectral")
    (('cpu', 'llvm_ad_spectral'), ('cuda', 'cuda_ad_spectral'), ('cpu', 'scalar_spectral'))
    """
    if device is None:
        key = check_variant(DEFAULT_VARIANT if variant is None else variant)
        return variant_device(key), key
    name = DEVICES.validate(device)
    if variant is None:
        return name, DEVICES[name]
    key = check_variant(variant)
    if variant_device(key) != name:
        raise SwatchError(f"Mitsuba variant {key!r} renders on the {variant_device(key)}, not on `device='{name}'`; "
                          "give the device or the variant, not both")
    return name, key


def check_denoise_size(quality: str | None, side_px: int) -> str | None:
    """A denoised render's size, checked: Intel Open Image Denoise runs on at most
    :data:`swatch.core.limits.MAX_DENOISE_PX` pixels a side (its time and memory: the limit's comment).

    Parameters
    ----------
    quality : str or None
        The checked ``denoise`` (:func:`check_denoise`; None: no denoising, any size).
    side_px : int
        The longer side of what is rendered (the image, or its film window), pixels.

    Returns
    -------
    str or None
        ``quality``.

    Raises
    ------
    SwatchError
        Denoising a larger picture (one line: the limit, and what to give instead).
    """
    if quality is not None and side_px > MAX_DENOISE_PX:
        raise SwatchError(f"the denoiser takes pictures of at most {MAX_DENOISE_PX} px a side (MAX_DENOISE_PX), this one "
                          f"is {side_px}; give `denoise=False` for a larger render (and more `spp`), or a smaller `size_px`")
    return quality


def check_denoise(denoise) -> str | None:
    """A render's ``denoise``, checked: Intel Open Image Denoise's filter quality, or None for no denoising.

    Parameters
    ----------
    denoise : bool or str or None
        True (the ``high`` quality), False or None (the raw path-traced estimate), or a quality name of
        :data:`swatch.core.choices.DENOISE_QUALITIES` (any case).

    Returns
    -------
    str or None
        The quality name (lower case), or None: no denoising.

    Raises
    ------
    SwatchError
        For anything else.
    """
    if denoise is True:
        return "high"
    if denoise is False or denoise is None:
        return None
    if isinstance(denoise, str) and denoise.lower() in DENOISE_QUALITIES:
        return denoise.lower()
    raise SwatchError(f"`denoise` must be True, False or one of {', '.join(DENOISE_QUALITIES)}, got {denoise!r}")
