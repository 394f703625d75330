"""Spectral OpenEXR files of reflectance, in the layout of Fichet, Pacanowski & Wilkie (2021).

Reflective (dimensionless) spectra are channels named
``T.<wavelength>nm`` with a decimal **comma**, the value written like C++ ``std::to_string``
(six decimals), e.g. ``T.550,000000nm``; emissive spectra would be ``S0.<wavelength>nm``
(Stokes component 0). The layout's version attribute ``spectralLayoutVersion = "1.0"`` is set.

References
----------
A. Fichet, R. Pacanowski, A. Wilkie, "An OpenEXR Layout for Spectral Images", Journal of Computer
Graphics Techniques 10(3), 2021, https://jcgt.org/published/0010/03/01/.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from swatch.core.errors import SwatchError
from swatch.io.imageio import as_hwc, write_exr

__all__ = ["write_spectral_exr", "reflective_channel_name", "parse_spectral_channel"]

_SPECTRAL_RE = re.compile(
    r"^(?:(?P<stokes>S[0-3])|T)\.(?P<value>(\d+(,\d*)?|,\d+)([eE][+-]?\d+)?)"
    r"(?P<mult>Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(?P<unit>m|Hz)$"
)
_PREFIX_SCALE_M = {
    "Y": 1e24, "Z": 1e21, "E": 1e18, "P": 1e15, "T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "h": 1e2,
    "da": 1e1, "": 1.0, "d": 1e-1, "c": 1e-2, "m": 1e-3, "u": 1e-6, "n": 1e-9, "p": 1e-12,
}


def reflective_channel_name(wavelength_nm: float) -> str:
    """The reflective channel name of Fichet et al. (JCGT 2021): ``T.`` + the wavelength with a decimal comma.

    Parameters
    ----------
    wavelength_nm : float
        The wavelength, nm.

    Returns
    -------
    str
        ``T.<nm with six decimals, comma>nm``.

    References
    ----------
    :cite:`Fichet2021`.

    Examples
    --------
    >>> reflective_channel_name(550)
    'T.550,000000nm'
    """
    return "T." + f"{float(wavelength_nm):.6f}".replace(".", ",") + "nm"


def parse_spectral_channel(name: str):
    """The kind and wavelength of a spectral channel name of the Fichet et al. (2021) layout.

    Parameters
    ----------
    name : str
        E.g. ``T.550,000000nm``, ``S0.0,55um``, ``T.545,077196THz``.

    Returns
    -------
    (str, float) or None
        ``"T"`` (reflective) or ``"S0"``…``"S3"`` (emissive Stokes), and the wavelength, nm; None otherwise.

    Examples
    --------
    >>> parse_spectral_channel("T.550,000000nm"), parse_spectral_channel("R")
    (('T', 550.0), None)
    """
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
    """A spectral EXR of reflectance (Fichet et al. 2021 layout, ``spectralLayoutVersion`` 1.0).

    Parameters
    ----------
    path : str or path-like
        The file to write (``.exr``); renamed into place when whole.
    reflectance : array_like, shape (H, W, Wl)
        Reflectance factors (dimensionless).
    wavelength_nm : array_like, shape (Wl,)
        The channels' wavelengths, nm, increasing.
    metadata : dict, optional
        ``swatch:`` attributes, as :func:`swatch.io.imageio.write_exr`.
    rgb : array_like, shape (H, W, 3), optional
        Linear RGB in ``space`` as ``R``, ``G``, ``B`` beside the spectral channels (what viewers show).
    space : str
        Names the RGB preview's primaries (``chromaticities``).
    half : bool
        16-bit floats; default 32-bit, as the layout's reference writer.

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """
    arr = as_hwc(reflectance, "spectral reflectance")
    wl = np.asarray(wavelength_nm, dtype=np.float64).reshape(-1)
    if wl.size != arr.shape[2]:
        raise SwatchError(f"spectral EXR has {arr.shape[2]} bands but {wl.size} wavelengths")
    names = [reflective_channel_name(x) for x in wl]
    if rgb is not None:
        rgb = as_hwc(rgb, "preview RGB")
        if rgb.shape != (*arr.shape[:2], 3):
            raise SwatchError("the spectral EXR's RGB preview must be (H, W, 3) like the spectra")
        arr = np.concatenate([np.asarray(rgb, dtype=np.float32), arr.astype(np.float32)], axis=2)
        names = ["R", "G", "B", *names]
    return write_exr(path, arr, metadata, channel_names=names, space=space if rgb is not None else None, half=half,
                     raw_attributes={"spectralLayoutVersion": "1.0"})
