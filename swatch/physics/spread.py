"""Thickness spread: the reflectance of a film whose local thickness varies over the lit area.

A real anodic film is not uniform: under the microscope a blue sample shows red and green spots
(Fujii et al., §2.3, Fig. 7). Over an area much wider than the coherence length of daylight the
local reflectances add (incoherent, lateral variation: not a coherent layer), so the colour of a
nominal thickness ``d`` is the reflectance averaged over a thickness distribution:

``R̄(d) = E[R(t)]``, ``t ~ Normal(d, σ(d)²)`` with ``σ(d) = min(spread_nm + spread_fraction × d, d / 3)``.

The cap ``σ ≤ d / 3`` keeps the distribution on ``t ≥ 0`` (at most 0.14 % of it falls below 0;
a local thickness is never negative, and a thinner film spreads less in nm): quadrature nodes
that still fall below 0 count as bare metal (``t = 0``). The expectation is computed by
Gauss–Hermite quadrature (probabilists' nodes ``z_i``, weights ``w_i``, ``Σ w_i = 1``):
``R̄ = Σ_i w_i R(d + σ z_i)``, with enough nodes for the largest round-trip phase spread
(``4π n σ / λ``) on the grid; the loop runs over the nodes only, each one a whole vectorised
reflectance evaluation.

A zero spread is no averaging at all: callers keep the uniform film's code path, so its outputs
stay byte-identical.

References
----------
.. [1] :cite:`Fujii2019`: §2.3 and Fig. 7, the non-uniform film.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.polynomial.hermite_e import hermegauss

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_SPREAD_FRACTION, MAX_SPREAD_NM

__all__ = ["NO_SPREAD", "ThicknessSpread", "parse_spread", "spread_sigma_nm", "node_count", "spread_nodes", "spread_average",
           "SIGMA_CAP_OF_THICKNESS"]

#: σ is capped at this fraction of the mean thickness (the normal's mass below 0 stays < 0.14 %).
SIGMA_CAP_OF_THICKNESS = 1.0 / 3.0
#: Quadrature nodes: ``ceil(NODES_PER_PHASE × a) + BASE_NODES`` for a phase spread ``a`` (rad), at most NODE_CAP.
#: Ten nodes per radian resolve the third harmonic of the Airy sum (``|r01 r12|³`` weight) to 1e-4.
NODES_PER_PHASE = 10.0
BASE_NODES = 8
NODE_CAP = 160


@dataclass(frozen=True)
class ThicknessSpread:
    """A normal thickness distribution's standard deviation: ``spread_nm + spread_fraction × d`` (nm).

    Parameters
    ----------
    spread_nm : float
        Constant part of the 1σ spread, nm, from 0 to ``MAX_SPREAD_NM`` (default 0).
    spread_fraction : float
        Part proportional to the mean thickness ``d`` (dimensionless), from 0 to
        ``MAX_SPREAD_FRACTION`` (default 0).

    Raises
    ------
    SwatchError
        For a bool, a non-number, a non-finite value or one outside its range.

    References
    ----------
    :cite:`Fujii2019`, §2.3.
    """

    spread_nm: float = 0.0
    spread_fraction: float = 0.0

    def __post_init__(self):
        for value, what, hi in ((self.spread_nm, "thickness spread", MAX_SPREAD_NM),
                                (self.spread_fraction, "thickness spread fraction", MAX_SPREAD_FRACTION)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                    or not 0.0 <= value <= hi:
                unit = " nm" if what == "thickness spread" else ""
                raise SwatchError(f"{what} must be a number from 0 to {hi:g}{unit} (got {value!r})")

    @property
    def is_zero(self) -> bool:
        """Whether the film is uniform (both parts 0: the uniform film's code path runs).

        Returns
        -------
        bool
            True when ``spread_nm`` and ``spread_fraction`` are both 0.
        """
        return self.spread_nm == 0.0 and self.spread_fraction == 0.0

    def metadata(self) -> dict:
        """The spread as metadata.

        Returns
        -------
        dict
            ``{"spread_nm", "spread_fraction"}`` when there is a spread, else ``{}`` (outputs unchanged).
        """
        if self.is_zero:
            return {}
        return {"spread_nm": float(self.spread_nm), "spread_fraction": float(self.spread_fraction)}

    def text(self) -> str:
        """The spread as a suffix for labels.

        Returns
        -------
        str
            ``" ± 4 nm + 2 % (1σ)"``; ``""`` for no spread.

        Examples
        --------
        >>> ThicknessSpread(4.0, 0.02).text()
        ' ± 4 nm + 2 % (1σ)'
        """
        if self.is_zero:
            return ""
        parts = [f"{self.spread_nm:g} nm"] if self.spread_nm else []
        if self.spread_fraction:
            parts.append(f"{100 * self.spread_fraction:g} %")
        return f" ± {' + '.join(parts)} (1σ)"


NO_SPREAD = ThicknessSpread()


def parse_spread(text: str | None) -> ThicknessSpread | None:
    """``--spread NM[,FRACTION]`` (``4`` or ``4,0.02`` or ``0,0.03``) → :class:`ThicknessSpread`; None → None.

    Parameters
    ----------
    text : str or None
        ``NM`` (the fraction is then 0) or ``NM,FRACTION``.

    Returns
    -------
    ThicknessSpread or None
        The spread (``spread_nm`` in nm, ``spread_fraction`` dimensionless), or None when ``text`` is None.

    Raises
    ------
    SwatchError
        For more than two parts, an empty part, a non-number, or a value :class:`ThicknessSpread` refuses.
    """
    if text is None:
        return None
    parts = str(text).split(",")
    if len(parts) > 2 or not all(p.strip() for p in parts):
        raise SwatchError(f"`spread` {text!r} must be NM or NM,FRACTION (e.g. 4 or 3,0.02)")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise SwatchError(f"`spread` {text!r} must be NM or NM,FRACTION (e.g. 4 or 3,0.02)") from None
    return ThicknessSpread(values[0], values[1] if len(values) == 2 else 0.0)


def spread_sigma_nm(thickness_nm, spread: ThicknessSpread) -> np.ndarray:
    """σ (nm) of the local thickness at mean thicknesses ``thickness_nm`` (nm): see the module docstring.

    Parameters
    ----------
    thickness_nm : array_like
        Mean thicknesses, nm, any shape.
    spread : ThicknessSpread
        The thickness spread: ``spread_nm`` (nm) and ``spread_fraction`` (of the mean thickness).

    Returns
    -------
    numpy.ndarray, float64, the shape of ``thickness_nm``
        ``spread_nm + spread_fraction × d``, capped at ``SIGMA_CAP_OF_THICKNESS × d``, nm.
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    return np.minimum(spread.spread_nm + spread.spread_fraction * d, SIGMA_CAP_OF_THICKNESS * d)


def node_count(sigma_max_nm: float, n_film_max: float, wavelength_min_nm: float) -> int:
    """Gauss–Hermite nodes for a phase spread ``a = 4π n σ / λ`` (the largest on the grid).

    Parameters
    ----------
    sigma_max_nm : float
        Largest thickness σ on the grid, nm.
    n_film_max : float
        Largest real film index on the grid.
    wavelength_min_nm : float
        Shortest wavelength, nm.

    Returns
    -------
    int
        ``ceil(NODES_PER_PHASE × a) + BASE_NODES``, at most ``NODE_CAP``.
    """
    a = 4.0 * math.pi * float(n_film_max) * float(sigma_max_nm) / float(wavelength_min_nm)
    return int(min(NODE_CAP, math.ceil(NODES_PER_PHASE * a) + BASE_NODES))


def spread_nodes(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Probabilists' Gauss–Hermite nodes ``z`` and weights ``w`` normalised to ``Σ w = 1`` (``count`` each).

    Parameters
    ----------
    count : int
        Number of nodes.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray), each of shape (count,)
        Nodes ``z`` (in units of σ) and weights ``w`` (summing to 1), from ``numpy.polynomial.hermite_e.hermegauss``.
    """
    z, w = hermegauss(int(count))
    return z, w / w.sum()


def spread_average(reflect: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], thickness_nm,
                   spread: ThicknessSpread, n_film_max: float, wavelength_min_nm: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Average ``reflect(t) -> (R_s, R_p)`` over the thickness distribution of :class:`ThicknessSpread`.

    Parameters
    ----------
    reflect : callable
        Thicknesses (nm, the shape of ``thickness_nm``) → ``(R_s, R_p)``, each of shape S + (W,).
    thickness_nm : array_like, nm
        Mean thicknesses ≥ 0.
    spread : ThicknessSpread
        The thickness spread: ``spread_nm`` (nm) and ``spread_fraction`` (of the mean thickness).
    n_film_max : float
        Largest real film index on the grid (sets the node count).
    wavelength_min_nm : float
        Shortest wavelength of the grid, nm.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The averaged ``R_s`` and ``R_p`` (fractions), shape S + (W,).
    """
    d = np.asarray(thickness_nm, dtype=np.float64)
    sigma = spread_sigma_nm(d, spread)
    z, w = spread_nodes(node_count(float(np.max(sigma, initial=0.0)), n_film_max, wavelength_min_nm))
    R_s: np.ndarray | None = None
    R_p: np.ndarray | None = None
    for zi, wi in zip(z, w, strict=True):  # over quadrature nodes; each call is vectorised
        rs, rp = reflect(np.maximum(d + sigma * zi, 0.0))
        if R_s is None or R_p is None:
            R_s, R_p = wi * rs, wi * rp
        else:
            R_s += wi * rs
            R_p += wi * rp
    assert R_s is not None and R_p is not None
    return R_s, R_p
