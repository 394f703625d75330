"""One thickness's preset files: the fitted parameters as written (rounded), each format's bytes, and
the exact Mitsuba pair; ``swatch preset`` writes them for one thickness, the catalog
(:mod:`swatch.catalog.presets`) for each swatch.
"""
from __future__ import annotations

import numpy as np

from swatch.physics.spread import NO_SPREAD
from swatch.presets import FORMAT_MODEL, anisotropy, mitsuba_bsdf, write
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00, fit_presets
from swatch.presets.naming import preset_file_name

__all__ = ["GEOMETRY_45_0", "round_params", "roughness_factor", "preset_bytes", "single_preset", "finish_alphas",
           "mitsuba_files", "single_mitsuba_preset"]

#: The catalog's reference geometry 45:0 as (facet angle, the angle the model is evaluated at):
#: three.js evaluates the film at N·V (0°), the others at the half vector (22.5°).
GEOMETRY_45_0 = {"threejs": (22.5, 0.0), "gltf": (22.5, 22.5), "cycles": (22.5, 22.5), "openpbr": (22.5, 22.5),
                 "materialx": (22.5, 22.5)}
_DIGITS = (3, 4, 4, 4, 4)  # thickness nm, IOR, base R G B, as written



def round_params(params) -> np.ndarray:
    """The fitted parameters as the files carry them (the errors are computed from these): thickness to
    0.001 nm, film IOR and base colour (linear Rec.709) to 1e-4.

    Parameters
    ----------
    params : array_like, shape (..., 5)
        (thickness nm, IOR, R, G, B).

    Returns
    -------
    numpy.ndarray, shape (..., 5)
        (thickness nm, IOR, R, G, B), rounded as written.

    Examples
    --------
    >>> round_params([150.12345, 2.123456, 0.5, 0.25, 0.125]).tolist()
    [150.123, 2.1235, 0.5, 0.25, 0.125]
    """
    p = np.asarray(params, dtype=np.float64)
    return np.stack([np.round(p[..., i], nd) for i, nd in enumerate(_DIGITS)], axis=-1)


def roughness_factor(alpha: float) -> float:
    """The glTF / Blender / OpenPBR roughness for a GGX α (α = roughness²).

    Parameters
    ----------
    alpha : float
        GGX α (dimensionless, > 0).

    Returns
    -------
    float
        To 1e-4.

    Examples
    --------
    >>> roughness_factor(0.09)
    0.3
    """
    return round(float(np.sqrt(alpha)), 4)


def preset_bytes(fmt: str, ident: str, title: str, params, alpha: float, max_dE: float, thickness_nm: float,
                 extension_dE: float | None = None, finish=None) -> bytes:
    """One preset file's bytes.

    Parameters
    ----------
    fmt : str
        ``gltf``, ``blender`` or ``materialx``.
    ident, title : str
        The swatch's id (``S001``, ``50.8nm``; in file names) and the material's display title.
    params : array_like, shape (5,)
        Rounded parameters (:func:`round_params`).
    alpha : float
        GGX α of the finish.
    max_dE : float
        The largest ΔE2000 over 0–60° in the targeted renderer (D65, CIE 1931 2°).
    thickness_nm : float
        Film thickness, nm (written in the file's notes).
    extension_dE : float, optional
        glTF: the same under the extension's reference model.
    finish : swatch.physics.finishes.Finish, optional
        Named; when anisotropic (brushed), written as each format's anisotropy
        (:mod:`swatch.presets.anisotropy`).

    Returns
    -------
    bytes
        The file's content (UTF-8 text), byte-identical for the same inputs.
    """

    rough = roughness_factor(alpha)
    aniso = None
    if finish is not None and finish.anisotropic:
        solve = {"gltf": anisotropy.gltf_anisotropy, "blender": anisotropy.blender_anisotropy,
                 "materialx": anisotropy.openpbr_anisotropy}[fmt]
        rough, aniso = solve(finish.alpha_u, finish.alpha_v)
    named = "" if finish is None else f"; finish {finish.label()}"
    if fmt == "gltf":
        info = {"thickness_nm": thickness_nm, "threejs_max_delta_E_00": round(max_dE, 2),
                "renderer": "three.js r187 (direct light; the film is evaluated at N.V)",
                "illuminant": "D65", "observer": "2", "mirror_angles_deg": [0, 60]}
        if extension_dE is not None:
            info["extension_max_delta_E_00"] = round(extension_dE, 2)
        if finish is not None:
            info["finish"] = finish.label()
        return write.gltf_bytes(title, params, rough, extras={"swatch": info}, anisotropy=aniso)
    if fmt == "blender":
        note = (f"oxide {thickness_nm:g} nm; max ΔE2000 {max_dE:.2f} over mirror angles 0–60° "
                "as Cycles renders it with GGX (D65, CIE 1931 2°)") + named
        return write.blender_bytes(title, params, rough, preset_file_name(ident, fmt), note, anisotropy=aniso)
    note = (f"oxide {thickness_nm:g} nm; fitted to MaterialX 1.39.5's GLSL (mx_fresnel_airy); max ΔE2000 "
            f"{max_dE:.2f} over mirror angles 0-60° (D65, CIE 1931 2°); other OpenPBR renderers not checked") + named
    return write.materialx_bytes(title, params, rough, note, anisotropy=aniso)


def single_preset(thickness_nm: float, fmt: str, film: str, substrate: str, film_index_scale: float,
                  roughness_alpha: float, spread=None, finish=None) -> tuple[bytes, str]:
    """One thickness's preset in ``fmt``, fitted to its exact colour (``swatch preset``).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    fmt : str
        Preset format (``gltf``, ``blender``, ``materialx``; a key of :data:`swatch.presets.FORMAT_MODEL`).
    film, substrate : str
        Optical table names.
    film_index_scale : float
        Factor on the film's real index (dimensionless).
    roughness_alpha : float
        GGX α.
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread; None: uniform.
    finish : swatch.physics.finishes.Finish, optional
        Named finish; when anisotropic (brushed), written as the format's anisotropy.

    Returns
    -------
    (bytes, str)
        The file's bytes and a line saying what was fitted and its largest ΔE2000 (D65, CIE 1931 2°).
    """

    d = np.array([float(thickness_nm)])
    model = FORMAT_MODEL[fmt]
    rough = roughness_factor(roughness_alpha)
    facet, at = GEOMETRY_45_0[model]
    fit = fit_presets(d, model, (facet,), film, substrate, film_index_scale, None, spread, rough, (at,))
    params = round_params(fit.params)
    dE = errors_delta_E_00(model, params, d, FIT_ANGLES_DEG, film, substrate, film_index_scale, spread, rough)[0]
    ext = (float(errors_delta_E_00("gltf", params, d, FIT_ANGLES_DEG, film, substrate, film_index_scale,
                                   spread).max())
           if model == "threejs" else None)
    data = preset_bytes(fmt, f"{d[0]:g}nm", f"anodised {d[0]:g} nm", params[0], roughness_alpha, float(dE.max()),
                        float(d[0]), ext, finish)
    p = params[0]
    summary = (f"{model} model, thickness {p[0]:g} nm, film IOR {p[1]:g}, base colour {p[2]:g} {p[3]:g} {p[4]:g} "
               f"(linear Rec.709); max ΔE2000 {dE.max():.2f} at 0–60°, {dE[FIT_ANGLES_DEG <= 45].max():.2f} at "
               f"0–45° (D65, 2°)") + ("" if finish is None else f"; finish {finish.label()}")
    return data, summary


def finish_alphas(alpha: float, finish) -> tuple[float, ...]:
    """The GGX α of a preset: the finish's (two when anisotropic: along, across the grain) or ``alpha``.

    Parameters
    ----------
    alpha : float
        The isotropic α without a finish.
    finish : swatch.physics.finishes.Finish or None
        The named finish, whose α replace ``alpha``; None: none.

    Returns
    -------
    tuple of float
        One or two α.
    """
    if finish is not None and finish.anisotropic:
        return (float(finish.alpha_u), float(finish.alpha_v))
    return (float(finish.alpha_u if finish is not None else alpha),)


def mitsuba_files(ident: str, thickness_nm: float, film: str, substrate: str, film_index_scale: float,
                  alphas: tuple[float, ...], spread, info: dict) -> dict[str, bytes]:
    """The exact Mitsuba preset pair of one swatch: the XML scene fragment and the JSON scene dictionary.

    Parameters
    ----------
    ident : str
        The swatch's id (``S001``; ``50.8nm`` for ``swatch preset``), in the file names and the BSDF's id.
    thickness_nm : float
        Film thickness, nm.
    film, substrate : str
        Optical table names.
    film_index_scale : float
        Factor on the film's real index (dimensionless).
    alphas : tuple of float
        GGX α, or (α_u, α_v) along and across the grain.
    spread : swatch.physics.spread.ThicknessSpread
        The film's thickness spread.
    info : dict
        The JSON's ``swatch`` entry (title first).

    Returns
    -------
    dict
        File name -> bytes.
    """
    bsdf = mitsuba_bsdf.bsdf_dict(thickness_nm, film, substrate, film_index_scale, alphas, spread, ident=ident)
    rough = (f"GGX alpha {alphas[0]:g}" if len(alphas) == 1
             else f"GGX alpha_u {alphas[0]:g} along dp/du (the grain), alpha_v {alphas[1]:g} across")
    xml_name = preset_file_name(ident, "mitsuba")
    comment = [f"Mitsuba {mitsuba_bsdf.MITSUBA_VERSION} preset written by swatch (anodic-swatch): {info['title']}",
               f"oxide {thickness_nm:g} nm{spread.text()}: {film} on {substrate}, film index scale "
               f"{film_index_scale:g}, {rough}, Smith height-correlated shadowing.",
               "Exact: swatch's anodic_film BSDF evaluates the catalog's own model (Airy film with the tables'",
               "complex dispersive indices on the half-vector facet, per sampled wavelength); nothing is fitted.",
               "Register the plugin first (Python, a spectral variant):",
               f"    {mitsuba_bsdf.REGISTER}",
               f"then mi.load_file(\"{xml_name}\"), or in a scene: <include filename=\"{xml_name}\"/> and",
               f"<ref id=\"{mitsuba_bsdf.preset_id(ident)}\"/> inside a shape."]
    return {xml_name: mitsuba_bsdf.mitsuba_xml_bytes(bsdf, comment),
            preset_file_name(ident, "mitsuba_json"): mitsuba_bsdf.mitsuba_json_bytes(bsdf, info)}


def single_mitsuba_preset(thickness_nm: float, film: str, substrate: str, film_index_scale: float,
                          roughness_alpha: float, spread=None, finish=None) -> tuple[dict[str, bytes], str]:
    """One thickness's exact Mitsuba presets (``swatch preset --format mitsuba``).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    film, substrate : str
        Table names.
    film_index_scale : float
        The process's film index scale.
    roughness_alpha : float
        GGX α (a finish's replaces it).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread; None: uniform.
    finish : swatch.physics.finishes.Finish, optional
        Named finish; its α (two when brushed) replace ``roughness_alpha``.

    Returns
    -------
    files : dict
        File name -> bytes (the XML and the JSON).
    summary : str
        A line saying what they hold.
    """
    d = float(thickness_nm)
    ident = f"{d:g}nm"
    spread = NO_SPREAD if spread is None else spread
    alphas = finish_alphas(roughness_alpha, finish)
    info = {"title": f"anodised {d:g} nm", "thickness_nm": d, "film": film, "substrate": substrate,
            "film_index_scale": film_index_scale, **spread.metadata(),
            "model": "exact: swatch's half-vector Airy model (nothing fitted)"}
    if finish is not None:
        info["finish"] = finish.label()
    files = mitsuba_files(ident, d, film, substrate, film_index_scale, alphas, spread, info)
    summary = (f"Mitsuba {mitsuba_bsdf.MITSUBA_VERSION} anodic_film BSDF (exact, nothing fitted), thickness {d:g} nm"
               f"{spread.text()}, {film} on {substrate}; XML and JSON (register the plugin: import swatch.mitsuba; "
               "swatch.mitsuba.register())")
    return files, summary

