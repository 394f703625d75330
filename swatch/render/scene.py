"""The scene of a swatch render: a pinhole camera, the shapes (behind the :class:`Shape` protocol),
the light, and where they are placed.

Scenes (world y up; the camera looks at the origin)
---------------------------------------------------
* ``flat``: a 2 × 2 square plate in the plane y = 0 (normal +y). The light is ``light_deg`` from
  the plate normal on the far side; the camera is 36° from the normal on the near side at
  3.2 units, so the view angle (along the centre line) runs from about 19° (near edge) to 48°
  (far edge): with the default 45° light the highlight sits near the far edge, the off-mirror
  interference colour toward the near edge.
* ``cylinder``: a sheet bent into a half cylinder (radius 1, height 2.2, vertical axis, convex
  side to the camera), seen from 20° above at 5.5 units. ``sphere``: a unit sphere, the whole
  visible hemisphere of normals, from 20° above at 4 units. For both, the light is
  ``light_deg`` away from the camera direction, from the left and 30° above the horizontal
  image axis; the highlight sits where the normal bisects light and view.

The chromaticity depends only on ``θ_d`` (the half angle between light and view): with a distant
light and a distant camera it would be one colour over the whole shape. The colour shift across a
curved swatch therefore comes from perspective, as in a close product photograph: the camera
sits a few object sizes away (field of view 30–45°), so the view direction, and with it ``θ_d``,
changes across the swatch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from swatch.core.choices import SHAPES
from swatch.core.errors import SwatchError
from swatch.physics import geometry
from swatch.render.camera import Camera, unit

__all__ = ["SHAPES", "Camera", "Shape", "Sphere", "HalfCylinder", "Plate", "Scene", "check_shape", "make_scene",
           "scene_geometry"]


def check_shape(shape: str) -> str:
    """The shape's key (one of :data:`swatch.core.choices.SHAPES`, case-insensitive).

    Parameters
    ----------
    shape : str
        A shape name (:data:`swatch.core.choices.SHAPES`; case and spaces ignored).

    Returns
    -------
    str
        The name, lower case.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other name.
    """
    key = str(shape).strip().lower()
    if key not in SHAPES:
        raise SwatchError(f"unknown swatch shape {shape!r}; use one of {', '.join(SHAPES)}")
    return key


class Shape(Protocol):
    """What the renderer needs of a shape (arrays planar, in the rays' precision): :meth:`intersect`,
    :meth:`trace` and :meth:`points`; implemented by :class:`Sphere`, :class:`HalfCylinder`,
    :class:`Plate` and :class:`swatch.render.mesh.MeshShape`.

    Attributes
    ----------
    name : str
        The shape's name (``flat``, ``cylinder``, ``sphere``, ``mesh``).
    """

    name: str

    def intersect(self, o: np.ndarray, dx: np.ndarray, dy: np.ndarray, dz: np.ndarray) -> tuple:
        """First hits of rays from ``o`` and the unit normals there.

        Parameters
        ----------
        o : numpy.ndarray, shape (3,)
            The rays' origin.
        dx, dy, dz : numpy.ndarray
            Unit directions (broadcast together).

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, nx, ny, nz)``.
        """
        ...

    def trace(self, cam: Camera, u: np.ndarray, w: np.ndarray, inv: np.ndarray, light: np.ndarray) -> tuple:
        """Camera rays at window coordinates ``(u, w)``: hit and the cosines to light and view.

        Parameters
        ----------
        cam : Camera
            The camera whose rays are traced (position and window).
        u, w : numpy.ndarray
            Window coordinates.
        inv : numpy.ndarray
            1/|ray| of each window point.
        light : numpy.ndarray, shape (3,)
            Unit direction to the light.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, cos_l, cos_v)``.
        """
        ...

    def points(self) -> np.ndarray:
        """Points on the shape, to frame the camera.

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            Points on the surface, scene units (the object fits the unit sphere).
        """
        ...


class Sphere:
    """A unit sphere at the origin."""

    name = "sphere"

    def intersect(self, o, dx, dy, dz):
        """First hits and unit normals of rays from ``o`` (:meth:`Shape.intersect`).

        Parameters
        ----------
        o, dx, dy, dz
            As :meth:`Shape.intersect`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, nx, ny, nz)``.
        """
        t32 = dx.dtype.type
        ox, oy, oz = (t32(v) for v in o)
        b = dx * ox + dy * oy + dz * oz
        disc = b * b - t32(float(o @ o) - 1.0)
        hit = disc >= 0
        t = -b - np.sqrt(np.maximum(disc, t32(0)))
        return hit, ox + t * dx, oy + t * dy, oz + t * dz

    def trace(self, cam: Camera, u, w, inv, light):
        """Camera rays at window coordinates: hit and the cosines to light and view (:meth:`Shape.trace`).

        Parameters
        ----------
        cam, u, w, inv, light
            As :meth:`Shape.trace`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, cos_l, cos_v)``.
        """
        t32 = inv.dtype.type
        o = cam.position
        b = cam.dot(u, w, inv, o)
        disc = b * b - t32(float(o @ o) - 1.0)
        hit = disc >= 0
        cos_v = np.sqrt(np.maximum(disc, t32(0)))
        t = -b - cos_v
        cos_l = t * cam.dot(u, w, inv, light) + t32(float(o @ light))
        return hit, cos_l, cos_v

    def points(self) -> np.ndarray:
        """Points on the shape, to frame the camera.

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            Points on the surface, scene units (the object fits the unit sphere).
        """
        th, ph = np.meshgrid(np.linspace(0, np.pi, 65), np.linspace(0, 2 * np.pi, 129), indexing="ij")
        return np.stack([np.sin(th) * np.cos(ph), np.cos(th), np.sin(th) * np.sin(ph)], -1).reshape(-1, 3)


class HalfCylinder:
    """A sheet bent into a half cylinder: radius 1 about the y axis, |y| ≤ ``half_height``, the half z ≥ 0.

    Both faces are the same anodised metal (the outer, convex face is the one mostly seen; near the
    top corners the inner face shows through the opening).

    Parameters
    ----------
    half_height : float
        Half the cylinder's length along y, in units of its radius.
    """

    name = "cylinder"

    def __init__(self, half_height: float = 1.1):
        self.h = float(half_height)

    def intersect(self, o, dx, dy, dz):
        """First hits and unit normals of rays from ``o`` (:meth:`Shape.intersect`).

        Parameters
        ----------
        o, dx, dy, dz
            As :meth:`Shape.intersect`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, nx, ny, nz)``.
        """
        t32 = dx.dtype.type
        ox, oy, oz = (t32(v) for v in o)
        h = t32(self.h)
        a = dx * dx + dz * dz
        b = dx * ox + dz * oz
        c = t32(float(o[0] ** 2 + o[2] ** 2) - 1.0)
        disc = b * b - a * c
        ok = disc >= 0
        sq = np.sqrt(np.maximum(disc, t32(0)))
        ia = t32(1.0) / np.maximum(a, t32(1e-12))
        t1 = (-b - sq) * ia
        y1 = oy + t1 * dy
        z1 = oz + t1 * dz
        hit = ok & (np.abs(y1) <= h) & (z1 >= 0)
        nx = ox + t1 * dx
        nz = z1
        # Rays passing the near face above/below the sheet may meet the inner face (far root).
        rest = np.flatnonzero(ok & ~hit)
        if rest.size:
            dxr, dyr, dzr = dx.reshape(-1)[rest], dy.reshape(-1)[rest], dz.reshape(-1)[rest]
            t2 = (-b.reshape(-1)[rest] + sq.reshape(-1)[rest]) * ia.reshape(-1)[rest]
            y2 = oy + t2 * dyr
            z2 = oz + t2 * dzr
            inner = (np.abs(y2) <= h) & (z2 >= 0) & (t2 > 0)
            idx = rest[inner]
            hit.reshape(-1)[idx] = True
            nx.reshape(-1)[idx] = -(ox + t2[inner] * dxr[inner])
            nz.reshape(-1)[idx] = -z2[inner]
        return hit, nx, t32(0.0), nz

    def trace(self, cam: Camera, u, w, inv, light):
        """Camera rays at window coordinates: hit and the cosines to light and view (:meth:`Shape.trace`).

        Parameters
        ----------
        cam, u, w, inv, light
            As :meth:`Shape.trace`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, cos_l, cos_v)``.
        """
        t32 = inv.dtype.type
        o = cam.position
        h = t32(self.h)
        ey, ez = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
        dy = cam.dot(u, w, inv, ey)
        dz = cam.dot(u, w, inv, ez)
        a = np.maximum(t32(1.0) - dy * dy, t32(1e-12))  # dx² + dz² for a unit d
        b = cam.dot(u, w, inv, np.array([o[0], 0.0, o[2]]))
        disc = b * b - a * t32(float(o[0] ** 2 + o[2] ** 2) - 1.0)
        ok = disc >= 0
        sq = np.sqrt(np.maximum(disc, t32(0)))
        ia = t32(1.0) / a
        t1 = (-b - sq) * ia
        hit = ok & (np.abs(t1 * dy + t32(o[1])) <= h) & (t1 * dz + t32(o[2]) >= 0)
        lxz = np.array([light[0], 0.0, light[2]])
        dl = cam.dot(u, w, inv, lxz)
        l0 = t32(float(o @ lxz))
        cos_l = t1 * dl + l0
        cos_v = sq
        rest = np.flatnonzero(ok & ~hit)
        if rest.size:
            t2 = (-b.reshape(-1)[rest] + sq.reshape(-1)[rest]) * ia.reshape(-1)[rest]
            dyr, dzr = dy.reshape(-1)[rest], dz.reshape(-1)[rest]
            inner = (np.abs(t2 * dyr + t32(o[1])) <= h) & (t2 * dzr + t32(o[2]) >= 0) & (t2 > 0)
            idx = rest[inner]
            hit.reshape(-1)[idx] = True
            cos_l.reshape(-1)[idx] = -(t2[inner] * dl.reshape(-1)[idx] + l0)
        return hit, cos_l, cos_v

    def points(self) -> np.ndarray:
        """Points on the shape, to frame the camera.

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            Points on the surface, scene units (the object fits the unit sphere).
        """
        ph, y = np.meshgrid(np.linspace(-np.pi / 2, np.pi / 2, 65), np.linspace(-self.h, self.h, 33), indexing="ij")
        return np.stack([np.sin(ph), y, np.cos(ph)], -1).reshape(-1, 3)


class Plate:
    """A flat square plate |x|, |z| ≤ ``half`` in the plane y = 0 (normal +y).

    Parameters
    ----------
    half : float
        Half the plate's side, scene units.
    """

    name = "flat"

    def __init__(self, half: float = 1.0):
        self.a = float(half)

    def intersect(self, o, dx, dy, dz):
        """First hits and unit normals of rays from ``o`` (:meth:`Shape.intersect`).

        Parameters
        ----------
        o, dx, dy, dz
            As :meth:`Shape.intersect`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, nx, ny, nz)``.
        """
        t32 = dx.dtype.type
        ox, oy, oz = (t32(v) for v in o)
        a = t32(self.a)
        t = -oy / np.minimum(dy, t32(-1e-30))
        hit = (dy < 0) & (np.abs(ox + t * dx) <= a) & (np.abs(oz + t * dz) <= a)
        return hit, t32(0.0), t32(1.0), t32(0.0)

    def trace(self, cam: Camera, u, w, inv, light):
        """Camera rays at window coordinates: hit and the cosines to light and view (:meth:`Shape.trace`).

        Parameters
        ----------
        cam, u, w, inv, light
            As :meth:`Shape.trace`.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, cos_l, cos_v)``.
        """
        t32 = inv.dtype.type
        o = cam.position
        a = t32(self.a)
        dy = cam.dot(u, w, inv, np.array([0.0, 1.0, 0.0]))
        t = t32(-o[1]) / np.minimum(dy, t32(-1e-30))
        hit = (dy < 0) & (np.abs(t * cam.dot(u, w, inv, np.array([1.0, 0.0, 0.0])) + t32(o[0])) <= a) \
            & (np.abs(t * cam.dot(u, w, inv, np.array([0.0, 0.0, 1.0])) + t32(o[2])) <= a)
        cos_v = -dy
        cos_l = np.full_like(cos_v, t32(light[1]))
        return hit, cos_l, cos_v

    def points(self) -> np.ndarray:
        """Points on the shape, to frame the camera.

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            Points on the surface, scene units (the object fits the unit sphere).
        """
        a = self.a
        return np.array([[-a, 0, -a], [a, 0, -a], [a, 0, a], [-a, 0, a]], dtype=np.float64)


@dataclass(frozen=True)
class Scene:
    """What a render shows and how.

    Attributes
    ----------
    shape : Shape
        The object rendered (sphere, half cylinder, plate or mesh).
    camera : Camera
        The camera looking at it.
    light : numpy.ndarray, shape (3,)
        Unit vector towards the point light.
    description, camera_description : str
        Object, light and camera (the point-light render's geometry); object and camera only.
    """
    shape: Shape
    camera: Camera
    light: np.ndarray  # unit vector towards the light
    description: str  # object, point light and camera (the point-light render's geometry)
    camera_description: str  # object and camera only (environment lighting has no point light)


#: Default camera polar angle from the plate's normal (world +y), per shape (degrees).
DEFAULT_VIEW_DEG = {"flat": 36.0, "cylinder": 70.0, "sphere": 70.0}


def _camera_position(dist: float, view_deg: float, view_azimuth_deg: float):
    """Camera position at ``dist`` from the origin, ``view_deg`` from +y, azimuth from +z towards
    +x; and the world-up vector for look-at (along the normal the image's up points away from
    the azimuth's side)."""
    t, p = math.radians(view_deg), math.radians(view_azimuth_deg)
    pos = dist * np.array([math.sin(t) * math.sin(p), math.cos(t), math.sin(t) * math.cos(p)])
    up = (0.0, 1.0, 0.0) if math.sin(t) > 1e-6 else (-math.sin(p), 0.0, -math.cos(p))
    return pos, up


def make_scene(shape: str, light_deg: float, view_deg: float | None = None, view_azimuth_deg: float = 0.0,
               mesh=None) -> Scene:
    """The camera, light and object of a swatch render (see the module documentation).

    Parameters
    ----------
    shape : str
        One of :data:`swatch.core.choices.SHAPES` (ignored with ``mesh``).
    light_deg : float
        The light's polar angle, degrees.
    view_deg : float, optional
        The camera's polar angle to the plate's normal (world +y), degrees; default :data:`DEFAULT_VIEW_DEG`.
    view_azimuth_deg : float
        Turns the camera about the normal (0 = the +z side), degrees; the light stays put.
    mesh : swatch.render.mesh.MeshShape, optional
        Shown instead of ``shape``, placed, lit and seen like the sphere.

    Returns
    -------
    Scene
        Camera (framing the object), shape and the point light's direction.

    Raises
    ------
    swatch.core.errors.SwatchError
        An unknown shape or an angle outside [0, 90).
    """
    shape = "sphere" if mesh is not None else check_shape(shape)
    light_deg = float(geometry.check_polar_deg(light_deg, "light_deg"))
    view = DEFAULT_VIEW_DEG[shape] if view_deg is None else float(geometry.check_polar_deg(view_deg, "view_deg"))
    azim = float(geometry.check_azimuth_deg(view_azimuth_deg, "view_azimuth_deg"))
    t = math.radians(light_deg)
    obj: Shape
    if shape == "flat":
        obj = Plate(1.0)
        pos, up = _camera_position(3.2, view, azim)
        cam = Camera.look_at(pos, world_up=up)
        light = np.array([0.0, math.cos(t), -math.sin(t)])
        what = "flat 2x2 plate, normal +y"
        cam_text = f"perspective camera {view:g} deg from the normal (azimuth {azim:g} deg) at 3.2 plate half-widths"
        desc = f"{what}; light {light_deg:g} deg from the normal on the far side; {cam_text}"
    else:
        if mesh is not None:
            obj, dist = mesh, 4.0
            what = f"mesh {mesh.file_name} ({mesh.triangles} triangles, scaled into the unit sphere, +y up)"
        elif shape == "cylinder":
            obj, dist, what = HalfCylinder(1.1), 5.5, "half cylinder (sheet bent to radius 1, height 2.2, vertical axis)"
        else:
            obj, dist, what = Sphere(), 4.0, "unit sphere"
        el = math.radians(20.0)
        ref = Camera.look_at(dist * np.array([0.0, math.sin(el), math.cos(el)]))
        c_hat = -ref.forward
        w = unit(-ref.right * math.cos(math.radians(30.0)) + ref.up * math.sin(math.radians(30.0)))
        light = math.cos(t) * c_hat + math.sin(t) * w
        pos, up = _camera_position(dist, view, azim)
        cam = Camera.look_at(pos, world_up=up)
        cam_text = f"perspective camera {view:g} deg from the vertical (azimuth {azim:g} deg) at {dist:g} radii"
        desc = (f"{what}; {cam_text}; light {light_deg:g} deg from the default camera direction (20 deg above the "
                f"horizon), from the left and 30 deg up")
    cam = cam.fitted(obj.points())
    return Scene(obj, cam, unit(light), desc, f"{what}; {cam_text}")


def scene_geometry(scene: Scene, size_px: int, dtype=np.float64):
    """Per-pixel (centre) normal, view, light and hit of a scene (tests, the benchmark's direct path).

    Parameters
    ----------
    scene : Scene
        The object, camera and light.
    size_px : int
        Image side, pixels (H = W = ``size_px``).
    dtype : numpy dtype
        Precision of the rays and results.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Normal (H, W, 3), light (3,), view (H, W, 3), hit (H, W).
    """
    size = int(size_px)
    c = np.arange(size, dtype=dtype) + dtype(0.5)
    dx, dy, dz = scene.camera.directions(c[None, :], c[:, None], size, dtype=dtype)
    hit, nx, ny, nz = scene.shape.intersect(scene.camera.position, dx, dy, dz)
    n = np.stack([np.broadcast_to(c, hit.shape) for c in (nx, ny, nz)], -1)
    v = -np.stack([dx, dy, dz], -1)
    return n, scene.light.astype(dtype), v, hit
