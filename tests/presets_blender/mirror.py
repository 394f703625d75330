"""Run a swatch Blender preset in real Blender (the ``bpy`` module) and measure its Fresnel colour.

Usage: ``python mirror.py PRESET.py OUT_DIR ANGLE_DEG...`` with a Python that has ``bpy`` (Blender
as a module, from PyPI), or ``blender -b --factory-startup --python mirror.py -- PRESET.py OUT_DIR
ANGLE_DEG...``; prints one line ``SWATCH-JSON {...}``. ``bpy`` needs numpy < 2, so it runs in its
own environment, never in the project's.

For each angle: a factory-empty scene, a 20 m plane, the preset script run with the plane
selected (as a user would run it), then Roughness set to 0 so the plane is a mirror of a white
world (radiance 1): each pixel is the Principled BSDF's Fresnel at that incidence angle, which is
what swatch fits (Cycles, 1 sample, orthographic camera ``ANGLE_DEG`` from the normal, scene-linear
Rec.709 written to a 32-bit EXR and read back by Blender). Also reports the material's inputs
after the script ran and whether the plane got the material.
"""
import json
import math
import sys

import bpy


def measure(preset: str, out_dir: str, angle_deg: float) -> dict:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    plane = bpy.context.active_object
    plane.select_set(True)
    with open(preset, encoding="utf-8") as fh:
        exec(compile(fh.read(), preset, "exec"), {"__name__": "__main__"})
    mat = plane.data.materials[0] if plane.data.materials else None
    bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    inputs = {}
    for key in ("Base Color", "Metallic", "Roughness", "Thin Film Thickness", "Thin Film IOR"):
        v = bsdf.inputs[key].default_value
        inputs[key] = list(v) if hasattr(v, "__len__") else float(v)
    bsdf.inputs["Roughness"].default_value = 0.0
    world = bpy.data.worlds.new("white")
    bpy.context.scene.world = world
    background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 1.0
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = 1.0
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    t = math.radians(angle_deg)
    cam.location = (0.0, -5.0 * math.sin(t), 5.0 * math.cos(t))
    cam.rotation_euler = (t, 0.0, 0.0)
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 4
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = f"{out_dir}/mirror_{angle_deg:g}.exr"
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(scene.render.filepath)
    px = list(img.pixels)
    n = len(px) // 4
    rgb = [sum(px[4 * i + c] for i in range(n)) / n for c in range(3)]
    return {"angle_deg": angle_deg, "rgb": rgb, "inputs": inputs, "assigned": mat is not None and mat.name}


def main(argv):
    preset, out_dir, angles = argv[0], argv[1], [float(a) for a in argv[2:]]
    out = {"blender": bpy.app.version_string, "results": [measure(preset, out_dir, a) for a in angles]}
    sys.stdout.write("SWATCH-JSON " + json.dumps(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
