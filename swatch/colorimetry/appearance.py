"""Thickness → colour: the half-vector spectrum of each thickness at one geometry, in colour terms.

References
----------
.. [1] :cite:`Fujii2019`: eqs. 2–5.
.. [2] :cite:`Carter2018`: CIELAB, LCh.
.. [3] :cite:`IEC1999`: sRGB.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.colorimeter import Colorimeter, Lab_to_LCh, delta_E_ab, srgb_hex
from swatch.core.limits import MAX_RUN_BYTES, plan_rows
from swatch.physics.model import Coating

__all__ = ["ThicknessColours", "thickness_colours"]

#: Working bytes per (thickness, layer, wavelength) of the half-vector evaluation (complex transfer
#: terms of both polarisations and their temporaries), with a margin.
_BYTES_PER_LAYER_SAMPLE = 1024


@dataclass(frozen=True)
class ThicknessColours:
    """Colours of a series of thicknesses at one light/view geometry (arrays with N rows).

    Attributes
    ----------
    thickness_nm : numpy.ndarray
        The film thicknesses, nm, shape (N,).
    theta_d_deg : float
        The facet incidence angle θ_d of the geometry, degrees.
    reflectance : numpy.ndarray
        Spectral reflectance at θ_d, shape (N, W).
    XYZ, Lab, LCh : numpy.ndarray
        Tristimulus values (Y = 100 for a perfect reflector), CIELAB and its LCh, under the
        colorimeter's illuminant and observer, shape (N, 3).
    srgb : numpy.ndarray
        Display-encoded sRGB clipped to [0, 1] (CIE 1931 2°), shape (N, 3).
    in_srgb_gamut, in_display_p3_gamut : numpy.ndarray
        Whether each colour is inside the gamut, bool, shape (N,).
    srgb_hex : numpy.ndarray
        ``#rrggbb`` of ``srgb``, shape (N,).
    delta_E_ab_to_previous : numpy.ndarray
        ΔE*ab to the row before, NaN for the first, shape (N,).
    """

    thickness_nm: np.ndarray
    theta_d_deg: float
    reflectance: np.ndarray  # (N, W)
    XYZ: np.ndarray  # (N, 3), Y = 100 for a perfect reflector
    Lab: np.ndarray
    LCh: np.ndarray
    srgb: np.ndarray  # display-encoded, clipped to [0, 1]
    in_srgb_gamut: np.ndarray  # (N,) bool
    srgb_hex: np.ndarray  # (N,) str
    in_display_p3_gamut: np.ndarray  # (N,) bool
    delta_E_ab_to_previous: np.ndarray  # (N,), NaN for the first row

    def rows(self) -> list[dict]:
        """JSON-ready rows (the public contract of ``swatch color --json``).

        Returns
        -------
        list of dict
            One per thickness: thickness, XYZ, Lab, LCh, sRGB and hex, gamut flags, ΔE*ab to the previous row.
        """
        columns = zip(self.thickness_nm.tolist(), self.XYZ.tolist(), self.Lab.tolist(), self.LCh.tolist(),
                      self.srgb_hex.tolist(), self.in_srgb_gamut.tolist(), self.in_display_p3_gamut.tolist(),
                      self.delta_E_ab_to_previous.tolist(), strict=True)  # (Python floats, bools, str: one pass)
        return [{"thickness_nm": d, "XYZ": XYZ, "Lab": Lab, "LCh": LCh, "srgb_hex": str(hx), "in_srgb_gamut": bool(g),
                 "in_display_p3_gamut": bool(p3), "delta_E_ab_to_previous": None if math.isnan(dE) else dE}
                for d, XYZ, Lab, LCh, hx, g, p3, dE in columns]


def thickness_colours(
    thickness_nm,
    light_deg: float,
    view_deg: float,
    coating: Coating,
    colorimeter: Colorimeter,
    light_azimuth_deg: float = 0.0,
    view_azimuth_deg: float | None = None,
) -> ThicknessColours:
    """The colours of a series of thicknesses at one light/view geometry.

    All thicknesses are evaluated in one vectorised call of the half-vector model and turned into
    colour by one matrix product (the colorimeter's tristimulus weights, ASTM E308).

    Parameters
    ----------
    thickness_nm : array_like, shape (N,)
        Film thicknesses, nm.
    light_deg, view_deg : float
        Polar angles of the light and the view from the surface normal, degrees, in [0, 90).
    coating : Coating
        Film, substrate and wavelength grid.
    colorimeter : Colorimeter
        Illuminant and observer of the Lab values (sRGB is always from CIE 1931 2°).
    light_azimuth_deg, view_azimuth_deg : float
        Azimuths, degrees; ``view_azimuth_deg`` None puts the view opposite the light (in plane).

    Returns
    -------
    ThicknessColours
        Reflectance (N, W), XYZ (N, 3) with Y = 100 for a perfect reflector, Lab, LCh, display sRGB,
        gamut flags, hex codes and ΔE*ab to the previous row.

    Examples
    --------
    >>> from swatch.colorimetry.colorimeter import get_colorimeter
    >>> from swatch.physics.model import get_coating
    >>> c = get_coating()
    >>> tc = thickness_colours([50.8, 140.0], 45.0, 0.0, c, get_colorimeter(c.wavelength_nm))
    >>> tc.Lab.shape
    (2, 3)
    """
    d = np.atleast_1d(np.asarray(thickness_nm, dtype=np.float64))
    # in chunks of thicknesses planned against the run's budget (a 0.01 nm range over 1000 nm under
    # overcoats needed 8.7 GB at once): each layer's transfer terms are complex, per wavelength
    # (a chunk's Reflectance holds R_s, R_p and both complex amplitudes, 48 bytes a sample: only its R is
    # kept, in the one table R, which the budget counts first: 2.5 GB at the 1 nm grid when all were kept)
    layers = 1 + len(getattr(coating, "overcoats", ()))
    W = coating.wavelength_nm.size
    table_bytes = d.size * W * 8
    plan_rows(table_bytes, "the colour table", "fewer thicknesses or a coarser wavelength grid")  # (refused beyond)
    rows = plan_rows(W * layers * _BYTES_PER_LAYER_SAMPLE, "the colour table",
                     budget=max(MAX_RUN_BYTES // 2 - table_bytes, 1))
    R = np.empty((d.size, W))
    theta_d: np.ndarray | float = 0.0
    for i in range(0, max(d.size, 1), rows):
        part, theta_d = coating.half_vector(d[i:i + rows], light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
        R[i:i + rows] = part.R
        del part
    XYZ = colorimeter.XYZ(R)
    Lab = colorimeter.Lab(XYZ)
    XYZ_2 = colorimeter.display_XYZ(R)  # display RGB is defined on CIE 1931 2° colorimetry
    srgb, gamut = colorimeter.display(XYZ_2, "srgb")
    _, gamut_p3 = colorimeter.display(XYZ_2, "display-p3")
    dE = np.full(d.shape, np.nan)
    if d.size > 1:
        dE[1:] = delta_E_ab(Lab[1:], Lab[:-1])
    return ThicknessColours(
        thickness_nm=d, theta_d_deg=float(theta_d), reflectance=R, XYZ=XYZ, Lab=Lab,
        LCh=Lab_to_LCh(Lab), srgb=srgb, in_srgb_gamut=gamut, srgb_hex=np.atleast_1d(srgb_hex(srgb)),
        in_display_p3_gamut=gamut_p3,
        delta_E_ab_to_previous=dE,
    )
