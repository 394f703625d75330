"""The built-in engine's environment fast path against its brute force, over sample counts and blur (#23).

    .venv/bin/python scripts/env_fastpath_sweep.py 0.3 24:0.35 128:0.25    (after python3 dev.py made .venv)

For one GGX α (first argument) and each ``samples:sigma_factor`` pair: ΔE00 (CIE 1931 2°, D65) of
``env_shading.shade`` (the fixed visible-normal samples on the per-sample blurred studio) against
``env_shading.shade_reference`` (8192 samples per pixel on the unblurred map, which equals an
independent quadrature: tests/render/test_environment.py) at every covered pixel of a 32² plate,
sphere and cylinder (view 45°), 30/80/160 nm: the worst centre pixel over the thicknesses, and the
worst median / p95 / max. The table in docs/mitsuba.md comes from these lines (about 1 min per pair
and α on 2 cores; the reference is computed once per run).
"""
from __future__ import annotations

import sys

import colour
import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.physics.model import get_coating
from swatch.render import environment, scene
from swatch.render.builtin import env_shading, shading

SIZE = 32
THICKNESSES_NM = (30.0, 80.0, 160.0)
_WHITE = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]


def _lab(rgb):
    return colour.XYZ_to_Lab(colour.RGB_to_XYZ(np.asarray(rgb, dtype=float), "sRGB"), _WHITE)


def _geometry(shape: str):
    normals, _, views, _ = scene.scene_geometry(scene.make_scene(shape, 45.0), SIZE)
    n, v = normals.reshape(-1, 3), views.reshape(-1, 3)
    ok = np.flatnonzero(np.linalg.norm(n, axis=-1) > 0.5)
    n = n[ok] / np.linalg.norm(n[ok], axis=-1, keepdims=True)
    v = v[ok] / np.linalg.norm(v[ok], axis=-1, keepdims=True)
    return n, v, int(np.flatnonzero(ok == (SIZE // 2) * SIZE + SIZE // 2)[0])


def main(argv: list[str]) -> int:
    alpha = float(argv[0])
    coating = get_coating()
    cm = get_colorimeter(coating.wavelength_nm)
    env = environment.get_environment("studio")
    maps = environment.levels(env)
    tables = {d: shading.facet_colour_table(d, coating, cm, 257, (0.0, 1.0)).to_rgb(cm).values.astype(float)
              for d in THICKNESSES_NM}
    geo = {shape: _geometry(shape) for shape in ("flat", "sphere", "cylinder")}
    ref = {(shape, d): env_shading.shade_reference(n, v, env, alpha, t, samples=8192)
           for shape, (n, v, _) in geo.items() for d, t in tables.items()}
    for pair in argv[1:]:
        count, factor = pair.split(":")
        env_shading.SIGMA_PER_FOOTPRINT = float(factor)  # read when a sample set is made
        ss = env_shading.SampleSet(alpha, int(count))
        parts = []
        for shape, (n, v, centre) in geo.items():
            rows = []
            for d, t in tables.items():
                fast = env_shading.shade(n, v, maps, ss, env_shading.band_weights(ss, t))
                de = colour.delta_E(_lab(fast), _lab(ref[shape, d]), method="CIE 2000")
                rows.append((de[centre], np.median(de), np.percentile(de, 95), de.max()))
            r = np.max(np.array(rows), axis=0)
            parts.append(f"{shape}: centre {r[0]:.2f} median {r[1]:.2f} p95 {r[2]:.2f} max {r[3]:.2f}")
        print(f"alpha {alpha:g}, {count} samples, sigma factor {factor}: " + " | ".join(parts), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
