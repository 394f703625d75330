"""Image files through OpenImageIO: EXR (half/float, any channels), spectral EXR, PNG, TIFF (drawing: :mod:`swatch.io.drawing`).

Every writer is

* **atomic**: the file is written to a temporary name in the target folder and renamed onto the
  final path (:class:`swatch.core.fileio.atomic_path`); an error leaves nothing behind;
* **deterministic**: the same pixels and metadata give byte-identical files. OpenImageIO's EXR
  writer stamps a ``DateTime`` attribute with the current time unless one is given; we give an
  empty one, which suppresses it. No ``Software`` or host attributes are written.

Metadata: a ``dict`` of name -> value. Names without a ``:`` get the ``swatch:`` prefix. In EXR
files floats are (32-bit) float attributes, ints int attributes, strings string attributes, and anything
else (bools, lists, tuples, dicts, numpy arrays) a JSON string. PNG files carry every value as a
UTF-8 ``iTXt`` chunk (floats written with ``repr``, so they read back exactly). :func:`read_metadata`
returns the ``swatch:`` attributes of either kind of file (prefix removed, types restored where
the file keeps them).

Spectral EXR (Fichet et al. 2021): :mod:`swatch.io.spectral_exr`.
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import colour
import numpy as np
import OpenImageIO as oiio

from swatch.colorimetry.colorimeter import RGB_SPACES, check_rgb_space
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_path
from swatch.io.imagecheck import finished_whole
from swatch.io.pngmeta import SRGB_INTENT, finish_png

__all__ = [
    "PREFIX",
    "write_exr",
    "write_png",
    "write_tiff",
    "TIFF_FIXED_DATETIME",
    "read_metadata",
    "read_channel_names",
    "chromaticities",
    "as_hwc",
]

PREFIX = "swatch:"
HALF_MAX = 65504.0


def _oiio():
    return oiio


# -- metadata ----------------------------------------------------------------------------------
def _key(name: str) -> str:
    name = str(name)
    return name if ":" in name else PREFIX + name


def _json_default(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"cannot serialise {type(obj).__name__} as metadata")


def _to_json(value) -> str:
    return json.dumps(value, default=_json_default, sort_keys=True, ensure_ascii=False, allow_nan=False)


def _exr_value(value):
    """(kind, value) for an EXR attribute: 'float', 'int' or 'string'."""
    if isinstance(value, (bool, np.bool_)):
        return "string", "true" if value else "false"
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        v = int(value)
        if -(2**31) <= v < 2**31:
            return "int", v
        return "string", str(v)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return ("float", f) if math.isfinite(f) else ("string", repr(f))
    if isinstance(value, str):
        return "string", value
    return "string", _to_json(value)


def _text_value(value) -> str:
    kind, v = _exr_value(value)
    return repr(v) if kind == "float" else str(v)


def _apply_metadata(spec, metadata: dict | None, text_only: bool) -> None:
    for name, value in sorted((metadata or {}).items(), key=lambda kv: _key(kv[0])):
        if value is None:
            continue
        key = _key(name)
        if text_only:
            spec.attribute(key, _text_value(value))
            continue
        kind, v = _exr_value(value)
        if kind == "float":
            spec.attribute(key, "float", v)
        elif kind == "int":
            spec.attribute(key, "int", v)
        else:
            spec.attribute(key, v)


def chromaticities(space: str = "srgb") -> tuple[float, ...]:
    """The EXR ``chromaticities`` of an RGB space, from colour-science.

    Parameters
    ----------
    space : str
        An RGB space of :data:`swatch.colorimetry.colorimeter.RGB_SPACES` (``srgb``, ``display-p3`` …).

    Returns
    -------
    tuple of float
        (rx, ry, gx, gy, bx, by, wx, wy), CIE 1931 xy.

    Examples
    --------
    >>> [round(v, 4) for v in chromaticities("srgb")]
    [0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329]
    """

    cs = colour.RGB_COLOURSPACES[RGB_SPACES[check_rgb_space(space)]]
    p = np.asarray(cs.primaries, dtype=np.float64).reshape(3, 2)
    w = np.asarray(cs.whitepoint, dtype=np.float64).reshape(2)
    return tuple(float(x) for x in np.concatenate([p.reshape(-1), w]))


# -- writers -----------------------------------------------------------------------------------
def as_hwc(pixels, what: str) -> np.ndarray:
    """An image array as (H, W, C) (a 2-D array gets one channel), checked non-empty.

    Parameters
    ----------
    pixels : array_like, shape (H, W) or (H, W, C)
        The image, H, W, C ≥ 1.
    what : str
        Names the array in the error.

    Returns
    -------
    numpy.ndarray, shape (H, W, C)
        The same values (a view where it can be), a 2-D input with C = 1.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other shape.
    """
    arr = np.asarray(pixels)
    if arr.ndim == 2:
        arr = arr[:, :, None]
    if arr.ndim != 3 or arr.shape[0] < 1 or arr.shape[1] < 1 or arr.shape[2] < 1:
        raise SwatchError(f"{what} must be an (H, W) or (H, W, C) array")
    return arr


def _write(path, spec, pixels: np.ndarray, fmt: str, finish=None) -> Path:
    """Write through OpenImageIO into a temporary file; ``finish(bytes) -> bytes`` may rewrite it
    (e.g. PNG metadata chunks) before it is renamed onto ``path``."""
    oiio = _oiio()
    path = Path(path)
    with atomic_path(path) as tmp:
        out = oiio.ImageOutput.create(str(path))  # format from the final name's extension
        if out is None:
            raise SwatchError(f"cannot write {path.suffix} images: {oiio.geterror()}")
        if not out.open(str(tmp), spec):
            raise SwatchError(f"cannot write {path}: {out.geterror()}")
        ok = out.write_image(np.ascontiguousarray(pixels))
        err = out.geterror()
        closed = out.close()  # (a full disk may fail only here, when the last buffer is flushed)
        err = err or out.geterror()
        if not ok or closed is False:
            raise SwatchError(f"cannot write {path}: {err or 'the image writer failed (is the disk full?)'}")
        if not finished_whole(tmp, spec, finish):  # (libpng, OpenEXR at a full disk: a cut or 0-byte file, no error)
            raise SwatchError(f"cannot write {path}: the written image is incomplete (is the disk full?)")
    return path


def write_exr(path, pixels, metadata: dict | None = None, channel_names=("R", "G", "B"),
              space: str | None = "srgb", half: bool = True, compression: str = "zip",
              raw_attributes: dict | None = None) -> Path:
    """Write an OpenEXR file (scanline; atomic and deterministic).

    Parameters
    ----------
    path : str or path-like
        The file to write (``.exr``); renamed into place when whole.
    pixels : array_like, shape (H, W) or (H, W, C)
        Any C, finite (NaN or inf refused).
    metadata : dict, optional
        ``swatch:`` attributes (see the module docstring).
    channel_names : sequence of str
        C distinct names.
    space : str or None
        Sets ``chromaticities`` to that RGB space (colour-science); None for non-colour data.
    half : bool
        16-bit floats (values clipped to ±65504, so a highlight never becomes inf); else 32-bit.
    compression : str
        An OpenEXR compression (``zip`` default).
    raw_attributes : dict, optional
        Written under their own names (no prefix), e.g. a layout's standard attributes.

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """
    oiio = _oiio()
    arr = as_hwc(pixels, "EXR pixels").astype(np.float32, copy=False)  # (no copy of a float32 image)
    names = [str(c) for c in channel_names]
    if len(names) != arr.shape[2] or len(set(names)) != len(names):
        raise SwatchError(f"EXR needs {arr.shape[2]} distinct channel names, got {len(names)}")
    lo, hi = (float(arr.min()), float(arr.max())) if arr.size else (0.0, 0.0)  # NaN propagates: no mask array
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise SwatchError("EXR pixels contain NaN or inf")
    if half and (lo < -HALF_MAX or hi > HALF_MAX):
        arr = np.clip(arr, -HALF_MAX, HALF_MAX)
    h, w, c = arr.shape
    spec = oiio.ImageSpec(w, h, c, "half" if half else "float")
    spec.channelnames = tuple(names)
    if "A" in names:
        spec.alpha_channel = names.index("A")
    spec.attribute("compression", compression)
    spec.attribute("DateTime", "")  # suppresses OIIO's time stamp: deterministic files
    if space is not None:
        spec.attribute("chromaticities", oiio.TypeDesc("float[8]"), chromaticities(space))
    _apply_metadata(spec, metadata, text_only=False)
    for name, value in sorted((raw_attributes or {}).items()):
        kind, v = _exr_value(value)
        spec.attribute(str(name), kind, v) if kind != "string" else spec.attribute(str(name), v)
    return _write(path, spec, arr, "exr")


def write_png(path, rgb, metadata: dict | None = None, xmp: str | None = None, dpi: float | None = None,
              flat: bool = False, intent: int | None = None) -> Path:
    """An sRGB PNG (gray, gray+alpha, RGB or RGBA; uint8, or uint16 for 16-bit) with metadata (atomic).

    Parameters
    ----------
    path : str or path-like
        The file to write (``.png``); renamed into place when whole.
    rgb : array_like, shape (H, W) or (H, W, 1–4), uint8 or uint16
        Display-encoded sRGB.
    metadata : dict, optional
        Each value a UTF-8 ``iTXt`` chunk (floats by ``repr``: they read back exactly).
    xmp : str, optional
        The XMP packet (:func:`swatch.io.pngmeta.xmp_packet`).
    dpi : float, optional
        The ``pHYs`` resolution, dots per inch.
    flat : bool
        Flat colour: PNG's row filters are skipped (no gain there, 2× faster).
    intent : int, optional
        The ``sRGB`` chunk's rendering intent (default perceptual, :mod:`swatch.io.pngmeta`).

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """

    oiio = _oiio()
    arr = as_hwc(rgb, "PNG pixels")
    if arr.dtype not in (np.uint8, np.uint16):
        raise SwatchError("PNG pixels must be uint8 or uint16 (display-encoded sRGB)")
    if arr.shape[2] not in (1, 2, 3, 4):
        raise SwatchError("PNG pixels need 1–4 channels")
    h, w, c = arr.shape
    spec = oiio.ImageSpec(w, h, c, "uint8" if arr.dtype == np.uint8 else "uint16")
    if c in (2, 4):
        spec.alpha_channel = c - 1
    spec.attribute("oiio:ColorSpace", "sRGB")
    spec.attribute("png:compressionLevel", 6)
    if flat:
        spec.attribute("png:filter", 8)  # PNG_FILTER_NONE
    _apply_metadata(spec, metadata, text_only=True)
    chunk_intent = SRGB_INTENT if intent is None else intent
    return _write(path, spec, np.ascontiguousarray(arr), "png",
                  finish=lambda blob: finish_png(blob, xmp, dpi, chunk_intent))


#: The TIFF DateTime of every TIFF written (the Unix epoch, as the CxF export's creation date).
TIFF_FIXED_DATETIME = "1970:01:01 00:00:00"


def write_tiff(path, rgb, dpi: float | None = None, icc_profile: bytes | None = None, title: str | None = None,
               description: str | None = None) -> Path:
    """An LZW-compressed TIFF (uint8 or uint16, display-encoded) with resolution, ICC profile and text (atomic).

    LZW, not Deflate: ``exiftool -validate`` flags Adobe Deflate (8) as an invalid IFD0 compression.
    ``DateTime`` is :data:`TIFF_FIXED_DATETIME`, so a rerun writes the same bytes.

    Parameters
    ----------
    path : str or path-like
        The file to write (``.tif``); renamed into place when whole.
    rgb : array_like, shape (H, W, C), uint8 or uint16
        Display-encoded pixels (gray, RGB or with alpha).
    dpi : float, optional
        Resolution, dots per inch.
    icc_profile : bytes, optional
        Embedded ICC profile.
    title, description : str, optional
        ``DocumentName`` and ``ImageDescription``.

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """
    oiio = _oiio()
    arr = as_hwc(rgb, "TIFF pixels")
    if arr.dtype not in (np.uint8, np.uint16):
        raise SwatchError("TIFF pixels must be uint8 or uint16")
    h, w, c = arr.shape
    spec = oiio.ImageSpec(w, h, c, "uint8" if arr.dtype == np.uint8 else "uint16")
    spec.attribute("compression", "lzw")
    spec.attribute("DateTime", TIFF_FIXED_DATETIME)
    if dpi is not None:
        spec.attribute("ResolutionUnit", "inch")
        spec.attribute("XResolution", float(dpi))
        spec.attribute("YResolution", float(dpi))
    if icc_profile is not None:
        spec.attribute("ICCProfile", oiio.TypeDesc(f"uint8[{len(icc_profile)}]"),
                       np.frombuffer(icc_profile, dtype=np.uint8))
    if title is not None:
        spec.attribute("DocumentName", title)
    if description is not None:
        spec.attribute("ImageDescription", description)
    return _write(path, spec, arr, "tif")


# -- readers -----------------------------------------------------------------------------------
def _restore(value, numeric_text: bool):
    if isinstance(value, str):
        s = value.strip()
        if s in ("true", "false"):
            return s == "true"
        if s[:1] in "[{":
            try:
                return json.loads(s)
            except ValueError:
                return value
        if not numeric_text:
            return value
        try:
            return float(s) if re.fullmatch(r"[-+]?(\d+\.\d*|\.\d+|\d+)([eE][-+]?\d+)?|[-+]?(inf|nan)", s) else value
        except ValueError:
            return value
    if isinstance(value, tuple):
        return list(value)
    return value


def read_metadata(path, prefix: str | None = PREFIX, restore: bool = True) -> dict:
    """Metadata of an image file read with OpenImageIO.

    Parameters
    ----------
    path : str or path-like
        The image file (any format OpenImageIO reads).
    prefix : str or None
        Only attributes with this prefix (default ``swatch:``), prefix removed; None: every attribute.
    restore : bool
        Turn JSON strings back into lists/dicts, ``true``/``false`` into bools, numeric PNG text into floats.

    Returns
    -------
    dict
        Attribute name → value (str, number, list or dict once restored).

    Raises
    ------
    swatch.core.errors.SwatchError
        The file cannot be opened.
    """
    oiio = _oiio()
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise SwatchError(f"cannot read {path}: {oiio.geterror()}")
    try:
        spec = inp.spec()
        numeric_text = inp.format_name() == "png"  # PNG text chunks carry numbers as text
        out = {}
        for attr in spec.extra_attribs:
            name = attr.name
            if prefix is not None:
                if not name.startswith(prefix):
                    continue
                name = name[len(prefix):]
            out[name] = _restore(attr.value, numeric_text) if restore else attr.value
        return out
    finally:
        inp.close()


def read_channel_names(path) -> list[str]:
    """The channel names of an image file (OpenImageIO).

    Parameters
    ----------
    path : str or path-like
        The image file (any format OpenImageIO reads).

    Returns
    -------
    list of str
        One per channel, in the file's order (e.g. ``R``, ``G``, ``B``, ``A``).

    Raises
    ------
    swatch.core.errors.SwatchError
        The file cannot be opened.
    """
    oiio = _oiio()
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise SwatchError(f"cannot read {path}: {oiio.geterror()}")
    try:
        return list(inp.spec().channelnames)
    finally:
        inp.close()
