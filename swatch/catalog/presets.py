"""Presets of a catalog's swatches: fitted once per content (cached), written next to the catalog.

:func:`catalog_presets` fits the three models for all the catalog's thicknesses (or reads the fit
from the build cache, keyed by the hash of what it depends on) and returns the files to write and
every record's ``presets`` entry (the build puts it on the typed record):

``presets/preset_S001.gltf``, ``presets/preset_S001_blender.py``, ``presets/preset_S001.mtlx`` and
the exact Mitsuba 3 presets ``presets/preset_S001_mitsuba.xml`` / ``presets/preset_S001_mitsuba.json``
(:func:`swatch.catalog.presets_mitsuba.mitsuba_presets`, nothing fitted; in the catalog's ``presets/`` folder), and in each record::

    "presets": {"gltf": "presets/preset_S001.gltf", "gltf_max_delta_E_00": 1.9,
                "blender": "presets/preset_S001_blender.py", "blender_max_delta_E_00": 1.4,
                "materialx": "presets/preset_S001.mtlx", "openpbr_max_delta_E_00": 2.2, ...,
                "mitsuba": "presets/preset_S001_mitsuba.xml", "mitsuba_json": "presets/preset_S001_mitsuba.json"}

The errors are ΔE2000 between the model evaluated with the parameters *as written* (rounded) and
the exact colour, CIE 1931 2° observer under D65, maximum over the facet angles 0–60°
(``*_max_delta_E_00``; ``*_max_delta_E_00_45`` over 0–45°).
"""
from __future__ import annotations

import hashlib
import json
from importlib import metadata
from pathlib import Path

import numpy as np

from swatch.catalog.folder import read_cache_json, remove_tree
from swatch.catalog.layout import PRESETS, preset_file_name
from swatch.catalog.presets_mitsuba import mitsuba_presets
from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.fileio import atomic_write_text
from swatch.core.sources import package_dir, sha256_file
from swatch.presets import FORMAT_MODEL, PRESET_FORMATS, anisotropy, materialx, mitsuba_bsdf, write
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00, exact_Lab, fit_presets
from swatch.presets.spectral import rgb_to_Lab

__all__ = ["catalog_presets", "single_preset", "round_params", "roughness_factor", "ERROR_KEYS"]

#: catalog.json key of each format's headline error: max ΔE2000 over mirror geometries 0–60° in the
#: renderer the preset targets (``_45``: 0–45°). glTF: what three.js r187 shows (``threejs_*``);
#: ``gltf_max_delta_E_00`` is the same file judged by the extension's own reference model.
ERROR_KEYS = {"gltf": "threejs_max_delta_E_00", "blender": "blender_max_delta_E_00",
              "materialx": "materialx_max_delta_E_00"}
#: The model each figure is computed with (swatch.presets.fit), by key prefix.
FIGURE_MODELS = {"threejs": "threejs", "gltf": "gltf", "blender": "cycles", "materialx": "materialx",
                 "openpbr": "openpbr"}
#: Which figures each format's record carries (key prefixes).
FORMAT_FIGURES = {"gltf": ("threejs", "gltf"), "blender": ("blender",), "materialx": ("materialx", "openpbr")}
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


def fit_key(spec, extra_angles) -> str:
    """Content hash of everything a catalog's preset fits depend on (the presets' and the optics' code, the
    three.js table, the spec's materials, thicknesses, geometries and roughness, library versions).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
    extra_angles : sequence of float
        The catalog's facet angles the fits weigh in, degrees.

    Returns
    -------
    str
    """
    pkg = package_dir()
    code = {p.name: sha256_file(p) for p in sorted((pkg / "presets").glob("*.py"))}
    modules = (("optics", "physics/optics.py"),
               ("model", "physics/model.py"),
               ("spread", "physics/spread.py"),
               ("materials", "physics/materials.py"),
               ("colorimetry", "colorimetry/colorimeter.py"))
    for m, f in modules:
        code[m] = sha256_file(pkg / f)
    code["threejs_dfg_lut"] = sha256_file(pkg / "tables" / "renderers" / "threejs_dfg_lut.csv")
    blob = {"d": [float(x) for x in spec.thickness_nm], "per_sheet": spec.per_sheet, "film": spec.film,
            "roughness": float(spec.roughness),
            "film_index_scale": spec.film_index_scale, **spec.spread.metadata(),
            "substrate": spec.substrate,
            "angles": [float(a) for a in extra_angles], "code": code,
            "versions": [metadata.version(x) for x in ("numpy", "scipy", "colour-science")]}
    return hashlib.sha256(json.dumps(blob, sort_keys=True).encode()).hexdigest()[:32]


def _figures(model: str, params, spec, rough: float) -> dict[str, np.ndarray]:
    """The errors (N,) of ``params`` as written under ``model``: max over 0–60° and 0–45°, and 45:0."""

    d = np.asarray(spec.thickness_nm, dtype=np.float64)
    dE = errors_delta_E_00(model, params, d, FIT_ANGLES_DEG, spec.film, spec.substrate, spec.film_index_scale,
                           spec.spread, rough)
    facet, at = GEOMETRY_45_0[model]
    if model == "materialx":  # at 45:0 MaterialX's energy compensation is taken at N·V = 1, F at V·H

        p = np.asarray(params, dtype=np.float64)
        F = materialx.displayed_fresnel(np.cos(np.radians(facet)), p[:, 0], p[:, 1], p[:, 2:], rough, cos_nv=1.0)
        e450 = delta_E_00(rgb_to_Lab(F), exact_Lab(d, [facet], spec.film, spec.substrate, spec.film_index_scale,
                                                   spec.spread)[:, 0])
    else:
        e450 = errors_delta_E_00(model, params, d, [facet], spec.film, spec.substrate, spec.film_index_scale,
                                 spec.spread, rough, [at])[:, 0]
    return {"60": dE.max(axis=1), "45": dE[:, FIT_ANGLES_DEG <= 45.0].max(axis=1), "45_0": e450}


def _read_cache(path: Path, n: int) -> dict | None:
    """The cached fits if the file is well formed for n swatches (it is read back: untrusted)."""

    data = read_cache_json(path)
    if not isinstance(data, dict):
        return None
    try:
        out = {}
        for fmt in PRESET_FORMATS:
            entry = data[fmt]
            figures = {prefix: {k: np.asarray(entry["figures"][prefix][k], dtype=np.float64)
                                for k in ("60", "45", "45_0")} for prefix in FORMAT_FIGURES[fmt]}
            out[fmt] = (np.asarray(entry["params"], dtype=np.float64), figures)
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None
    for p, figures in out.values():
        arrays = [a for f in figures.values() for a in f.values()]
        if p.shape != (n, 5) or any(a.shape != (n,) for a in arrays):
            return None
        if not (np.all(np.isfinite(p)) and all(np.all(np.isfinite(a)) for a in arrays)):
            return None
    return out


def _geometries(spec) -> list[float]:
    return sorted({g.theta_d_deg for g in (spec.reference, *spec.multi_angle) if g.theta_d_deg <= 60.0})


def fit_format(spec, fmt: str):
    """Fit the model of preset format ``fmt`` for every swatch of ``spec`` (no cache).

    The catalog's geometries (facet angles ≤ 60°) weigh in; three.js, which evaluates the film at
    N·V, is fitted at the reference 45:0 with its own N·V instead.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
    fmt : str
        ``gltf``, ``blender`` or ``materialx``.

    Returns
    -------
    swatch.presets.fit.PresetFit
    """

    model = FORMAT_MODEL[fmt]
    groups = np.arange(len(spec.thickness_nm)) // spec.per_sheet  # coupled within a sheet only
    if model == "threejs":
        extra, at = [GEOMETRY_45_0[model][0]], [GEOMETRY_45_0[model][1]]
    else:
        extra, at = _geometries(spec), None
    return fit_presets(spec.thickness_nm, model, extra, spec.film, spec.substrate, spec.film_index_scale,
                       groups, spec.spread, roughness_factor(spec.roughness), at)


def _fits(spec, cache: Path | None) -> dict:
    key = fit_key(spec, _geometries(spec))
    path = cache / f"presets-{key}.json" if cache is not None else None
    if path is not None:  # the cache is untrusted: checked, else refitted
        cached = _read_cache(path, len(spec.thickness_nm))
        if cached is not None:
            return cached
    rough = roughness_factor(spec.roughness)
    out = {}
    for fmt in PRESET_FORMATS:
        written = round_params(fit_format(spec, fmt).params)
        out[fmt] = (written, {prefix: _figures(FIGURE_MODELS[prefix], written, spec, rough)
                              for prefix in FORMAT_FIGURES[fmt]})
    if path is not None and cache is not None:

        for stale in path.parent.glob("presets-*.json"):
            remove_tree(stale)
        atomic_write_text(path, json.dumps({fmt: {"params": p.tolist(), "figures": {
            prefix: {k: v.tolist() for k, v in f.items()} for prefix, f in figures.items()}}
            for fmt, (p, figures) in out.items()}))
    return out


def preset_bytes(fmt: str, ident: str, title: str, params, alpha: float, max_dE: float, thickness_nm: float,
                 extension_dE: float | None = None, finish=None) -> bytes:
    """One preset file's bytes.

    Parameters
    ----------
    fmt : str
        ``gltf``, ``blender`` or ``materialx``.
    ident, title : str
    params : array_like, shape (5,)
        Rounded parameters (:func:`round_params`).
    alpha : float
        GGX α of the finish.
    max_dE : float
        The largest ΔE2000 over 0–60° in the targeted renderer (D65, CIE 1931 2°).
    thickness_nm : float
    extension_dE : float, optional
        glTF: the same under the extension's reference model.
    finish : swatch.physics.finishes.Finish, optional
        Named; when anisotropic (brushed), written as each format's anisotropy
        (:mod:`swatch.presets.anisotropy`).

    Returns
    -------
    bytes
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


#: What each figure prefix is measured in, for the record's ``conditions``.
RENDERERS = {
    "threejs": "three.js r187 MeshPhysicalMaterial via GLTFLoader, direct light, relative to a white metal",
    "gltf": "KHR_materials_iridescence reference model (the extension text)",
    "blender": "Blender 5.0-5.2 Cycles, Principled BSDF, GGX",
    "materialx": "MaterialX 1.39.5 GLSL (open_pbr_surface, mx_fresnel_airy), direct light, relative to a white metal",
    "openpbr": "OpenPBR Surface as its specification recommends (Belcour-Barla, Gulbrandsen metal; port only: "
               "no OpenPBR renderer was checked)",
    "mitsuba": f"Mitsuba {mitsuba_bsdf.MITSUBA_VERSION} with swatch's anodic_film BSDF (swatch.mitsuba.register()): "
               "the catalog's own model, nothing fitted; ΔE2000 0 by construction (checked in Mitsuba 3.9.1 at 45:0, "
               "the multi-angle geometries and mirror 0-60°: below 0.01)",
}


def catalog_presets(spec, records: list[dict], cache: Path | None) -> tuple[dict[str, bytes], list[dict]]:
    """The preset files of a catalog's swatches and each record's ``presets`` entry (fits cached in
    ``cache``, keyed by :func:`fit_key`; ``records`` are read only).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
    records : list of dict
    cache : pathlib.Path or None
        The build cache (None: fit every time).

    Returns
    -------
    (dict, list of dict)
        {file name: bytes} and the entries (file names, ΔE2000 figures, conditions, renderers).
    """
    fits = _fits(spec, cache)
    files: dict[str, bytes] = {}
    entries: list[dict] = []
    for i, rec in enumerate(records):
        entry: dict = {}
        for fmt in PRESET_FORMATS:
            params, figures = fits[fmt]
            name = f"{PRESETS}/{preset_file_name(rec['id'], fmt)}"  # (issue 21: the presets/ subfolder)
            title = f"{rec['id']} anodised {rec['thickness_nm']:g} nm"
            head = ERROR_KEYS[fmt].removesuffix("_max_delta_E_00")
            ext = float(figures["gltf"]["60"][i]) if "gltf" in figures and head != "gltf" else None
            files[name] = preset_bytes(fmt, rec["id"], title, params[i], spec.roughness,
                                       float(figures[head]["60"][i]), rec["thickness_nm"], ext, spec.finish_spec)
            entry[fmt] = name
            for prefix in FORMAT_FIGURES[fmt]:
                f = figures[prefix]
                entry[f"{prefix}_max_delta_E_00"] = round(float(f["60"][i]), 2)
                entry[f"{prefix}_max_delta_E_00_45"] = round(float(f["45"][i]), 2)
                entry[f"{prefix}_delta_E_00_45_0"] = round(float(f["45_0"][i]), 2)
        entry["conditions"] = ("ΔE2000 vs exact colour, D65, CIE 1931 2°: *_max_delta_E_00 over mirror geometries "
                               "0–60° (_45: 0–45°), *_delta_E_00_45_0 at 45:0")
        entry["renderers"] = {p: RENDERERS[p] for f in PRESET_FORMATS for p in FORMAT_FIGURES[f]}
        entries.append(entry)
    exact_files, exact_entries = mitsuba_presets(spec, records)
    for entry, exact in zip(entries, exact_entries, strict=True):
        entry.update(exact)
        entry["renderers"]["mitsuba"] = RENDERERS["mitsuba"]
    return files | exact_files, entries


def single_preset(thickness_nm: float, fmt: str, film: str, substrate: str, film_index_scale: float,
                  roughness_alpha: float, spread=None, finish=None) -> tuple[bytes, str]:
    """One thickness's preset in ``fmt``, fitted to its exact colour (``swatch preset``).

    Parameters
    ----------
    thickness_nm : float
    fmt : str
    film, substrate : str
    film_index_scale : float
    roughness_alpha : float
        GGX α.
    spread : swatch.physics.spread.ThicknessSpread, optional
    finish : swatch.physics.finishes.Finish, optional

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
