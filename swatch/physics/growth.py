"""The anodic growth law: film thickness from the anodising voltage and back (numpy only).

``thickness = offset_nm + nm_per_V × voltage_V``, or with a knee ``nm_per_V`` up to ``knee_V`` and
``nm_per_V_above_knee`` beyond it (continuous). Light (no optics), so a process profile and a catalog
spec use it at import time, and every caller computes the law the same way (:func:`growth_law_nm`).

References
----------
.. [1] :cite:`Fujii2019`: Table 2: 50.8 nm at 25 V.
"""
from __future__ import annotations

import math

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_THICKNESS_NM, MAX_VOLTAGE_V

__all__ = ["DEFAULT_NM_PER_V", "VOLTAGE_DECIMALS", "check_growth_rate", "growth_law_nm", "voltage_to_thickness_nm",
           "thickness_to_voltage_V", "voltage_text"]

#: Anodic growth rate, nm per volt: the paper's blue sample (Fig. 3) was anodised at 25 V and its
#: thickness estimated at 50.8 nm (Table 2), i.e. 2.032 nm/V. Published anodic-TiO2 rates are
#: 1.5–3 nm/V depending on electrolyte; override it with ``--nm-per-volt``.
DEFAULT_NM_PER_V = 50.8 / 25.0
#: Decimals of a voltage a person reads (text, cards, figures; JSON keeps full precision): 0.1 V. No growth law
#: supports more: the calibrated example line (examples/line.toml) knows a voltage to ±0.15 V at 25 V (its rate's
#: and offset's standard errors, 0.0115 nm/V and 0.16 nm, over 2.2 nm/V), and a rectifier is set in 0.1 V steps.
VOLTAGE_DECIMALS = 1


def check_growth_rate(nm_per_V: float) -> float:
    """A growth rate, checked: a number from 0.1 to 10 nm/V.

    Parameters
    ----------
    nm_per_V : float
        Anodic growth rate, nm of oxide per volt.

    Returns
    -------
    float
        The rate as a float, nm/V, in [0.1, 10].

    Raises
    ------
    SwatchError
        Otherwise.
    """
    if not (isinstance(nm_per_V, (int, float)) and math.isfinite(nm_per_V) and 0.1 <= nm_per_V <= 10):
        raise SwatchError("growth rate must be between 0.1 and 10 nm per volt")
    return float(nm_per_V)


def growth_law_nm(voltage_V, nm_per_V, offset_nm=0.0, knee_V=None, nm_per_V_above_knee=None) -> np.ndarray:
    """The growth law itself, unchecked (callers check their inputs and outputs their own way).

    Parameters
    ----------
    voltage_V : array_like
        Anodising voltage, V.
    nm_per_V : float or array_like
        Growth rate, nm/V (up to the knee, with one).
    offset_nm : float or array_like, optional
        Thickness at 0 V, nm.
    knee_V, nm_per_V_above_knee : float, array_like or None, optional
        The knee (V) and the rate above it (nm/V); None: linear.

    Returns
    -------
    numpy.ndarray
        Thickness, nm, float64: ``voltage_V`` broadcast with the parameters (scalars: the shape of
        ``voltage_V``; columns of parameter rows, as the calibration search passes them: rows × voltages).

    Examples
    --------
    >>> growth_law_nm([25.0, 100.0], 2.032).tolist()
    [50.8, 203.2]
    >>> float(growth_law_nm(100.0, 2.0, 4.0, knee_V=50.0, nm_per_V_above_knee=3.0))
    254.0
    """
    v = np.asarray(voltage_V, dtype=np.float64)
    offset = np.asarray(offset_nm, dtype=np.float64)
    if knee_V is None or nm_per_V_above_knee is None:
        return np.asarray(offset + v * nm_per_V, dtype=np.float64)
    k = np.asarray(knee_V, dtype=np.float64)
    return np.asarray(offset + nm_per_V * np.minimum(v, k) + nm_per_V_above_knee * np.maximum(v - k, 0.0),
                      dtype=np.float64)


def voltage_to_thickness_nm(voltage_V, nm_per_V: float = DEFAULT_NM_PER_V, offset_nm: float = 0.0,
                            knee_V: float | None = None, nm_per_V_above_knee: float | None = None) -> np.ndarray:
    """Film thickness for an anodising voltage by the growth law ``offset_nm + nm_per_V × voltage_V``
    (with a knee: ``nm_per_V`` up to ``knee_V`` and ``nm_per_V_above_knee`` beyond it, continuous).

    Parameters
    ----------
    voltage_V : array_like
        Anodising (cell) voltage, V, from 0 to ``MAX_VOLTAGE_V``.
    nm_per_V : float
        Growth rate, nm per volt.
    offset_nm : float
        Thickness at 0 V (the initial oxide), nm.
    knee_V, nm_per_V_above_knee : float or None
        A two-slope law's knee voltage (V) and its rate above the knee (nm/V); None: linear.

    Returns
    -------
    numpy.ndarray
        Film thickness, nm, float64, the shape of ``voltage_V``.

    Raises
    ------
    SwatchError
        Naming ```voltage_V``` (the CLI: ``--voltage``) for a voltage out of range or one whose film
        is outside what the model takes (0 to ``MAX_THICKNESS_NM``); for a growth rate out of range.
    """
    v = np.asarray(voltage_V, dtype=np.float64)
    if v.size == 0:
        raise SwatchError("no voltage given (`voltage_V` is empty)")
    bad = ~(np.isfinite(v) & (v >= 0) & (v <= MAX_VOLTAGE_V))
    if bad.any():
        raise SwatchError(f"`voltage_V` must be a number from 0 to {MAX_VOLTAGE_V:g} V "
                          f"(got {float(v.reshape(-1)[bad.reshape(-1)][0]):g})")
    rate = check_growth_rate(nm_per_V)
    above = None if knee_V is None or nm_per_V_above_knee is None else check_growth_rate(nm_per_V_above_knee)
    d = growth_law_nm(v, rate, offset_nm, knee_V if above is not None else None, above)
    out = ~((d >= 0) & (d <= MAX_THICKNESS_NM))
    if out.any():
        raise SwatchError(f"`voltage_V` {float(v.reshape(-1)[out.reshape(-1)][0]):g} V gives a "
                          f"{float(d.reshape(-1)[out.reshape(-1)][0]):g} nm film by the growth law; the model takes "
                          f"0 to {MAX_THICKNESS_NM:g} nm")
    return d


def thickness_to_voltage_V(thickness_nm, nm_per_V: float = DEFAULT_NM_PER_V, offset_nm: float = 0.0,
                           knee_V: float | None = None, nm_per_V_above_knee: float | None = None) -> np.ndarray:
    """Anodising voltage for a film thickness, V: the inverse of :func:`voltage_to_thickness_nm`.

    Parameters
    ----------
    thickness_nm : array_like
        Film thickness, nm.
    nm_per_V : float
        Growth rate, nm per volt (up to the knee, with one).
    offset_nm : float
        Thickness at 0 V (the initial oxide), nm.
    knee_V, nm_per_V_above_knee : float or None
        A two-slope law's knee voltage (V) and its rate above the knee (nm/V); None: linear.

    Returns
    -------
    numpy.ndarray, float64, the shape of ``thickness_nm``
        Voltage, V. Below the initial oxide ``offset_nm`` it is negative: no voltage grows so thin a film.

    Examples
    --------
    >>> float(thickness_to_voltage_V(101.6, nm_per_V=2.032))
    50.0
    """
    d = np.asarray(thickness_nm, dtype=np.float64) - float(offset_nm)
    rate = check_growth_rate(nm_per_V)
    if knee_V is None or nm_per_V_above_knee is None:
        return d / rate
    k = float(knee_V)
    at_knee = rate * k
    return np.where(d <= at_knee, d / rate, k + (d - at_knee) / check_growth_rate(nm_per_V_above_knee))


def voltage_text(voltage_V: float) -> str:
    """A voltage as a person reads it: :data:`VOLTAGE_DECIMALS` decimals, no unit.

    Parameters
    ----------
    voltage_V : float
        Volts.

    Returns
    -------
    str
        ``"11.2"`` for 11.1724; ``"0.0"`` for a negative value that rounds to zero.

    Examples
    --------
    >>> voltage_text(11.1724), voltage_text(100), voltage_text(-0.01)
    ('11.2', '100.0', '0.0')
    """
    text = f"{float(voltage_V):.{VOLTAGE_DECIMALS}f}"
    return "0.0" if float(text) == 0.0 else text
