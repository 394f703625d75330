"""Import swatch's .usdz presets into real Blender (the ``bpy`` module) and render them with Cycles.

Usage: ``python blender_usd_render.py OUT_DIR SIZE [SAMPLES] -- PRESET.usdz...`` with a Python that has ``bpy`` (Blender
as a module, from PyPI: ``bpy>=5.0,<5.1`` needs numpy < 2, so it runs in its own environment, ``.venv-blender``,
never the project's); prints one line ``SWATCH-JSON {...}``. scripts/usd_in_blender.py drives it.

For each preset: a factory-empty scene, the .usdz imported by Blender's own USD importer
(``bpy.ops.wm.usd_import``, Y-up converted to Blender's Z-up), the material it made left as imported, and
Cycles on the CPU (fixed seed, no denoising, the Standard view transform) rendering ``OUT_DIR/blender_N.png``
(8-bit sRGB) of the sphere from the front, a little above, under a studio-like light: a dark-grey world
(radiance 0.05), an overhead soft box and two tall strip lights left and right. Reported per preset: the
imported material's name, node types and Principled BSDF inputs (what Blender read from the file).
"""
import json
import math
import sys

import bpy

_INPUTS = ("Base Color", "Metallic", "Roughness", "Thin Film Thickness", "Thin Film IOR")


def _area(scene, name: str, size_xy: tuple, location: tuple, rotation_deg: tuple, power_w: float) -> None:
    light = bpy.data.lights.new(name, "AREA")
    light.shape = "RECTANGLE"
    light.size, light.size_y = size_xy
    light.energy = power_w
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    obj.rotation_euler = tuple(math.radians(a) for a in rotation_deg)
    scene.collection.objects.link(obj)


def _studio(scene) -> None:
    world = bpy.data.worlds.new("world")
    scene.world = world
    background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 0.05
    _area(scene, "overhead", (0.4, 0.4), (0.0, -0.05, 0.35), (0.0, 0.0, 0.0), 4.0)  # faces down (-Z)
    _area(scene, "left", (0.08, 0.5), (-0.3, -0.15, 0.05), (90.0, 0.0, -60.0), 1.5)
    _area(scene, "right", (0.08, 0.5), (0.3, -0.15, 0.05), (90.0, 0.0, 60.0), 1.5)


def _camera(scene) -> None:
    data = bpy.data.cameras.new("camera")
    data.lens = 85.0
    cam = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(cam)
    t = math.radians(15.0)  # 15° above the horizon, looking at the sphere's centre
    distance = 0.32
    cam.location = (0.0, -distance * math.cos(t), distance * math.sin(t))
    cam.rotation_euler = (math.radians(90.0) - t, 0.0, 0.0)
    scene.camera = cam


def render(preset: str, path: str, size: int, samples: int) -> dict:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.usd_import(filepath=preset)
    scene = bpy.context.scene
    meshes = [o for o in scene.objects if o.type == "MESH"]
    out: dict = {"preset": preset, "meshes": [o.name for o in meshes]}
    mat = meshes[0].active_material if meshes and meshes[0].active_material else None
    out["material"] = mat.name if mat else None
    if mat is not None and mat.node_tree is not None:
        out["nodes"] = sorted(n.type for n in mat.node_tree.nodes)
        bsdf = next((n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
        if bsdf is not None:
            values = {}
            for key in _INPUTS:
                v = bsdf.inputs[key].default_value
                values[key] = [round(float(x), 4) for x in v] if hasattr(v, "__len__") else round(float(v), 4)
            out["principled"] = values
    _studio(scene)
    _camera(scene)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.seed = 0
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "8"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    out["png"] = path
    return out


def main(argv) -> None:
    split = argv.index("--")
    out_dir, size = argv[0], int(argv[1])
    samples = int(argv[2]) if split > 2 else 64
    results = [render(p, f"{out_dir}/blender_{i}.png", size, samples) for i, p in enumerate(argv[split + 1:])]
    sys.stdout.write("SWATCH-JSON " + json.dumps({"blender": bpy.app.version_string, "results": results}) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
