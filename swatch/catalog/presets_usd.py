"""The catalog's USDZ presets and its physicallybased.info document (``[presets] usd`` / ``physicallybased``).

- ``[presets] usd = true``: each swatch gets ``presets/preset_S001.usdz`` (:mod:`swatch.presets.usd`: the
  OpenPBR network of its ``.mtlx`` preset as MaterialX nodes, and a UsdPreviewSurface fallback fitted at
  45:0) on the spec's part (``render.mesh``) or a sphere; its record's ``presets`` entry gets ``"usdz"`` (the
  file) and ``"usd_preview_max_delta_E_00"`` / ``_45`` (the fallback's largest ΔE2000 over mirror
  geometries 0–60° / 0–45°, D65, CIE 1931 2°).
- ``[presets] physicallybased = true``: one ``presets/physicallybased.json`` with a material per swatch
  (:mod:`swatch.presets.physicallybased`) and the two pictures each names, ``presets/preset_S001_physicallybased_300.png``
  and ``_600.png`` (:mod:`swatch.report.physicallybased`: the built-in engine's sphere under the studio); their URLs
  are relative to the document, or absolute under ``[presets] physicallybased_base_url``.
"""
from __future__ import annotations

import numpy as np

from swatch.catalog.layout import PRESETS
from swatch.physics.materials import metal_name
from swatch.presets import physicallybased, usd
from swatch.presets.fit import FIT_ANGLES_DEG
from swatch.presets.naming import preset_file_name
from swatch.presets.preview import preview_base_color, preview_delta_E_00
from swatch.presets.usd_files import usd_preset
from swatch.report.physicallybased import material_with_pictures

__all__ = ["PHYSICALLYBASED_FILE", "usd_presets", "physicallybased_files"]

#: The catalog's physicallybased.info document (in its ``presets/``).
PHYSICALLYBASED_FILE = f"{PRESETS}/physicallybased.json"


def usd_presets(spec, records: list[dict], params, materialx_dE, mesh=None) -> tuple[dict[str, bytes], list[dict]]:
    """Every swatch's ``.usdz`` and its record entries.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec (materials, index scale, spread, roughness or finish).
    records : list of dict
        The swatches' records (``id``, ``thickness_nm``; read only).
    params : array_like, shape (N, 5)
        The MaterialX presets' parameters as written.
    materialx_dE : array_like, shape (N,)
        Their largest ΔE2000 over mirror geometries 0–60° in MaterialX's GLSL.
    mesh : swatch.render.mesh.MeshShape, optional
        The spec's part; None: a sphere.

    Returns
    -------
    files : dict
        File name (in ``presets/``) -> bytes.
    entries : list of dict
        Each record's ``usdz`` and ``usd_preview_max_delta_E_00`` (``_45``) entries.
    """
    d = np.asarray([float(r["thickness_nm"]) for r in records])
    rgb = preview_base_color(d, spec.film, spec.substrate, spec.film_index_scale, spec.spread)
    dE = preview_delta_E_00(rgb, d, FIT_ANGLES_DEG, spec.film, spec.substrate, spec.film_index_scale, spec.spread)
    if mesh is None:
        part = usd.sphere_part()
    else:
        corners, normals = mesh.triangle_soup()
        part = usd.triangle_part(corners, normals, mesh.file_name)
    files: dict[str, bytes] = {}
    entries: list[dict] = []
    for i, rec in enumerate(records):
        name = preset_file_name(rec["id"], "usdz")
        preset = usd_preset(f"{rec['id']} anodised {rec['thickness_nm']:g} nm", params[i], spec.roughness,
                            float(materialx_dE[i]), float(rec["thickness_nm"]), rgb[i], float(dE[i].max()), part,
                            spec.finish_spec)
        files[f"{PRESETS}/{name}"] = usd.usdz_bytes(preset, name.removesuffix(".usdz"))
        entries.append({"usdz": f"{PRESETS}/{name}", "usd_preview_max_delta_E_00": round(float(dE[i].max()), 2),
                        "usd_preview_max_delta_E_00_45": round(float(dE[i, FIT_ANGLES_DEG <= 45.0].max()), 2)})
    return files, entries


def physicallybased_files(spec, records: list[dict]) -> dict[str, bytes]:
    """The catalog's one physicallybased.info v2 document, a material per swatch, and each one's pictures.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec.
    records : list of dict
        The swatches' records (``id``, ``thickness_nm``; read only).

    Returns
    -------
    dict
        {:data:`PHYSICALLYBASED_FILE`: bytes} and each picture (``presets/preset_S001_physicallybased_300.png``,
        ``_600.png``: bytes).
    """
    coating = spec.coating(None)  # film, substrate, index scale, spread
    materials: list[dict] = []
    files: dict[str, bytes] = {}
    metal = metal_name(spec.substrate).capitalize()
    for r in records:
        entry, pictures = material_with_pictures(r["id"], f"{metal} (Anodized, {r['thickness_nm']:g} nm, {r['id']})",
                                                 float(r["thickness_nm"]), coating, spec.roughness,
                                                 spec.presets_physicallybased_base_url, f" Catalog {spec.name}.")
        materials.append(entry)
        files |= {f"{PRESETS}/{name}": blob for name, blob in pictures.items()}
    return {PHYSICALLYBASED_FILE: physicallybased.document_bytes(materials)} | files
