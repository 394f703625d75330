"""Run swatch Blender presets in real Blender (the ``bpy`` module) and measure what Cycles renders.

Usage: ``python mirror.py OUT_DIR MEASUREMENT... -- PRESET.py...`` with a Python that has ``bpy``
(Blender as a module, from PyPI), or ``blender -b --factory-startup --python mirror.py -- OUT_DIR
MEASUREMENT... -- PRESET.py...``; prints one line ``SWATCH-JSON {...}``. ``bpy`` 5.0 needs numpy < 2,
so it runs in its own environment, never in the project's.

For each preset and measurement: a factory-empty scene, a 20 m plane, the preset script run with
the plane selected (as a user would run it), Cycles on the CPU with an orthographic camera and a
fixed seed, scene-linear Rec.709 written to a 32-bit EXR and read back by Blender. Measurements:

- ``mirror:ANGLE`` — Roughness set to 0 after the script, a white world (radiance 1), the camera
  ``ANGLE`` degrees from the normal: each pixel is the Principled BSDF's Fresnel at that angle.
- ``sun:LIGHT`` — the preset's own roughness and distribution, a sun lamp (angle 0) ``LIGHT``
  degrees from the normal, the camera along the normal, black world (geometry LIGHT:0).
- ``furnace:VIEW`` — the preset's own roughness and distribution, a white world (radiance 1), the
  camera ``VIEW`` degrees from the normal.

``sun`` and ``furnace`` also render the same plate with a white metal (Base Color 1, no thin film,
everything else as the script left it) with the same seed: the ratio of the two is the preset's
Fresnel factor (``sun``: exactly F at the half-vector angle for single-scatter GGX; ``furnace``: F
averaged over the GGX lobe). Also reported: the material's inputs and distribution after the
script ran and whether the plane got the material.
"""
import json
import math
import sys

import bpy

_INPUTS = ("Base Color", "Metallic", "Roughness", "Thin Film Thickness", "Thin Film IOR")


def _scene(preset: str):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    plane = bpy.context.active_object
    plane.select_set(True)
    with open(preset, encoding="utf-8") as fh:
        exec(compile(fh.read(), preset, "exec"), {"__name__": "__main__"})
    mat = plane.data.materials[0] if plane.data.materials else None
    bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    return mat, bsdf


def _camera(scene, angle_deg: float) -> None:
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = 1.0
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    t = math.radians(angle_deg)
    cam.location = (0.0, -5.0 * math.sin(t), 5.0 * math.cos(t))
    cam.rotation_euler = (t, 0.0, 0.0)
    scene.camera = cam


def _world(scene, radiance: float) -> None:
    world = bpy.data.worlds.new("world")
    scene.world = world
    background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = radiance


def _render(scene, path: str, size: int, samples: int) -> list:
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.seed = 0
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    px = list(img.pixels)
    bpy.data.images.remove(img)
    n = len(px) // 4
    return [sum(px[4 * i + c] for i in range(n)) / n for c in range(3)]


def measure(preset: str, out_dir: str, kind: str, angle_deg: float, tag: str) -> dict:
    mat, bsdf = _scene(preset)
    inputs = {}
    for key in _INPUTS:
        v = bsdf.inputs[key].default_value
        inputs[key] = list(v) if hasattr(v, "__len__") else float(v)
    scene = bpy.context.scene
    out = {"kind": kind, "angle_deg": angle_deg, "inputs": inputs, "distribution": bsdf.distribution,
           "assigned": mat is not None and mat.name}
    path = f"{out_dir}/{tag}_{kind}_{angle_deg:g}"
    if kind == "mirror":
        bsdf.inputs["Roughness"].default_value = 0.0
        _world(scene, 1.0)
        _camera(scene, angle_deg)
        out["rgb"] = _render(scene, path + ".exr", 4, 1)
        return out
    if kind == "sun":
        _world(scene, 0.0)
        light = bpy.data.lights.new("sun", "SUN")
        light.energy = 1.0
        light.angle = 0.0
        sun = bpy.data.objects.new("sun", light)
        sun.rotation_euler = (0.0, math.radians(angle_deg), 0.0)  # its -Z points down at angle_deg
        scene.collection.objects.link(sun)
        _camera(scene, 0.0)
        size, samples = 4, 1
    elif kind == "furnace":
        _world(scene, 1.0)
        _camera(scene, angle_deg)
        size, samples = 16, 1024
    else:
        raise SystemExit(f"unknown measurement {kind!r}")
    out["rgb"] = _render(scene, path + ".exr", size, samples)
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Thin Film Thickness"].default_value = 0.0
    out["white_rgb"] = _render(scene, path + "_white.exr", size, samples)
    return out


def main(argv):
    split = argv.index("--")
    out_dir, specs, presets = argv[0], argv[1:split], argv[split + 1:]
    results = []
    for i, preset in enumerate(presets):
        rows = []
        for spec in specs:
            kind, angle = spec.split(":")
            rows.append(measure(preset, out_dir, kind, float(angle), f"p{i}"))
        results.append({"preset": preset, "measurements": rows})
    out = {"blender": bpy.app.version_string, "results": results}
    sys.stdout.write("SWATCH-JSON " + json.dumps(out) + "\n")


if __name__ == "__main__":
    args = sys.argv[1:]
    if "--python" in sys.argv:  # blender -b --python mirror.py -- OUT_DIR ... -- PRESET...
        args = sys.argv[sys.argv.index("--") + 1:]
    main(args)
