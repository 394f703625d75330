"""3-D material presets: fit time for the default catalog, and the errors left (ΔE2000, D65, 2°).

Lines: ``presets_fit_s`` (the three formats' models, 57 swatches, no cache: glTF is fitted to what
three.js shows), per model
``presets_<model>_dE00_45_median/_max`` (over swatches, of each swatch's maximum over facet angles
0–45°) and ``_60_max``, and ``presets_<model>_by_hand_median/_max`` for the obvious settings
(the real thickness, the film's n at 550 nm, bare-metal F0), all over 0–60°.
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks.timing import DEFAULT_SPEC, TINY


def run() -> list[str]:
    from swatch.catalog.presets import fit_format
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
    fits = {FORMAT_MODEL[fmt]: fit_format(spec, fmt) for fmt in PRESET_FORMATS}  # as the catalog build fits them
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
    return lines
