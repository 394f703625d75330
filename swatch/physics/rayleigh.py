"""The Rayleigh criterion (the paper's §2): is a surface of roughness Ra optically rough?

A surface scatters off the mirror direction (the microfacet / half-vector picture applies) when its
height variation exceeds ``h = λ / (8 cos θ)``; below it, it is a mirror with colour only near the
specular direction. The paper's blue sample (Ra 268 nm) is rough: ``h`` spans 47.5–195 nm over
380–780 nm and 0–60°.

References
----------
.. [1] :cite:`Fujii2019`: §2, the Rayleigh criterion applied to the blue sample.
.. [2] :cite:`Beckmann1963`: the Rayleigh criterion.
"""
from __future__ import annotations

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_RA_NM

__all__ = ["ANGLES_DEG", "WAVELENGTHS_NM", "MAX_RA_NM", "rayleigh_criterion", "rayleigh_text", "rayleigh_json"]

#: Incidence angles and wavelengths the criterion is tabulated at.
ANGLES_DEG = np.arange(0.0, 61.0, 10.0)
WAVELENGTHS_NM = np.array([380.0, 480.0, 580.0, 680.0, 780.0])


def rayleigh_criterion(ra_nm: float) -> dict:
    """The criterion's table and verdict for an arithmetic mean roughness ``ra_nm`` (nm).

    Parameters
    ----------
    ra_nm : float
        Arithmetic mean roughness Ra, nm, from 0 to ``MAX_RA_NM``.

    Returns
    -------
    dict
        ``h_nm`` (numpy.ndarray, shape (7, 5): :data:`ANGLES_DEG` × :data:`WAVELENGTHS_NM`, nm),
        ``h_min_nm``, ``h_max_nm`` (float, nm), ``verdict`` (``rough`` when Ra > every h,
        ``smooth`` when Ra < every h, else ``partly rough``) and ``text`` (what it means).

    Raises
    ------
    SwatchError
        For a non-finite or negative Ra, or one above ``MAX_RA_NM``.

    References
    ----------
    :cite:`Fujii2019`, §2.
    """
    if not np.isfinite(ra_nm) or ra_nm < 0 or ra_nm > MAX_RA_NM:
        raise SwatchError("`ra_nm` must be a roughness from 0 to 1e6 nm")
    h = WAVELENGTHS_NM[None, :] / (8.0 * np.cos(np.radians(ANGLES_DEG))[:, None])
    h_min, h_max = float(h.min()), float(h.max())
    if ra_nm > h_max:
        verdict = "rough"
        text = "optically rough over the whole visible range and 0–60°: facets scatter off-mirror (half-vector model applies)"
    elif ra_nm < h_min:
        verdict = "smooth"
        text = "optically smooth over the whole visible range and 0–60°: a mirror; colour only near the specular direction"
    else:
        verdict = "partly rough"
        text = "rough for short wavelengths or steep angles, smooth otherwise"
    return {"h_nm": h, "h_min_nm": h_min, "h_max_nm": h_max, "verdict": verdict, "text": text}


def rayleigh_text(r: dict, ra_nm: float) -> list[str]:
    """The lines ``swatch roughness`` prints for :func:`rayleigh_criterion`'s result ``r``.

    Parameters
    ----------
    r : dict
        The result of :func:`rayleigh_criterion`.
    ra_nm : float
        The roughness it was computed for, nm (printed in the verdict line).

    Returns
    -------
    list of str
        A header, the column titles, one row of h (nm) per angle, and the verdict.
    """
    lines = [f"Rayleigh criterion h = λ/(8 cos θ): {r['h_min_nm']:.1f}–{r['h_max_nm']:.1f} nm over 380–780 nm, 0–60°",
             f"{'θ_deg':>6} " + " ".join(f"{w:>7.0f}nm" for w in WAVELENGTHS_NM)]
    lines += [f"{a:6.0f} " + " ".join(f"{v:9.1f}" for v in row) for a, row in zip(ANGLES_DEG, r["h_nm"], strict=True)]
    return [*lines, f"Ra = {ra_nm:g} nm: {r['text']}"]


def rayleigh_json(r: dict, ra_nm: float) -> dict:
    """``swatch roughness --json``: the criterion's table and verdict for ``ra_nm``.

    Parameters
    ----------
    r : dict
        The result of :func:`rayleigh_criterion`.
    ra_nm : float
        The roughness it was computed for, nm.

    Returns
    -------
    dict
        ``ra_nm``, ``h_min_nm``, ``h_max_nm``, ``verdict``, ``angle_deg`` (7), ``wavelength_nm`` (5)
        and ``h_nm`` (7 lists of 5, nm): plain JSON types.
    """
    return {"ra_nm": ra_nm, "h_min_nm": r["h_min_nm"], "h_max_nm": r["h_max_nm"], "verdict": r["verdict"],
            "angle_deg": ANGLES_DEG.tolist(), "wavelength_nm": WAVELENGTHS_NM.tolist(), "h_nm": r["h_nm"].tolist()}
