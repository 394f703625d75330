"""PNG metadata the way image tools read it: UTF-8 text in iTXt, an XMP packet, sRGB intent, DPI.

OpenImageIO writes the pixels and the colour chunks (sRGB, gAMA, cHRM); :func:`finish_png`
then rewrites the file's ancillary chunks (the PNG chunk layout is length, type, data, CRC-32):

* every ``tEXt`` chunk becomes an ``iTXt`` chunk: ``tEXt`` is Latin-1 by the PNG specification,
  so UTF-8 text in it (``20–300 nm``, ``10°``) reads as mojibake; ``iTXt`` is UTF-8. Text longer
  than :data:`COMPRESS_OVER` bytes is zlib-compressed (level 9: deterministic);
* an XMP packet (``iTXt`` keyword ``XML:com.adobe.xmp``, uncompressed as the XMP specification
  asks for PNG) with ``dc:title``, ``dc:description`` and swatch properties (Lab, thickness …),
  which Bridge, Lightroom and exiftool show;
* the ``sRGB`` chunk's rendering intent becomes perceptual (0) for images, relative colorimetric
  (1) for colour chips (:data:`CHIP_SRGB_INTENT`: a chip's colour is its measurement, to be kept,
  not an image's look) — OpenImageIO writes absolute colorimetric (3), which is meant for proofing;
* a ``pHYs`` chunk (pixels per metre) when a resolution in dots per inch is given;
* OpenImageIO's empty ``eXIf`` and zero ``oFFs`` chunks are dropped.
"""
from __future__ import annotations

import struct
import zlib
from xml.sax.saxutils import escape

__all__ = ["finish_png", "xmp_packet", "XMP_KEYWORD", "SWATCH_XMP_NS", "COMPRESS_OVER", "SRGB_INTENT",
           "CHIP_SRGB_INTENT"]

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
XMP_KEYWORD = "XML:com.adobe.xmp"
#: The namespace of swatch's own XMP properties (XMP namespace URIs end in "/" or "#").
SWATCH_XMP_NS = "urn:anodic-swatch:xmp:1.0/"
COMPRESS_OVER = 1024
#: sRGB chunk rendering intent of images: 0 perceptual (1 relative colorimetric, 3 absolute colorimetric).
SRGB_INTENT = 0
#: ... of colour chips (and their ICC profile's header): relative colorimetric.
CHIP_SRGB_INTENT = 1
_INCH_M = 0.0254


def _chunks(blob: bytes):
    """The chunks of a whole PNG file; ValueError for one that is cut short (a writer that ran out of
    disk space may leave a file whose last chunk is truncated and has no IEND) or damaged."""
    if blob[:8] != PNG_SIGNATURE:
        raise ValueError("not a PNG file")
    pos = 8
    chunks = []
    while pos < len(blob):
        if pos + 12 > len(blob):
            raise ValueError("PNG file cut short")
        (n,) = struct.unpack_from(">I", blob, pos)
        kind = blob[pos + 4:pos + 8]
        if pos + 12 + n > len(blob):
            raise ValueError("PNG file cut short")
        data = blob[pos + 8:pos + 8 + n]
        (crc,) = struct.unpack_from(">I", blob, pos + 8 + n)
        if crc != zlib.crc32(kind + data) & 0xFFFFFFFF:
            raise ValueError(f"PNG chunk {kind!r} damaged (CRC)")
        chunks.append((kind, data))
        pos += 12 + n
    if not chunks or chunks[-1][0] != b"IEND":
        raise ValueError("PNG file has no IEND chunk (cut short)")
    return chunks


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _itxt(keyword: str, text: str, compress: bool | None = None) -> bytes:
    raw = text.encode("utf-8")
    if compress is None:
        compress = len(raw) > COMPRESS_OVER
    body = zlib.compress(raw, 9) if compress else raw
    key = keyword.encode("latin-1")[:79]
    return _chunk(b"iTXt", key + b"\0" + bytes([1 if compress else 0, 0]) + b"\0\0" + body)


def xmp_packet(title: str, description: str, properties: dict | None = None) -> str:
    """An XMP packet: ``dc:title``, ``dc:description`` (language alternatives, x-default) and ``anodic:<name>``
    simple properties (a prefix of its own: OpenImageIO reads XMP properties into attributes, which must
    not shadow the ``swatch:`` text chunks).

    Parameters
    ----------
    title, description : str
        Escaped for XML.
    properties : dict, optional
        Name → value (written as text, names sorted).

    Returns
    -------
    str
        The packet, ``<?xpacket begin=…?>`` to ``<?xpacket end="r"?>``.

    Examples
    --------
    >>> "<anodic:thickness_nm>140</anodic:thickness_nm>" in xmp_packet("S001", "Ti", {"thickness_nm": 140})
    True
    """
    props = "".join(f"\n   <anodic:{k}>{escape(str(v))}</anodic:{k}>" for k, v in sorted((properties or {}).items()))
    return (
        '<?xpacket begin="\ufeff" id="W5M0MpCehiHzreSzNTczkc9d"?>\n'
        '<x:xmpmeta xmlns:x="adobe:ns:meta/">\n'
        ' <rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">\n'
        '  <rdf:Description rdf:about=""\n'
        '    xmlns:dc="http://purl.org/dc/elements/1.1/"\n'
        f'    xmlns:anodic="{SWATCH_XMP_NS}">\n'
        f'   <dc:title><rdf:Alt><rdf:li xml:lang="x-default">{escape(title)}</rdf:li></rdf:Alt></dc:title>\n'
        f'   <dc:description><rdf:Alt><rdf:li xml:lang="x-default">{escape(description)}</rdf:li></rdf:Alt>'
        f'</dc:description>{props}\n'
        '  </rdf:Description>\n'
        ' </rdf:RDF>\n'
        '</x:xmpmeta>\n'
        '<?xpacket end="r"?>'
    )


def finish_png(blob: bytes, xmp: str | None = None, dpi: float | None = None, intent: int = SRGB_INTENT) -> bytes:
    """The PNG ``blob`` with its text in iTXt (UTF-8), the XMP packet, the sRGB ``intent`` and a resolution.

    Parameters
    ----------
    blob : bytes
        A PNG as OpenImageIO wrote it.
    xmp : str, optional
        An XMP packet (:func:`xmp_packet`), written before the first IDAT.
    dpi : float, optional
        Resolution, dots per inch (a ``pHYs`` chunk in pixels per metre).
    intent : int
        The sRGB chunk's rendering intent: :data:`SRGB_INTENT` (0, perceptual) for images,
        :data:`CHIP_SRGB_INTENT` (1, relative colorimetric) for colour chips.

    Returns
    -------
    bytes
        The rewritten PNG (OpenImageIO's empty ``eXIf`` and zero ``oFFs`` dropped); deterministic.

    References
    ----------
    :cite:`W3C2025` (iTXt, sRGB, pHYs).
    """
    out = [PNG_SIGNATURE]
    for kind, data in _chunks(blob):
        if kind == b"tEXt":
            key, _, text = data.partition(b"\0")
            out.append(_itxt(key.decode("latin-1"), text.decode("utf-8")))
            continue
        if kind == b"sRGB":
            data = bytes([intent])
        elif (kind == b"eXIf" and len(data) <= 14) or (kind in (b"oFFs", b"pHYs")
                                                         and (kind == b"pHYs" or not any(data[:8]))):
            # an empty eXIf (a TIFF header and an IFD without entries), or OIIO's own oFFs/pHYs
            continue
        elif kind == b"IDAT" and out[-1][4:8] != b"IDAT":
            if dpi is not None:
                ppm = round(float(dpi) / _INCH_M)
                out.append(_chunk(b"pHYs", struct.pack(">IIB", ppm, ppm, 1)))
            if xmp is not None:
                out.append(_itxt(XMP_KEYWORD, xmp, compress=False))
        out.append(_chunk(kind, data))
    return b"".join(out)


def image_xmp(title: str, meta: dict) -> str:
    """The XMP packet of a render or an angular map from its metadata.

    Parameters
    ----------
    title : str
        The packet's title.
    meta : dict
        The image's metadata (``thickness_nm`` required; ``voltage_V``, ``film``, ``substrate``,
        ``illuminant``, ``observer``, ``model`` and ``Lab_reference`` when present).

    Returns
    -------
    str
        The XMP packet (XML text) for :func:`swatch.io.imageio.write_png`.
    """
    props = {k: meta[k] for k in ("thickness_nm", "voltage_V", "film", "substrate", "illuminant", "observer",
                                  "model") if meta.get(k) is not None}
    if meta.get("Lab_reference") is not None:
        props["Lab_reference"] = " ".join(f"{float(x):.2f}" for x in meta["Lab_reference"])
    description = (f"{meta.get('film')} on {meta.get('substrate')}, {float(meta['thickness_nm']):g} nm oxide. "
                   f"Lab_reference: CIELAB at 45:0 under {meta.get('illuminant')}, {meta.get('observer')} "
                   f"observer; pixels: sRGB from CIE 1931 2 deg colorimetry.")
    return xmp_packet(title, description, props)
