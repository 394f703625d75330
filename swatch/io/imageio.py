"""Image files through OpenImageIO: EXR (half/float, any channels), spectral EXR, PNG, text drawing.

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

Spectral EXR: the layout of Fichet, Pacanowski & Wilkie, "An OpenEXR Layout for Spectral
Images", JCGT 10(3), 2021. Reflective (dimensionless) spectra are channels named
``T.<wavelength>nm`` with a decimal **comma**, the value written like C++ ``std::to_string``
(six decimals), e.g. ``T.550,000000nm``; emissive spectra would be ``S0.<wavelength>nm``
(Stokes component 0). The layout's version attribute ``spectralLayoutVersion = "1.0"`` is set.
"""
from __future__ import annotations

import functools
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
    "write_spectral_exr",
    "write_png",
    "write_tiff",
    "TIFF_FIXED_DATETIME",
    "read_metadata",
    "read_channel_names",
    "reflective_channel_name",
    "parse_spectral_channel",
    "chromaticities",
    "font_path",
    "draw_text",
    "text_width",
    "drawable_text",
    "draw_rect",
    "draw_line",
]

PREFIX = "swatch:"
HALF_MAX = 65504.0
_SPECTRAL_RE = re.compile(
    r"^(?:(?P<stokes>S[0-3])|T)\.(?P<value>(\d+(,\d*)?|,\d+)([eE][+-]?\d+)?)"
    r"(?P<mult>Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(?P<unit>m|Hz)$"
)
_PREFIX_SCALE_M = {
    "Y": 1e24, "Z": 1e21, "E": 1e18, "P": 1e15, "T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "h": 1e2,
    "da": 1e1, "": 1.0, "d": 1e-1, "c": 1e-2, "m": 1e-3, "u": 1e-6, "n": 1e-9, "p": 1e-12,
}


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
    """(rx, ry, gx, gy, bx, by, wx, wy) of an RGB space from colour-science."""

    cs = colour.RGB_COLOURSPACES[RGB_SPACES[check_rgb_space(space)]]
    p = np.asarray(cs.primaries, dtype=np.float64).reshape(3, 2)
    w = np.asarray(cs.whitepoint, dtype=np.float64).reshape(2)
    return tuple(float(x) for x in np.concatenate([p.reshape(-1), w]))


# -- writers -----------------------------------------------------------------------------------
def _as_hwc(pixels, what: str) -> np.ndarray:
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
    """Write an OpenEXR file (scanline, ``compression`` zip by default).

    ``pixels`` (H, W) or (H, W, C) with ``len(channel_names) == C`` (any C). With ``space`` the
    ``chromaticities`` attribute is set to that RGB space's primaries and white (colour-science);
    ``space=None`` leaves it out (non-colour data). ``half`` stores 16-bit floats (values are
    clipped to ±65504, the half range, so a highlight never becomes inf). ``raw_attributes`` are
    written under their own names (no ``swatch:`` prefix), e.g. a layout's standard attributes.
    """
    oiio = _oiio()
    arr = _as_hwc(pixels, "EXR pixels").astype(np.float32, copy=False)  # (no copy of a float32 image)
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


def reflective_channel_name(wavelength_nm: float) -> str:
    """Fichet et al. (JCGT 2021) reflective channel name: ``T.550,000000nm``."""
    return "T." + f"{float(wavelength_nm):.6f}".replace(".", ",") + "nm"


def parse_spectral_channel(name: str):
    """(kind, wavelength_nm) for a spectral channel name ('T' reflective, 'S0'..'S3' emissive), else None."""
    m = _SPECTRAL_RE.match(str(name))
    if not m:
        return None
    value = float(m.group("value").replace(",", "."))
    scale = _PREFIX_SCALE_M[m.group("mult") or ""]
    if m.group("unit") == "Hz":
        nm = 299792458.0 / (value * scale) * 1e9
    else:
        nm = value * scale * 1e9 if m.group("mult") != "n" else value
    return (m.group("stokes") or "T"), nm


def write_spectral_exr(path, reflectance, wavelength_nm, metadata: dict | None = None, rgb=None,
                       space: str = "srgb", half: bool = False) -> Path:
    """A spectral EXR of reflectance (H, W, Wl) on ``wavelength_nm`` (Fichet et al. 2021 layout).

    ``rgb`` (H, W, 3): linear RGB in ``space`` written as ``R``, ``G``, ``B`` channels beside the
    spectral ones (the layout's reference writer always adds them, and ordinary viewers show
    them); the ``chromaticities`` attribute then names ``space``. 32-bit floats by default, as the
    reference writer; ``half`` for 16-bit.
    """
    arr = _as_hwc(reflectance, "spectral reflectance")
    wl = np.asarray(wavelength_nm, dtype=np.float64).reshape(-1)
    if wl.size != arr.shape[2]:
        raise SwatchError(f"spectral EXR has {arr.shape[2]} bands but {wl.size} wavelengths")
    names = [reflective_channel_name(x) for x in wl]
    if rgb is not None:
        rgb = _as_hwc(rgb, "preview RGB")
        if rgb.shape != (*arr.shape[:2], 3):
            raise SwatchError("the spectral EXR's RGB preview must be (H, W, 3) like the spectra")
        arr = np.concatenate([np.asarray(rgb, dtype=np.float32), arr.astype(np.float32)], axis=2)
        names = ["R", "G", "B", *names]
    return write_exr(path, arr, metadata, channel_names=names, space=space if rgb is not None else None, half=half,
                     raw_attributes={"spectralLayoutVersion": "1.0"})


def write_png(path, rgb, metadata: dict | None = None, xmp: str | None = None, dpi: float | None = None,
              flat: bool = False, intent: int | None = None) -> Path:
    """An sRGB PNG (gray, gray+alpha, RGB or RGBA; uint8, or uint16 for 16-bit) with metadata.

    Metadata values are UTF-8 ``iTXt`` chunks; ``xmp`` (see :func:`swatch.io.pngmeta.xmp_packet`)
    is embedded as the file's XMP packet; ``dpi`` sets the ``pHYs`` resolution. The ``sRGB``
    chunk carries the perceptual rendering intent (:mod:`swatch.io.pngmeta`), or ``intent``. ``flat``: the image is
    flat colour, so PNG's row filters are skipped (no gain there, 2× faster).
    """

    oiio = _oiio()
    arr = _as_hwc(rgb, "PNG pixels")
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
    """An LZW-compressed TIFF (uint8 or uint16, display-encoded) with resolution in dots per
    inch, an embedded ICC profile and ``DocumentName`` / ``ImageDescription`` text.

    LZW, not Deflate: ``exiftool -validate`` flags Adobe Deflate (8) as an invalid IFD0
    compression, LZW (5) is baseline-extension TIFF every reader (libtiff) has. ``DateTime`` is
    :data:`TIFF_FIXED_DATETIME` (OpenImageIO stamps the current time when it writes text or a
    profile, and an empty value is an invalid date): valid and byte-identical on rerun.
    """
    oiio = _oiio()
    arr = _as_hwc(rgb, "TIFF pixels")
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

    With ``prefix`` (default ``swatch:``) only those attributes, with the prefix removed; with
    ``prefix=None`` every attribute under its own name. ``restore`` turns JSON strings back into
    lists/dicts, "true"/"false" into bools and numeric PNG text back into floats.
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
    oiio = _oiio()
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise SwatchError(f"cannot read {path}: {oiio.geterror()}")
    try:
        return list(inp.spec().channelnames)
    finally:
        inp.close()


# -- drawing -----------------------------------------------------------------------------------
@functools.lru_cache(maxsize=4)
def font_path(name: str = "DroidSans") -> str:
    """A TrueType font shipped inside the OpenImageIO wheel (share/fonts/OpenImageIO/<name>.ttf)."""
    oiio = _oiio()
    base = Path(oiio.__file__).resolve().parent
    for cand in (base / "share" / "fonts" / "OpenImageIO" / f"{name}.ttf",):
        if cand.is_file():
            return str(cand)
    found = sorted(base.rglob(f"{name}.ttf"))
    if found:
        return str(found[0])
    raise SwatchError(f"font {name}.ttf not found in the OpenImageIO package at {base}")


def _color_tuple(color, nch: int) -> tuple:
    c = np.asarray(color, dtype=np.float64).reshape(-1)
    if c.size == 1:
        c = np.repeat(c, 3)
    c = c / 255.0 if c.max(initial=0) > 1.0 else c
    vals = list(c[:nch]) + [1.0] * (nch - min(c.size, nch))
    return tuple(float(v) for v in vals[:nch])


@functools.lru_cache(maxsize=4096)
def _has_glyph(char: str, font: str) -> bool:
    """Whether ``font`` draws ``char`` (a missing glyph has an advance but leaves no ink)."""
    if char.isspace():
        return True
    roi = _oiio().ImageBufAlgo.text_size(char, 32, font_path(font))
    return bool(roi.defined and roi.width > 1)


def drawable_text(text: str, font: str = "DroidSans") -> str:
    """``text`` with the characters the font cannot draw (CJK, many symbols) replaced by ``?``,
    so that text is never silently invisible; the metadata keeps the original."""
    return "".join(ch if _has_glyph(ch, font) else "?" for ch in str(text))


def text_width(text: str, size_px: int, font: str = "DroidSans") -> int:
    """Width in pixels of ``text`` rendered at ``size_px``."""
    oiio = _oiio()
    roi = oiio.ImageBufAlgo.text_size(drawable_text(text, font), int(size_px), font_path(font))
    return int(roi.width) if roi.defined else 0


def draw_text(image_uint8, text: str, x: int, y: int, size_px: int = 16, color=(0, 0, 0),
              align: str = "left", valign: str = "baseline", font: str = "DroidSans",
              inplace: bool = False) -> np.ndarray:
    """Render ``text`` into a copy of an (H, W, C) uint8 image with OpenImageIO (anti-aliased).

    ``(x, y)`` is the anchor: ``align`` left|center|right, ``valign`` baseline|top|center|bottom.
    ``color`` as 0–255 or 0–1 values. Returns the new image (the input is not modified), or with
    ``inplace`` the input itself, drawn on (a figure of many labels: no copy per label). Only the band
    of rows the text can reach is converted, so a label costs the same on a tall figure as on a small one.
    """
    oiio = _oiio()
    img = _as_hwc(image_uint8, "image")
    if img.dtype != np.uint8:
        raise SwatchError("draw_text works on uint8 images")
    h, w, c = img.shape
    pad = 2 * int(size_px) + 4  # the glyphs lie within two sizes of the anchor, whatever the valign
    y0, y1 = max(0, int(y) - pad), min(h, int(y) + pad)
    out_img = img if inplace else img.copy()
    if y1 <= y0:
        return out_img
    band = img[y0:y1]
    buf = oiio.ImageBuf(oiio.ImageSpec(w, y1 - y0, c, "float"))
    buf.set_pixels(oiio.ROI(0, w, 0, y1 - y0), band.astype(np.float32) / 255.0)
    ok = oiio.ImageBufAlgo.render_text(buf, int(x), int(y) - y0, drawable_text(text, font), int(size_px),
                                       font_path(font), _color_tuple(color, c), align, valign)
    if not ok:
        raise SwatchError(f"cannot draw text: {buf.geterror()}")
    out = buf.get_pixels(oiio.FLOAT).reshape(y1 - y0, w, c)
    out_img[y0:y1] = np.clip(np.round(out * 255.0), 0, 255).astype(np.uint8)
    return out_img


def draw_rect(image_uint8, x0: int, y0: int, x1: int, y1: int, color, fill: bool = True, width: int = 1,
              inplace: bool = False) -> np.ndarray:
    """A filled (or outlined) axis-aligned rectangle [x0, x1) × [y0, y1) on a copy of the image (``inplace``:
    on the image itself)."""
    img = _as_hwc(image_uint8, "image")
    img = img if inplace else img.copy()
    col = np.round(np.asarray(_color_tuple(color, img.shape[2])) * 255).astype(np.uint8)
    h, w = img.shape[:2]
    x0, x1 = max(0, int(x0)), min(w, int(x1))
    y0, y1 = max(0, int(y0)), min(h, int(y1))
    if x1 <= x0 or y1 <= y0:
        return img
    if fill:
        img[y0:y1, x0:x1] = col
    else:
        t = int(width)
        img[y0:min(y1, y0 + t), x0:x1] = col
        img[max(y0, y1 - t):y1, x0:x1] = col
        img[y0:y1, x0:min(x1, x0 + t)] = col
        img[y0:y1, max(x0, x1 - t):x1] = col
    return img


def draw_line(image_uint8, x0: int, y0: int, x1: int, y1: int, color, width: int = 1,
              inplace: bool = False) -> np.ndarray:
    """A horizontal or vertical line (axes, ticks) of ``width`` pixels on a copy of the image (``inplace``:
    on the image itself)."""
    if x0 != x1 and y0 != y1:
        raise SwatchError("draw_line draws horizontal or vertical lines only")
    t = int(width)
    if y0 == y1:
        return draw_rect(image_uint8, min(x0, x1), y0 - t // 2, max(x0, x1) + 1, y0 - t // 2 + t, color,
                         inplace=inplace)
    return draw_rect(image_uint8, x0 - t // 2, min(y0, y1), x0 - t // 2 + t, max(y0, y1) + 1, color,
                     inplace=inplace)
