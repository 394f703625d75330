"""3-D material presets: fit time for the default catalog, and the errors left (ΔE2000, D65, 2°).

Lines: ``presets_fit_s`` (the three formats' models, 57 swatches, no cache: glTF is fitted to what
three.js shows), per model
``presets_<model>_dE00_45_median/_max`` (over swatches, of each swatch's maximum over facet angles
0–45°) and ``_60_max``, and ``presets_<model>_by_hand_median/_max`` for the obvious settings
(the real thickness, the film's n at 550 nm, bare-metal F0), all over 0–60°. ``presets_modelviewer_dE00_45_median``,
``_45_max`` and ``_60_max`` are measured, not ported: the catalog's ``<model-viewer>`` presets
(swatch.catalog.ar.viewer_fit) rendered by the vendored ``<model-viewer>`` 4.4.0 in headless Chromium
(benchmarks/modelviewer_view.py: a plate in an even white surround, tone mapping off, views 0, 5, …, 60° from
the normal, relative to a white metal plate), ΔE2000 against the exact colour at that facet angle (D65,
CIE 1931 2°); skipped without Chromium and Playwright.
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks.timing import DEFAULT_SPEC, TINY


def run() -> list[str]:
    from swatch.catalog.preset_fit import fit_model
    from swatch.catalog.spec import load_spec
    from swatch.physics.materials import load_material
    from swatch.presets import FORMAT_MODEL, PRESET_FORMATS
    from swatch.presets.files import roughness_factor, round_params
    from swatch.presets.fit import FIT_ANGLES_DEG, _bare_metal_rgb, errors_delta_E_00, fit_presets

    spec, _ = load_spec(DEFAULT_SPEC)
    if TINY:  # three swatches
        import dataclasses

        spec = dataclasses.replace(spec, thickness_nm=spec.thickness_nm[::20])
    d = np.asarray(spec.thickness_nm)
    rough = roughness_factor(spec.roughness)
    fit_presets(d[:2], "threejs", [22.5], roughness=rough, extra_model_angles_deg=[0.0])  # imports and tables
    lines = []
    t0 = time.perf_counter()
    fits = {FORMAT_MODEL[fmt]: fit_model(spec, FORMAT_MODEL[fmt]) for fmt in PRESET_FORMATS}  # as the catalog build fits them
    lines.append(f"presets_fit_s={time.perf_counter() - t0:.2f}")
    n550 = float(np.real(load_material(spec.film).nk(np.array([550.0]))[0]))
    bare = np.tile(_bare_metal_rgb(spec.substrate), (d.size, 1))
    naive = np.column_stack([d, np.full(d.size, n550), bare])
    for m, f in fits.items():
        e = errors_delta_E_00(m, round_params(f.params), d, FIT_ANGLES_DEG, spec.film, spec.substrate, roughness=rough)
        e45 = e[:, FIT_ANGLES_DEG <= 45].max(axis=1)
        hand = errors_delta_E_00(m, naive, d, FIT_ANGLES_DEG, spec.film, spec.substrate, roughness=rough)
        jumps = int((np.abs(np.diff(f.params[:, 0] - d)) > 10.0).sum())
        lines.append(f"presets_{m}_jumps_over_10nm={jumps} presets_{m}_dE00_45_median={np.median(e45):.2f} "
                     f"presets_{m}_dE00_45_max={e45.max():.2f} "
                     f"presets_{m}_dE00_60_max={e.max():.2f} presets_{m}_by_hand_median={np.median(hand):.1f} "
                     f"presets_{m}_by_hand_max={hand.max():.1f}")
    lines.append(_modelviewer_line(spec))
    return lines


def _modelviewer_line(spec) -> str:
    """The ``<model-viewer>`` presets' errors as the vendored <model-viewer> shows them (headless Chromium)."""
    from pathlib import Path

    from benchmarks.modelviewer_view import CHROMIUM_BUILDS, modelviewer_figures

    if not any(Path(c).exists() for c in CHROMIUM_BUILDS):
        return "presets_modelviewer: skipped (no Chromium)"
    try:
        import playwright  # noqa: F401
    except ImportError:
        return "presets_modelviewer: skipped (playwright missing)"
    return " ".join(f"presets_modelviewer_{k}={v:.2f}" for k, v in modelviewer_figures(spec).items())
