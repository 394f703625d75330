"""Angular colour maps: the colour of one thickness over in-plane light × view angles (the paper's
Fig. 5/11), as a reflectance factor per wavelength, XYZ, CIELAB, linear RGB and a display image."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from swatch.colorimetry.colorimeter import check_rgb_space
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_ANGULAR_SAMPLES
from swatch.physics import geometry, microfacet
from swatch.physics.model import check_thickness_nm
from swatch.render.builtin import shading
from swatch.render.display import HUE_SHOULDER_RULE, PAPER_EXPOSURE_RULE, display_encode, display_encode_hue, exposure
from swatch.render.metadata import coating_and_colorimeter, common_metadata

__all__ = ["AngularMap", "angular_map", "check_angular_size"]

#: Cell-wavelength samples of the optics per block (~16 bytes × 8 temporaries each).
_BLOCK_SAMPLES = 1 << 20


def check_angular_size(n_light: int, n_view: int, n_wavelengths: int) -> None:
    """Refuse an angular map whose arrays would exceed the run's memory budget.

    Parameters
    ----------
    n_light, n_view : int
        Cells along the light and view axes.
    n_wavelengths : int
        Wavelengths of the spectral grid.

    Returns
    -------
    None
        Returns only when the map fits the memory cap.

    Raises
    ------
    swatch.core.errors.SwatchError
        More than :data:`MAX_ANGULAR_SAMPLES` samples (cells × wavelengths); the message gives a size that fits.
    """
    samples = n_light * n_view * n_wavelengths
    if samples > MAX_ANGULAR_SAMPLES:
        cells = MAX_ANGULAR_SAMPLES // n_wavelengths
        raise SwatchError(f"angular map too large: {n_light} × {n_view} cells × {n_wavelengths} wavelengths; at most "
                          f"{MAX_ANGULAR_SAMPLES:,} samples (cells × wavelengths), e.g. {cells:,} cells "
                          f"({int(cells ** 0.5)} × {int(cells ** 0.5)}) at {n_wavelengths} wavelengths")


@dataclass
class AngularMap:
    """Colour over light angle (rows) × view angle (columns), in plane, on opposite sides.

    Attributes
    ----------
    thickness_nm : float
        Film thickness, nm.
    light_deg, view_deg : numpy.ndarray, shapes (L,) and (V,)
        The angles of the rows and columns, degrees from the normal.
    theta_d_deg : numpy.ndarray, shape (L, V)
        Incidence angle on the half-vector facet, degrees.
    XYZ, Lab : numpy.ndarray, shape (L, V, 3)
        Colour of the reflectance factor (Y = 100 for a white diffuser).
    linear_rgb : numpy.ndarray, float, shape (L, V, 3)
        Scene-referred linear RGB in the map's space.
    display_rgb : numpy.ndarray, uint8, shape (L, V, 3)
        Display sRGB with ``exposure`` applied.
    exposure : float
        Display exposure factor applied to the linear map for the PNG.
    spectral : numpy.ndarray, shape (L, V, W)
        Reflectance factor per wavelength.
    wavelength_nm : numpy.ndarray, shape (W,)
        The spectra's wavelength grid, nm.
    metadata : dict
        What the files written from the map record about it.
    """

    thickness_nm: float
    light_deg: np.ndarray
    view_deg: np.ndarray
    theta_d_deg: np.ndarray
    XYZ: np.ndarray
    Lab: np.ndarray
    linear_rgb: np.ndarray
    display_rgb: np.ndarray
    exposure: float
    spectral: np.ndarray
    wavelength_nm: np.ndarray
    metadata: dict = field(default_factory=dict)


#: Default light and view polar angles of a map: 0–85° in 1° steps.
DEFAULT_ANGLES_DEG = tuple(range(86))


def angular_map(thickness_nm: float, light_deg=DEFAULT_ANGLES_DEG, view_deg=DEFAULT_ANGLES_DEG, coating=None,
                colorimeter=None, model: str = "paper", roughness_alpha: float = 0.3, distribution: str = "ggx",
                space: str = "srgb") -> AngularMap:
    """The colour of one thickness over all in-plane light × view angles (the paper's Fig. 5/11).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    light_deg, view_deg : array_like, shapes (L,) and (V,)
        Polar angles of the light and the view, degrees, on opposite sides of the normal (in plane).
    coating, colorimeter : Coating, Colorimeter or None
        The film and the colour conditions (defaults: the default process; D65 and CIE 1964 10° for
        XYZ/Lab; RGB always from CIE 1931 2°).
    model : {"paper", "microfacet"}
        The half-vector reflectance alone, or D·G·F/(4 cos θl cos θv).
    roughness_alpha : float
        GGX/Beckmann alpha (microfacet model).
    distribution : {"ggx", "beckmann"}
        The microfacet normal distribution of the microfacet model.
    space : {"srgb", "acescg"}
        Primaries of ``linear_rgb``.

    Returns
    -------
    AngularMap
        ``spectral`` (L, V, W) is the reflectance factor per wavelength: ``F`` for the paper's model,
        ``π D G F / (4 cos θ_l cos θ_v)`` for the microfacet model (no ``cos θ_l`` irradiance factor:
        a gonio-spectrophotometer's reflectance factor). ``XYZ``/``Lab`` are its colour (Y = 100 for a
        white diffuser; L* may exceed 100 in the mirror region); ``linear_rgb`` in ``space``;
        ``display_rgb`` sRGB uint8 with ``exposure`` applied (1 for the paper's model; for the
        microfacet model chosen as in :mod:`swatch.render.display`).

    References
    ----------
    :cite:`Fujii2019`, Fig. 5 and 11; :cite:`Walter2007`.
    """

    d = float(check_thickness_nm(float(thickness_nm)))
    model = shading.check_model(model)
    roughness_alpha = microfacet.check_roughness_alpha(roughness_alpha)
    distribution = microfacet.check_distribution(distribution)
    lt, vw = (np.atleast_1d(a) for a in geometry.check_light_view_deg(light_deg, view_deg))
    if lt.ndim != 1 or vw.ndim != 1:
        raise SwatchError("light and view angles must be 1-D lists")
    space = check_rgb_space(space)
    coating, colorimeter = coating_and_colorimeter(coating, colorimeter)
    L, V = lt[:, None], vw[None, :]
    cos_d = geometry.cos_theta_d(L, V)
    theta_d = geometry.theta_d_deg(L, V)
    check_angular_size(lt.size, vw.size, coating.wavelength_nm.size)
    # (L, V, W), in blocks of light rows: the optics' complex temporaries stay ~100 MB at any map size
    spectral = np.empty((*cos_d.shape, coating.wavelength_nm.size), dtype=np.float64)
    rows = max(1, _BLOCK_SAMPLES // (vw.size * coating.wavelength_nm.size))
    for i in range(0, lt.size, rows):
        spectral[i:i + rows] = coating.reflectance_cos(d, cos_d[i:i + rows]).R
    if model == "microfacet":
        cl = np.cos(np.radians(L)) + 0 * V
        cv = np.cos(np.radians(V)) + 0 * L
        ch = geometry.cos_theta_h(L, V)
        s = shading.intensity(cl, cv, ch, cos_d, model, roughness_alpha, distribution, irradiance=False)
        spectral *= s[..., None]
        k, rule = exposure(model, s, ch, np.ones_like(s, dtype=bool), roughness_alpha, distribution)
        rule = rule.replace("F=1 intensity", "F=1 reflectance factor").replace(
            "the brighter highlight rolls off to white with a smooth per-channel shoulder above 0.8",
            HUE_SHOULDER_RULE)
        rule += "" if HUE_SHOULDER_RULE in rule else "; " + HUE_SHOULDER_RULE
    else:
        k, rule = 1.0, PAPER_EXPOSURE_RULE
    XYZ = colorimeter.XYZ(spectral)
    Lab = colorimeter.Lab(XYZ)
    XYZ_2 = colorimeter.display_XYZ(spectral)  # RGB from CIE 1931 2° colorimetry
    rgb = np.asarray(colorimeter.rgb_linear(XYZ_2, space), dtype=np.float32)
    srgb = rgb if space == "srgb" else np.asarray(colorimeter.rgb_linear(XYZ_2, "srgb"), dtype=np.float32)
    # the microfacet map's mirror region is far above white: a hue-preserving shoulder (swatch.render.display)
    display = display_encode_hue(srgb, k) if model == "microfacet" else display_encode(srgb * np.float32(k))
    meta = common_metadata(d, coating, colorimeter, model, distribution, roughness_alpha)
    meta.update({
        "geometry": "angular map: rows = light polar angle, columns = view polar angle, in one plane on "
                    "opposite sides of the normal (light = view is the mirror direction)",
        "light_deg": f"{lt[0]:g}:{lt[-1]:g} ({lt.size} rows)",
        "view_deg": f"{vw[0]:g}:{vw[-1]:g} ({vw.size} columns)",
        "rgb_space": space,
        "units": "reflectance factor (1.0 = perfect white diffuser); XYZ with Y = 100 for it",
        "exposure": round(float(k), 9),
        "exposure_rule": rule,
    })
    return AngularMap(d, lt, vw, theta_d, XYZ, Lab, rgb, display, float(k), spectral,
                      np.asarray(coating.wavelength_nm, dtype=np.float64), meta)
