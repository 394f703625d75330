"""A renderer's model fitted to every swatch of a catalog: the one fit the catalog's presets
(:mod:`swatch.catalog.presets`) and the page's ``<model-viewer>`` files (:mod:`swatch.catalog.ar`) share.

The swatches of a sheet are fitted together (their parameters coupled, so neighbours on a sheet stay in order), and the
catalog's own geometries up to 60° weigh in; three.js, which evaluates the film at N·V, is fitted at the reference
45:0 with its own N·V instead (:data:`swatch.presets.files.GEOMETRY_45_0`).
"""
from __future__ import annotations

import numpy as np

from swatch.presets.files import GEOMETRY_45_0, roughness_factor
from swatch.presets.fit import PresetFit, fit_presets

__all__ = ["catalog_geometries", "fit_model"]


def catalog_geometries(spec) -> list[float]:
    """The facet angles of the catalog's geometries that weigh in a fit (≤ 60°), ascending.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    list of float
        Facet angles θ_d of the reference and multi-angle geometries, degrees, each once.
    """
    return sorted({g.theta_d_deg for g in (spec.reference, *spec.multi_angle) if g.theta_d_deg <= 60.0})


def fit_model(spec, model: str) -> PresetFit:
    """Fit renderer model ``model`` (:func:`swatch.presets.fit.fit_presets`) for every swatch of ``spec`` (no cache).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    model : str
        A model of :mod:`swatch.presets.fit` (``threejs``, ``cycles``, ``materialx``, ``modelviewer`` …).

    Returns
    -------
    swatch.presets.fit.PresetFit
        The fitted parameters per swatch (thickness nm, IOR, linear RGB) and their ΔE2000 per facet angle.
    """
    groups = np.arange(len(spec.thickness_nm)) // spec.per_sheet  # coupled within a sheet only
    if model == "threejs":
        extra, at = [GEOMETRY_45_0[model][0]], [GEOMETRY_45_0[model][1]]
    else:
        extra, at = catalog_geometries(spec), None
    return fit_presets(spec.thickness_nm, model, extra, spec.film, spec.substrate, spec.film_index_scale,
                       groups, spec.spread, roughness_factor(spec.roughness), at)
