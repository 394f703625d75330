"""The film's and the substrate's optical tables for the Mitsuba plugin, looked up in constant time.

The plugin needs four tabulated spectra at every sampled wavelength: the film's n and k and the
substrate's n and k, each linear between its table's nodes (as ``np.interp``). Mitsuba's ``irregular``
spectrum finds a wavelength's segment by binary search, about eight dependent gather steps per table and
wavelength, traced at both places the BSDF evaluates its Fresnel factor (``sample`` and ``eval_pdf``): the
four lookups were ~75 KB of each ~160 KB render kernel's LLVM IR, ~1.2 s of its ~2.1 s compile (#17;
``roughconductor`` 70 KB, 0.8 s). Here the four tables share one grid, the union of both tables' nodes
(each table's piecewise-linear function is linear between those, so its values there reproduce it), and
a bucket table over a uniform partition of the span gives a wavelength its segment in one gather and at
most a few forward steps (:func:`bucket_starts`); the values are then the same linear interpolation.

Functions and classes
---------------------
* :func:`shared_grid`: the tables resampled exactly onto the union of their nodes, within a span.
* :func:`bucket_starts`: a uniform partition's first segments and the forward steps a lookup needs.
* :class:`SpectralTables`: the tables on Dr.Jit arrays, evaluated at a Mitsuba spectrum of wavelengths.
"""
from __future__ import annotations

import math
from typing import Any

import drjit as dr
import mitsuba as mi
import numpy as np

__all__ = ["BUCKETS", "LOOKUP_STEPS", "shared_grid", "bucket_starts", "SpectralTables"]

#: Buckets of the uniform partition of the grid's span (600 nm: ~0.6 nm each, below the default film
#: table's 1.7 nm node spacing, so a bucket holds at most a node or two).
BUCKETS = 1024
#: Forward steps every lookup takes at least (the shipped tables need at most 2): with the span and
#: the counts passed to the kernel as data, not as constants, every pair of tables that needs no more
#: compiles to the same kernel (another film or substrate is not another compile).
LOOKUP_STEPS = 2
#: Floats a gather loads at once (``mi.Vector4f``): the tables' values and slopes are stored in packets of 4.
_PACKET = 4


def shared_grid(tables, lo_nm: float, hi_nm: float) -> tuple[np.ndarray, np.ndarray]:
    """Tables on one grid: ``lo_nm``, ``hi_nm`` and every table's nodes between them.

    Parameters
    ----------
    tables : sequence of (array_like, array_like)
        ``(wavelength_nm, values)`` per table, wavelengths ascending (nm).
    lo_nm, hi_nm : float
        The span kept, nm (within every table's range; lookups are clamped to it).

    Returns
    -------
    grid_nm : numpy.ndarray, float32, shape (N,)
        Strictly ascending (nodes that coincide in float32 merged), ``lo_nm`` first and ``hi_nm`` last.
    values : numpy.ndarray, float32, shape (len(tables), N)
        Each table's piecewise-linear value at the grid's nodes (``np.interp`` in float64).

    Examples
    --------
    >>> grid, values = shared_grid([([400, 500, 600], [1.0, 2.0, 1.0]), ([450, 550], [0.0, 1.0])], 425, 575)
    >>> grid.tolist(), values.tolist()
    ([425.0, 450.0, 500.0, 550.0, 575.0], [[1.25, 1.5, 2.0, 1.5, 1.25], [0.0, 0.0, 0.5, 1.0, 1.0]])
    """
    lo, hi = float(lo_nm), float(hi_nm)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"the span must be finite and ascending, got {lo_nm!r} to {hi_nm!r}")
    nodes = [np.asarray(wl, dtype=np.float64) for wl, _ in tables]
    inside = np.concatenate([[lo, hi]] + [wl[(wl > lo) & (wl < hi)] for wl in nodes])
    grid = np.unique(inside.astype(np.float32))
    at = grid.astype(np.float64)
    values = np.stack([np.interp(at, wl, np.asarray(v, dtype=np.float64)) for wl, (_, v) in zip(nodes, tables,
                                                                                                strict=True)])
    return grid, values.astype(np.float32)


def bucket_starts(grid_nm: np.ndarray, buckets: int = BUCKETS) -> tuple[np.ndarray, int]:
    """The segment each bucket of a uniform partition starts in, and the forward steps a lookup needs.

    Bucket ``j`` covers ``[g0 + j Δ, g0 + (j + 1) Δ)`` with ``Δ = (g_last − g0) / buckets``. Its start is
    taken a quarter bucket early, and its steps count the nodes up to a quarter bucket past its end, so
    that a float32 bucket index off by a rounding still lands in a bucket whose start is at or below
    the wavelength and whose steps reach it.

    Parameters
    ----------
    grid_nm : numpy.ndarray, shape (N,), N ≥ 2
        Strictly ascending nodes, nm.
    buckets : int
        Bucket count (≥ 1).

    Returns
    -------
    starts : numpy.ndarray, uint32, shape (buckets,)
        Index of the segment (0 … N − 2) that holds each bucket's (early) start.
    steps : int
        The most nodes any (widened) bucket holds past its start: the lookup's forward steps.
    """
    g = np.asarray(grid_nm, dtype=np.float64)
    width = (g[-1] - g[0]) / buckets
    edges = g[0] + width * np.arange(buckets + 1)
    last = g.size - 2
    starts = np.clip(np.searchsorted(g, edges[:-1] - 0.25 * width, side="right") - 1, 0, last)
    ends = np.clip(np.searchsorted(g, edges[1:] + 0.25 * width, side="right") - 1, 0, last)
    return starts.astype(np.uint32), int(np.max(ends - starts))


class SpectralTables:
    """Tabulated spectra on one grid, evaluated at the wavelengths a spectral Mitsuba variant samples.

    Parameters
    ----------
    tables : sequence of (array_like, array_like)
        ``(wavelength_nm, values)`` per table (see :func:`shared_grid`).
    lo_nm, hi_nm : float
        The span, nm: wavelengths outside are clamped to it.
    """

    def __init__(self, tables, lo_nm: float, hi_nm: float):
        grid, values = shared_grid(tables, lo_nm, hi_nm)
        self.span_nm = (float(grid[0]), float(grid[-1]))
        self.count = len(values)
        self._numpy = (grid, values)
        if not dr.is_jit_v(mi.Float):  # scalar variants: np.interp on the four wavelengths of a path
            return
        starts, steps = bucket_starts(grid)
        self._steps = max(steps, LOOKUP_STEPS)
        slopes = np.diff(values.astype(np.float64), axis=1) / np.diff(grid.astype(np.float64))
        slopes = np.concatenate([slopes, np.zeros((self.count, 1))], axis=1)  # (the last node starts no segment)
        self._rows = -(-self.count // _PACKET)  # packets of tables per node: values then slopes, node-major
        width = self._rows * _PACKET
        rows = np.zeros((grid.size, 2, width), dtype=np.float32)
        rows[:, 0, :self.count], rows[:, 1, :self.count] = values.T, slopes.T
        self._packets = mi.Float(rows.reshape(-1).tolist())
        self._grid = mi.Float(grid.tolist())
        self._starts = mi.UInt32(starts.tolist())
        self._last = dr.opaque(mi.UInt32, grid.size - 2)
        self._lo, self._hi = dr.opaque(mi.Float, self.span_nm[0]), dr.opaque(mi.Float, self.span_nm[1])
        self._inv_width = dr.opaque(mi.Float, BUCKETS / (self.span_nm[1] - self.span_nm[0]))

    def eval(self, wavelength_nm, active=True) -> list:
        """Every table at the wavelengths (clamped into the span).

        Parameters
        ----------
        wavelength_nm : mitsuba.UnpolarizedSpectrum
            Wavelengths, nm (a spectral variant's ``si.wavelengths``).
        active : mitsuba.Bool, optional
            Lanes to look up.

        Returns
        -------
        list of mitsuba.UnpolarizedSpectrum
            One spectrum per table, in the tables' order.
        """
        spectrum = mi.UnpolarizedSpectrum
        if not dr.is_jit_v(mi.Float):
            grid, values = self._numpy
            at = np.clip(np.asarray(wavelength_nm, dtype=np.float64), self.span_nm[0], self.span_nm[1])
            return [spectrum(*np.interp(at, grid, v).tolist()) for v in values]
        wl: Any = dr.clip(spectrum(wavelength_nm), self._lo, self._hi)
        out: list[list] = [[] for _ in range(self.count)]
        for lane in range(dr.size_v(spectrum)):  # the (four) wavelengths of a path: traced, not a data loop
            x = wl[lane]
            bucket = dr.minimum(mi.UInt32((x - self._lo) * self._inv_width), BUCKETS - 1)
            i = dr.gather(mi.UInt32, self._starts, bucket, active)
            for _ in range(self._steps):
                ahead = dr.gather(mi.Float, self._grid, i + 1, active) <= x
                i = dr.select(ahead & (i < self._last), i + 1, i)
            dx = x - dr.gather(mi.Float, self._grid, i, active)
            for row in range(self._rows):
                v = dr.gather(mi.Vector4f, self._packets, (i * 2) * self._rows + row, active)
                sl = dr.gather(mi.Vector4f, self._packets, (i * 2 + 1) * self._rows + row, active)
                for c in range(_PACKET):
                    table = row * _PACKET + c
                    if table < self.count:
                        out[table].append(dr.fma(dx, sl[c], v[c]))
        return [spectrum(*lanes) for lanes in out]
