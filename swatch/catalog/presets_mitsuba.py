"""The catalog's exact Mitsuba 3 presets (``presets/preset_SNNN_mitsuba.xml`` and ``_mitsuba.json``).

Nothing is fitted: the files name swatch's ``anodic_film`` BSDF plugin (:mod:`swatch.presets.mitsuba_bsdf`)
with the swatch's thickness, materials, index scale, spread and roughness, so Mitsuba renders the
catalog's own model. ``swatch preset --format mitsuba`` writes the same pair for one thickness.
"""
from __future__ import annotations

from swatch.catalog.layout import PRESETS
from swatch.presets.files import finish_alphas, mitsuba_files
from swatch.presets.naming import preset_file_name

__all__ = ["mitsuba_presets"]


def mitsuba_presets(spec, records: list[dict]) -> tuple[dict[str, bytes], list[dict]]:
    """The exact Mitsuba 3 presets of every swatch (XML and JSON; text, nothing fitted).

    A thickness spread is written as the plugin's ``spread_nm`` / ``spread_fraction``.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        Materials, index scale, spread, roughness or finish, illuminant and observer.
    records : list of dict
        The swatches' records (``id``, ``thickness_nm``, ``Lab``; read only).

    Returns
    -------
    files : dict
        File name (in ``presets/``) -> bytes.
    entries : list of dict
        Each record's ``mitsuba`` / ``mitsuba_json`` entries (the files' names).
    """
    alphas = finish_alphas(spec.roughness, spec.finish_spec)
    files: dict[str, bytes] = {}
    entries: list[dict] = []
    for rec in records:
        info = {"title": f"{rec['id']} anodised {rec['thickness_nm']:g} nm", "id": rec["id"],
                "thickness_nm": rec["thickness_nm"], "film": spec.film, "substrate": spec.substrate,
                "film_index_scale": spec.film_index_scale, **spec.spread.metadata(),
                "model": "exact: the catalog's half-vector Airy model (nothing fitted)",
                "catalog_Lab": rec["Lab"], "catalog_colour": f"{spec.illuminant}, CIE observer {spec.observer}°, "
                                                            "geometry 45:0 (the catalog's reference)"}
        if spec.finish_spec is not None:
            info["finish"] = spec.finish_spec.label()
        written = mitsuba_files(rec["id"], float(rec["thickness_nm"]), spec.film, spec.substrate,
                                 spec.film_index_scale, alphas, spec.spread, info)
        files |= {f"{PRESETS}/{name}": blob for name, blob in written.items()}
        entries.append({"mitsuba": f"{PRESETS}/{preset_file_name(rec['id'], 'mitsuba')}",
                        "mitsuba_json": f"{PRESETS}/{preset_file_name(rec['id'], 'mitsuba_json')}"})
    return files, entries


