"""USD presets as files: one swatch's :class:`~swatch.presets.usd.UsdPreset` (the OpenPBR network of its
``.mtlx`` preset and the UsdPreviewSurface fallback, with the documentation string that states both errors) and one
thickness's ``.usda``/``.usdz`` (``swatch preset --format usd|usdz``).

Apart from :mod:`swatch.presets.files` because it loads usd-core (``pxr``: a few hundred MB of address space), which
only a USD preset needs: the other formats, and a catalog without USD, never load it.
"""
from __future__ import annotations

import numpy as np

from swatch.presets import anisotropy, usd
from swatch.presets.files import GEOMETRY_45_0, roughness_factor, round_params
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00, fit_presets
from swatch.presets.preview import PREVIEW_FACET_DEG, preview_base_color, preview_delta_E_00

__all__ = ["usd_preset", "single_usd_preset"]


def usd_preset(title: str, params, alpha: float, materialx_dE: float, thickness_nm: float, preview_rgb,
               preview_dE: float, part, finish=None) -> usd.UsdPreset:
    """One swatch's USD preset: the OpenPBR network of its ``.mtlx`` preset and the UsdPreviewSurface fallback.

    Parameters
    ----------
    title : str
        The material's display title.
    params : array_like, shape (5,)
        The MaterialX preset's rounded parameters (:func:`round_params`).
    alpha : float
        GGX α of the finish (brushed: the isotropic α of the same lobe area, the fallback's).
    materialx_dE : float
        The OpenPBR network's largest ΔE2000 over mirror geometries 0–60° in MaterialX's GLSL (D65, CIE 1931 2°).
    thickness_nm : float
        Film thickness, nm.
    preview_rgb : array_like, shape (3,)
        The fallback's ``diffuseColor`` (:func:`swatch.presets.preview.preview_base_color`).
    preview_dE : float
        The fallback's largest ΔE2000 over mirror geometries 0–60° (D65, CIE 1931 2°).
    part : swatch.presets.usd.UsdPart
        The mesh.
    finish : swatch.physics.finishes.Finish, optional
        Named; brushed: OpenPBR's anisotropy.

    Returns
    -------
    swatch.presets.usd.UsdPreset
        What the file holds.
    """
    rough, aniso = roughness_factor(alpha), None
    if finish is not None and finish.anisotropic:
        rough, aniso = anisotropy.openpbr_anisotropy(finish.alpha_u, finish.alpha_v)
    doc = (f"swatch (anodic-swatch) preset {title}: oxide {thickness_nm:g} nm on a {part.name} of radius "
           f"{usd.PART_RADIUS_M:g} m. outputs:mtlx:surface: OpenPBR Surface (MaterialX nodes, the thin film over the "
           f"metal) fitted to MaterialX 1.39.5's GLSL, max ΔE2000 {materialx_dE:.2f} over mirror angles 0-60°. "
           "outputs:surface: UsdPreviewSurface fallback, metallic, its colour fitted at 45:0 (facet "
           f"{PREVIEW_FACET_DEG:g}°): UsdPreviewSurface has no thin film and no view input, so it cannot shift with "
           f"angle; max ΔE2000 {preview_dE:.2f} over mirror angles 0-60°. D65, CIE 1931 2°; colours linear Rec.709."
           + ("" if finish is None else f" Finish {finish.label()}" + (
               " (the fallback is isotropic)." if aniso is not None else ".")))
    return usd.UsdPreset(title, np.asarray(params, dtype=np.float64), rough, np.asarray(preview_rgb), doc, part,
                         aniso, None if aniso is None else roughness_factor(alpha))  # (fallback: isotropic, same area)


def single_usd_preset(thickness_nm: float, fmt: str, film: str, substrate: str, film_index_scale: float,
                      roughness_alpha: float, spread=None, finish=None, part=None) -> tuple[bytes, str]:
    """One thickness's USD (``.usda``) or USDZ preset (``swatch preset --format usd|usdz``).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    fmt : str
        ``usd`` or ``usdz``.
    film, substrate : str
        Optical table names.
    film_index_scale : float
        Factor on the film's real index.
    roughness_alpha : float
        GGX α.
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread; None: uniform.
    finish : swatch.physics.finishes.Finish, optional
        Named finish.
    part : swatch.presets.usd.UsdPart, optional
        The designer's mesh; None: a sphere.

    Returns
    -------
    (bytes, str)
        The file's bytes and a line with both surfaces' largest ΔE2000 (D65, CIE 1931 2°).
    """
    d = np.array([float(thickness_nm)])
    rough = roughness_factor(roughness_alpha)
    facet, at = GEOMETRY_45_0["materialx"]
    fit = fit_presets(d, "materialx", (facet,), film, substrate, film_index_scale, None, spread, rough, (at,))
    params = round_params(fit.params)
    dE = errors_delta_E_00("materialx", params, d, FIT_ANGLES_DEG, film, substrate, film_index_scale, spread, rough)[0]
    rgb = preview_base_color(d, film, substrate, film_index_scale, spread)
    pdE = preview_delta_E_00(rgb, d, FIT_ANGLES_DEG, film, substrate, film_index_scale, spread)[0]
    ident = f"{d[0]:g}nm"
    preset = usd_preset(f"anodised {d[0]:g} nm", params[0], roughness_alpha, float(dE.max()), float(d[0]), rgb[0],
                        float(pdE.max()), usd.sphere_part() if part is None else part, finish)
    data = usd.usdz_bytes(preset, f"preset_{ident}") if fmt == "usdz" else usd.usda_bytes(preset)
    summary = (f"OpenPBR (mtlx) max ΔE2000 {dE.max():.2f}; UsdPreviewSurface fallback (one colour, fitted at 45:0) "
               f"max ΔE2000 {pdE.max():.2f} at mirror 0–60° (D65, 2°)")
    return data, summary
