"""Render the pictures of docs/mitsuba.md with ``swatch render --engine mitsuba``'s Python API (#23).

    python3 scripts/mitsuba_gallery.py docs/        # writes docs/mitsuba-gallery.png (about 1 min on 2 cores)

Four scenes, 50.8 nm (blue) unless noted, at 64 spp, denoised (Intel Open Image Denoise, the engine's
default, #37): a polished sphere and the brushed bent sheet (120 nm, gold-magenta; hairlines along its
axis) in the studio, a satin bowl (a mesh with a concavity: it reflects and shadows itself) in the studio,
and a façade-like wall of slightly tilted panels (80 nm, GGX α 0.12) under Mitsuba's sun and sky.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import trimesh

from swatch.io import imageio
from swatch.physics.finishes import get_finish
from swatch.render.mesh import MeshShape
from swatch.render.mitsuba.engine import Sun, mitsuba_lighting, render_swatch_mitsuba

SIZE, SPP = 256, 64


def bowl() -> MeshShape:
    """A thin-walled bowl (revolved profile) standing on its foot."""
    t = np.linspace(0.0, math.pi / 2, 24)
    outer = np.stack([0.15 + 0.85 * np.sin(t), 0.85 * (1 - np.cos(t))], -1)
    inner = np.stack([0.12 + 0.80 * np.sin(t[::-1]), 0.05 + 0.80 * (1 - np.cos(t[::-1]))], -1)
    prof = np.concatenate([[[0.0, 0.0]], outer, inner, [[0.0, 0.05]]])
    m = trimesh.creation.revolve(prof, sections=96)
    m.apply_transform(trimesh.transformations.rotation_matrix(-math.pi / 2, [1, 0, 0]))  # revolve axis z -> y
    return MeshShape(m, "bowl.glb", "gallery-bowl")


def panel_wall() -> MeshShape:
    """Five rows of four panels, each tilted a few degrees (as titanium cladding is), facing +z."""
    rng = np.random.default_rng(2)
    panels = []
    for r in range(5):
        for c in range(4):
            p = trimesh.creation.box(extents=[0.46, 0.34, 0.02])
            rot = trimesh.transformations.rotation_matrix(math.radians(rng.uniform(-7, 7)), [1, 0, 0]) @ \
                trimesh.transformations.rotation_matrix(math.radians(rng.uniform(-5, 5)), [0, 1, 0])
            p.apply_transform(rot)
            p.apply_translation([(c - 1.5) * 0.5, (r - 2) * 0.38, 0.0])
            panels.append(p)
    back = trimesh.creation.box(extents=[2.1, 1.95, 0.02])
    back.apply_translation([0, 0, -0.05])
    return MeshShape(trimesh.util.concatenate([*panels, back]), "panel-wall.glb", "gallery-wall")


def main(out_dir: str) -> int:
    studio = mitsuba_lighting("studio")
    polished, satin, brushed = (get_finish(f) for f in ("polished", "satin", "brushed"))
    shots = [
        render_swatch_mitsuba(50.8, "sphere", SIZE, SPP, lighting_name=studio, roughness_alpha=polished.alpha_u),
        render_swatch_mitsuba(120.0, "cylinder", SIZE, SPP, lighting_name=studio,
                              roughness_alpha=(brushed.alpha_u, brushed.alpha_v)),
        render_swatch_mitsuba(50.8, "sphere", SIZE, SPP, lighting_name=studio, roughness_alpha=satin.alpha_u,
                              mesh=bowl()),
        render_swatch_mitsuba(80.0, "sphere", SIZE, SPP, lighting_name=mitsuba_lighting("sun", Sun(40.0, 60.0)),
                              roughness_alpha=0.12, mesh=panel_wall(), exposure=1.0),
    ]
    strip = np.concatenate([s.display_rgb for s in shots], axis=1)
    out = Path(out_dir) / "mitsuba-gallery.png"
    imageio.write_png(out, strip, {"source": "scripts/mitsuba_gallery.py", "spp": SPP,
                                   "denoise": shots[0].metadata["denoise"],
                                   "scenes": "polished sphere 50.8 nm studio; brushed bent sheet 120 nm studio; "
                                             "satin bowl 50.8 nm studio; "
                                             "panel wall 80 nm, sun 40 deg elevation, azimuth 60 deg, turbidity 3, display exposure 1"})
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "docs"))
