"""A user's environment map: an equirectangular EXR or Radiance HDR, read, checked and resampled.

The file is latitude–longitude (equirectangular), read with OpenImageIO: row 0 is the zenith (+y),
the centre column looks along −z (away from the camera) and longitude grows towards +x
(``u = 0.5 + atan2(x, −z)/2π``, ``v = acos(y)/π``). Untrusted input: the size is checked from the
header before any pixel is read (:data:`swatch.core.limits.MAX_ENV_PIXELS`), the values must be
finite and ≥ 0, and RGB is taken as linear Rec.709/sRGB primaries (1 channel: grey; 2 are refused).
:func:`equirect_to_octa` resamples it onto the octahedral map (:mod:`swatch.render.octahedral`)
that :mod:`swatch.render.environment` normalises.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from swatch.core.choices import lightings_of
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_ENV_FILE_BYTES, MAX_ENV_PIXELS, MAX_ENV_SIDE
from swatch.render.octahedral import octa_encode, texel_directions

__all__ = ["MAP_RES", "read_equirect", "equirect_to_octa"]

#: Octahedral map resolution (texels per side) of an environment's radiance.
MAP_RES = 128


def read_equirect(path) -> np.ndarray:
    """Read and check an equirectangular EXR or Radiance HDR (module doc).

    Parameters
    ----------
    path : str or path-like
        The file: OpenEXR or Radiance HDR, twice as wide as tall (±1 pixel), at most
        ``MAX_ENV_SIDE`` per side, ``MAX_ENV_PIXELS`` pixels and ``MAX_ENV_FILE_BYTES`` bytes.

    Returns
    -------
    numpy.ndarray
        Linear RGB radiance, shape ``(H, W, 3)`` float32 (1- or 2-channel files repeated as grey).

    Raises
    ------
    SwatchError
        When the file is missing, too large (checked from the header before pixels are read), of
        another format or shape, or has negative, infinite or NaN values (one line, what is allowed).
    """
    p = Path(path)
    if not p.is_file():
        raise SwatchError(f"environment map {str(p)!r} is not a file; give an equirectangular .exr or .hdr "
                          f"or one of {', '.join(lightings_of('builtin'))}")
    if p.stat().st_size > MAX_ENV_FILE_BYTES:
        raise SwatchError(f"environment map {p.name!r} is larger than {MAX_ENV_FILE_BYTES >> 20} MiB")
    inp = oiio.ImageInput.open(str(p))
    if inp is None:
        raise SwatchError(f"cannot read environment map {p.name!r}: {oiio.geterror().strip() or 'unknown format'}")
    try:
        if inp.format_name() not in ("openexr", "hdr"):
            raise SwatchError(f"environment map {p.name!r} is not an OpenEXR or Radiance HDR file; give an "
                              "equirectangular .exr or .hdr")
        spec = inp.spec()
        w, h, nch = int(spec.width), int(spec.height), int(spec.nchannels)
        if w < 2 or h < 1 or w > MAX_ENV_SIDE or h > MAX_ENV_SIDE or w * h > MAX_ENV_PIXELS:
            raise SwatchError(f"environment map {p.name!r} is {w}x{h}; allowed up to {MAX_ENV_SIDE} per side "
                              f"and {MAX_ENV_PIXELS} pixels")
        if abs(w - 2 * h) > 1:
            raise SwatchError(f"environment map {p.name!r} is {w}x{h}; an equirectangular map is twice as wide as tall")
        if nch != 1 and not 3 <= nch <= 64:  # (2: grey + alpha, or two colours of three? not a radiance map)
            raise SwatchError(f"environment map {p.name!r} has {nch} channels; give 1 (grey) or 3 to 64 (RGB first)")
        pix = inp.read_image(0, 0, 0, min(nch, 3), "float")
    finally:
        inp.close()
    if pix is None:
        raise SwatchError(f"cannot read the pixels of environment map {p.name!r}")
    a = np.asarray(pix, dtype=np.float32).reshape(h, w, -1)
    if a.shape[-1] < 3:
        a = np.repeat(a[..., :1], 3, axis=-1)
    if not np.all(np.isfinite(a)) or a.min() < 0:
        raise SwatchError(f"environment map {p.name!r} has negative, infinite or NaN values; radiance must be "
                          "finite and >= 0")
    return a


def equirect_to_octa(img: np.ndarray, res: int = MAP_RES) -> np.ndarray:
    """Resample a latitude–longitude map onto the octahedral map, keeping energy.

    Splatting: every source pixel (split into sub-pixels when the source is small) adds radiance ×
    solid angle to the texel its direction falls in; each texel is the solid-angle-weighted mean
    (energy is kept, a constant map stays constant). Texels that receive nothing take their
    bilinear value. Memory is bounded by working on blocks of rows.

    Parameters
    ----------
    img : numpy.ndarray
        Equirectangular radiance, shape ``(H, W, 3)`` (orientation as in the module doc).
    res : int, optional
        Texels per side of the octahedral map.

    Returns
    -------
    numpy.ndarray
        The octahedral map, shape ``(res, res, 3)`` float64 (texel order of
        :func:`swatch.render.octahedral.texel_directions`).

    Examples
    --------
    >>> import numpy as np
    >>> m = equirect_to_octa(np.full((8, 16, 3), 2.0, dtype=np.float32), res=8)
    >>> m.shape, bool(np.allclose(m, 2.0))
    ((8, 8, 3), True)
    """
    h, w, _ = img.shape
    sub = max(1, int(np.ceil(np.sqrt(8.0 * res * res / (h * w)))))
    out_num = np.zeros((res * res, 3))
    out_den = np.zeros(res * res)
    for r0 in range(0, h, max(1, 262144 // (w * sub * sub))):  # bounded memory per block of rows
        r1 = min(h, r0 + max(1, 262144 // (w * sub * sub)))
        rows = (np.arange(r0 * sub, r1 * sub) + 0.5) / (h * sub)
        cols = (np.arange(w * sub) + 0.5) / (w * sub)
        theta = np.pi * rows[:, None]
        phi = 2.0 * np.pi * (cols[None, :] - 0.5)
        st = np.sin(theta)
        x, y, z = st * np.sin(phi), np.cos(theta) + 0 * phi, -st * np.cos(phi)
        s, t = octa_encode(x, y, z)
        idx = (np.minimum((t * res).astype(np.int64), res - 1) * res
               + np.minimum((s * res).astype(np.int64), res - 1)).reshape(-1)
        om = np.broadcast_to(st, x.shape).reshape(-1)  # dω ∝ sin θ
        vals = np.repeat(np.repeat(img[r0:r1], sub, axis=0), sub, axis=1).reshape(-1, 3)
        out_num += np.stack([np.bincount(idx, om * vals[:, k], res * res) for k in range(3)], -1)
        out_den += np.bincount(idx, om, res * res)
    empty = out_den <= 0
    out = out_num / np.where(empty, 1.0, out_den)[:, None]
    if empty.any():
        d = texel_directions(res)[empty]
        th = np.arccos(np.clip(d[:, 1], -1, 1))
        ph = np.arctan2(d[:, 0], -d[:, 2])
        fy = np.clip(th / np.pi * h - 0.5, 0, h - 1)
        fx = (ph / (2 * np.pi) + 0.5) * w - 0.5
        out[empty] = _bilinear_wrap(img, fy, fx)
    return out.reshape(res, res, 3)


def _bilinear_wrap(img, fy, fx):
    """Bilinear lookup at fractional (row, column) ``(fy, fx)``, the columns wrapping around."""
    h, w, _ = img.shape
    y0 = np.floor(fy).astype(int)
    x0 = np.floor(fx).astype(int)
    ay, ax = (fy - y0)[:, None], (fx - x0)[:, None]
    y1 = np.minimum(y0 + 1, h - 1)
    x0w, x1w = x0 % w, (x0 + 1) % w
    top = img[y0, x0w] * (1 - ax) + img[y0, x1w] * ax
    bot = img[y1, x0w] * (1 - ax) + img[y1, x1w] * ax
    return top * (1 - ay) + bot * ay
