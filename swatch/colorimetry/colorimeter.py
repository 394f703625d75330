"""Colorimetry through colour-science: spectra -> XYZ -> CIELAB / LCh -> display RGB, and ΔE.

A :class:`Colorimeter` is built once for a wavelength grid, illuminant and observer. Its weights (W, 3) come from
colour-science itself: ``colour.msds_to_XYZ`` (ASTM E308, ``colour.sd_to_XYZ``'s default method) on the grid's unit
impulses; the conversion being linear, ``R @ weights`` equals ``colour.sd_to_XYZ`` of any spectrum R on the grid.
XYZ has Y = 100 for the perfect reflecting diffuser (colour-science's scale); CIELAB uses the illuminant's own
white under the chosen observer.

Display RGB (sRGB, Display P3, ACEScg) is defined on CIE 1931 2° colorimetry (IEC 61966-2-1), whatever observer
the Lab numbers use: every RGB value comes from the spectrum through :attr:`Colorimeter.display_colorimeter` (same
grid and illuminant, 2°: :meth:`~Colorimeter.display_XYZ`, then :meth:`~Colorimeter.display`).

References
----------
.. [1] :cite:`Carter2018`: observers, illuminants, CIELAB.
.. [2] :cite:`ASTME308`: the weights.
.. [3] :cite:`IEC1999`: sRGB on CIE 1931 2°.
.. [4] :cite:`Sharma2005b`.
"""
from __future__ import annotations

import difflib
import functools
import warnings

import colour
import numpy as np

from swatch.colorimetry.grid import ASTM_E308_STEPS_NM, GRID_TOLERANCE_NM, astm_e308_grid
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_LAB_AB
from swatch.core.ranges import parse_hex

__all__ = ["OBSERVERS", "DISPLAY_OBSERVER", "RGB_SPACES", "check_rgb_space", "Colorimeter", "get_colorimeter",
           "illuminant_names", "delta_E_ab", "delta_E_00", "Lab_to_LCh", "srgb_hex", "hex_to_Lab_2deg", "parse_Lab"]

OBSERVERS = {
    "10": "CIE 1964 10 Degree Standard Observer",
    "2": "CIE 1931 2 Degree Standard Observer",
}
RGB_SPACES = {"srgb": "sRGB", "display-p3": "Display P3", "acescg": "ACEScg"}
#: The observer display RGB is defined on (sRGB: IEC 61966-2-1 uses CIE 1931 2° colorimetry).
DISPLAY_OBSERVER = "2"


def check_rgb_space(space: str) -> str:
    """The key of an RGB space of :data:`RGB_SPACES` (``srgb``, ``display-p3``, ``acescg``).

    Parameters
    ----------
    space : str
        Case-insensitive name.

    Returns
    -------
    str
        The lower-case key.

    Raises
    ------
    SwatchError
        For an unknown space.
    """
    key = str(space).lower()
    if key not in RGB_SPACES:
        raise SwatchError(f"unknown RGB space {space!r}; use one of {', '.join(RGB_SPACES)}")
    return key


def illuminant_names() -> list[str]:
    """The illuminant names colour-science has spectra for.

    Returns
    -------
    list of str
        The keys of ``colour.SDS_ILLUMINANTS``, sorted.
    """
    return sorted(colour.SDS_ILLUMINANTS.keys())


def _observer_name(observer) -> str:
    key = str(observer).strip().lower().replace("°", "").replace("deg", "").strip()
    if key in OBSERVERS:
        return OBSERVERS[key]
    for name in OBSERVERS.values():
        if key == name.lower():
            return name
    raise SwatchError(f"unknown observer {observer!r}; use 10 (CIE 1964 10°) or 2 (CIE 1931 2°)")


def _illuminant_name(illuminant: str) -> str:
    for name in colour.SDS_ILLUMINANTS:
        if name.lower() == str(illuminant).strip().lower():
            return name
    key = str(illuminant).strip().upper()
    near = [n for n in illuminant_names() if n.upper().replace("FL", "F") == key.replace("FL", "F")]
    near = near or difflib.get_close_matches(str(illuminant).strip(), illuminant_names(), n=1, cutoff=0.75)
    if near:  # F11 is colour-science's FL11
        raise SwatchError(f"unknown illuminant {illuminant!r}; did you mean {near[0]!r}?")
    raise SwatchError(
        f"unknown illuminant {illuminant!r}; use one of colour-science's: "
        + ", ".join(n for n in illuminant_names() if len(n) <= 6)
        + " ..."
    )


class Colorimeter:
    """Converts reflectance spectra on one wavelength grid to colour coordinates.

    Parameters
    ----------
    wavelength_nm : array_like, shape (W,), nm
        An even 1, 5, 10 or 20 nm grid of at least 6 samples inside the observer's range (ASTM E308).
    illuminant : str
        A colour-science illuminant name (D65, D50, A, FL2, ...), case-insensitive.
    observer : {"10", "2"}
        CIE 1964 10° or CIE 1931 2° standard observer.

    Attributes
    ----------
    weights : numpy.ndarray, shape (W, 3)
        ASTM E308 tristimulus weights from ``colour.msds_to_XYZ`` on unit impulses:
        ``XYZ = R @ weights`` equals ``colour.sd_to_XYZ`` (Y = 100 for R = 1).
    white_XYZ : numpy.ndarray, shape (3,)
        The perfect reflecting diffuser under the illuminant.
    white_xy : numpy.ndarray, shape (2,)
        Its chromaticity (the CIELAB reference white).
    """

    def __init__(self, wavelength_nm, illuminant: str = "D65", observer="10"):
        wl = np.asarray(wavelength_nm, dtype=np.float64)
        if wl.ndim != 1 or wl.size < 6:
            raise SwatchError("colorimetry needs a wavelength grid of at least 6 samples")
        steps = np.diff(wl)
        step = float(steps[0])
        if not np.allclose(steps, step) or not any(np.isclose(step, s) for s in ASTM_E308_STEPS_NM):
            raise SwatchError("colorimetry needs an evenly spaced 1, 5, 10 or 20 nm grid (ASTM E308)")
        if not np.isclose(wl[0] / step, round(float(wl[0] / step)), rtol=0.0, atol=1e-6):
            raise SwatchError(f"colorimetry needs a grid on the ASTM E308 tables' wavelengths (a start that is a "
                              f"multiple of the {step:g} nm step), got a start of {wl[0]:g} nm; e.g. 380:780:5")
        exact = astm_e308_grid(wl)  # the grid colour-science integrates on (its steps exactly equal)
        if exact is None:
            raise SwatchError(f"colorimetry needs an evenly spaced 1, 5, 10 or 20 nm grid (ASTM E308), every "
                              f"wavelength within {GRID_TOLERANCE_NM:g} nm of it; {wl[0]:g}–{wl[-1]:g} nm "
                              f"drifts off the {step:g} nm grid")
        self.observer_name = _observer_name(observer)
        self.illuminant_name = _illuminant_name(illuminant)
        cmfs = colour.MSDS_CMFS[self.observer_name]
        lo, hi = cmfs.shape.start, cmfs.shape.end
        if wl[0] < lo or wl[-1] > hi:
            raise SwatchError(
                f"wavelength grid {wl[0]:g}–{wl[-1]:g} nm is outside the observer's range {lo:g}–{hi:g} nm"
            )
        self.wavelength_nm = wl
        self.observer = "10" if "1964" in self.observer_name else "2"
        self.illuminant = self.illuminant_name
        self.cmfs = cmfs
        self.illuminant_sd = colour.SDS_ILLUMINANTS[self.illuminant_name]
        basis = colour.MultiSpectralDistributions(np.eye(wl.size), exact)
        with warnings.catch_warnings():
            # ASTM E308 aligns the spectra to its practice range (and says so); that is exactly
            # what colour.sd_to_XYZ does to a single spectrum, which these weights reproduce.
            warnings.simplefilter("ignore", colour.utilities.ColourRuntimeWarning)
            #: (W, 3) weights: XYZ = R @ weights, Y = 100 for R = 1.
            self.weights = np.ascontiguousarray(
                colour.msds_to_XYZ(basis, cmfs, self.illuminant_sd, method="ASTM E308")
            )
        if self.weights.shape != (wl.size, 3):  # (the tables did not cover the grid point for point)
            raise SwatchError(f"colorimetry: the ASTM E308 tables do not cover the grid {wl[0]:g}–{wl[-1]:g} nm "
                              f"at {step:g} nm point for point; e.g. 380:780:5")
        self.white_XYZ = self.weights.sum(axis=0)
        self.white_xy = colour.XYZ_to_xy(self.white_XYZ / 100.0)

    # -- conversions (all vectorised over leading axes) --------------------------------------
    def XYZ(self, reflectance) -> np.ndarray:
        """Tristimulus values of reflectance spectra: one matrix product.

        Parameters
        ----------
        reflectance : array_like, shape (..., W)
            Reflectance factors (fraction, 1 = perfect white) on the grid.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            CIE XYZ under the illuminant and observer, Y = 100 for R = 1.
        """
        return np.asarray(reflectance, dtype=np.float64) @ self.weights

    def Lab(self, XYZ) -> np.ndarray:
        """CIELAB relative to the illuminant's white under this observer.

        Parameters
        ----------
        XYZ : array_like, shape (..., 3)
            Tristimulus values, Y = 100 for the white.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            L* (0–100 for reflectors), a*, b*.
        """
        return colour.XYZ_to_Lab(np.asarray(XYZ) / 100.0, self.white_xy)

    def Lab_to_XYZ(self, Lab) -> np.ndarray:
        """The inverse of :meth:`Lab`.

        Parameters
        ----------
        Lab : array_like, shape (..., 3)
            CIELAB relative to this colorimeter's white.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            XYZ with Y = 100 for the white.
        """
        return colour.Lab_to_XYZ(np.asarray(Lab), self.white_xy) * 100.0

    def spectrum_Lab(self, reflectance) -> np.ndarray:
        """CIELAB of reflectance spectra: :meth:`Lab` of :meth:`XYZ`.

        Parameters
        ----------
        reflectance : array_like, shape (..., W)
            Reflectance factors on the grid.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            L*, a*, b* under this colorimeter's illuminant and observer.
        """
        return self.Lab(self.XYZ(reflectance))

    # -- display RGB (always from CIE 1931 2° colorimetry) ----------------------------------
    @property
    def display_colorimeter(self) -> Colorimeter:
        """The colorimeter display RGB is computed with: same grid and illuminant, CIE 1931 2°.

        Returns
        -------
        Colorimeter
            ``self`` when it is already 2°.
        """
        if self.observer == DISPLAY_OBSERVER:
            return self
        return get_colorimeter(self.wavelength_nm, self.illuminant, DISPLAY_OBSERVER)

    def display_XYZ(self, reflectance) -> np.ndarray:
        """CIE 1931 2° tristimulus values of reflectance spectra, the input of display RGB.

        Parameters
        ----------
        reflectance : array_like, shape (..., W)
            Reflectance factors on the grid.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            XYZ (2°, this illuminant), Y = 100 for R = 1.
        """
        return self.display_colorimeter.XYZ(reflectance)

    def rgb_linear(self, XYZ_2, space: str = "srgb") -> np.ndarray:
        """Linear RGB in ``space`` from CIE 1931 2° XYZ, the illuminant's white adapted to the space's (Bradford).

        Parameters
        ----------
        XYZ_2 : array_like, shape (..., 3)
            CIE 1931 2° XYZ (:meth:`display_XYZ`), Y = 100 for the white.
        space : {"srgb", "display-p3", "acescg"}
            The RGB space (its primaries and white; the default is sRGB), case-insensitive.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            Linear RGB, 1.0 = the white's Y; out-of-gamut colours have components outside [0, 1].
        """
        name = RGB_SPACES[check_rgb_space(space)]
        return colour.XYZ_to_RGB(
            np.asarray(XYZ_2) / 100.0,
            name,
            illuminant=self.display_colorimeter.white_xy,
            chromatic_adaptation_transform="Bradford",
        )

    def display(self, XYZ_2, space: str = "srgb") -> tuple[np.ndarray, np.ndarray]:
        """Display-encoded RGB and an in-gamut flag per colour, from CIE 1931 2° XYZ.

        Parameters
        ----------
        XYZ_2 : array_like, shape (..., 3)
            CIE 1931 2° XYZ (:meth:`display_XYZ`), Y = 100 for the white.
        space : {"srgb", "display-p3", "acescg"}
            The RGB space (its primaries, white and transfer function; the default is sRGB), case-insensitive.

        Returns
        -------
        encoded : numpy.ndarray, shape (..., 3)
            The space's transfer function applied to the linear RGB clipped to [0, 1].
        in_gamut : numpy.ndarray of bool, shape (...)
            All linear components within [-1e-3, 1 + 1e-3].
        """
        rgb = self.rgb_linear(XYZ_2, space)
        # The spaces' whitepoints are given to 4 digits, so the adapted perfect white lands
        # within 2e-4 of (1, 1, 1): allow 1e-3 (a quarter of one 8-bit code value).
        tol = 1e-3
        in_gamut = np.all((rgb >= -tol) & (rgb <= 1.0 + tol), axis=-1)
        name = RGB_SPACES[str(space).lower()]
        encoded = colour.RGB_COLOURSPACES[name].cctf_encoding(np.clip(rgb, 0.0, 1.0))
        return np.clip(encoded, 0.0, 1.0), in_gamut

    def reflectance_rgb(self, reflectance, space: str = "srgb") -> np.ndarray:
        """Linear RGB of reflectance spectra, by CIE 1931 2° colorimetry.

        Parameters
        ----------
        reflectance : array_like, shape (..., W)
            Reflectance factors (0–1) on the colorimeter's grid.
        space : str, optional
            ``srgb``, ``display-p3`` or ``acescg``.

        Returns
        -------
        numpy.ndarray, shape (..., 3)
            1.0 = white (unclipped).
        """
        return self.rgb_linear(self.display_XYZ(reflectance), space)

    def reflectance_display(self, reflectance, space: str = "srgb") -> tuple[np.ndarray, np.ndarray]:
        """Display-encoded RGB and in-gamut flags of reflectance spectra (CIE 1931 2°).

        Parameters
        ----------
        reflectance : array_like, shape (..., W)
            Reflectance factors (0–1) on the colorimeter's grid.
        space : str, optional
            ``srgb``, ``display-p3`` or ``acescg``.

        Returns
        -------
        encoded, in_gamut : numpy.ndarray, shape (..., 3) and (...)
            As :meth:`display`: encoded RGB clipped to [0, 1], and bool flags.
        """
        return self.display(self.display_XYZ(reflectance), space)


@functools.lru_cache(maxsize=32)
def _cached(grid: tuple, illuminant: str, observer: str) -> Colorimeter:
    return Colorimeter(np.array(grid), illuminant, observer)


def get_colorimeter(wavelength_nm, illuminant: str = "D65", observer="10") -> Colorimeter:
    """A cached :class:`Colorimeter` (the weights are computed once per grid, illuminant, observer).

    Parameters
    ----------
    wavelength_nm, illuminant, observer
        As :class:`Colorimeter`: the grid (nm), an illuminant name, ``"10"`` (CIE 1964 10°, the default) or
        ``"2"`` (CIE 1931 2°) for XYZ and Lab; display RGB is always 2° (:attr:`Colorimeter.display_colorimeter`).

    Returns
    -------
    Colorimeter
        The colorimeter of this grid, illuminant and observer (cached: an equal request returns it again).
    """
    return _cached(tuple(np.asarray(wavelength_nm, dtype=float).tolist()), str(illuminant), str(observer))


def delta_E_ab(Lab1, Lab2) -> np.ndarray:
    """CIE 1976 colour difference ΔE*ab (the paper's eq. 6), by colour-science.

    Calls ``colour.difference.delta_E_CIE1976`` directly, without ``colour.delta_E``'s dispatch (the fits' inner loop).

    Parameters
    ----------
    Lab1, Lab2 : array_like, shape (..., 3)
        CIELAB values; broadcast together.

    Returns
    -------
    numpy.ndarray, shape (...)
        Euclidean distance in L*a*b*.
    """
    return colour.difference.delta_E_CIE1976(np.asarray(Lab1), np.asarray(Lab2))


def delta_E_00(Lab1, Lab2) -> np.ndarray:
    """CIEDE2000 colour difference ΔE00, by colour-science (``colour.difference.delta_E_CIE2000``).

    Parameters
    ----------
    Lab1, Lab2 : array_like, shape (..., 3)
        CIELAB values; broadcast together.

    Returns
    -------
    numpy.ndarray, shape (...)
        ΔE00, dimensionless (CIEDE2000 with k_L = k_C = k_H = 1).
    """
    return colour.difference.delta_E_CIE2000(np.asarray(Lab1), np.asarray(Lab2))


def Lab_to_LCh(Lab) -> np.ndarray:
    """CIE LCh(ab): lightness, chroma and hue angle.

    Parameters
    ----------
    Lab : array_like, shape (..., 3)
        CIELAB values L*, a*, b*.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        L*, C*ab, h in degrees [0, 360).
    """
    return colour.Lab_to_LCHab(np.asarray(Lab))  # type: ignore[attr-defined]  # exported, not in colour's stubs


def srgb_hex(encoded_rgb) -> np.ndarray | str:
    """``#rrggbb`` strings of display-encoded RGB values.

    Parameters
    ----------
    encoded_rgb : array_like, shape (..., 3)
        Encoded values in [0, 1] (clipped), rounded to 8 bits.

    Returns
    -------
    str or numpy.ndarray of str, shape (...)
        One string for a single colour (shape (3,)), else an object array.
    """
    arr = np.asarray(encoded_rgb, dtype=np.float64)
    ints = np.round(np.clip(arr, 0.0, 1.0) * 255.0).astype(np.int64)
    flat = ints.reshape(-1, 3)
    out = np.array(["#{:02x}{:02x}{:02x}".format(*v) for v in flat], dtype=object)
    return out[0] if arr.ndim == 1 else out.reshape(arr.shape[:-1])


def hex_to_Lab_2deg(hex_code: str, colorimeter: Colorimeter) -> np.ndarray:
    """CIELAB of an sRGB hex colour under the colorimeter's illuminant and the CIE 1931 2° observer.

    Parameters
    ----------
    hex_code : str
        ``RRGGBB`` (a leading ``#`` is allowed).
    colorimeter : Colorimeter
        Gives the illuminant (its 2° counterpart is used).

    Returns
    -------
    numpy.ndarray, shape (3,)
        L*, a*, b* (2° observer: sRGB is defined on it, and a hex code has no spectrum, so no 10° Lab).
    """
    rgb = colour.RGB_COLOURSPACES["sRGB"].cctf_decoding(parse_hex(hex_code))
    cm2 = colorimeter.display_colorimeter
    XYZ = colour.RGB_to_XYZ(rgb, "sRGB", illuminant=cm2.white_xy, chromatic_adaptation_transform="Bradford")
    return cm2.Lab(XYZ * 100.0)


def parse_Lab(text: str, what: str = "Lab") -> np.ndarray:
    """CIELAB from the text ``L,a,b``.

    Parameters
    ----------
    text : str
        Three numbers separated by commas or whitespace, finite, L in [0, 100].
    what : str
        The option or field name, for the error message.

    Returns
    -------
    numpy.ndarray, shape (3,)
        L*, a*, b* as float64 (L* in [0, 100], a* and b* within ±``MAX_LAB_AB``).
    """
    # "60,5,30", "60, 5, 30" or "60 5 30" (as the catalog page takes it)
    t = str(text).strip()
    parts = [p.strip() for p in t.split(",")] if "," in t else t.split()
    try:
        if len(parts) != 3:
            raise ValueError
        vals = np.array([float(p) for p in parts])
    except ValueError:
        raise SwatchError(f"{what} {text!r} must be three numbers L,a,b, e.g. 45,-5,-30") from None
    if not np.all(np.isfinite(vals)) or not 0 <= vals[0] <= 100 or not np.all(np.abs(vals[1:]) <= MAX_LAB_AB):
        raise SwatchError(f"{what} needs finite values with L between 0 and 100 and a, b within ±{MAX_LAB_AB:g}")
    return vals
