"""One document, one observer: how colours given without a spectrum cross between observers.

A swatch document (a spec, a QC report, a match) states its CIELAB under one illuminant and one
observer (the spec's: D65 and CIE 1964 10° by default). Two kinds of colour arrive without a
spectrum and must cross observers:

* an sRGB **hex target** is defined on CIE 1931 2° colorimetry under D65 (IEC 61966-2-1), and has
  no 10° value of its own;
* a part measured as **CIELAB only** (no spectra) under the document's observer must be drawn as a
  display chip, and display RGB is 2° colorimetry too.

The bridge: the colour is taken to be the surface of the **smoothest reflectance** that has its
tristimulus values — the least sum of squared neighbour differences, the objective of Meng et al.
(2015), "Physically Meaningful Rendering using Tristimulus Colours" (``colour.recovery``'s
``Meng 2015``), without its 0–1 bounds so that it has a closed form and is linear. The smooth
spectra of sRGB under D65 / 2° form a 3-dimensional family (:func:`smooth_basis`); a colour is the
member of that family with the given tristimulus values under any illuminant and observer, so:

* hex → document: sRGB → 2° XYZ (D65) → the smooth spectrum → XYZ and CIELAB under the document's
  illuminant and observer (:func:`hex_to_document_Lab`); under D65 / 2° it is the hex's own CIELAB.
* document CIELAB → display: the member of the family with that CIELAB, drawn exactly as the model's
  spectra are (:meth:`swatch.colorimetry.colorimeter.Colorimeter.reflectance_display`, 2°),
  :func:`document_Lab_display`; the two directions are inverse to each other.

It is a convention (a colour without a spectrum has no value under another observer); its size is
the observer metamerism of a smooth surface, typically below 1 ΔE00 for the colours of anodised
titanium. Every document says it uses it (:data:`HEX_CONVENTION`).

References
----------
.. [1] :cite:`Meng2015c`: the smoothest reflectance.
.. [2] :cite:`IEC1999`: sRGB on CIE 1931 2° under D65.
.. [3] :cite:`Carter2018`: the CIE 1931 2° and CIE 1964 10° observers.
"""
from __future__ import annotations

import functools

import colour
import numpy as np

from swatch.colorimetry.colorimeter import DISPLAY_OBSERVER, Colorimeter, get_colorimeter
from swatch.core.ranges import parse_hex

__all__ = ["HEX_CONVENTION", "LAB_CHIP_CONVENTION", "smooth_basis", "srgb_to_document_XYZ", "hex_to_document_Lab",
           "hex_display", "document_Lab_display"]

#: How a hex target is brought into a document's observer (printed with it).
HEX_CONVENTION = ("sRGB hex (CIE 1931 2°, D65) brought into the document's illuminant and observer through its "
                  "smoothest reflectance (Meng et al. 2015, unbounded)")
#: How a CIELAB-only measurement is drawn as a chip (printed with it).
LAB_CHIP_CONVENTION = ("CIELAB only: drawn through its smoothest reflectance (Meng et al. 2015, unbounded), "
                       "displayed by CIE 1931 2° sRGB")
#: The illuminant and observer sRGB is defined on.
SRGB_ILLUMINANT = "D65"


@functools.lru_cache(maxsize=8)
def _basis(grid: tuple) -> np.ndarray:
    wl = np.asarray(grid)
    A = get_colorimeter(wl, SRGB_ILLUMINANT, DISPLAY_OBSERVER).weights.T  # (3, W): XYZ = A @ R
    W = wl.size
    D = np.diff(np.eye(W), axis=0)  # first differences (W-1, W)
    kkt = np.zeros((W + 3, W + 3))
    kkt[:W, :W] = 2.0 * D.T @ D
    kkt[:W, W:] = A.T
    kkt[W:, :W] = A
    rhs = np.zeros((W + 3, 3))
    rhs[W:] = np.eye(3)
    K = np.linalg.solve(kkt, rhs)[:W]  # (W, 3): R = K @ XYZ_2 (Y = 100 for the white)
    K.setflags(write=False)
    return K


def smooth_basis(wavelength_nm) -> np.ndarray:
    """The smoothest reflectance with given D65 / 2° tristimulus values, as a linear map.

    Minimises ``sum(diff(R)**2)`` subject to ``R @ weights = XYZ`` (the CIE 1931 2° weights of
    :class:`swatch.colorimetry.colorimeter.Colorimeter` under D65): Meng et al. (2015)'s objective
    without its bounds, solved in closed form (the KKT system). ``R = XYZ @ K.T``; the white
    (``XYZ`` of R = 1) gives R = 1 exactly.

    Parameters
    ----------
    wavelength_nm : array_like, shape (W,)
        The grid, nm.

    Returns
    -------
    numpy.ndarray, shape (W, 3)
        ``K``: reflectance per unit of X, Y, Z (Y = 100 for the white).
    """
    return _basis(tuple(float(v) for v in np.asarray(wavelength_nm, dtype=np.float64)))


def _to_document(cm: Colorimeter) -> np.ndarray:
    """(3, 3): XYZ under ``cm`` of the smooth spectrum with 2° D65 XYZ (column vectors)."""
    return cm.weights.T @ smooth_basis(cm.wavelength_nm)


def srgb_to_document_XYZ(rgb_linear, cm: Colorimeter) -> np.ndarray:
    """XYZ under the document's illuminant and observer of linear sRGB (the bridge above).

    Parameters
    ----------
    rgb_linear : array_like, shape (..., 3)
        Linear sRGB, 1.0 = white.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The document's colorimeter.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        XYZ, Y = 100 for the white (linear in ``rgb_linear``: the catalog page takes it as a matrix).
    """
    cm2 = get_colorimeter(cm.wavelength_nm, SRGB_ILLUMINANT, DISPLAY_OBSERVER)
    XYZ_2 = 100.0 * colour.RGB_to_XYZ(np.asarray(rgb_linear, dtype=np.float64), "sRGB", illuminant=cm2.white_xy,
                                      chromatic_adaptation_transform="Bradford")
    return XYZ_2 @ _to_document(cm).T


def hex_to_document_Lab(hex_code: str, cm: Colorimeter) -> np.ndarray:
    """CIELAB of an sRGB hex colour under the document's illuminant and observer (the bridge above).

    Parameters
    ----------
    hex_code : str
        ``RRGGBB`` (a leading ``#`` allowed).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The document's colorimeter (grid, illuminant, observer).

    Returns
    -------
    numpy.ndarray, shape (3,)
        L*, a*, b* under ``cm``'s illuminant and observer; under D65 / 2° the hex's own CIELAB.
    """
    rgb = colour.RGB_COLOURSPACES["sRGB"].cctf_decoding(parse_hex(hex_code))
    return cm.Lab(srgb_to_document_XYZ(rgb, cm))


def document_Lab_display(Lab, cm: Colorimeter, space: str = "srgb") -> tuple[np.ndarray, np.ndarray]:
    """Display RGB of CIELAB given under the document's colorimeter, with in-gamut flags.

    The smooth spectrum of the family of :func:`smooth_basis` that has this CIELAB under ``cm``, drawn
    as the model's spectra are (2° colorimetry, ``cm``'s illuminant, Bradford to the space's white).
    Under D65 / 2° this is the plain CIELAB → XYZ → sRGB conversion.

    Parameters
    ----------
    Lab : array_like, shape (..., 3)
        CIELAB under ``cm``'s illuminant and observer.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The document's colorimeter (its grid, illuminant and observer): the Lab's own.
    space : {"srgb", "display-p3", "acescg"}
        The display RGB space (default sRGB).

    Returns
    -------
    encoded : numpy.ndarray, shape (..., 3)
        Display-encoded RGB, 0–1 (clipped).
    in_gamut : numpy.ndarray of bool, shape (...)
        Whether the colour is inside the space's gamut (otherwise the chip is only the nearest clip).
    """
    XYZ = cm.Lab_to_XYZ(np.asarray(Lab, dtype=np.float64))
    XYZ_basis = np.linalg.solve(_to_document(cm), np.moveaxis(XYZ, -1, 0).reshape(3, -1))  # D65 / 2° coordinates
    R = (smooth_basis(cm.wavelength_nm) @ XYZ_basis).T.reshape(*XYZ.shape[:-1], -1)
    return cm.reflectance_display(R, space)


def hex_display(hex_code: str) -> str:
    """The hex code normalised: ``#rrggbb``.

    Parameters
    ----------
    hex_code : str
        Six hex digits ``RRGGBB``, optionally after ``#``, any case.

    Returns
    -------
    str
        ``#`` and the six digits in lower case (``#1f4e9a``).
    """
    parse_hex(hex_code)
    return "#" + str(hex_code).strip().lstrip("#").lower()
