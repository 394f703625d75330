"""From scene-referred linear RGB to a display image: exposure, the tone shoulder, sRGB encoding.

Only the display images (PNG) pass through here; the EXR files keep the scene values.

Exposure: for the microfacet model the mirror region is far brighter than the rest. The exposure
``k`` is chosen from the geometry alone (so a series of thicknesses shares it, like photographs
taken with one camera setting): over the off-mirror pixels (``D(h) < D(n)/2``, outside the half
maximum of the specular lobe) ``k = 1 / median(s)``, with ``s`` the intensity factor (the value a
white, F = 1 reflector would have). An off-mirror pixel therefore shows the half-vector
reflectance colour at its own brightness relative to that median (a typical off-mirror white
lands at 1.0 before the shoulder); the brighter highlight rolls off to white with the smooth
per-channel shoulder of :func:`tone` (identity up to :data:`KNEE` = 0.8, then
``y = 0.8 + 0.2 (1 − exp(−(x − 0.8)/0.2))``), as film or a camera does. Without an off-mirror
region in view the median is over every lit pixel. The paper's model has no mirror peak:
``k = 1`` (reflectance shown as is).

Angular maps of the microfacet model span two orders of magnitude (the mirror factor grows as
``1/cos²`` towards grazing), so the per-channel shoulder turned a third of a default map white.
Their display uses :func:`display_encode_hue` instead: the shoulder on the largest channel and
the pixel's RGB scaled with it, so the mirror region keeps its hue and saturation and only its
brightness rolls off (the EXR keeps the scene values).
"""
from __future__ import annotations

import functools

import numpy as np

from swatch.physics import microfacet

__all__ = ["KNEE", "BACKGROUND_LINEAR", "tone", "display_encode", "display_encode_hue", "exposure", "PAPER_EXPOSURE_RULE",
           "HUE_SHOULDER_RULE"]

#: Start of the display shoulder (linear value); below it the display is linear.
KNEE = 0.8
#: Linear value of the neutral grey a display image is composited on (sRGB 118).
BACKGROUND_LINEAR = 0.18
PAPER_EXPOSURE_RULE = "paper model: reflectance shown as is (k = 1); display shoulder above 0.8"
_LUT_N = 16384
_LUT_XMAX = 16.0


def tone(x) -> np.ndarray:
    """The display shoulder: identity up to :data:`KNEE` (0.8), then ``0.8 + 0.2 (1 − exp(−(x − 0.8)/0.2))`` (per channel).

    Parameters
    ----------
    x : array_like
        Exposed linear values (negative ones clip to 0).

    Returns
    -------
    numpy.ndarray
        In [0, 1), the shape of ``x``.

    Examples
    --------
    >>> [round(float(v), 4) for v in tone([0.5, 0.8, 2.0])]
    [0.5, 0.8, 0.9995]
    """
    x = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    return np.where(x <= KNEE, x, KNEE + (1.0 - KNEE) * (1.0 - np.exp(-(x - KNEE) / (1.0 - KNEE))))


@functools.lru_cache(maxsize=1)
def _lut() -> np.ndarray:
    """sRGB-encoded uint8 of the toned value, indexed by ``floor(sqrt(x / 16) · (N − 1))``."""
    # Entry j serves indices floor(sqrt(x/16)·(N-1)) = j: its value is taken at the bucket's middle.
    x = ((np.arange(_LUT_N, dtype=np.float64) + 0.5) / (_LUT_N - 1)) ** 2 * _LUT_XMAX
    x[0] = 0.0  # exact black stays black
    y = np.clip(tone(x), 0.0, 1.0)
    enc = np.where(y <= 0.0031308, 12.92 * y, 1.055 * np.power(y, 1.0 / 2.4) - 0.055)
    return np.round(np.clip(enc, 0.0, 1.0) * 255.0).astype(np.uint8)


def display_encode(linear_srgb, exposure: float = 1.0, background=None, out=None) -> np.ndarray:
    """Linear sRGB × ``exposure`` → tone shoulder → sRGB-encoded uint8, through a lookup table.

    The table is indexed by ``floor(sqrt(x / 16) · 16383)`` and holds each bucket's middle value, so the
    8-bit result equals the exact encoding (IEC 61966-2-1) to within a fraction of a code (negative
    values clip to 0, values ≥ 16 map to white).

    Parameters
    ----------
    linear_srgb : array_like, shape (..., 3)
        Scene-referred linear sRGB.
    exposure : float
        The display exposure ``k`` (:func:`exposure`).
    background : (numpy.ndarray of bool, float), optional
        (mask of shape (...), linear value): masked pixels get that value (no exposure).
    out : numpy.ndarray of uint8, optional
        Written in place and returned.

    Returns
    -------
    numpy.ndarray of uint8, shape (..., 3)
        Display sRGB, 8 bits (exposure, background and shoulder applied).

    Examples
    --------
    >>> display_encode([[0.0, 0.18, 1.0]]).tolist()  # 1.0 lies on the shoulder: 0.93
    [[0, 118, 247]]
    """
    n1 = np.float32(_LUT_N - 1)
    scale = np.float32(float(exposure) / _LUT_XMAX) * n1 * n1
    x = np.multiply(np.asarray(linear_srgb, dtype=np.float32), scale)
    if background is not None:
        mask, value = background
        np.copyto(x, np.float32(value / _LUT_XMAX) * n1 * n1, where=np.asarray(mask)[..., None])
    np.clip(x, np.float32(0.0), n1 * n1, out=x)
    np.sqrt(x, out=x)
    idx = x.astype(np.int32)  # floor; the table holds each bucket's middle value
    if out is None:
        return _lut()[idx]
    np.take(_lut(), idx, out=out)
    return out


def exposure(model: str, s: np.ndarray, cos_h: np.ndarray, seen: np.ndarray, roughness_alpha: float,
             distribution: str) -> tuple[float, str]:
    """The display exposure ``k`` of a render and a sentence saying how it was chosen (see the module doc).

    Parameters
    ----------
    model : str
        ``"paper"`` (k = 1) or ``"microfacet"``.
    s : numpy.ndarray
        Intensity factor of a white (F = 1) reflector per pixel.
    cos_h : numpy.ndarray
        Cosine of the half vector to the normal per pixel.
    seen : numpy.ndarray of bool
        The pixels on the object (all arrays of one shape).
    roughness_alpha : float
        GGX / Beckmann α.
    distribution : str
        The microfacet distribution (:data:`swatch.core.choices.DISTRIBUTIONS`).

    Returns
    -------
    (float, str)
        ``k`` (1 / the median F = 1 intensity over the off-mirror pixels, ``D(h) < D(n)/2``) and the rule.
    """
    if model == "paper":
        return 1.0, PAPER_EXPOSURE_RULE
    seen = seen & (s > 0)
    off = seen & (microfacet.D_ratio(np.clip(cos_h, 0, 1), roughness_alpha, distribution) < 0.5)
    if off.sum() >= max(16, 0.01 * seen.sum()):
        p = float(np.median(s[off]))
        rule = ("k = 1 / median F=1 intensity over the off-mirror region (D(h) < D(n)/2, outside the half "
                "maximum of the specular lobe): off-mirror pixels show the half-vector reflectance colour "
                "at their own brightness; the brighter highlight rolls off to white with a smooth "
                "per-channel shoulder above 0.8")
    elif seen.any():
        p = float(np.median(s[seen]))
        rule = "no off-mirror region in view: k = 1 / median F=1 intensity; shoulder above 0.8"
    else:
        return 1.0, "nothing lit in view: k = 1"
    return (1.0 / p if p > 0 else 1.0), rule


HUE_SHOULDER_RULE = ("hue-preserving shoulder: above 0.8 the largest channel rolls off as the render shoulder and "
                     "the other channels are scaled with it (colour kept, brightness compressed; no clipping to white)")


def display_encode_hue(linear_srgb, exposure: float = 1.0) -> np.ndarray:
    """Linear sRGB × ``exposure`` → sRGB uint8 with the hue-preserving shoulder (angular maps).

    ``rgb · tone(m)/m`` where the largest channel ``m`` exceeds :data:`KNEE`, identity below: the mirror
    region keeps its hue and saturation, only its brightness rolls off.

    Parameters
    ----------
    linear_srgb : array_like, shape (..., 3)
        Scene-referred linear sRGB (1.0 = display white before exposure).
    exposure : float
        Factor on the linear values before encoding.

    Returns
    -------
    numpy.ndarray of uint8, shape (..., 3)
        Display sRGB, 8 bits, the hue kept where a channel would clip.

    Examples
    --------
    >>> display_encode_hue([[4.0, 2.0, 0.0]]).tolist()
    [[255, 188, 0]]
    """
    x = np.maximum(np.asarray(linear_srgb, dtype=np.float64) * float(exposure), 0.0)
    m = x.max(axis=-1, keepdims=True)
    y = np.clip(np.where(m > KNEE, x * (tone(m) / np.where(m > 0, m, 1.0)), x), 0.0, 1.0)
    enc = np.where(y <= 0.0031308, 12.92 * y, 1.055 * np.power(y, 1.0 / 2.4) - 0.055)
    return np.round(enc * 255.0).astype(np.uint8)
