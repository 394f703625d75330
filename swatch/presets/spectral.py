"""Spectral integration in Fourier space for thin-film models (Belcour & Barla 2017), and RGB→Lab.

The thin-film models integrate the Airy reflectance against colour-matching functions with a
series whose terms are Fourier transforms of the CMFs at multiples of the optical path
difference (OPD). Two forms are used by the renderers ported here:

- :func:`gltf_sensitivity` — the Gaussian fit of the XYZ CMFs' transforms that
  ``KHR_materials_iridescence`` prints (``evalSensitivity``), converted to linear Rec.709;
- :func:`cmf_sensitivity` — the tabulated transform Cycles builds: ``doc/precompute/
  thin_film_table.py`` (blender/blender 687f190bf2bfd87be2fd1b8939fe3442d6c3b202) resamples the
  CIE 1931 2° XYZ CMFs on a uniform frequency grid (1022 points, 0–60 µm, with the 1/ν²
  Jacobian), takes ``numpy.fft.rfft`` (512 complex rows), and ``ShaderManager::
  compute_thin_film_table`` (intern/cycles/scene/shader.cpp) converts XYZ to Rec.709 and
  normalises each channel by its DC term; the kernel reads the table at
  ``x = 2π·OPD/60000 nm`` with clamped linear interpolation (``lookup_table_read``). The CMFs
  come from colour-science (same CIE data), interpolated with scipy's CubicSpline as the script does.

Colour of an RGB reflectance: the models' output is a linear Rec.709 (sRGB primaries, D65 white)
reflectance; :func:`rgb_to_Lab` converts it to XYZ with colour-science's sRGB matrix and to
CIELAB relative to D65 (CIE 1931 2°), the colorimetry the fits are judged in.
"""
from __future__ import annotations

import functools

import colour
import numpy as np
from scipy.interpolate import CubicSpline

__all__ = ["XYZ_TO_REC709", "gltf_sensitivity", "gaussian_sensitivity_xyz", "cmf_sensitivity", "rgb_to_Lab", "CYCLES_TABLE_SIZE",
           "SENSITIVITY_FIT_VAL", "SENSITIVITY_FIT_POS", "SENSITIVITY_FIT_VAR", "SENSITIVITY_FIT_X2", "SENSITIVITY_FIT_NORM"]

#: XYZ (D65) to linear Rec.709, as printed by the glTF extension and Cycles' init_xyz_transforms.
XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])
CYCLES_TABLE_SIZE = 512
#: Belcour & Barla's Gaussian fit of the CIE 1931 XYZ CMFs' Fourier transforms (their code's
#: ``evalSensitivity``, printed by KHR_materials_iridescence and MaterialX): per component X, Y, Z the
#: amplitude, position (per m of optical path, times 2π) and variance; X's second lobe (amplitude,
#: position, variance); the normalisation. Defined once: glTF, MaterialX and OpenPBR use them.
SENSITIVITY_FIT_VAL = np.array([5.4856e-13, 4.4201e-13, 5.2481e-13])
SENSITIVITY_FIT_POS = np.array([1.6810e06, 1.7953e06, 2.2084e06])
SENSITIVITY_FIT_VAR = np.array([4.3278e09, 9.3046e09, 6.6121e09])
SENSITIVITY_FIT_X2 = (9.7470e-14, 2.2399e06, 4.5282e09)
SENSITIVITY_FIT_NORM = 1.0685e-7
_CYCLES_TABLE_SPAN_NM = 60000.0


def gltf_sensitivity(opd_nm, shift) -> np.ndarray:
    """``evalSensitivity(OPD, shift)`` of KHR_materials_iridescence: (..., 3) linear Rec.709.

    ``opd_nm`` (...) is the optical path difference in nm; ``shift`` (..., 3) the phase shift per
    component (applied to X, Y, Z in that order, as the reference code does).

    Parameters
    ----------
    opd_nm : array_like
        Optical path difference, nm.
    shift : array_like, shape (..., 3)
        Phase shifts, radians.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Linear Rec.709.
    """
    return gaussian_sensitivity_xyz(opd_nm, shift) @ XYZ_TO_REC709.T


def gaussian_sensitivity_xyz(opd_nm, shift) -> np.ndarray:
    """Belcour & Barla's Gaussian fits of the XYZ CMFs' transforms at ``opd_nm`` with per-component
    phase ``shift`` (..., 3): XYZ, before any conversion to RGB (MaterialX's ``mx_eval_sensitivity``).

    Parameters
    ----------
    opd_nm : array_like
        Optical path difference, nm.
    shift : array_like, shape (..., 3)
        Phase shifts, radians.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        XYZ, normalised as the reference code (÷ 1.0685e-7).

    References
    ----------
    :cite:`Belcour2017`.
    """
    phase = 2.0 * np.pi * np.asarray(opd_nm, dtype=np.float64)[..., None] * 1.0e-9
    shift = np.asarray(shift, dtype=np.float64)
    val, pos, var = SENSITIVITY_FIT_VAL, SENSITIVITY_FIT_POS, SENSITIVITY_FIT_VAR
    a2, p2, v2 = SENSITIVITY_FIT_X2
    xyz = val * np.sqrt(2.0 * np.pi * var) * np.cos(pos * phase + shift) * np.exp(-(phase ** 2) * var)
    extra = (a2 * np.sqrt(2.0 * np.pi * v2) * np.cos(p2 * phase[..., 0] + shift[..., 0])
             * np.exp(-v2 * phase[..., 0] ** 2))
    return np.concatenate([(xyz[..., 0] + extra)[..., None], xyz[..., 1:]], axis=-1) / SENSITIVITY_FIT_NORM


@functools.lru_cache(maxsize=1)
def _cycles_table() -> np.ndarray:
    """The (512, 3) complex Rec.709 table of Cycles' thin-film sensitivity (DC = 1 per channel)."""

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl = np.asarray(cmfs.wavelengths, dtype=np.float64)
    xyz = np.asarray(cmfs.values, dtype=np.float64)
    # The script pads the 360–830 nm data with a zero sample on each side (359 and 831 nm).
    wl = np.concatenate([[wl[0] - 1.0], wl, [wl[-1] + 1.0]])
    xyz = np.vstack([np.zeros(3), xyz, np.zeros(3)])
    spline = CubicSpline(wl, xyz, axis=0, extrapolate=False)
    n = 2 * CYCLES_TABLE_SIZE - 2  # 1022 real samples -> 512 complex rows
    span_um = _CYCLES_TABLE_SPAN_NM / 1000.0
    freq = np.clip(np.linspace(0.0, np.pi * (n - 1) / span_um, n), 1e-40, None)  # 1/µm
    resampled = np.nan_to_num(spline(1000.0 / freq) / (freq * freq)[:, None])
    spectrum = np.fft.rfft(resampled, axis=0)  # (512, 3) complex, XYZ
    rgb = spectrum @ XYZ_TO_REC709.T
    return rgb / rgb[0].real


def cmf_sensitivity(opd_nm) -> np.ndarray:
    """Cycles' ``iridescence_lookup_sensitivity(OPD)``: (..., 3) complex (re, im per channel).

    Parameters
    ----------
    opd_nm : array_like
        Optical path difference, nm.

    Returns
    -------
    numpy.ndarray
        Complex, shape ``opd_nm.shape + (3,)``.
    """
    table = _cycles_table()
    x = 2.0 * np.pi * np.asarray(opd_nm, dtype=np.float64) / _CYCLES_TABLE_SPAN_NM
    pos = np.clip(x, 0.0, 1.0) * (CYCLES_TABLE_SIZE - 1)
    i0 = np.minimum(pos.astype(np.int64), CYCLES_TABLE_SIZE - 2)
    t = (pos - i0)[..., None]
    lo = np.take(table, i0, axis=0)
    return lo + (np.take(table, i0 + 1, axis=0) - lo) * t


@functools.lru_cache(maxsize=1)
def rgb_to_xyz_matrix() -> tuple[np.ndarray, np.ndarray]:
    """sRGB (Rec.709 primaries) linear RGB → XYZ matrix (3, 3) and the D65 white point xy (colour-science).

    Returns
    -------
    matrix : numpy.ndarray, shape (3, 3)
        XYZ = matrix @ RGB.
    white_xy : numpy.ndarray, shape (2,)
        The sRGB white point (D65) as CIE 1931 xy chromaticity.
    """

    space = colour.RGB_COLOURSPACES["sRGB"]
    return np.asarray(space.matrix_RGB_to_XYZ, dtype=np.float64), np.asarray(space.whitepoint, dtype=np.float64)


def rgb_to_Lab(rgb) -> np.ndarray:
    """CIELAB (D65, CIE 1931 2°) of a linear Rec.709 reflectance (..., 3); 1 = perfect white.

    Parameters
    ----------
    rgb : array_like, shape (..., 3)
        Linear Rec.709 reflectance.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        L*, a*, b* under D65 and the CIE 1931 2° observer (white: L* = 100).

    Examples
    --------
    >>> round(float(rgb_to_Lab([1.0, 1.0, 1.0])[0]), 4)  # white: L* = 100
    100.0
    """

    m, white = rgb_to_xyz_matrix()
    XYZ = np.asarray(rgb, dtype=np.float64) @ m.T
    return colour.XYZ_to_Lab(XYZ, white)
