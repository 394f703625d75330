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

With ``[presets] usd = true`` each swatch also gets ``presets/preset_S001.usdz`` (record: ``"usdz"`` and
``usd_preview_max_delta_E_00``), with ``[presets] physicallybased = true`` the catalog gets one
``presets/physicallybased.json`` (:mod:`swatch.catalog.presets_usd`).

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

from swatch.catalog.ar import RENDERER as VIEWER_RENDERER
from swatch.catalog.ar import viewer_presets
from swatch.catalog.context import catalog_mesh
from swatch.catalog.folder import read_cache_json, remove_tree
from swatch.catalog.layout import PRESETS
from swatch.catalog.preset_fit import catalog_geometries, fit_model
from swatch.catalog.presets_mitsuba import mitsuba_presets
from swatch.colorimetry.colorimeter import delta_E_00
from swatch.core.fileio import atomic_write_text
from swatch.core.sources import code_hash, package_dir
from swatch.presets import FORMAT_MODEL, PRESET_FORMATS, materialx, mitsuba_bsdf
from swatch.presets.files import GEOMETRY_45_0, preset_bytes, roughness_factor, round_params
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00, exact_Lab
from swatch.presets.naming import preset_file_name
from swatch.presets.spectral import rgb_to_Lab

__all__ = ["catalog_presets", "ERROR_KEYS"]

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
def fit_key(spec, extra_angles) -> str:
    """Content hash of everything a catalog's preset fits depend on (the presets' and the optics' code, the
    three.js table, the spec's materials, thicknesses, geometries and roughness, library versions).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    extra_angles : sequence of float
        The catalog's facet angles the fits weigh in, degrees.

    Returns
    -------
    str
        32 hex digits (the cache entry's name).
    """
    # this module and every module it imports (the presets' models, the optics, the colorimetry), and the
    # three.js table the threejs model reads
    code = code_hash(__name__, extra=(package_dir() / "tables" / "renderers" / "threejs_dfg_lut.csv",))
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


def _fits(spec, cache: Path | None) -> dict:
    key = fit_key(spec, catalog_geometries(spec))
    path = cache / f"presets-{key}.json" if cache is not None else None
    if path is not None:  # the cache is untrusted: checked, else refitted
        cached = _read_cache(path, len(spec.thickness_nm))
        if cached is not None:
            return cached
    rough = roughness_factor(spec.roughness)
    out = {}
    for fmt in PRESET_FORMATS:
        written = round_params(fit_model(spec, FORMAT_MODEL[fmt]).params)
        out[fmt] = (written, {prefix: _figures(FIGURE_MODELS[prefix], written, spec, rough)
                              for prefix in FORMAT_FIGURES[fmt]})
    if path is not None and cache is not None:

        for stale in path.parent.glob("presets-*.json"):
            remove_tree(stale)
        atomic_write_text(path, json.dumps({fmt: {"params": p.tolist(), "figures": {
            prefix: {k: v.tolist() for k, v in f.items()} for prefix, f in figures.items()}}
            for fmt, (p, figures) in out.items()}))
    return out


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
    "usd_preview": "UsdPreviewSurface fallback of the .usdz (metallic, Schlick Fresnel as its specification writes "
                   "it; port only: no renderer was checked): one colour fitted at 45:0, no thin film, no view input",
}


def catalog_presets(spec, records: list[dict], cache: Path | None, mesh=None) -> tuple[dict[str, bytes], list[dict]]:
    """The preset files of a catalog's swatches and each record's ``presets`` entry (fits cached in
    ``cache``, keyed by :func:`fit_key`; ``records`` are read only).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (JSON view; read only).
    cache : pathlib.Path or None
        The build cache (None: fit every time).
    mesh : swatch.render.mesh.MeshShape, optional
        The spec's part as the build read it (its context's); None: read here (:func:`catalog_mesh`) where the spec
        names one.

    Returns
    -------
    (dict, list of dict)
        {file name: bytes} and the entries (file names, ΔE2000 figures, conditions, renderers).
    """
    fits = _fits(spec, cache)
    part = mesh if mesh is not None else catalog_mesh(spec) if spec.ar or spec.presets_usd else None
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
    if spec.ar:  # the page's <model-viewer> files and figures (swatch.catalog.ar)
        viewer_files, viewer_entries = viewer_presets(spec, records, part)
        for entry, viewer in zip(entries, viewer_entries, strict=True):
            entry.update(viewer)
            entry["renderers"]["modelviewer"] = VIEWER_RENDERER
        exact_files |= viewer_files
    if spec.presets_usd or spec.presets_physicallybased:
        from swatch.catalog.presets_usd import physicallybased_files, usd_presets  # usd-core only when asked for
    if spec.presets_usd:  # the .usdz of each swatch (swatch.catalog.presets_usd); off: the bytes of before
        mtlx_params, mtlx_figures = fits["materialx"]
        usd_files, usd_entries = usd_presets(spec, records, mtlx_params, mtlx_figures["materialx"]["60"], part)
        for entry, extra in zip(entries, usd_entries, strict=True):
            entry.update(extra)
            entry["renderers"]["usd_preview"] = RENDERERS["usd_preview"]
        exact_files |= usd_files
    if spec.presets_physicallybased:  # one physicallybased.info document for the catalog
        exact_files |= physicallybased_files(spec, records)
    return files | exact_files, entries


