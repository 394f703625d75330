"""Render the references of the denoiser's accuracy tests (#37): tests/data/denoise/<shape>_<finish>.exr.

    PYTHONPATH=. python3 scripts/denoise_references.py        # ~3 min on 2 cores

Each is the case of tests/mitsuba/denoise_cases.py rendered by the Mitsuba engine without denoising at
REFERENCE_SPP samples per pixel (seed REFERENCE_SEED, not the tests' seed), written as a half-float EXR
with the render's metadata. Rerun after a change that changes the pictures (the scene, the plugin).
"""
from __future__ import annotations

import sys

from swatch.io import imageio
from tests.mitsuba import denoise_cases as dc


def main() -> int:
    dc.DATA.mkdir(parents=True, exist_ok=True)
    for shape, finish, d in dc.CASES:
        img = dc.render(shape, finish, d, dc.REFERENCE_SPP, dc.REFERENCE_SEED, denoise=False)
        path = dc.reference_path(shape, finish)
        imageio.write_exr(path, img.linear_rgb, img.metadata | {"case": f"{shape} {finish} {d:g} nm"})
        print(path, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
