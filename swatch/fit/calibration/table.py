"""The colour tables behind ``swatch calibrate``'s model search (:mod:`swatch.fit.calibration.model`).

For each film × substrate table pair the tristimulus values are tabulated once over the optical
growth ``u`` (film thickness × film index scale, every :data:`U_STEP_NM`) at film index scales
:data:`TABLE_SCALES`; a model's colour is then a lookup in (scale, u), quadratic in the scale and
linear in u (XYZ is linear in the spectrum, so the thickness spread's Gauss–Hermite average is
taken over the looked-up XYZ, tabulated at the spread fractions :data:`TABLE_SPREADS`). Tables are
cached by what they depend on (:func:`build_table`, :func:`clear_tables`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import sparse

from swatch.physics import optics
from swatch.physics.model import get_coating
from swatch.physics.spread import node_count, spread_nodes

__all__ = ["TABLE_SCALES", "TABLE_SPREADS", "U_STEP_NM", "U_MAX_NM", "ComboTable", "build_table", "clear_tables"]

#: Film index scales the tables are computed at (the fit interpolates quadratically between them:
#: at most 0.02 ΔE2000 off the exact colour at 0.05 spacing, against 0.26 for linear interpolation).
TABLE_SCALES = np.round(np.arange(0.80, 1.2001, 0.05), 4)
#: Spread fractions the spread tables are computed at (linear interpolation between them).
TABLE_SPREADS = np.round(np.arange(0.0, 0.0901, 0.01), 4)
U_STEP_NM = 0.5
U_MAX_NM = 1200.0


@dataclass
class ComboTable:
    """XYZ of one film × substrate pair over the optical growth u at film index scales.

    Attributes
    ----------
    film, substrate : str
        The optical table names of the pair.
    XYZ : numpy.ndarray, shape (S, U, 3)
        At the scales ``scales`` and u every :data:`U_STEP_NM` from 0 (Y = 100 for a white diffuser).
    n_film_max : float
        The film's largest real index at the largest scale (sizes the spread's quadrature).
    wavelength_min_nm : float
        The shortest wavelength of the grid, nm (sizes the spread's quadrature).
    scales : numpy.ndarray, shape (S,)
        Default :data:`TABLE_SCALES`.
    XYZ_spread : numpy.ndarray, shape (S, F, U, 3), or None
        After :meth:`add_spread`: the spread averages at :data:`TABLE_SPREADS`.
    """

    film: str
    substrate: str
    XYZ: np.ndarray
    n_film_max: float
    wavelength_min_nm: float
    scales: np.ndarray = field(default_factory=lambda: TABLE_SCALES)
    XYZ_spread: np.ndarray | None = None

    def _scale_weights(self, s: np.ndarray):
        """Three nodes and quadratic Lagrange weights in s (shape T each, and T + (3,)); a table of one
        scale is used as it is."""
        S = self.scales.size
        if S == 1:
            s = np.asarray(s, dtype=np.float64)
            return np.zeros(s.shape, np.int64), np.concatenate([np.ones((*s.shape, 1)), np.zeros((*s.shape, 2))], -1)
        x = (np.asarray(s, dtype=np.float64) - self.scales[0]) / (self.scales[1] - self.scales[0])
        i0 = np.clip(np.rint(x).astype(np.int64) - 1, 0, S - 3)
        t = np.clip(x, 0.0, S - 1.0) - i0
        w = np.stack([(t - 1) * (t - 2) / 2, -t * (t - 2), t * (t - 1) / 2], axis=-1)
        return i0, w

    def XYZ_at(self, s, u, f=None, row=None) -> np.ndarray:
        """Look up XYZ: quadratic in the scale, linear in u (and in the spread fraction).

        Parameters
        ----------
        s : array_like
            Film index scale (broadcast to the shape T of ``u``).
        u : array_like, shape T
            Optical growth, nm.
        f : array_like, optional
            Spread fraction (needs :meth:`add_spread`).
        row : array_like of int, optional
            The table row to use instead of a scale (a stack of screening tables).

        Returns
        -------
        numpy.ndarray, shape T + (3,)
            CIE XYZ (Y = 100 for a white diffuser) under the table's illuminant and observer.
        """
        fu = np.clip(np.asarray(u, dtype=np.float64) / U_STEP_NM, 0.0, self.XYZ.shape[1] - 1 - 1e-9)
        if row is not None:
            fu, row = np.broadcast_arrays(fu, row)
            j = fu.astype(np.int64)
            b = (fu - j)[..., None]
            return _lerp(self.XYZ, row * self.XYZ.shape[1] + j, b)
        if f is None:
            s, fu = np.broadcast_arrays(np.asarray(s, dtype=np.float64), fu)
        else:
            s, fu, f = np.broadcast_arrays(np.asarray(s, dtype=np.float64), fu, np.asarray(f, dtype=np.float64))
        i0, ws = self._scale_weights(s)
        j = fu.astype(np.int64)
        b = (fu - j)[..., None]
        out = np.zeros((*fu.shape, 3))
        ks = range(3) if self.scales.size > 1 else range(1)
        if f is None:
            T = self.XYZ
            at = i0 * T.shape[1] + j  # the flat (scale, u) row of node i0, j
            for k in ks:
                term = _lerp(T, at + k * T.shape[1], b)
                term *= ws[..., k:k + 1]
                out += term
            return out
        assert self.XYZ_spread is not None, "add_spread() first"
        ff = np.clip(f / (TABLE_SPREADS[1] - TABLE_SPREADS[0]), 0.0, TABLE_SPREADS.size - 1 - 1e-9)
        m = ff.astype(np.int64)
        c = (ff - m)[..., None]
        T = self.XYZ_spread
        F, U = T.shape[1], T.shape[2]
        at = (i0 * F + m) * U + j  # the flat (scale, spread, u) row of node i0, m, j
        for k in ks:
            lo = _lerp(T, at + k * F * U, b)
            hi = _lerp(T, at + k * F * U + U, b)
            lo *= 1 - c
            hi *= c
            lo += hi
            lo *= ws[..., k:k + 1]
            out += lo
        return out

    def add_spread(self) -> None:
        """Tabulate the spread average ``Σ w XYZ(u (1 + f z))`` (Gauss–Hermite nodes z, weights w) at the
        fractions :data:`TABLE_SPREADS` into ``XYZ_spread`` (once; one sparse (U, U) product per fraction).

        Returns
        -------
        None
        """
        if self.XYZ_spread is not None:
            return
        S, U = self.XYZ.shape[0], self.XYZ.shape[1]
        u = np.arange(U) * U_STEP_NM
        out = np.empty((S, TABLE_SPREADS.size, U, 3))
        out[:, 0] = self.XYZ
        columns = self.XYZ.transpose(1, 0, 2).reshape(U, S * 3)  # (U, S·3): one column per scale and channel
        for m, f in enumerate(TABLE_SPREADS[1:], start=1):  # nine spreads, each one sparse product
            z, w = spread_nodes(min(32, node_count(f * u[-1], self.n_film_max, self.wavelength_min_nm)))
            un = np.clip(u[:, None] * (1.0 + f * z[None, :]) / U_STEP_NM, 0.0, U - 1 - 1e-9)  # (U, Z)
            j = un.astype(np.int64)
            b = un - j
            rows = np.broadcast_to(np.arange(U)[:, None], j.shape)
            M = sparse.csr_matrix((np.concatenate([((1.0 - b) * w).ravel(), (b * w).ravel()]),
                                   (np.concatenate([rows.ravel(), rows.ravel()]),
                                    np.concatenate([j.ravel(), (j + 1).ravel()]))), shape=(U, U))
            out[:, m] = np.asarray(M @ columns).reshape(U, S, 3).transpose(1, 0, 2)
        self.XYZ_spread = out


def _lerp(T: np.ndarray, at: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``(1 − b) T[at] + b T[at + 1]`` over the flattened rows of ``T`` (…, 3): XYZ linear in u between two nodes
    (one flat gather each: a third of the time of indexing T's axes)."""
    flat = T.reshape(-1, 3)
    lo = np.take(flat, at, axis=0)
    hi = np.take(flat, at + 1, axis=0)
    lo *= 1 - b
    hi *= b
    lo += hi
    return lo


#: Tables kept between calls (bounded): the same line's coupons calibrated again reuse them.
_TABLES: dict[tuple, ComboTable] = {}
_TABLES_KEPT = 12


def clear_tables() -> None:
    """Forget the cached tables (:func:`build_table`): the next calibration computes them afresh.

    Returns
    -------
    None
    """
    _TABLES.clear()


def build_table(film: str, substrate: str, wavelength_nm, cm, cos_d: float, u_max_nm: float = U_MAX_NM,
                scales=TABLE_SCALES) -> ComboTable:
    """Tabulate XYZ of a film × substrate pair over u from 0 to ``u_max_nm`` at film index ``scales``.

    Parameters
    ----------
    film, substrate : str
        Optical table names.
    wavelength_nm : array_like, shape (W,)
        The wavelength grid, nm (that of ``cm``).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The calibration's illuminant and observer on that grid.
    cos_d : float
        cos θ_d of the measuring geometry.
    u_max_nm : float
        The largest optical growth, nm (at most :data:`U_MAX_NM`).
    scales : array_like
        Film index scales (:data:`TABLE_SCALES`, or one for a fixed-scale screening).

    Returns
    -------
    ComboTable
        Cached by everything it depends on (the last ``_TABLES_KEPT``; read only but for
        :meth:`ComboTable.add_spread`, which adds to them once).
    """
    grid = np.asarray(wavelength_nm, dtype=np.float64)
    scale_row = np.atleast_1d(np.asarray(scales, dtype=np.float64))
    key = (film, substrate, grid.tobytes(), cm.illuminant, cm.observer, float(cos_d), float(u_max_nm),
           scale_row.tobytes())
    table = _TABLES.get(key)
    if table is None:
        table = _build_table(film, substrate, grid, cm, cos_d, u_max_nm, scale_row)
        while len(_TABLES) >= _TABLES_KEPT:
            _TABLES.pop(next(iter(_TABLES)))
        _TABLES[key] = table
    return table


def _build_table(film: str, substrate: str, wavelength_nm, cm, cos_d: float, u_max_nm: float,
                 scales: np.ndarray) -> ComboTable:
    coating = get_coating(film, substrate, wavelength_nm)
    count = round(min(u_max_nm, U_MAX_NM) / U_STEP_NM) + 1
    scales = np.atleast_1d(np.asarray(scales, dtype=np.float64))
    XYZ = np.empty((scales.size, count, 3))
    for k, s in enumerate(scales):  # one thickness sweep per scale
        n = s * coating.n_film.real + 1j * coating.n_film.imag
        film_at = optics.FilmAtAngles(np.asarray(cos_d, dtype=np.float64), coating.wavelength_nm, n,
                                      coating.n_substrate)
        XYZ[k] = cm.XYZ(film_at.sweep(0.0, U_STEP_NM / s, count).R)
    return ComboTable(film, substrate, XYZ, float(np.max(coating.n_film.real)) * float(scales[-1]),
                      float(np.min(coating.wavelength_nm)), scales)
