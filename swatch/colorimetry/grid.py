"""The wavelength grids colour-science's ASTM E308 integration accepts, and the one a wavelength axis lies on.

ASTM E308 tabulates its weights at 1, 5, 10 and 20 nm intervals (:data:`ASTM_E308_STEPS_NM`), on whole
multiples of the interval. colour-science takes a grid as even only when its steps are exactly equal, so an
axis that is such a grid but for float noise (an instrument's 729.99999999 for 730 nm) is replaced by the grid
itself (:func:`astm_e308_grid`) before it is integrated; any other axis is interpolated onto a grid on purpose
(:func:`swatch.fit.result.colour_grid`).

References
----------
.. [1] :cite:`ASTME308`: the intervals of its weight tables.
.. [2] :cite:`Carter2018`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["ASTM_E308_STEPS_NM", "GRID_TOLERANCE_NM", "astm_e308_grid"]

#: Wavelength steps the ASTM E308 practice (colour.sd_to_XYZ's default) accepts, nm.
ASTM_E308_STEPS_NM = (1.0, 5.0, 10.0, 20.0)
#: A wavelength within this of an ASTM E308 grid's is that grid's, nm (instruments write 729.99999999 for 730).
GRID_TOLERANCE_NM = 1e-6


def astm_e308_grid(wavelength_nm) -> np.ndarray | None:
    """The ASTM E308 grid ``wavelength_nm`` lies on, exactly: an even 1, 5, 10 or 20 nm step from a multiple
    of the step, every wavelength within :data:`GRID_TOLERANCE_NM` of it; None when it lies on none.

    The grid's wavelengths are whole nanometres, so its steps are exactly equal, as colour-science's
    ASTM E308 integration requires (it refuses a step of 9.99999999 nm).

    Parameters
    ----------
    wavelength_nm : array_like, shape (W,)
        Wavelengths, nm (two or more; any that are not finite or not increasing lie on no grid).

    Returns
    -------
    numpy.ndarray, shape (W,), or None
        ``step * (k0 + arange(W))``, nm, or None.

    Examples
    --------
    >>> astm_e308_grid([380.0, 390.0, 399.99999999]).tolist(), astm_e308_grid([380.0, 387.0, 394.0])
    ([380.0, 390.0, 400.0], None)
    """
    wl = np.asarray(wavelength_nm, dtype=np.float64).ravel()
    if wl.size < 2 or not np.all(np.isfinite(wl)) or not np.all(np.abs(wl) < 1e12):
        return None
    step = (wl[-1] - wl[0]) / (wl.size - 1)
    for s in ASTM_E308_STEPS_NM:
        if abs(step - s) <= 2 * GRID_TOLERANCE_NM:
            grid = s * (np.round(wl[0] / s) + np.arange(wl.size, dtype=np.float64))
            return grid if np.all(np.abs(wl - grid) <= GRID_TOLERANCE_NM) else None
    return None
