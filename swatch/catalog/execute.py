"""The execute side of a catalog build: the stages a full build runs (issue 36).

:mod:`swatch.catalog.build` is the plan: it loads the spec, takes the fingerprint and answers an
up-to-date catalog without loading anything heavier than numpy. When something must be built it imports
this module, once: the records (colour-science), tiles and sheets (the renderer, OpenImageIO), chips,
exports, presets, hero renders and the page, all imported here at the top.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from swatch.catalog import chips as chipmod
from swatch.catalog import sheets as sheetmod
from swatch.catalog import tiles as tilemod
from swatch.catalog.chips import chip_names
from swatch.catalog.context import CatalogContext, catalog_context
from swatch.catalog.csv_table import csv_bytes
from swatch.catalog.explorer import (
    COS_NODES,
    GRID_STEP_NM,
    MATCH_STEP_NM,
    chip_colours,
    explorer_data,
    thickness_axis,
    tile_rects,
)
from swatch.catalog.explorer_env import environment_data_cached
from swatch.catalog.explorer_set import baked_set
from swatch.catalog.exports import ase_bytes, cxf_bytes, metal_symbol
from swatch.catalog.fingerprint import slug
from swatch.catalog.hero import catalog_heroes, prune_heroes
from swatch.catalog.html import index_html
from swatch.catalog.presets import catalog_presets
from swatch.catalog.record import PrintChip
from swatch.catalog.records import PROCESS_STEP_NM, compute, process_json
from swatch.catalog.spec import CatalogSpec
from swatch.colorimetry.tolerance import METRICS
from swatch.core.version import __version__
from swatch.physics.finishes import get_finish

__all__ = ["check_buildable", "catalog_header", "finish_params", "mesh_json", "final_records", "page", "compute", "catalog_heroes", "prune_heroes",
           "catalog_presets", "csv_bytes", "cxf_bytes", "ase_bytes", "metal_symbol", "chipmod", "sheetmod", "tilemod"]


def check_buildable(spec: CatalogSpec) -> CatalogContext:
    """Refuse, without building, what the build would refuse beyond the spec parser (``catalog validate``
    and the build run the same checks): the colorimetry, the explorer's thickness axes and the sheets'
    memory; and build the catalog's context once.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    swatch.catalog.context.CatalogContext
        Grid, coating, colorimeters and tolerance, passed down to every stage.

    Raises
    ------
    swatch.core.errors.SwatchError
        An unknown illuminant, an explorer axis over its cap, or a sheet too big for the memory budget.
    """
    ctx = catalog_context(spec)
    for step in (GRID_STEP_NM, MATCH_STEP_NM):
        thickness_axis(spec.thickness_nm, step)
    sheetmod.plan_jobs(spec, 1)
    return ctx


def catalog_header(spec: CatalogSpec, data, spec_name: str) -> dict:
    """The ``catalog`` header of catalog.json (and of the sheets' metadata): film, colorimetry, model,
    geometry, render options, tolerance, export names and the swatch version.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec.
    data : swatch.catalog.records.CatalogData
        The computed records (illuminant, observer, wavelength grid).
    spec_name : str
        The spec file's name (recorded as ``spec_file``).

    Returns
    -------
    dict
        JSON-ready header.
    """

    tol = spec.tolerance
    return {
        "name": spec.name,
        "description": spec.description,
        "spec_file": spec_name,
        "film": spec.film,
        "substrate": spec.substrate,
        "process": process_json(spec),
        "illuminant": data.illuminant,
        "observer": data.observer,
        "observer_name": "1964 10°" if data.observer == "10" else "1931 2°",
        "wavelength_nm": {"start": float(data.wavelength_nm[0]), "stop": float(data.wavelength_nm[-1]),
                          "step": spec.wavelength_step_nm},
        "model": "half-vector thin film (Fujii et al. 2019): Airy reflectance factor at theta_d",
        "lab_definition": (
            "CIELAB of the spectral reflectance factor R(theta_d) of the film on the half-vector facet, "
            "theta_d = 1/2 arccos(l.v), under the illuminant and observer above (colour-science, ASTM E308); "
            "no intensity or microfacet-distribution term"),
        "srgb_definition": ("srgb_hex, chips and pictures: sRGB (IEC 61966-2-1) of the spectrum by CIE 1931 2° "
                            "colorimetry under the illuminant above (Bradford-adapted to D65), whatever the "
                            "observer of the Lab numbers"),
        "Lab_D50_2_definition": "Lab_D50_2: CIELAB of the reference-geometry spectrum under D50, CIE 1931 2° "
                                "(ICC / ISO 13655; what the ASE file holds)",
        "reference_geometry": spec.reference.to_json(),
        "multi_angle_geometries": [g.to_json() for g in spec.multi_angle],
        "render": {"shapes": list(spec.shapes), "size_px": spec.size_px, "model": spec.model,
                   "roughness": spec.roughness, "angular_map": spec.angular_map,
                   **({"finish": spec.finish_spec.metadata()} if spec.finish_spec is not None else {}),
                   "finishes": list(spec.finishes), "finish_params": finish_params(spec.finishes),
                   **({"mesh": mesh_json(spec, data.context.mesh)} if spec.mesh is not None else {})},
        "tolerance": {"scheme": tol.scheme, "grade": tol.label, "metric": tol.metric, "max": tol.max,
                      "metric_name": METRICS.description(tol.metric), "text": tol.text,
                      "grade_description": tol.description,
                      "note": (f"the bound on {METRICS.description(tol.metric)} (the metric the tolerance is defined in) "
                               "between the colour at d±δ and at d, at the reference geometry"),
                      "search_nm": spec.search_nm, "search_step_nm": PROCESS_STEP_NM},
        "exports": {"cxf": f"{slug(spec.name)}.cxf", "ase": f"{slug(spec.name)}.ase",
                    "ase_srgb": f"{slug(spec.name)}-srgb.ase"},
        "swatch_version": __version__,
    }


def finish_params(finishes: Sequence[str]) -> dict:
    """``catalog.render.finish_params``: each offered finish's lobe, for the page's live view.

    Parameters
    ----------
    finishes : sequence of str
        Finish names (:data:`swatch.core.choices.FINISHES`).

    Returns
    -------
    dict
        Name to ``roughness_alpha`` (the isotropic GGX α of the same lobe area), ``anisotropic``, ``alpha_u`` and
        ``alpha_v`` (along and across the grain, anisotropic finishes only), ``label`` and ``description``.

    Examples
    --------
    >>> finish_params(["polished", "brushed"])["brushed"]["alpha_v"]
    0.4
    """
    out = {}
    for name in finishes:
        f = get_finish(name)
        out[name] = {"roughness_alpha": f.roughness_alpha, "anisotropic": f.anisotropic,
                     **({"alpha_u": f.alpha_u, "alpha_v": f.alpha_v} if f.anisotropic else {}),
                     "label": f.label(), "description": f.description}
    return out


def mesh_json(spec: CatalogSpec, mesh) -> dict:
    """``catalog.render.mesh``: the designer's part the heroes and sheets show.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec (the part's name as given and its hash).
    mesh : swatch.render.mesh.MeshShape
        The part, read (its triangle count).

    Returns
    -------
    dict
        ``file`` (as the spec names it), ``sha256`` (its bytes) and ``triangles``.
    """
    return {"file": spec.mesh, "sha256": spec.mesh_sha256, "triangles": mesh.triangles}


def final_records(spec, data, preset_entries: Sequence[dict | None], hero_entries: list,
                  hero_finishes: Sequence[dict | None] | None = None) -> list[dict]:
    """The typed records with the stages' entries (print chip, presets, hero), serialised once.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec (print chips on or off, their size and resolution).
    data : swatch.catalog.records.CatalogData
        The computed swatches and records.
    preset_entries, hero_entries : list of dict or None
        Each swatch's presets and hero entry (None: none).
    hero_finishes : list of dict or None, optional
        Each swatch's heroes by finish (``hero_finishes``; None: none).

    Returns
    -------
    list of dict
        The records' JSON views, in swatch order.
    """

    out = []
    by_finish = [None] * len(data.swatches) if hero_finishes is None else hero_finishes
    for swatch, rec, presets, hero, finishes in zip(data.swatches, data.records, preset_entries, hero_entries,
                                                    by_finish, strict=True):
        chip = PrintChip(*chip_names(rec), spec.chip_size_mm, spec.chip_dpi) if spec.chips else None
        out.append(replace(swatch, print_chip=chip, presets=presets, hero=hero, hero_finishes=finishes).to_json())
    return out


def page(spec, data, page_doc: dict, cache: Path | None = None) -> str:
    """index.html with the explorer's colour table, the tiles' places in the sheets, P3 chips and the live
    view's environment lighting (cached in ``cache``).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated spec.
    data : swatch.catalog.records.CatalogData
        The computed records and their context.
    page_doc : dict
        catalog.json's document (header, sheets, swatches).
    cache : pathlib.Path, optional
        The build cache (the environment lighting's data is kept there).

    Returns
    -------
    str
        The page's HTML.
    """

    # the heroes' studio set around each shape of the live view (baked by Mitsuba) where the catalog has heroes
    studio = baked_set(data.context.mesh, spec.mesh_sha256, cache) if spec.hero else None
    return index_html(page_doc, explorer_data(data.context), tile_rects(spec, page_doc["swatches"]),
                      chip_colours(data), environment_data_cached(
                          spec.roughness, COS_NODES, cache, studio,
                          {f: get_finish(f).roughness_alpha for f in spec.finishes} if len(spec.finishes) > 1 else None))
