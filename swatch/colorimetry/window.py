"""The process window of a nominal thickness: how far the film may stray before its colour leaves a tolerance.

One definition for the catalog's records (:mod:`swatch.catalog.records`), the finish specification
(:mod:`swatch.production.spec`) and, mirrored, the page's ``colour.js`` (tests/js/match.test.mjs checks
them against each other): ΔE(Lab(d ± δ), Lab(d)) at one measuring geometry
(:class:`swatch.colorimetry.geometry.Geometry`), in the tolerance's own metric.

References
----------
.. [1] :cite:`Carter2018`: CIELAB, ΔE*ab.
.. [2] :cite:`Sharma2005b`: ΔE00.
"""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.geometry import Geometry
from swatch.colorimetry.tolerance import delta_E
from swatch.core.limits import MAX_THICKNESS_NM

__all__ = ["PROCESS_STEP_NM", "geometry_reflectance", "process_window", "window_voltage_V"]

#: Grid step of the process-window search, nm (the crossing is then interpolated linearly).
PROCESS_STEP_NM = 0.05
#: Thicknesses per chunk of the search (bounds the memory of the (N, K, W) spectra).
_CHUNK = 8


def geometry_reflectance(coating, d, g: Geometry) -> np.ndarray:
    """The film's reflectance factor on the half-vector facet of a measuring geometry.

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        The film on its substrate, on its wavelength grid.
    d : array_like
        Film thicknesses, nm, any shape S.
    g : swatch.colorimetry.geometry.Geometry
        The in-plane light/view geometry.

    Returns
    -------
    numpy.ndarray, shape S + (W,)
        Reflectance factor (0–1, s and p averaged) per wavelength of the coating's grid.
    """
    refl, _ = coating.half_vector(d, g.light_deg, g.view_deg, 0.0, g.view_azimuth_deg)
    return refl.R


def process_window(coating, cm, d: np.ndarray, g: Geometry, bound: float, search_nm: float, metric: str = "dEab"):
    """The process window of nominal thicknesses: the largest deviations keeping the colour within the bound.

    ΔE(Lab(d ± δ), Lab(d)) in ``metric`` on a δ grid of :data:`PROCESS_STEP_NM` up to ``search_nm``;
    the edge is the first grid crossing of ``bound``, interpolated linearly. ``capped`` means no
    crossing within the search (or, below, before zero thickness): the window is then the search
    limit (or ``d`` itself).

    Parameters
    ----------
    coating : swatch.physics.model.Coating
        The film on its substrate (wavelength grid, index scale, spread).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The colorimetry the tolerance is judged in (illuminant, observer).
    d : numpy.ndarray, shape (N,)
        Nominal thicknesses, nm.
    g : swatch.colorimetry.geometry.Geometry
        The geometry the colour is judged at.
    bound : float
        The tolerance, in ``metric``.
    search_nm : float
        nm.
    metric : str
        ``dEab`` or ``dE00`` (:data:`swatch.colorimetry.tolerance.METRICS`).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray, numpy.ndarray)
        minus_nm, plus_nm, minus_capped, plus_capped, each shape (N,).
    """

    if d.size > _CHUNK:  # bound the memory of the (N, K, W) spectra
        parts = [process_window(coating, cm, d[i:i + _CHUNK], g, bound, search_nm, metric)
                 for i in range(0, d.size, _CHUNK)]
        return tuple(np.concatenate([p[j] for p in parts]) for j in range(4))
    n_steps = round(search_nm / PROCESS_STEP_NM)
    delta = PROCESS_STEP_NM * np.arange(n_steps + 1)  # (K,), delta[0] = 0
    Lab0 = cm.Lab(cm.XYZ(geometry_reflectance(coating, d, g)))  # (N, 3)
    out = []
    for sign in (-1.0, +1.0):
        dd = d[:, None] + sign * delta[None, :]  # (N, K)
        valid = (dd >= 0.0) & (dd <= MAX_THICKNESS_NM)
        Lab = cm.Lab(cm.XYZ(geometry_reflectance(coating, np.clip(dd, 0.0, MAX_THICKNESS_NM), g)))  # (N, K, 3)
        dE = delta_E(metric, Lab, np.broadcast_to(Lab0[:, None, :], Lab.shape))  # (N, K)
        dE = np.where(valid, dE, np.inf)  # leaving the physical range ends the window
        over = dE > bound
        has = over.any(axis=1)
        k = np.where(has, over.argmax(axis=1), n_steps)  # first index outside
        kk = np.maximum(k, 1)
        rows = np.arange(d.size)
        e0 = dE[rows, kk - 1]
        e1 = dE[rows, kk]
        finite = np.isfinite(e1)
        frac = np.where(finite & (e1 > e0), (bound - e0) / np.where(e1 > e0, e1 - e0, 1.0), 0.0)
        edge = delta[kk - 1] + np.clip(frac, 0.0, 1.0) * PROCESS_STEP_NM
        edge = np.where(has, edge, delta[-1])
        capped = ~has | ~finite  # no crossing in the search, or stopped by zero thickness
        if sign < 0:
            edge = np.where(~finite, np.minimum(delta[kk - 1], d), edge)
            edge = np.minimum(edge, d)
        out += [edge, capped]
    return out[0], out[2], out[1], out[3]


def window_voltage_V(voltage_of, thickness_nm, minus_nm, plus_nm):
    """The process window in volts: the voltage steps from the nominal to the window's edges.

    The one definition for the catalog and ``swatch spec``: through the process profile's own growth
    law (``voltage_of``: a catalog's :meth:`swatch.catalog.spec.CatalogSpec.voltage_of` or
    :meth:`swatch.physics.process.Process.voltage_V`, one slope or two with a knee), so a window
    above or across the knee is converted at the slope(s) it spans.

    Parameters
    ----------
    voltage_of : callable
        Thickness (nm, array) → voltage (V, same shape), or None without a growth rate.
    thickness_nm, minus_nm, plus_nm : array_like, one shape (N,)
        Nominal thicknesses and the window's extents below and above them, nm.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray) or None
        ``V(d) − V(d − minus)`` and ``V(d + plus) − V(d)``, V, shape (N,); None without a rate.
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    v0 = voltage_of(d)
    if v0 is None:
        return None
    return v0 - voltage_of(d - np.asarray(minus_nm)), voltage_of(d + np.asarray(plus_nm)) - v0
