"""References the environment-lighting tests share (#12, #17): the thin-film GGX directional albedo by
quadrature (Byrnes' ``tmm.coh_tmm`` for the film, ``scipy.integrate.quad_vec`` for the integral, GGX ``D``
and height-correlated Smith ``G`` written out here), CIELAB of spectra by ``colour.sd_to_XYZ``, and a
writer of equirectangular test maps (OpenImageIO). Used by tests/render/test_environment.py,
test_env_render.py, test_mesh.py and tests/catalog/test_catalog_explorer_env_browser.py."""
from __future__ import annotations

import functools

import colour
import numpy as np
import OpenImageIO as oiio
from scipy import integrate
from scipy.interpolate import CubicSpline

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.physics.materials import load_material
from swatch.physics.model import get_coating
from tests.tmm_reference import unpolarised_R

ALPHA = 0.3
COATING = get_coating()
CM = get_colorimeter(COATING.wavelength_nm)
CM2 = CM.display_colorimeter  # CIE 1931 2°: the observer RGB is defined on
WL = np.asarray(COATING.wavelength_nm, dtype=float)


@functools.cache
def indices():
    return load_material("TiO2-Siefke").nk(WL), load_material("Ti-Johnson").nk(WL)


def tmm_R(d_nm: float, theta_rad: float) -> np.ndarray:
    nf, ns = indices()
    return unpolarised_R([1.0, nf, ns], [np.inf, d_nm, np.inf], theta_rad, WL)


def ggx_lambda(c, a):
    t2 = (1.0 - c * c) / (c * c)
    return 0.5 * (np.sqrt(1.0 + a * a * t2) - 1.0)


@functools.cache
def albedo_normal_view(d_nm: float, a: float = ALPHA) -> np.ndarray:
    """Spectral directional albedo (W,) for the view along the normal, by quadrature."""
    nodes = np.radians(np.arange(0.0, 46.0, 3.0))  # θ_d from 0 to 45°
    spline = CubicSpline(nodes, np.stack([tmm_R(d_nm, t) for t in nodes]), axis=0)

    def integrand(theta_l):
        cl = np.cos(theta_l)
        ch = np.cos(theta_l / 2)  # h bisects l and n
        den = (a * a - 1.0) * ch * ch + 1.0
        D = a * a / (np.pi * den * den)
        G = 1.0 / (1.0 + ggx_lambda(max(cl, 1e-12), a))  # Λ(v) = 0 along the normal
        f = D * G / (4.0 * cl * 1.0)
        return 2.0 * np.pi * f * cl * np.sin(theta_l) * spline(theta_l / 2)

    val, _err = integrate.quad_vec(integrand, 0.0, np.pi / 2 - 1e-9, epsrel=1e-7)
    return val


def xyz_of_srgb(rgb) -> np.ndarray:
    """CIE 1931 2° XYZ (Y = 100 white) of linear sRGB (display RGB is defined on 2° colorimetry;
    1.0 = white)."""
    A = CM.rgb_linear(np.eye(3) * 100.0, "srgb").T  # rgb = A @ XYZ_2 / 100
    return 100.0 * np.linalg.solve(A, np.asarray(rgb, dtype=float).T).T


def lab_2deg(XYZ_2):
    """CIELAB of 2° tristimulus values (D65 white of the 2° observer)."""
    return CM2.Lab(XYZ_2)


def lab_of_spectrum(R):
    """CIELAB (D65, CIE 1931 2°) of a reflectance spectrum by colour.sd_to_XYZ (ASTM E308)."""
    sd = colour.SpectralDistribution(R, WL)
    xyz = colour.sd_to_XYZ(sd, colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], colour.SDS_ILLUMINANTS["D65"])
    return CM2.Lab(xyz)


def write_equirect(path, pixels):
    h, w, c = pixels.shape
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(w, h, c, oiio.FLOAT))
    out.write_image(np.ascontiguousarray(pixels, dtype=np.float32))
    out.close()
