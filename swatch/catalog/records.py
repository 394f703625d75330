"""Swatch records: the numbers of every swatch of a catalog, computed in one vectorised pass.

For each thickness: CIELAB / LCh / sRGB at the reference geometry (default 45°:0°), CIELAB at
each multi-angle geometry (illumination 45°, aspecular -15° ... 110°), ΔE*ab and ΔE2000 to the
neighbouring swatches, and the process window.

Colour model: the paper's half-vector model (Fujii et al., eqs. 2–5) — the spectral reflectance
factor of the film on the facet whose normal is the half vector of light and view, i.e. the
Airy reflectance at ``theta_d = 1/2 arccos(l.v)``, taken as the reflectance factor of the
swatch at that geometry (no intensity / distribution term: the Lab describes the interference
colour that the tilted facets show, as in the paper's Table 3 comparison).

Process window: the largest thickness deviations ``-δ-`` / ``+δ+`` such that the colour
difference between the colour at ``d ± δ`` and the colour at the nominal ``d`` (both at the
reference geometry) stays within the tolerance for every deviation up to it, the difference
computed in the tolerance's own metric (a CSAJ grade bounds ΔE*ab; a written tolerance such as
``{ metric = "dE00", max = 2.0 }`` bounds ΔE2000). Voltage window: the thickness window's edges
through the profile's growth law, one slope or two with a knee (:func:`window_voltage_V`; none when
the process profile has no rate).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from swatch.catalog.context import CatalogContext
from swatch.catalog.layout import SHEETS
from swatch.catalog.record import Neighbours, ProcessWindowEntry, SwatchRecord
from swatch.colorimetry.colorimeter import Lab_to_LCh, delta_E_00, delta_E_ab, srgb_hex
from swatch.colorimetry.names import NEUTRAL_CHROMA, colour_name
from swatch.colorimetry.window import PROCESS_STEP_NM, geometry_reflectance, process_window, window_voltage_V

__all__ = ["CatalogData", "compute", "hue_family", "process_json", "process_window", "window_voltage_V",
           "PROCESS_STEP_NM", "HUE_FAMILIES"]

#: CIELAB hue-angle families (degrees, [start, end)); chroma below NEUTRAL_CHROMA is "neutral"
#: (80 nm of TiO2, C* 7.6, is a near-grey, not "cyan"), and pale yellow-greens (C* below
#: PALE_STRAW_CHROMA from 105° to 135°, the 85–100 nm straws) are "yellow", not "green".
HUE_FAMILIES = (
    ("red", 345.0, 35.0),
    ("orange", 35.0, 70.0),
    ("yellow", 70.0, 105.0),
    ("green", 105.0, 165.0),
    ("cyan", 165.0, 225.0),
    ("blue", 225.0, 290.0),
    ("purple", 290.0, 345.0),
)
PALE_STRAW_CHROMA = 35.0


def hue_family(chroma: float, hue_deg: float) -> str:
    """The CIELAB hue-angle family of a colour (:data:`HUE_FAMILIES`; ``neutral`` below
    :data:`swatch.colorimetry.names.NEUTRAL_CHROMA`, pale yellow-greens ``yellow``).

    Parameters
    ----------
    chroma : float
        C*ab.
    hue_deg : float
        h_ab, degrees.

    Returns
    -------
    str
        A family name of :data:`HUE_FAMILIES` (``red``, ``orange`` …) or ``neutral``.

    Examples
    --------
    >>> hue_family(40.0, 250.0), hue_family(2.0, 250.0), hue_family(20.0, 120.0)
    ('blue', 'neutral', 'yellow')
    """
    if chroma < NEUTRAL_CHROMA:
        return "neutral"
    h = hue_deg % 360.0
    if 105.0 <= h < 135.0 and chroma < PALE_STRAW_CHROMA:
        return "yellow"
    for name, lo, hi in HUE_FAMILIES:
        if (lo <= h < hi) if lo < hi else (h >= lo or h < hi):
            return name
    return "red"  # unreachable: the families cover the circle


@dataclass
class CatalogData:
    """Arrays for N swatches at the reference geometry, plus their typed records.

    Attributes
    ----------
    thickness_nm, voltage_V : numpy.ndarray, shape (N,)
        nm; V (NaN without a growth rate).
    wavelength_nm : numpy.ndarray, shape (W,)
        The colour grid, nm.
    reflectance : numpy.ndarray, shape (N, W)
        At the reference geometry.
    multi_reflectance : numpy.ndarray, shape (G, N, W)
        Reflectance factors at the G multi-angle geometries.
    Lab, LCh : numpy.ndarray, shape (N, 3)
        Under the catalog's illuminant and observer.
    Lab_D50_2 : numpy.ndarray, shape (N, 3)
        D50, CIE 1931 2° (ICC / ISO 13655).
    srgb_hex : list of str
        ``#rrggbb`` per swatch, sRGB from CIE 1931 2°.
    swatches : tuple of swatch.catalog.record.SwatchRecord
        The typed records, in catalog order.
    illuminant, observer : str
        colour-science's names.
    context : swatch.catalog.context.CatalogContext
        What the numbers were computed with.
    """

    thickness_nm: np.ndarray
    voltage_V: np.ndarray
    wavelength_nm: np.ndarray
    reflectance: np.ndarray  # (N, W) at the reference geometry
    multi_reflectance: np.ndarray  # (G, N, W)
    Lab: np.ndarray
    LCh: np.ndarray
    Lab_D50_2: np.ndarray  # (N, 3) at the reference geometry, D50 and CIE 1931 2° (ICC / ISO 13655)
    srgb_hex: list[str]
    swatches: tuple[SwatchRecord, ...]
    illuminant: str  # colour-science's name
    observer: str
    context: CatalogContext  # what the numbers were computed with (grid, coating, colorimeters, tolerance)

    @functools.cached_property
    def records(self) -> list[dict]:
        """The swatches as ``catalog.json`` writes them before the build's later stages (chips, presets and
        heroes are put on the typed records by the build).

        Returns
        -------
        list of dict
            One JSON-ready dict per swatch, in catalog order (thickness, Lab, sRGB, window, sheet …).
        """
        return [s.to_json() for s in self.swatches]


def compute(ctx: CatalogContext) -> CatalogData:
    """All the numbers of a catalog, vectorised over thicknesses and geometries.

    Parameters
    ----------
    ctx : swatch.catalog.context.CatalogContext
        The build's context: the spec, wavelength grid, coating, colorimeters and tolerance.

    Returns
    -------
    CatalogData
        Every swatch's spectra, colours, neighbours' ΔE, process window and typed record.
    """

    spec = ctx.spec
    wl, coating, cm = ctx.wavelength_nm, ctx.coating, ctx.colorimeter
    d = np.asarray(spec.thickness_nm, dtype=np.float64)
    n = d.size
    volts = (np.asarray(spec.voltage_V, dtype=np.float64) if spec.voltage_V is not None
             else spec.voltage_of(d))
    if volts is None:  # the process has no growth rate: thicknesses only
        volts = np.full(n, np.nan)

    R = geometry_reflectance(coating, d, spec.reference)
    XYZ = cm.XYZ(R)
    Lab = cm.Lab(XYZ)
    LCh = Lab_to_LCh(Lab)
    enc, gamut = cm.reflectance_display(R, "srgb")  # sRGB from CIE 1931 2° colorimetry
    # What print workflows and Adobe applications assume Lab to be (ICC PCS, ISO 13655): D50, 2°.
    cm_d50 = ctx.colorimeter_icc
    Lab_D50_2 = cm_d50.Lab(cm_d50.XYZ(R))
    hexes = [str(h) for h in np.atleast_1d(srgb_hex(enc))]

    G = len(spec.multi_angle)
    multi_R = np.stack([geometry_reflectance(coating, d, g) for g in spec.multi_angle]) if G else np.zeros((0, n, wl.size))
    multi_XYZ = cm.XYZ(multi_R)
    multi_Lab = cm.Lab(multi_XYZ) if G else np.zeros((0, n, 3))
    multi_LCh = Lab_to_LCh(multi_Lab) if G else np.zeros((0, n, 3))
    multi_hex = (np.atleast_2d(srgb_hex(cm.reflectance_display(multi_R, "srgb")[0])) if G
                 else np.zeros((0, n), dtype=object))

    dab = np.full((n, 2), np.nan)  # previous, next
    d00 = np.full((n, 2), np.nan)
    if n > 1:
        e_ab = np.atleast_1d(delta_E_ab(Lab[1:], Lab[:-1]))
        e_00 = np.atleast_1d(delta_E_00(Lab[1:], Lab[:-1]))
        dab[1:, 0], dab[:-1, 1] = e_ab, e_ab
        d00[1:, 0], d00[:-1, 1] = e_00, e_00

    tol = ctx.tolerance
    minus, plus, minus_cap, plus_cap = process_window(coating, cm, d, spec.reference, tol.max, spec.search_nm,
                                                      tol.metric)
    window_V = window_voltage_V(spec.voltage_of, d, minus, plus)

    def r(x, nd=4):
        return None if x is None or not np.isfinite(x) else round(float(x), nd)

    per_sheet = spec.per_sheet
    swatches: list[SwatchRecord] = []
    for i in range(n):
        sheet = i // per_sheet + 1
        slot = i % per_sheet
        swatches.append(SwatchRecord(
            id=f"S{i + 1:03d}",
            index=i + 1,
            thickness_nm=r(d[i]),
            voltage_V=r(volts[i]),
            Lab=tuple(r(v) for v in Lab[i]),
            LCh=tuple(r(v) for v in LCh[i]),
            XYZ=tuple(r(v) for v in XYZ[i]),
            Lab_D50_2=tuple(r(v) for v in Lab_D50_2[i]),
            srgb_hex=hexes[i],
            in_srgb_gamut=bool(gamut[i]),
            hue_family=hue_family(float(LCh[i, 1]), float(LCh[i, 2])),
            colour_name=colour_name(*(float(v) for v in LCh[i])),
            multi_angle={g.name: [r(v) for v in multi_Lab[j, i]] for j, g in enumerate(spec.multi_angle)},
            multi_angle_LCh={g.name: [r(v) for v in multi_LCh[j, i]] for j, g in enumerate(spec.multi_angle)},
            multi_angle_srgb_hex={g.name: str(multi_hex[j, i]) for j, g in enumerate(spec.multi_angle)},
            delta_E_ab_to_neighbours=Neighbours(previous=r(dab[i, 0]), next=r(dab[i, 1])),
            delta_E_00_to_neighbours=Neighbours(previous=r(d00[i, 0]), next=r(d00[i, 1])),
            process_window=ProcessWindowEntry(
                grade=tol.label,
                scheme=tol.scheme,
                metric=tol.metric,
                max=tol.max,
                thickness_minus_nm=r(minus[i], 3),
                thickness_plus_nm=r(plus[i], 3),
                voltage_minus_V=None if window_V is None else r(window_V[0][i], 3),
                voltage_plus_V=None if window_V is None else r(window_V[1][i], 3),
                minus_capped=bool(minus_cap[i]),
                plus_capped=bool(plus_cap[i]),
            ),
            sheet=sheet,
            sheet_png=f"{SHEETS}/sheet_{sheet:02d}.png",
            sheet_exr=f"{SHEETS}/sheet_{sheet:02d}.exr",
            tile=(slot // spec.columns + 1, slot % spec.columns + 1),
        ))
    return CatalogData(
        thickness_nm=d, voltage_V=volts, wavelength_nm=wl, reflectance=R, multi_reflectance=multi_R,
        Lab=Lab, LCh=LCh, Lab_D50_2=Lab_D50_2, srgb_hex=hexes, swatches=tuple(swatches), illuminant=cm.illuminant, observer=cm.observer,
        context=ctx,
    )


def process_json(spec) -> dict:
    """``catalog.json`` → ``catalog.process``: the profile's name, origin and growth law (a knee and a
    thickness spread only when the profile has them).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    dict
        The catalog's process: profile name and origin, growth rate (nm/V), offset (nm), knee (V) if any,
        film index scale, thickness spread, and the growth law in words.
    """
    knee = {} if spec.knee_V is None else {"knee_V": spec.knee_V, "nm_per_V_above_knee": spec.nm_per_V_above_knee}
    law = ("none: thicknesses only (the profile has no growth rate)" if spec.nm_per_V is None
           else "thickness_nm = offset_nm + nm_per_V * voltage_V" if spec.knee_V is None
           else "thickness_nm = offset_nm + nm_per_V * min(voltage_V, knee_V) + "
                "nm_per_V_above_knee * max(voltage_V - knee_V, 0)")
    return {"name": spec.process, "origin": spec.process_origin, "nm_per_V": spec.nm_per_V,
            "offset_nm": spec.offset_nm, "film_index_scale": spec.film_index_scale, **spec.spread.metadata(),
            **knee, "growth_law": law}
