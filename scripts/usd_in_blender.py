"""docs/usd-in-blender.png: swatch's .usdz presets imported into real Blender and rendered by Cycles, above
what swatch's exact model renders of the same thicknesses.

    python scripts/usd_in_blender.py OUT.png     # or: python scripts/docs_pictures.py usd-in-blender.png

Top row: ``swatch preset --format usdz`` (the library call behind it) at 50.8, 120 and 210 nm on its
sphere, roughness α 0.3, imported by Blender 5.0's own USD importer and rendered by Cycles on the CPU
(scripts/blender_usd_render.py: 320 px, 64 samples, no denoising, Standard view transform, a dark-grey
world, an overhead soft box and two strip lights). Blender reads the file's UsdPreviewSurface (the
fallback: one metallic colour, no thin film), not its MaterialX OpenPBR network: so the sphere keeps one
hue at every angle. Bottom row: swatch's built-in engine, the exact thin-film model (Airy on the half-vector
facet), the same thicknesses and roughness on a sphere in its studio (another light than Blender's: compare
hues, not highlights).

Blender runs as the ``bpy`` module in its own environment (bpy 5.0 needs numpy < 2): ``.venv-blender`` as
.ci/run installs it (``python3 -m venv .venv-blender && .venv-blender/bin/pip install "bpy>=5.0,<5.1"``), or the
Python named by ``SWATCH_BLENDER_PYTHON``.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
THICKNESS_NM = (50.8, 120.0, 210.0)
SIZE_PX = 320
SAMPLES = 64
ROUGHNESS_ALPHA = 0.3


def blender_python() -> str:
    """The Python with ``bpy``: ``SWATCH_BLENDER_PYTHON``, else ``.venv-blender/bin/python``."""
    path = os.environ.get("SWATCH_BLENDER_PYTHON") or str(ROOT / ".venv-blender" / "bin" / "python")
    if not Path(path).is_file():
        raise SystemExit(f"usd_in_blender: no Blender Python at {path}; install it as .ci/run does: python3 -m venv "
                         '.venv-blender && .venv-blender/bin/pip install "bpy>=5.0,<5.1"')
    return path


def make(out: Path) -> dict:
    """Write the picture to ``out``; return what Blender reported (its version, each imported material)."""
    import OpenImageIO as oiio

    from swatch.io import imageio
    from swatch.io.drawing import draw_text
    from swatch.physics.process import DEFAULT_PROCESS, load_process
    from swatch.presets.usd_files import single_usd_preset
    from swatch.render import render_swatch

    proc = load_process(DEFAULT_PROCESS)
    with tempfile.TemporaryDirectory(prefix="swatch-usd-blender-") as tmp:
        files = []
        for d in THICKNESS_NM:
            data, _ = single_usd_preset(d, "usdz", proc.film, proc.substrate, proc.film_index_scale, ROUGHNESS_ALPHA)
            files.append(Path(tmp) / f"preset_{d:g}nm.usdz")
            files[-1].write_bytes(data)
        done = subprocess.run([blender_python(), str(ROOT / "scripts" / "blender_usd_render.py"), tmp, str(SIZE_PX),
                               str(SAMPLES), "--", *map(str, files)], capture_output=True, text=True, check=False)
        line = next((x for x in done.stdout.splitlines() if x.startswith("SWATCH-JSON ")), None)
        if done.returncode != 0 or line is None:
            raise SystemExit(f"usd_in_blender: Blender failed ({done.returncode}): {done.stderr.strip()[-2000:]}")
        report = json.loads(line.removeprefix("SWATCH-JSON "))
        top = [oiio.ImageBuf(r["png"]).get_pixels(oiio.UINT8)[..., :3] for r in report["results"]]
    bottom = [render_swatch(d, "sphere", SIZE_PX, environment="studio", roughness_alpha=ROUGHNESS_ALPHA)
              .display_rgb[..., :3] for d in THICKNESS_NM]
    rows = [np.concatenate(top, axis=1), np.concatenate(bottom, axis=1)]
    picture = np.ascontiguousarray(np.concatenate(rows, axis=0))
    for i, d in enumerate(THICKNESS_NM):
        picture = draw_text(picture, f"{d:g} nm", i * SIZE_PX + 8, 22, 15, color=(235, 235, 235))
    picture = draw_text(picture, f"Blender {report['blender']} Cycles: the .usdz", 8, SIZE_PX - 10, 15,
                        color=(235, 235, 235))
    picture = draw_text(picture, "swatch: exact model (built-in engine, studio)", 8, 2 * SIZE_PX - 10, 15,
                        color=(235, 235, 235))
    imageio.write_png(out, picture, {"source": "scripts/usd_in_blender.py: top, Blender "
                                     f"{report['blender']} Cycles ({SAMPLES} spp) rendering the imported .usdz "
                                     "(UsdPreviewSurface); bottom, swatch render_swatch sphere, studio"})
    return report


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: python scripts/usd_in_blender.py OUT.png")
    print(json.dumps(make(Path(sys.argv[1])), indent=1))
