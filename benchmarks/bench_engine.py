"""Engine benchmark: the thin-film kernel against colour-science's thin_film_tmm and tmm.coh_tmm.

Grid: thickness 0–300 nm step 1 × angle 0–89° step 1 × 380–780 nm step 5, both polarisations.
* ours: swatch.physics.optics.film_reflectance_sweep on the whole grid;
* colour-science: colour.phenomena.thin_film_tmm on the whole grid (the two interleaved three
  times, medians of each);
* tmm: coh_tmm on a random sample of (thickness, angle, wavelength) points, s and p each,
  scaled per spectral sample (one spectral sample = R_s and R_p at one d, angle, wavelength).
Also the compute time of ``swatch color`` over 20–300 nm step 1 (colorimeter built cold).
"""
from __future__ import annotations

import numpy as np

from benchmarks.timing import median_seconds, pick


def run() -> list[str]:
    import tmm
    from colour.phenomena import thin_film_tmm

    import swatch  # noqa: F401  (silences colour-science's plotting notice)
    from swatch.colorimetry.appearance import thickness_colours
    from swatch.colorimetry.colorimeter import Colorimeter
    from swatch.physics import optics
    from swatch.physics.model import get_coating

    coating = get_coating()
    wl = coating.wavelength_nm
    d = np.arange(0.0, pick(301.0, 31.0))
    angles = np.arange(0.0, 90.0, pick(1.0, 10.0))
    samples = d.size * angles.size * wl.size

    n_stack = np.stack([np.ones_like(wl), coating.n_film, coating.n_substrate]).astype(np.complex128)

    def ours():
        optics.film_reflectance_sweep(0.0, 1.0, d.size, angles, wl, coating.n_film, coating.n_substrate)

    def theirs():
        thin_film_tmm(n_stack, d, wl, angles)

    # Interleaved, so both see the same machine noise; medians of each.
    ours()
    times_ours, times_colour = [], []
    for _ in range(pick(3, 1)):
        times_ours.append(median_seconds(ours, repeats=3, warmup=0))
        times_colour.append(median_seconds(theirs, repeats=1, warmup=0))
    t_ours = float(np.median(times_ours))
    t_colour = float(np.median(times_colour))

    rng = np.random.default_rng(0)
    picks = [(rng.choice(d), rng.choice(angles), rng.integers(wl.size)) for _ in range(pick(300, 10))]

    def tmm_sample():
        for di, ai, wi in picks:
            for pol in ("s", "p"):
                tmm.coh_tmm(pol, [1.0, coating.n_film[wi], coating.n_substrate[wi]],
                            [np.inf, di, np.inf], np.radians(ai), wl[wi])

    t_tmm = median_seconds(tmm_sample, repeats=3) / len(picks) * samples

    thick = np.arange(20.0, 301.0, 1.0)

    def color_cold():
        cm = Colorimeter(wl, "D65", "10")
        thickness_colours(thick, 45.0, 0.0, coating, cm)

    t_color = median_seconds(color_cold, repeats=5)

    per = 1e9 / samples
    return [
        f"kernel_grid={d.size}x{angles.size}x{wl.size} samples={samples}",
        f"ours_s={t_ours:.4f} ({t_ours * per:.1f} ns/sample)",
        f"colour_thin_film_tmm_s={t_colour:.3f} ({t_colour * per:.1f} ns/sample)",
        f"tmm_coh_tmm_s_scaled={t_tmm:.1f} ({t_tmm * per:.0f} ns/sample, from {len(picks)} sampled points)",
        f"color_20_300_step1_s={t_color:.4f}",
        f"ratio_vs_colour={t_colour / t_ours:.1f} ratio_vs_tmm={t_tmm / t_ours:.0f}",
    ]
