"""Grain of ``swatch render --engine mitsuba`` as a designer sees it: the standard deviation of the display
PNG's codes (0–255, all three channels) after removing a 5 × 5 box blur, in 24 × 24-pixel patches of the
backdrop (top left) and of the object's face (the image's centre), raw and denoised.

    python scripts/mitsuba_grain.py [SIZE_PX] [SPP]     # default: 512 px at the CLI's 64 spp

Two scenes: the polished 140 nm sphere and the brushed 80 nm bent sheet, in the studio, seed 0.
"""
from __future__ import annotations

import sys

import numpy as np
from scipy.ndimage import uniform_filter

from swatch.physics.finishes import get_finish
from swatch.render import render_swatch

SCENES = (("sphere", "polished", 140.0), ("cylinder", "brushed", 80.0))


def grain(display: np.ndarray, y: int, x: int, side: int = 24) -> float:
    """Standard deviation of the display codes in a ``side``² patch at (y, x) after a 5 × 5 box blur is removed."""
    codes = display.astype(np.float64)
    detail = codes - uniform_filter(codes, size=(5, 5, 1), mode="nearest")
    return float(detail[y:y + side, x:x + side].std())


def main(argv: list[str]) -> int:
    size = int(argv[0]) if argv else 512
    spp = int(argv[1]) if len(argv) > 1 else 64
    for shape, finish, d in SCENES:
        row = []
        for denoise in (False, True):
            img = render_swatch(d, shape, size, engine="mitsuba", spp=spp, environment="studio",
                                finish=get_finish(finish), denoise=denoise)
            back = grain(img.display_rgb, size // 16, size // 16)
            face = grain(img.display_rgb, size // 2 - 12, size // 2 - 12)
            row.append(f"{'denoised' if denoise else 'raw'} backdrop {back:.2f} face {face:.2f}")
        print(f"{finish} {d:g} nm {shape}, {size} px, {spp} spp: " + "; ".join(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
