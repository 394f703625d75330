"""Mesh renders (``swatch render --mesh``): a torus on a plate (9 228 triangles), 512 × 512.

* ``render_mesh_512_s``: median wall time of a point-light render (primary rays, shadow rays,
  shading), the mesh loaded once.
* ``render_mesh_env_512_s``: the same under the studio environment (the scene's gather recomputed).
* ``mesh_raycast_ratio``: trimesh's pure-numpy ray/triangle intersector (the reference the tests
  check Embree's hits against) timed on every 16th image row, scaled to all 512² primary rays,
  divided by the Embree cast of all of them.
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks.timing import median_seconds, pick


def run(size: int | None = None, repeats: int = 5) -> list[str]:
    size = size or pick(512, 64)
    import trimesh
    from trimesh.ray.ray_triangle import RayMeshIntersector

    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.physics.model import get_coating
    from swatch.render import mesh, render_swatch, scene
    from swatch.render.builtin import env_render

    coating = get_coating()
    cm = get_colorimeter(coating.wavelength_nm)
    torus = trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=96, minor_sections=48)
    torus.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    box = trimesh.creation.box(extents=[2.6, 0.1, 2.6])
    box.apply_translation([0, -0.45, 0])
    obj = trimesh.util.concatenate([torus, box])
    shape = mesh.MeshShape(obj, "torus.glb", "bench")

    def point():
        return render_swatch(80.0, "mesh", size, coating=coating, colorimeter=cm, mesh=shape, environment="point")

    def env():
        env_render._CACHE.clear()
        return render_swatch(80.0, "mesh", size, coating=coating, colorimeter=cm, mesh=shape,
                                    environment="studio")

    t_point = median_seconds(point, repeats)
    t_env = median_seconds(env, repeats)
    sc = scene.make_scene("sphere", 45.0, mesh=shape)
    c = np.arange(size, dtype=np.float32) + np.float32(0.5)
    d = np.stack([np.broadcast_to(a, (size, size)) for a in sc.camera.directions(c[None, :], c[:, None], size)],
                 -1).reshape(-1, 3).astype(np.float64)
    o = np.broadcast_to(sc.camera.position, d.shape)
    t_embree = median_seconds(lambda: shape._rays.intersects_id(o, d, multiple_hits=False, return_locations=True),
                              repeats)
    rows = d.reshape(size, size, 3)[::16].reshape(-1, 3)
    t0 = time.perf_counter()
    RayMeshIntersector(shape._mesh).intersects_id(o[:rows.shape[0]], rows, multiple_hits=False, return_locations=True)
    t_ref = (time.perf_counter() - t0) * d.shape[0] / rows.shape[0]
    return [f"render_mesh_{size}_s={t_point:.3f} render_mesh_env_{size}_s={t_env:.3f} "
            f"mesh_raycast_ratio={t_ref / t_embree:.0f} (triangles={shape.triangles})"]


if __name__ == "__main__":
    for line in run():
        print(line)
