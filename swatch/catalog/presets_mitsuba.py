"""The catalog's exact Mitsuba 3 presets (``presets/preset_SNNN_mitsuba.xml`` and ``_mitsuba.json``).

Nothing is fitted: the files name swatch's ``anodic_film`` BSDF plugin (:mod:`swatch.presets.mitsuba_bsdf`)
with the swatch's thickness, materials, index scale, spread and roughness, so Mitsuba renders the
catalog's own model. ``swatch preset --format mitsuba`` writes the same pair for one thickness.
"""
from __future__ import annotations

from swatch.catalog.layout import PRESETS, preset_file_name
from swatch.physics.spread import NO_SPREAD
from swatch.presets import mitsuba_bsdf

__all__ = ["finish_alphas", "mitsuba_presets", "single_mitsuba_preset"]


def finish_alphas(alpha: float, finish) -> tuple[float, ...]:
    """The GGX α of a preset: the finish's (two when anisotropic: along, across the grain) or ``alpha``.

    Parameters
    ----------
    alpha : float
        The isotropic α without a finish.
    finish : swatch.physics.finishes.Finish or None

    Returns
    -------
    tuple of float
        One or two α.
    """
    if finish is not None and finish.anisotropic:
        return (float(finish.alpha_u), float(finish.alpha_v))
    return (float(finish.alpha_u if finish is not None else alpha),)


def _mitsuba_files(ident: str, thickness_nm: float, film: str, substrate: str, film_index_scale: float,
                   alphas: tuple[float, ...], spread, info: dict) -> dict[str, bytes]:
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
        written = _mitsuba_files(rec["id"], float(rec["thickness_nm"]), spec.film, spec.substrate,
                                 spec.film_index_scale, alphas, spec.spread, info)
        files |= {f"{PRESETS}/{name}": blob for name, blob in written.items()}
        entries.append({"mitsuba": f"{PRESETS}/{preset_file_name(rec['id'], 'mitsuba')}",
                        "mitsuba_json": f"{PRESETS}/{preset_file_name(rec['id'], 'mitsuba_json')}"})
    return files, entries


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
    files = _mitsuba_files(ident, d, film, substrate, film_index_scale, alphas, spread, info)
    summary = (f"Mitsuba {mitsuba_bsdf.MITSUBA_VERSION} anodic_film BSDF (exact, nothing fitted), thickness {d:g} nm"
               f"{spread.text()}, {film} on {substrate}; XML and JSON (register the plugin: import swatch.mitsuba; "
               "swatch.mitsuba.register())")
    return files, summary
