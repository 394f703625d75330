"""Per-swatch print chips: a flat patch of each swatch's colour at print size (PNG and TIFF).

A chip is the swatch's colour at the reference geometry as sRGB from CIE 1931 2° colorimetry
(the hex code's colour, unquantised: 16 bits per channel), ``size_mm`` square at ``dpi``
(default 50 mm at 300 dpi: 591 × 591 pixels). Both files say how to print them:

* PNG: 16-bit RGB, ``sRGB`` chunk (relative colorimetric intent, the convention for colour
  chips; tagged sRGB), ``pHYs`` resolution, the swatch's numbers as UTF-8 ``iTXt`` text and an
  XMP packet (:mod:`swatch.io.pngmeta`);
* TIFF: 16-bit RGB, LZW-compressed (what ``exiftool -validate`` accepts; a fixed DateTime), X/Y
  resolution in dots per inch, the sRGB ICC profile embedded (LittleCMS's sRGB profile through
  Pillow's ImageCms, its creation date fixed so the bytes are deterministic, its header's rendering
  intent relative colorimetric, the profile ID recomputed), a description with the swatch's numbers.

A flat chip costs little: one broadcast array and two compressed writes per swatch.
"""
from __future__ import annotations

import functools
import hashlib
import struct
from pathlib import Path

import numpy as np
from PIL import ImageCms

from swatch.catalog.chip_size import CHIP_DPI, CHIP_SIZE_MM, chip_px
from swatch.catalog.exports import ase_name
from swatch.catalog.layout import CHIPS
from swatch.io.imageio import write_png, write_tiff
from swatch.io.pngmeta import CHIP_SRGB_INTENT, xmp_packet

__all__ = ["chip_names", "srgb_icc_profile", "encoded_16bit",
           "chip_batches", "write_chips"]

#: The ICC header's creation date, fixed (bytes 24–35: year, month, day, hour, minute, second).
_ICC_DATE = (2000, 1, 1, 0, 0, 0)


def chip_names(rec: dict) -> tuple[str, str]:
    """The (PNG, TIFF) names of a swatch's print chip in the catalog folder (in its ``chips/``).

    Parameters
    ----------
    rec : dict
        The record (its ``id``).

    Returns
    -------
    (str, str)
        ``chips/chip_<id>.png`` and ``chips/chip_<id>.tif``.
    """
    return f"{CHIPS}/chip_{rec['id']}.png", f"{CHIPS}/chip_{rec['id']}.tif"


@functools.lru_cache(maxsize=1)
def srgb_icc_profile() -> bytes:
    """The sRGB ICC profile (LittleCMS, via Pillow) with a fixed creation date and the relative
    colorimetric rendering intent in its header; the profile ID (MD5 over the profile with the flags,
    intent and ID fields zeroed, ICC.1 7.2.18) recomputed when the profile carries one.

    Returns
    -------
    bytes
        The same bytes on every run.

    References
    ----------
    :cite:`ICC1`, §7.2.18 (profile ID).
    """
    raw = bytearray(ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes())
    raw[24:36] = struct.pack(">6H", *_ICC_DATE)
    raw[64:68] = struct.pack(">I", CHIP_SRGB_INTENT)
    if any(raw[84:100]):
        zeroed = bytearray(raw)
        zeroed[44:48] = zeroed[64:68] = bytes(4)
        zeroed[84:100] = bytes(16)
        raw[84:100] = hashlib.md5(bytes(zeroed)).digest()
    return bytes(raw)


def encoded_16bit(data) -> np.ndarray:
    """16-bit display-encoded sRGB of the reference spectra (CIE 1931 2°, the context's colorimeter).

    Parameters
    ----------
    data : swatch.catalog.records.CatalogData
        The catalog's computed colours (its reference spectra and colorimeter).

    Returns
    -------
    numpy.ndarray of uint16, shape (N, 3)
        sRGB-encoded R, G, B per swatch, 0–65535 (clipped to the gamut).
    """

    cm = data.context.colorimeter
    enc, _ = cm.reflectance_display(data.reflectance, "srgb")
    return np.round(np.clip(enc, 0.0, 1.0) * 65535.0).astype(np.uint16)


def _texts(rec: dict, metal: str, header: dict, size_mm: float, dpi: float) -> tuple[str, str, dict]:
    cs = f"{header['illuminant']}, CIE {header['observer_name']}"
    title = ase_name(rec, metal)
    L, a, b = rec["Lab"]
    L50, a50, b50 = rec["Lab_D50_2"]
    description = (f"{title}: {header['film']} on {header['substrate']}. Print chip {size_mm:g} mm at {dpi:g} dpi, "
                   f"sRGB {rec['srgb_hex']} (CIE 1931 2° colorimetry). L*a*b* at {header['reference_geometry']['name']}:"
                   f" {L:.2f} {a:.2f} {b:.2f} ({cs}); {L50:.2f} {a50:.2f} {b50:.2f} (D50, CIE 1931 2°).")
    volts = "" if rec["voltage_V"] is None else f"{rec['voltage_V']:g}"  # none without a growth rate
    props = {"id": rec["id"], "thickness_nm": f"{rec['thickness_nm']:g}", "voltage_V": volts,
             "Lab": f"{L:.2f} {a:.2f} {b:.2f}", "Lab_D50_2": f"{L50:.2f} {a50:.2f} {b50:.2f}",
             "illuminant": header["illuminant"], "observer": header["observer"], "srgb_hex": rec["srgb_hex"]}
    return title, description, props


def chip_batches(folder, header: dict, data, records: list[dict], metal: str, size_mm: float, dpi: float,
                 batches: int) -> list[tuple]:
    """Arguments of :func:`write_chips` for ``batches`` groups of swatches (for a process pool).

    Parameters
    ----------
    folder : path-like
        The staging folder.
    header : dict
        ``catalog.json``'s ``catalog``.
    data : swatch.catalog.records.CatalogData
        The colours.
    records : list of dict
        The metadata, as catalog.json writes them.
    metal : str
        The substrate's element symbol printed on the chips (``Ti``).
    size_mm : float
        The chip's side, mm.
    dpi : float
        Print resolution, dots per inch.
    batches : int
        How many groups to split the chips into (one per worker process).

    Returns
    -------
    list of tuple
        One argument tuple per non-empty group, each group's swatches in catalog order.
    """
    values = encoded_16bit(data)
    n = len(records)
    step = max(1, -(-n // max(1, batches)))
    return [(folder, header, records[i:i + step], values[i:i + step], metal, size_mm, dpi)
            for i in range(0, n, step)]


def write_chips(folder, header: dict, records: list[dict], values, metal: str, size_mm: float = CHIP_SIZE_MM,
                dpi: float = CHIP_DPI) -> list[str]:
    """Write the chips (PNG and TIFF, 16-bit, flat colour, with the sRGB profile and XMP) of ``records``.

    Parameters
    ----------
    folder : path-like
        The staging folder the chips are written into (its ``chips/``).
    header : dict
        The catalog header (illuminant, observer, name) printed on the chips.
    records : list of dict
        The swatches' records (JSON view) of this batch.
    values : numpy.ndarray of uint16, shape (N, 3)
        :func:`encoded_16bit`.
    metal : str
        The substrate's element symbol (``Ti``).
    size_mm : float
        mm.
    dpi : float
        Print resolution, dots per inch.

    Returns
    -------
    list of str
        The catalog-relative names written.
    """

    folder = Path(folder)
    n = chip_px(size_mm, dpi)
    names = []
    for rec, rgb in zip(records, values, strict=True):
        png, tif = chip_names(rec)
        title, description, props = _texts(rec, metal, header, size_mm, dpi)
        pixels = np.broadcast_to(np.asarray(rgb, dtype=np.uint16), (n, n, 3))
        meta = {"id": rec["id"], "record": rec,
                "chip": f"{size_mm:g} mm at {dpi:g} dpi; sRGB from CIE 1931 2° colorimetry"}
        write_png(folder / png, pixels, meta, xmp=xmp_packet(title, description, props), dpi=dpi, flat=True,
                  intent=CHIP_SRGB_INTENT)
        write_tiff(folder / tif, pixels, dpi=dpi, icc_profile=srgb_icc_profile(), title=title,
                   description=description)
        names += [png, tif]
    return names
