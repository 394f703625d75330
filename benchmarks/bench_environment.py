"""Environment-lit renders: a 1024 × 1024 cylinder under the studio light box, against the
brute-force integration measured in the same run.

* ``render_env_1024_s``: median wall time of ``render_swatch(..., environment="studio")`` with the
  scene's environment gather recomputed every time (only the sample set and the environment's
  blur levels, built once per process, are warm): what one image costs.
* ``render_env_1024_next_s``: the next thickness of the same scene (the gather is cached; a
  catalog pays this per swatch).
* ``render_env_ratio``: the brute force (4096 visible-normal samples per pixel on the unfiltered
  map, F at every sample's θ_d), timed on every 97th covered pixel and scaled per pixel to all
  covered pixels, divided by ``render_env_1024_s``.
* ``env_error_dE00_median`` / ``_p95`` / ``_max``: CIEDE2000 between the render's pixel-centre
  values and the brute force at those pixels (sRGB linear → CIE 1931 2° XYZ, white = 1, D65).
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks.timing import median_seconds, pick


def run(size: int | None = None, repeats: int = 5) -> list[str]:
    size = size or pick(1024, 64)
    from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
    from swatch.physics.model import get_coating
    from swatch.render import environment, render_swatch, scene
    from swatch.render.builtin import env_render, env_shading, shading

    coating = get_coating()
    cm = get_colorimeter(coating.wavelength_nm)
    d = 50.8

    def one():
        env_render._CACHE.clear()
        return render_swatch(d, "cylinder", size, coating=coating, colorimeter=cm, environment="studio")

    img = one()  # warm-up: sample set, blur levels
    t_env = median_seconds(one, repeats, warmup=0)
    t_next = median_seconds(lambda: render_swatch(d + 5, "cylinder", size, coating=coating, colorimeter=cm,
                                                       environment="studio"), repeats, warmup=0)

    sc = scene.make_scene("cylinder", 45.0)
    c = np.arange(size, dtype=np.float32) + np.float32(0.5)
    hit, n, v = env_render._normals_views(sc, c[None, :], c[:, None], size)
    inner = hit & (img.coverage == 1.0)
    nn, vv, got = n[inner][::97], v[inner][::97], img.linear_rgb[inner][::97]
    env = environment.get_environment("studio")
    tab = shading.facet_colour_table(d, coating, cm, env_render.F_TABLE_NODES, (0.0, 1.0)).to_rgb(cm).values
    t0 = time.perf_counter()
    ref = env_shading.shade_reference(nn, vv, env, 0.3, tab.astype(np.float64))
    t_ref = (time.perf_counter() - t0) / nn.shape[0] * int(hit.sum())
    A = cm.rgb_linear(np.eye(3) * 100.0, "srgb").T  # RGB from CIE 1931 2° XYZ
    cm2 = cm.display_colorimeter
    dE = delta_E_00(cm2.Lab(100.0 * np.linalg.solve(A, got.T.astype(np.float64)).T),
                    cm2.Lab(100.0 * np.linalg.solve(A, ref.T).T))
    return [f"render_env_{size}_s={t_env:.3f} render_env_{size}_next_s={t_next:.3f} "
            f"render_env_ratio={t_ref / t_env:.0f}",
            f"env_error_dE00_median={np.median(dE):.2f} env_error_dE00_p95={np.percentile(dE, 95):.2f} "
            f"env_error_dE00_max={dE.max():.2f} (n={dE.size} pixels)"]


if __name__ == "__main__":
    for line in run():
        print(line)
