"""Render benchmark: a 1024 × 1024 cylinder swatch by the table-lookup path, against the direct
per-pixel spectral path measured in the same run.

* ``render_1024_s``: median wall time of :func:`swatch.render.render_swatch` (compute only: the
  colour table, geometry, shading, anti-aliasing, exposure and display encoding; no file I/O),
  over several runs after one warm-up.
* ``render_ratio``: the direct path's time for the same image divided by ``render_1024_s``. The
  direct path (full Airy spectrum on the 81-sample grid at every pixel's own θ_d, then the
  colorimeter's weights, times the same intensity factor) is timed on a subset of the image's
  covered pixels (every 8th) and scaled per pixel to all covered pixels: its cost is linear in the
  pixel count (it works in fixed-size chunks), and timing all of it would take a minute.
  Geometry for the direct path (normals, views) is precomputed and *not* charged to it, so the
  ratio is conservative.
"""
from __future__ import annotations

from benchmarks.timing import median_seconds, pick


def run(size: int | None = None, repeats: int = 7) -> list[str]:
    size = size or pick(1024, 64)
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.physics.model import get_coating
    from swatch.render import render_swatch
    from swatch.render import scene as scene_mod
    from swatch.render.builtin import shading

    coating = get_coating()
    cm = get_colorimeter(coating.wavelength_nm)
    d = 50.8
    render_swatch(d, "cylinder", size, coating=coating, colorimeter=cm, environment="point")  # warm-up (caches, LUT)
    t_table = median_seconds(lambda: render_swatch(d, "cylinder", size, coating=coating, colorimeter=cm,
                                                       environment="point"), repeats, warmup=0)

    scene = scene_mod.make_scene("cylinder", 45.0)
    n, l, v, hit = scene_mod.scene_geometry(scene, size)
    n_hit = int(hit.sum())
    nn, vv = n[hit][::8], v[hit][::8]
    t_sub = median_seconds(lambda: shading.shade_direct(nn, l, vv, d, coating, cm, "microfacet", 0.3), 3, warmup=0)
    t_direct = t_sub / nn.shape[0] * n_hit
    return [f"render_{size}_s={t_table:.4f} render_ratio={t_direct / t_table:.1f}"]


if __name__ == "__main__":
    for line in run():
        print(line)
