"""Mitsuba scene dictionaries of a swatch render: the built-in renderer's camera and shapes, and the lighting.

Geometry is that of :mod:`swatch.render.scene` (world y up, the camera on the +z side): the same pinhole
camera and framing (its off-centre window becomes Mitsuba's principal-point offset), the 2 × 2
plate, the unit sphere, the half cylinder (a tessellated sheet, both faces the finish) and a
designer's mesh (placed as by :class:`swatch.render.mesh.MeshShape`, creases split). Every object is
the finish on both faces (a sheet's inner face and a mesh's back faces): the film plugin with its
``two_sided`` option (one traced BSDF: a render kernel ~35 % smaller, compiled ~0.5 s sooner, than with
the ``twosided`` wrapper, which traces the plugin as a second BSDF), any other BSDF in ``twosided``.

Lighting (:func:`lighting`)
---------------------------
* ``studio``: a photographic studio: a grey cyclorama (floor sweeping up into a back wall,
  diffuse albedo 0.45) under the object, an overhead key soft box, a tall strip box on the camera's
  left and a weaker one on the right (rectangular area lights, neutral D65), and a dim ambient
  fill (0.05) so nothing is pitch black;
* ``sun``: Mitsuba's ``sunsky`` (Hosek–Wilkie sky and sun, spectral) over a mid-grey ground
  (albedo 0.2); the sun by elevation and azimuth, or by latitude, longitude, date and time
  (the scene's −z is north, +x west: a wall facing the camera faces south);
* ``uniform``: radiance 1 (D65) from every direction, nothing else in the scene;
* a user's HDRI (equirectangular EXR or Radiance HDR, as :func:`swatch.render.hdri.read_equirect`
  orients it: row 0 the zenith, the centre column looking along −z).
"""
from __future__ import annotations

import math

import mitsuba as mi
import numpy as np

from swatch.render import studio_set as ss
from swatch.render.lighting import Sun
from swatch.render.mitsuba.bsdf import PLUGIN_NAME
from swatch.render.scene import Camera

__all__ = ["Sun", "jit_float", "load_scene", "camera_dict", "object_shapes", "lighting", "triangle_mesh", "half_cylinder_arrays",
           "SUNSKY_TO_WORLD"]

#: How often next-event estimation picks the studio's dim ambient fill, relative to a soft box's
#: radiance × area (the key's is 48): the emitters are chosen in proportion to their power rather than
#: uniformly (the same expected image, ~15 % less noise at equal samples; a hit on the fill by the path's
#: own bounce still counts, by multiple importance sampling).
FILL_SAMPLING_WEIGHT = 2.0
#: sunsky's frame (z up, x south, y west) into the world (y up, +z south, +x west, −z north).
SUNSKY_TO_WORLD = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def load_scene(scene: dict):
    """``mitsuba.load_dict`` of a whole scene, with the parser's object merging off.

    Mitsuba 3.9's ``optimize`` pass (merging identical objects) leaves the scene's shapes and
    emitters in an order that changes from load to load (the two strip boxes swapped in about one
    load in eight, in this process or the next); the light sampler picks emitters by index, so the
    same seed then drew a different sample stream (a different image, #23). Without it the order is
    the dictionary's, every time.

    Parameters
    ----------
    scene : dict
        A Mitsuba scene dictionary.

    Returns
    -------
    mitsuba.Scene
        The loaded scene, its shapes and emitters in the dictionary's order.
    """
    return mi.load_dict(scene, optimize=False)


def jit_float(values) -> mi.Float:
    """``values`` as a Dr.Jit ``Float`` of the current variant, read from a 64-byte-aligned float32 copy.

    Dr.Jit maps a NumPy buffer without copying it and compiles the kernels that read it for its address
    (``unaligned`` unless a multiple of 32 bytes: drjit-core's ``jitc_var_mem_map``); NumPy's buffers are
    16-byte aligned, so kernels fed NumPy arrays came out as one of two programs at random and missed
    Dr.Jit's kernel cache (~/.drjit) about half the time, compiled again (#17). The values are those of
    ``np.float32(values)``; Dr.Jit keeps the copy alive with the array.

    Parameters
    ----------
    values : array_like
        Numbers (any shape: flattened).

    Returns
    -------
    mitsuba.Float
        The values flattened, float32, in a 64-byte-aligned buffer.
    """
    a = np.ascontiguousarray(values, dtype=np.float32).reshape(-1)
    buf = np.empty(a.size + 16, dtype=np.float32)
    start = (-buf.ctypes.data % 64) // 4
    out = buf[start:start + a.size]
    out[:] = a
    return mi.Float(out)


def _transform(matrix) -> mi.ScalarTransform4f:
    return mi.ScalarTransform4f(np.asarray(matrix, dtype=np.float64).tolist())


def camera_dict(cam: Camera, size_px: int, spp: int, window_px: tuple[int, int, int, int] | None = None,
                sampler: str = "independent") -> dict:
    """Mitsuba's perspective sensor for a :class:`swatch.render.scene.Camera` (same rays through pixel centres).

    Parameters
    ----------
    cam : swatch.render.scene.Camera
        The pinhole camera (eye in scene units, orthonormal frame, window in tan units).
    size_px : int
        Pixels per side of the film.
    spp : int
        Samples per pixel.
    window_px : (int, int, int, int), optional
        ``(x, y, width, height)``: only that window of the film is rendered (Mitsuba's film crop), in
        pixels from the top-left corner; checked by the caller.
    sampler : str, optional
        Mitsuba's sampler: ``independent`` or ``ldsampler`` (low-discrepancy: ``spp`` a power of 4, which
        it would otherwise round up).

    Returns
    -------
    dict
        The sensor's scene entry (with its film and sampler).
    """
    m = np.eye(4)
    # Mitsuba's camera looks along +z with +x to the image's left and +y up.
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = -cam.right, cam.up, cam.forward, cam.position
    film = {"type": "hdrfilm", "width": int(size_px), "height": int(size_px), "pixel_format": "rgba",
            "component_format": "float32", "rfilter": {"type": "box"}}
    if window_px is not None:
        x, y, w, h = (int(v) for v in window_px)
        film.update(crop_offset_x=x, crop_offset_y=y, crop_width=w, crop_height=h)
    return {
        "type": "perspective",
        "fov": math.degrees(2.0 * math.atan(cam.half)),
        "fov_axis": "x",
        "principal_point_offset_x": cam.cx / (2.0 * cam.half),
        "principal_point_offset_y": -cam.cy / (2.0 * cam.half),
        "near_clip": 0.01,
        "far_clip": 1000.0,
        "to_world": _transform(m),
        "film": film,
        "sampler": {"type": sampler, "sample_count": int(spp)},
    }


def triangle_mesh(name: str, positions: np.ndarray, faces: np.ndarray, normals: np.ndarray | None, bsdf):
    """A ``mitsuba.Mesh`` from arrays.

    Parameters
    ----------
    name : str
        The shape's id in the scene (``cylinder``, ``mesh``, ``cyclorama``).
    positions : numpy.ndarray
        Vertex positions, shape (N, 3).
    faces : numpy.ndarray
        Vertex indices of the triangles, shape (F, 3).
    normals : numpy.ndarray or None
        Vertex normals, shape (N, 3); None: flat faces.
    bsdf : mitsuba.BSDF
        The loaded material of every face.

    Returns
    -------
    mitsuba.Mesh
        The triangle mesh with its vertex data uploaded (``params.update()`` done).
    """
    props = mi.Properties()
    props["bsdf"] = bsdf
    pos = np.ascontiguousarray(positions, dtype=np.float32)
    tri = np.ascontiguousarray(faces, dtype=np.uint32)
    mesh = mi.Mesh(name, pos.shape[0], tri.shape[0], props=props, has_vertex_normals=normals is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(pos.reshape(-1))
    params["faces"] = mi.UInt32(tri.reshape(-1))
    if normals is not None:
        params["vertex_normals"] = mi.Float(np.ascontiguousarray(normals, dtype=np.float32).reshape(-1))
    params.update()
    return mesh


def half_cylinder_arrays(half_height: float = 1.1, segments: int = 256):
    """The half cylinder of :class:`swatch.render.scene.HalfCylinder` (radius 1, |y| ≤ h, z ≥ 0) as a strip:
    positions, faces, outward normals.

    Parameters
    ----------
    half_height : float, optional
        Half its length along y.
    segments : int, optional
        Facets around the half circle.

    Returns
    -------
    positions, faces, normals : numpy.ndarray
        Shapes (2(S+1), 3), (2S, 3), (2(S+1), 3).
    """
    ph = np.linspace(-math.pi / 2, math.pi / 2, segments + 1)
    x, z = np.sin(ph), np.cos(ph)
    pos = np.concatenate([np.stack([x, np.full_like(x, -half_height), z], -1),
                          np.stack([x, np.full_like(x, half_height), z], -1)])
    nrm = np.concatenate([np.stack([x, 0 * x, z], -1)] * 2)
    i = np.arange(segments)
    n = segments + 1
    faces = np.concatenate([np.stack([i, i + 1, i + n], -1), np.stack([i + 1, i + 1 + n, i + n], -1)])
    return pos, faces, nrm


def object_shapes(shape: str, bsdf: dict, mesh=None) -> dict:
    """The swatch object(s) of ``shape`` (flat, cylinder, sphere) or ``mesh``, with ``bsdf`` on both faces.

    Parameters
    ----------
    shape : str
        ``flat``, ``cylinder``, ``sphere`` or ``mesh``.
    bsdf : dict
        The BSDF's scene entry.
    mesh : swatch.render.mesh.MeshShape, optional
        With ``shape="mesh"``.

    Returns
    -------
    dict
        Scene entries.
    """
    two = dict(bsdf, two_sided=True) if bsdf.get("type") == PLUGIN_NAME else {"type": "twosided", "material": bsdf}
    if shape == "flat":
        # rectangle: [-1, 1]² in z = 0, normal +z; turned to y = 0, normal +y
        return {"object": {"type": "rectangle", "bsdf": two,
                           "to_world": mi.ScalarTransform4f().rotate([1.0, 0.0, 0.0], -90.0)}}
    if shape == "sphere":
        return {"object": {"type": "sphere", "radius": 1.0, "bsdf": two}}
    loaded = mi.load_dict(two)
    if shape == "cylinder":
        pos, faces, nrm = half_cylinder_arrays()
        return {"object": triangle_mesh("cylinder", pos, faces, nrm, loaded)}
    corners, normals = mesh.triangle_soup()
    f = corners.shape[0]
    return {"object": triangle_mesh("mesh", corners.reshape(-1, 3), np.arange(3 * f).reshape(f, 3),
                                    normals.reshape(-1, 3), loaded)}


def _cyclorama(floor_y: float, bsdf) -> mi.Mesh:
    """The set's cyclorama (:mod:`swatch.render.studio_set`): a floor at ``floor_y`` from z = FRONT_Z to the cove,
    a quarter-circle cove and a back wall, tessellated (16 facets on the cove, smooth normals)."""
    r, z_wall = ss.COVE_RADIUS, ss.WALL_Z
    a = np.linspace(0.0, math.pi / 2, 17)
    prof = [(floor_y, ss.FRONT_Z), (floor_y, z_wall + r)]
    prof += [(floor_y + r - r * math.cos(t), z_wall + r - r * math.sin(t)) for t in a[1:]]
    prof += [(floor_y + ss.WALL_HEIGHT, z_wall)]
    yz = np.array(prof)
    nrm_yz = np.array([(1.0, 0.0), (1.0, 0.0)] + [(math.cos(t), math.sin(t)) for t in a[1:]] + [(0.0, 1.0)])
    k = yz.shape[0]
    xs = (-ss.HALF_WIDTH, ss.HALF_WIDTH)
    pos = np.concatenate([np.stack([np.full(k, x), yz[:, 0], yz[:, 1]], -1) for x in xs])
    nrm = np.concatenate([np.stack([np.zeros(k), nrm_yz[:, 0], nrm_yz[:, 1]], -1)] * 2)
    i = np.arange(k - 1)
    faces = np.concatenate([np.stack([i, i + k, i + 1], -1), np.stack([i + 1, i + k, i + k + 1], -1)])
    return triangle_mesh("cyclorama", pos, faces, nrm, bsdf)


def _box(box: ss.SoftBox) -> dict:
    """A soft box of the set (one-sided area light) at its centre facing its target; chosen for next-event
    estimation in proportion to its power (radiance × area: ``sampling_weight``)."""
    t = mi.ScalarTransform4f().look_at(origin=list(box.centre), target=list(box.target), up=list(box.up()))
    size = box.size
    return {"type": "rectangle", "to_world": t @ mi.ScalarTransform4f().scale([size[0] / 2, size[1] / 2, 1.0]),
            "emitter": {"type": "area", "radiance": float(box.radiance),
                        "sampling_weight": float(box.radiance) * size[0] * size[1]},
            "bsdf": {"type": "diffuse", "reflectance": 0.0}}


def lighting(kind: str, floor_y: float, sun: Sun | None = None, hdri: np.ndarray | None = None) -> dict:
    """Scene entries of a lighting ``kind`` (module doc): emitters, and the studio's cyclorama or the ground.

    Parameters
    ----------
    kind : str
        ``uniform``, ``studio``, ``sun`` or ``map``.
    floor_y : float
        The height of the floor or ground (just under the object).
    sun : swatch.render.lighting.Sun, optional
        With ``kind="sun"``.
    hdri : numpy.ndarray, optional
        With ``kind="map"``: the equirectangular radiance (H, W, 3) of a user map, already checked.

    Returns
    -------
    dict
        Scene entries.
    """
    if kind == "uniform":
        return {"light": {"type": "constant", "radiance": 1.0}}
    if kind == "studio":
        return {
            "cyclorama": _cyclorama(floor_y, mi.load_dict({"type": "diffuse", "reflectance": ss.CYCLORAMA_ALBEDO})),
            **{box.name: _box(box) for box in ss.SOFT_BOXES},
            "fill": {"type": "constant", "radiance": ss.FILL_RADIANCE, "sampling_weight": FILL_SAMPLING_WEIGHT},
        }
    if kind == "sun":
        assert sun is not None, "sun lighting needs a Sun"
        d: dict = {"type": "sunsky", "turbidity": float(sun.turbidity), "to_world": _transform(SUNSKY_TO_WORLD)}
        if sun.by_place:
            d.update(latitude=float(sun.latitude_deg or 0.0), longitude=float(sun.longitude_deg or 0.0),
                     timezone=float(sun.timezone_h), year=int(sun.year), month=int(sun.month), day=int(sun.day),
                     hour=float(sun.hour))
        else:
            el, az = math.radians(float(sun.elevation_deg or 0.0)), math.radians(sun.azimuth_deg)
            world = np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
            d["sun_direction"] = world.tolist()  # in world coordinates (sunsky applies to_world to its sky only)
        ground = {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": 0.2},
                  "to_world": mi.ScalarTransform4f().translate([0.0, floor_y, 0.0])
                  @ mi.ScalarTransform4f().rotate([1.0, 0.0, 0.0], -90.0) @ mi.ScalarTransform4f().scale(200.0)}
        return {"light": d, "ground": ground}
    assert hdri is not None, "a user map needs its pixels"
    bitmap = mi.Bitmap(np.ascontiguousarray(hdri, dtype=np.float32), mi.Bitmap.PixelFormat.RGB)
    # Mitsuba's envmap centre column looks along +z; the map's (swatch's) along -z: half a turn about y.
    return {"light": {"type": "envmap", "bitmap": bitmap, "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 180)}}
