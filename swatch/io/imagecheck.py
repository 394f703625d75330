"""Whether an image file was written whole: libpng and OpenEXR may stop at a full disk's end
without reporting it (a 0-byte or truncated file that a later reader refuses), so every image is
checked before it is renamed into place (:func:`swatch.core.fileio.atomic_path`)."""
from __future__ import annotations

import OpenImageIO as oiio

__all__ = ["reads_back", "finished_whole"]


def reads_back(path, spec) -> bool:
    """Whether ``path`` opens with ``spec``'s size and channels and its last row reads.

    The last row is the data a writer stopped by a full disk never stored: a read of a few kilobytes,
    not of the whole image.

    Parameters
    ----------
    path : str or os.PathLike
        The file just written.
    spec : OpenImageIO.ImageSpec
        What was written.

    Returns
    -------
    bool
        False when it does not open, differs from ``spec`` or its last row fails to read.
    """
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        oiio.geterror()  # (clear it)
        return False
    try:
        got = inp.spec()
        if (got.width, got.height, got.nchannels) != (spec.width, spec.height, spec.nchannels):
            return False
        last = got.y + got.height - 1
        row = inp.read_scanlines(0, 0, last, last + 1, 0, 0, got.nchannels, "float")
        return row is not None and not inp.has_error
    finally:
        inp.close()


def finished_whole(path, spec, finish=None) -> bool:
    """Whether the image just written at ``path`` is whole; ``finish(bytes) -> bytes`` (the PNG chunk
    rewrite, which parses every chunk and its CRC: ValueError for a cut file) is applied when given.

    Parameters
    ----------
    path : pathlib.Path
        The temporary file.
    spec : OpenImageIO.ImageSpec
        What was written.
    finish : callable or None
        Rewrites the file's bytes; without it the file is read back (:func:`reads_back`).

    Returns
    -------
    bool
        True when whole (and rewritten by ``finish``); False for a cut file.
    """
    if finish is None:
        return reads_back(path, spec)
    try:
        blob = finish(path.read_bytes())
    except ValueError:  # what the writer left is not a whole image
        return False
    path.write_bytes(blob)
    return True
