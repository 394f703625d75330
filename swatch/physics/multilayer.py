"""Coherent reflectance of a stack of films on a substrate (the transfer-matrix product).

Used for clear layers over the oxide (:mod:`swatch.physics.overcoat`); with one film it equals
Airy's formula (:func:`swatch.physics.optics.film_reflectance`).

References
----------
.. [1] :cite:`Born1999`: §1.6.2–1.6.5, the characteristic matrix of a stratified medium.
.. [2] :cite:`Byrnes2016`: the formulation of the ``tmm`` package, the independent reference the tests compare with.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from swatch.core.errors import SwatchError
from swatch.physics.optics import Reflectance, check_film_geometry, check_index, check_wavelengths, fresnel_r, layer_q

__all__ = ["stack_reflectance"]


def stack_reflectance(
    thicknesses_nm: Sequence,
    n_layers: Sequence,
    n_substrate,
    incidence_deg,
    wavelength_nm,
    n_ambient: float = 1.0,
) -> Reflectance:
    """Coherent reflectance of a stack of films on a substrate by the transfer-matrix product.

    The characteristic matrix is ``M = D_01 P_1 D_12 P_2 ... D_N,sub`` with
    ``D_ij = [[1, r_ij], [r_ij, 1]] / t_ij`` and ``P_j = diag(exp(-i delta_j), exp(i delta_j))``;
    ``r = M_10 / M_00`` (the 1/t factors cancel in the ratio and are left out). With one film
    this equals :func:`swatch.physics.optics.film_reflectance`.

    Parameters
    ----------
    thicknesses_nm : sequence of array_like, nm
        One thickness per film, listed from the ambient side (e.g. a clear lacquer first, then
        the oxide); each broadcasts with ``incidence_deg`` to S.
    n_layers : sequence of array_like, complex, shape (W,) or scalar
        The films' indices, in the same order.
    n_substrate : array_like, complex, shape (W,) or scalar
        The substrate's (metal's) index ``n + i k`` (k ≥ 0) on the grid.
    incidence_deg : array_like, degrees
        Incidence angles in [0, 90).
    wavelength_nm : array_like, shape (W,), nm
        The wavelength grid, positive nm (checked by :func:`swatch.physics.optics.check_wavelengths`).
    n_ambient : float
        Real index of the ambient medium.

    Returns
    -------
    Reflectance
        ``R_s``, ``R_p``, ``r_s``, ``r_p`` of shape S + (W,).
    """
    if len(thicknesses_nm) != len(n_layers):
        raise SwatchError("a stack needs one thickness per film layer")
    wl = check_wavelengths(wavelength_nm)
    theta = np.asarray(incidence_deg, dtype=np.float64)
    ds = [np.asarray(t, dtype=np.float64) for t in thicknesses_nm]
    for d in ds:
        check_film_geometry(d, theta)
    n0 = float(np.real(n_ambient))
    ns = [np.asarray(n0, dtype=np.complex128)] + [
        check_index(n, wl, f"layer {j + 1}") for j, n in enumerate(n_layers)
    ] + [check_index(n_substrate, wl, "substrate")]
    kx = n0 * np.sin(np.radians(theta))[..., None]
    qs = [layer_q(n, kx) for n in ns]
    # the films' phase factors, shared by both polarisations: e^(∓iδ) of the films before the last, and for the
    # last one (next to the substrate, the one whose thickness varies) e^(2iδ) alone: M P D's ratio M_10/M_00
    # is (m10 + m11 z) / (m00 + m01 z) with z = r e^(2iδ) (the numerator and denominator over e^(−iδ))
    if not ds:
        raise SwatchError("a stack needs at least one film layer")
    delta = [(2.0 * np.pi / wl) * qs[j] * ds[j - 1][..., None] for j in range(1, len(ns) - 1)]
    inner = [(np.exp(-1j * dj), np.exp(1j * dj)) for dj in delta[:-1]]
    z_phase = np.exp(2j * delta[-1])
    interfaces = [fresnel_r(ns[j], qs[j], ns[j + 1], qs[j + 1]) for j in range(len(ns) - 1)]  # (r_s, r_p) each
    out: dict[str, np.ndarray] = {}
    for k, pol in enumerate(("s", "p")):
        rs = [rj[k] for rj in interfaces]
        m00: Any = 1.0  # D_01
        m01: Any = rs[0]
        m10: Any = rs[0]
        m11: Any = 1.0
        for (em, ep), r in zip(inner, rs[1:-1], strict=True):  # multiply by P_j then D_j,j+1
            a00, a01, a10, a11 = m00 * em, m01 * ep, m10 * em, m11 * ep
            m00, m01 = a00 + a01 * r, a00 * r + a01
            m10, m11 = a10 + a11 * r, a10 * r + a11
        z = rs[-1] * z_phase
        out[pol] = (m10 + m11 * z) / (m00 + m01 * z)
    r_s, r_p = out["s"], out["p"]
    return Reflectance(R_s=np.abs(r_s) ** 2, R_p=np.abs(r_p) ** 2, r_s=r_s, r_p=r_p)
