"""The cases of the denoiser's accuracy tests (#37), shared by tests/mitsuba/test_mitsuba_denoise.py and the
script that renders their references (scripts/denoise_references.py).

Each case is a small studio render (:data:`SIZE_PX` px) of one shape in one named finish at one thickness;
its reference is the same scene without denoising at :data:`REFERENCE_SPP` samples per pixel (another
seed), stored as a half-float EXR in tests/data/denoise/ (~40 KB each). Colour differences are CIEDE2000
of CIELAB under D65, CIE 1931 2° observer (the renders' linear sRGB → XYZ by colour-science), the geometry
that of the render's camera, averaged over 4 × 4-pixel blocks of linear RGB.
"""
from __future__ import annotations

import math
from pathlib import Path

import colour
import numpy as np

SIZE_PX = 96
SPP = 32
REFERENCE_SPP = 4096
REFERENCE_SEED = 4099
BLOCK_PX = 4
DATA = Path(__file__).resolve().parents[1] / "data" / "denoise"
#: (shape, finish, thickness_nm): every shape (plate, bent sheet, sphere, a mesh) and finish (polished, satin,
#: brushed) at least once, in four interference colours.
CASES = (("sphere", "polished", 80.0), ("sphere", "satin", 140.0), ("sphere", "brushed", 50.8),
         ("flat", "satin", 120.0), ("cylinder", "brushed", 80.0), ("mesh", "polished", 140.0))


def torus():
    """The mesh case: a torus tilted towards the camera (it shadows and reflects itself)."""
    import trimesh

    from swatch.render.mesh import MeshShape

    t = trimesh.creation.torus(major_radius=1.0, minor_radius=0.4, major_sections=64, minor_sections=32)
    t.apply_transform(trimesh.transformations.rotation_matrix(math.radians(60.0), [1.0, 0.0, 0.0]))
    return MeshShape(t, "torus.ply", "denoise-torus")


def render(shape: str, finish: str, thickness_nm: float, spp: int, seed: int, denoise: bool):
    """The case rendered by the Mitsuba engine in the studio (a :class:`swatch.render.image.SwatchImage`)."""
    from swatch.physics.finishes import get_finish
    from swatch.render.mitsuba.engine import render_swatch_mitsuba

    f = get_finish(finish)
    lobe = (f.alpha_u, f.alpha_v) if f.anisotropic else f.roughness_alpha
    return render_swatch_mitsuba(thickness_nm, "sphere" if shape == "mesh" else shape, SIZE_PX, spp, seed,
                                 "studio", roughness_alpha=lobe, mesh=torus() if shape == "mesh" else None,
                                 denoise=denoise)


def reference_path(shape: str, finish: str) -> Path:
    return DATA / f"{shape}_{finish}.exr"


def lab(rgb) -> np.ndarray:
    """CIELAB (D65, CIE 1931 2°) of linear sRGB (1 = the white diffuser: L* 100), by colour-science."""
    cs = colour.RGB_COLOURSPACES["sRGB"]
    XYZ = colour.RGB_to_XYZ(np.asarray(rgb, dtype=np.float64), cs, apply_cctf_decoding=False)
    return colour.XYZ_to_Lab(XYZ, cs.whitepoint)


def blocks(rgb, b: int = BLOCK_PX) -> np.ndarray:
    """Means of ``b`` × ``b`` blocks of an (H, W, C) image."""
    h, w, c = rgb.shape
    return rgb[:h // b * b, :w // b * b].reshape(h // b, b, w // b, b, c).mean(axis=(1, 3))


def block_delta_E00(a, b) -> np.ndarray:
    """CIEDE2000 between the 4 × 4-pixel block means of two linear sRGB images."""
    return colour.delta_E(lab(blocks(a)), lab(blocks(b)), method="CIE 2000")
