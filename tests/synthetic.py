"""Synthetic sBRDF measurements made by an independent route (used by tests and benchmarks).

Reflectance on the half-vector facet from Byrnes' ``tmm.coh_tmm`` (not swatch.physics.optics), the facet
angle from vector algebra written here (not swatch.physics.geometry), times a GGX microfacet intensity
``D G / (4 cos_l cos_v)`` (Trowbridge–Reitz D, separable Smith G; normalised to 1 at the brightest
geometry of the set, so values stay fractions), times an unknown global scale (0.3–1),
plus Gaussian noise of ``noise`` × the geometry's mean level (1 % by default), with a fixed seed.
Only the optical constants come from swatch's tables (the measured data the model is fitted with).
"""
from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, load_material
from tests.tmm_reference import unpolarised_R

#: The paper's estimated thicknesses (Table 2), nm.
PAPER_THICKNESSES_NM = (15.9, 50.8, 60.6, 87.5, 121.4, 138.4, 160.6, 173.9, 226.6, 264.4)
#: A 10 × 10 in-plane light × view grid (100 geometries, view on the far side).
GRID_ANGLES_DEG = np.arange(0.0, 80.0, 8.0)
WAVELENGTHS_NM = np.arange(380.0, 781.0, 5.0)


def grid_geometries(angles=GRID_ANGLES_DEG) -> tuple[np.ndarray, np.ndarray]:
    light, view = np.meshgrid(angles, angles, indexing="ij")
    return light.ravel(), view.ravel()


def _unit(polar_deg, azimuth_deg) -> np.ndarray:
    t, p = np.radians(polar_deg), np.radians(azimuth_deg)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


def half_vector_geometry(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None):
    """(theta_d_rad, cos_h, cos_l, cos_v): the facet incidence angle and cosines for GGX."""
    light_deg = np.asarray(light_deg, dtype=float)
    la = np.broadcast_to(np.asarray(light_azimuth_deg, dtype=float), light_deg.shape)
    va = la + 180.0 if view_azimuth_deg is None else np.broadcast_to(np.asarray(view_azimuth_deg, dtype=float), light_deg.shape)
    l = _unit(light_deg, la)
    v = _unit(view_deg, va)
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    cos_d = np.clip(np.sum(l * h, axis=-1), -1.0, 1.0)
    return np.arccos(cos_d), h[..., 2], l[..., 2], v[..., 2]


def ggx_factor(cos_h, cos_l, cos_v, alpha: float = 0.3) -> np.ndarray:
    """GGX D(h) G(l, v) / (4 cos_l cos_v)."""
    a2 = alpha * alpha
    D = a2 / (np.pi * (cos_h * cos_h * (a2 - 1.0) + 1.0) ** 2)

    def g1(c):
        return 2.0 * c / (c + np.sqrt(a2 + (1.0 - a2) * c * c))

    return D * g1(cos_l) * g1(cos_v) / (4.0 * cos_l * cos_v)


@functools.lru_cache(maxsize=4096)
def _tmm_R(thickness_nm: float, theta_rad: float, wavelengths: tuple, film: str, substrate: str) -> np.ndarray:
    wl = np.array(wavelengths)
    nf = load_material(film).nk(wl)
    ns = load_material(substrate).nk(wl)
    return unpolarised_R([1.0, nf, ns], [np.inf, thickness_nm, np.inf], theta_rad, wl)


def tmm_half_vector_reflectance(thickness_nm, light_deg, view_deg, wavelength_nm=WAVELENGTHS_NM,
                                light_azimuth_deg=0.0, view_azimuth_deg=None,
                                film=DEFAULT_FILM, substrate=DEFAULT_SUBSTRATE) -> np.ndarray:
    """(G, W) unpolarised Airy reflectance by tmm at each geometry's facet angle."""
    theta, _, _, _ = half_vector_geometry(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    wl = tuple(float(w) for w in np.asarray(wavelength_nm))
    keys = np.round(theta, 12)
    uniq, inv = np.unique(keys, return_inverse=True)
    rows = np.stack([_tmm_R(float(thickness_nm), float(t), wl, film, substrate) for t in uniq])
    return rows[inv.reshape(-1)]


def make_measurement(thickness_nm, light_deg, view_deg, wavelength_nm=WAVELENGTHS_NM,
                     light_azimuth_deg=0.0, view_azimuth_deg=None, alpha: float = 0.3,
                     noise: float = 0.01, seed: int = 0, scale: float | None = None):
    """(reflectance (G, W), global scale): tmm × GGX × scale + noise."""
    light_deg = np.asarray(light_deg, dtype=float)
    view_deg = np.asarray(view_deg, dtype=float)
    rng = np.random.default_rng(seed)
    if scale is None:
        scale = float(rng.uniform(0.3, 1.0))
    R = tmm_half_vector_reflectance(thickness_nm, light_deg, view_deg, wavelength_nm,
                                    light_azimuth_deg, view_azimuth_deg)
    _, cos_h, cos_l, cos_v = half_vector_geometry(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    I = ggx_factor(cos_h, cos_l, cos_v, alpha)
    I = I / I.max()  # an instrument's relative intensity: the brightest geometry is 1
    clean = scale * I[:, None] * R
    level = clean.mean(axis=1, keepdims=True)
    noisy = clean + noise * level * rng.standard_normal(clean.shape)
    return noisy, scale


def write_long_csv(path, light_deg, view_deg, wavelength_nm, reflectance, percent: bool = False,
                   light_azimuth_deg=None, view_azimuth_deg=None) -> Path:
    """Write an sBRDF set in long form (azimuth columns only when given)."""
    path = Path(path)
    with_az = light_azimuth_deg is not None
    head = "light_deg,view_deg," + ("light_azimuth_deg,view_azimuth_deg," if with_az else "") + "wavelength_nm,reflectance"
    lines = [head]
    f = 100.0 if percent else 1.0
    for g in range(len(light_deg)):
        az = f"{light_azimuth_deg[g]:g},{view_azimuth_deg[g]:g}," if with_az else ""
        for w, lam in enumerate(wavelength_nm):
            lines.append(f"{light_deg[g]:g},{view_deg[g]:g},{az}{lam:g},{reflectance[g, w] * f:.8g}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@functools.cache
def paper_dataset(index: int, seed: int = 0):
    """(thickness_nm, light (100,), view (100,), wavelength (81,), reflectance (100, 81), scale)."""
    d = PAPER_THICKNESSES_NM[index]
    light, view = grid_geometries()
    R, scale = make_measurement(d, light, view, WAVELENGTHS_NM, seed=seed + index)
    return d, light, view, WAVELENGTHS_NM, R, scale


CXF3_NAMESPACE = "http://colorexchangeformat.com/CxF3-core"


def write_multi_angle_cxf(path, spectra: dict, aspecular_deg, wavelength_nm, creator: str):
    """A multi-angle CxF3 document as an instrument exports it, written with lxml and validated against the
    official XSD (tests/data/cxf3): per sample, one reflectance spectrum per BRDF angle (light 45°, the
    aspecular angles), D65 / 10°, the wavelengths evenly spaced.

    ``spectra`` maps a sample's name to its (G, W) reflectance factors (G = len(aspecular_deg)). Returns
    ``path``."""
    from lxml import etree

    cc = CXF3_NAMESPACE

    def el(parent, tag, text=None, **attrib):
        e = etree.SubElement(parent, f"{{{cc}}}{tag}", {k: str(v) for k, v in attrib.items()})
        if text is not None:
            e.text = str(text)
        return e

    wl = np.asarray(wavelength_nm, dtype=np.float64)
    start, step = round(float(wl[0])), round(float(wl[1] - wl[0]))
    root = etree.Element(f"{{{cc}}}CxF", nsmap={"cc": cc})
    info = el(root, "FileInformation")
    el(info, "Creator", creator)
    el(info, "CreationDate", "2026-12-01T00:00:00")
    res = el(root, "Resources")
    objs = el(res, "ObjectCollection")
    for name, rows in spectra.items():
        o = el(objs, "Object", ObjectType="Sample", Name=name, Id=name)
        el(o, "CreationDate", "2026-12-01T00:00:00")
        cv = el(o, "ColorValues")
        for k, R in enumerate(rows):
            el(cv, "ReflectanceSpectrum", " ".join(f"{x:.6f}" for x in R), ColorSpecification=f"CS{k}",
               StartWL=start)
    specs = el(res, "ColorSpecificationCollection")
    for k, a in enumerate(aspecular_deg):
        cs = el(specs, "ColorSpecification", Id=f"CS{k}")
        ts = el(cs, "TristimulusSpec")
        el(ts, "Illuminant", "D65")
        el(ts, "Observer", "10_Degree")
        el(ts, "Method", "E308_Table6")
        ms = el(cs, "MeasurementSpec")
        el(ms, "MeasurementType", "Spectrum_Reflectance")
        b = el(el(el(ms, "GeometryChoice"), "MultiAngle"), "BRDFAngle", Notation=f"45as{a:g}")
        el(b, "IlluminationAngle", 45.0)
        el(b, "Aspecular", a)
        el(ms, "WavelengthRange", StartWL=start, Increment=step)
    schema = etree.XMLSchema(etree.parse(str(Path(__file__).resolve().parent / "data" / "cxf3" / "CxF3_Core.xsd")))
    schema.assertValid(root)
    Path(path).write_bytes(etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True))
    return path
