"""OpenPBR Surface: the thin film on a metal base (``thin_film_*`` over ``base_metalness`` 1), in numpy.

Port of the specification: AcademySoftwareFoundation/OpenPBR ``index.html`` at commit
f8d6d947dfae4c9b599965a86c22826ea7a8dbfb, sections "Metal" and "Thin-film iridescence":

- the film (``thin_film_thickness`` in µm, ``thin_film_ior``) sits on the base and modifies the
  Fresnel factor of the metal's microfacet BSDF; the recommended model is Belcour & Barla (2017):
  Airy summation with polarised Fresnel amplitudes and phases at both interfaces, integrated in
  Fourier space against the CIE 1931 XYZ CMFs per linear Rec.709 channel. The CMFs' transform is
  taken exactly (:func:`swatch.presets.spectral.cmf_sensitivity`, three orders) rather than through
  the paper's Gaussian fit (:func:`gaussian_sensitivity`, kept for reference): the specification
  leaves the spectral integration to the implementation, and the exact transform makes the port
  agree with a transfer-matrix reference to a few tenths of ΔE2000 (tests/presets/test_presets.py);
- the metal is specified by the F82-tint Fresnel (F0 = ``base_color``, the value at cos = 1/7 =
  ``specular_color`` × Schlick); for the film the specification suggests mapping it to an
  effective complex IOR, e.g. Gulbrandsen (2014): n, k from r = F0 and g = that F82 value, then
  the exact conductor Fresnel (amplitude and phase) at the film/metal interface.

Output: the Fresnel factor (..., 3) in linear Rec.709 (the MaterialX document's colour space).
"""
from __future__ import annotations

import numpy as np

from swatch.presets.cycles import (
    airy_summation,
    conductor_polarized,
    dielectric_polarized,
    f82,
    f82tint_B,
    gulbrandsen_nk,
    sensitivities,
)
from swatch.presets.spectral import (
    SENSITIVITY_FIT_NORM,
    SENSITIVITY_FIT_POS,
    SENSITIVITY_FIT_VAL,
    SENSITIVITY_FIT_VAR,
    SENSITIVITY_FIT_X2,
    XYZ_TO_REC709,
)

__all__ = ["thin_film_metal_fresnel", "gaussian_sensitivity"]


def gaussian_sensitivity(opd_nm) -> np.ndarray:
    """Belcour & Barla's Gaussian fit of the XYZ CMFs' Fourier transform, as complex Rec.709 (..., 3).

    Re(e^{iφ}·conj(S)) equals the real ``evalSensitivity(OPD, φ)`` of the paper's code for one
    phase φ on all components.

    Parameters
    ----------
    opd_nm : array_like
        Optical path difference, nm.

    Returns
    -------
    numpy.ndarray
        Complex linear Rec.709, shape ``opd_nm.shape + (3,)``.

    References
    ----------
    :cite:`Belcour2017`.
    """
    phase = 2.0 * np.pi * np.asarray(opd_nm, dtype=np.float64)[..., None] * 1.0e-9
    val, pos, var = SENSITIVITY_FIT_VAL, SENSITIVITY_FIT_POS, SENSITIVITY_FIT_VAR
    a2, p2, v2 = SENSITIVITY_FIT_X2
    xyz = val * np.sqrt(2.0 * np.pi * var) * np.exp(-1j * pos * phase) * np.exp(-(phase ** 2) * var)
    extra = (a2 * np.sqrt(2.0 * np.pi * v2) * np.exp(-1j * p2 * phase[..., 0])
             * np.exp(-v2 * phase[..., 0] ** 2))
    xyz = np.concatenate([(xyz[..., 0] + extra)[..., None], xyz[..., 1:]], axis=-1) / SENSITIVITY_FIT_NORM
    return xyz @ XYZ_TO_REC709.T


def thin_film_metal_fresnel(cos_theta, thickness_nm, film_ior, base_color, specular_color=1.0) -> np.ndarray:
    """Fresnel (..., 3), linear Rec.709, of an OpenPBR metal under a thin film (weight 1).

    ``thickness_nm`` is ``thin_film_thickness`` × 1000; ``base_color`` (..., 3) the F0 colour.

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the incidence angle on the facet.
    thickness_nm, film_ior : array_like
        ``thin_film_thickness`` × 1000 and ``thin_film_ior``, broadcast with ``cos_theta``.
    base_color : array_like, shape (..., 3)
        F0 colour (linear Rec.709).
    specular_color : array_like, optional
        The F82 tint.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        In [0, 1].
    """
    cos1 = np.asarray(cos_theta, dtype=np.float64)
    d = np.asarray(thickness_nm, dtype=np.float64)
    eta = np.asarray(film_ior, dtype=np.float64)
    cos1, d, eta = np.broadcast_arrays(cos1, d, eta)
    F0 = np.clip(np.asarray(base_color, dtype=np.float64), 0.0, 1.0)
    tint = np.minimum(np.asarray(specular_color, dtype=np.float64), 1.0)
    g = f82(1.0 / 7.0, F0, f82tint_B(F0, tint))
    n, k = gulbrandsen_nk(F0, g)
    R12_s, R12_p, sgn_s, sgn_p, cos2 = dielectric_polarized(cos1, eta)
    R23_s, R23_p, ph_s, ph_p = conductor_polarized(cos2[..., None], eta[..., None], n, k)
    opd = 2.0 * eta * d * cos2
    ph_s = ph_s * -sgn_s[..., None]
    ph_p = ph_p * -sgn_p[..., None]
    S = sensitivities(opd)
    Rs = airy_summation(R12_s[..., None], R23_s, S, ph_s)
    Rp = airy_summation(R12_p[..., None], R23_p, S, ph_p)
    return np.clip(0.5 * (Rs + Rp), 0.0, 1.0)
