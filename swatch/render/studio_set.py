"""The path tracer's photo studio as geometry: a cyclorama and three soft boxes (the heroes' studio).

The Mitsuba engine builds its ``studio`` lighting from these numbers (:func:`swatch.render.mitsuba.scene.lighting`),
and the catalog page's live view draws the same set around the part (backdrop, floor, horizon and the soft boxes'
reflections: :mod:`swatch.catalog.explorer_env`), so that turning the part keeps the look of the path-traced
picture. World frame of a swatch render: **y up**, the camera on the +z side, the object at the origin standing on
the floor at ``floor_y`` (just under it).

* The **cyclorama**: a diffuse grey (albedo :data:`CYCLORAMA_ALBEDO`) floor from ``z = +8`` back to the cove, a
  quarter-circle cove of radius :data:`COVE_RADIUS` sweeping up into a back wall at ``z = -5``, 20 units wide.
  Its points are named by ``(x, s)``: ``x`` across, ``s`` the arc length along the profile from the floor's front
  edge (:func:`profile_point`).
* The **soft boxes** (:data:`SOFT_BOXES`): rectangles emitting towards the object (one-sided, neutral D65): an
  overhead key, a tall strip on the camera's left and a weaker one on the right.
* A dim **fill**: radiance :data:`FILL_RADIANCE` from every direction nothing else covers.

The cyclorama's radiance (lit by the boxes and the fill, with the object's shadow and every bounce) is what the
path tracer computes; :func:`swatch.render.dispatch.studio_lightmap` bakes it onto the ``(x, s)`` grid of
:func:`lightmap_axes`, which is dense near the object and coarse far away.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CYCLORAMA_ALBEDO", "COVE_RADIUS", "WALL_Z", "FRONT_Z", "HALF_WIDTH", "WALL_HEIGHT", "FILL_RADIANCE",
           "SoftBox", "SOFT_BOXES", "profile_length", "profile_point", "cyclorama_hit", "box_frames",
           "LIGHTMAP_WARP", "lightmap_axes", "set_radiance"]

#: Diffuse albedo of the cyclorama (grey).
CYCLORAMA_ALBEDO = 0.45
#: Radius of the cove between the floor and the back wall, scene units (the object's radius is 1).
COVE_RADIUS = 2.0
#: The back wall's plane, ``z`` (scene units).
WALL_Z = -5.0
#: The floor's front edge (towards and behind the camera), ``z``.
FRONT_Z = 8.0
#: Half the cyclorama's width, ``|x|`` at most.
HALF_WIDTH = 10.0
#: The back wall's top above the floor.
WALL_HEIGHT = 10.0
#: Radiance of the dim fill from every direction the set does not cover (relative to a box's, D65).
FILL_RADIANCE = 0.05


@dataclass(frozen=True)
class SoftBox:
    """A rectangular soft box: an area light facing ``target`` from ``centre``.

    Parameters
    ----------
    name : str
        Its id in the scene.
    centre, target : tuple of float
        The box's centre and the point it faces (world, scene units).
    size : tuple of float
        Its width and height, scene units (width along the box's horizontal axis).
    radiance : float
        Emitted radiance (D65, relative to the fill's units).
    """

    name: str
    centre: tuple[float, float, float]
    target: tuple[float, float, float]
    size: tuple[float, float]
    radiance: float

    def up(self) -> tuple[float, float, float]:
        """The up vector of the box's frame (as Mitsuba's ``look_at``): world y unless it looks nearly straight down.

        Returns
        -------
        tuple of float
            A unit vector, world frame.
        """
        return (0.0, 1.0, 0.0) if abs(self.centre[1] - self.target[1]) < 0.9 * math.dist(self.centre, self.target) \
            else (0.0, 0.0, -1.0)


#: The studio's soft boxes: the overhead key, the tall strip on the camera's left, the weaker one on the right.
SOFT_BOXES = (
    SoftBox("key", (0.0, 3.2, -0.4), (0.0, 0.0, 0.0), (3.0, 2.0), 8.0),
    SoftBox("strip_left", (-3.2, 0.8, 0.6), (0.0, 0.0, 0.0), (0.8, 3.0), 7.0),
    SoftBox("strip_right", (3.2, 0.8, -0.8), (0.0, 0.0, 0.0), (0.8, 3.0), 3.5),
)


def box_frames() -> np.ndarray:
    """Each soft box's frame as Mitsuba's ``look_at`` builds it: centre, half-size axes and facing normal.

    Returns
    -------
    numpy.ndarray, shape (len(SOFT_BOXES), 4, 3)
        Per box: its centre, the half-width axis (``left`` of ``look_at`` × width / 2), the half-height axis
        (its up × height / 2) and the unit normal it emits along (towards the target), world frame.
    """
    out = np.zeros((len(SOFT_BOXES), 4, 3))
    for i, b in enumerate(SOFT_BOXES):
        c, t, up = np.asarray(b.centre), np.asarray(b.target), np.asarray(b.up())
        d = (t - c) / np.linalg.norm(t - c)
        left = np.cross(up, d)
        left /= np.linalg.norm(left)
        new_up = np.cross(d, left)
        out[i] = (c, left * b.size[0] / 2, new_up * b.size[1] / 2, d)
    return out


def profile_length() -> float:
    """The cyclorama profile's whole arc length: floor, cove and wall, scene units.

    Returns
    -------
    float
        ``s`` at the wall's top.
    """
    return (FRONT_Z - (WALL_Z + COVE_RADIUS)) + 0.5 * math.pi * COVE_RADIUS + (WALL_HEIGHT - COVE_RADIUS)


def profile_point(s, floor_y: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The cyclorama's profile at arc length ``s``: position and (inward) normal in the y–z plane.

    Parameters
    ----------
    s : array_like
        Arc length from the floor's front edge (``z = FRONT_Z``), scene units, 0 to :func:`profile_length`.
    floor_y : float
        The floor's height.

    Returns
    -------
    y, z, ny, nz : numpy.ndarray
        The point's height and depth and its unit normal (towards the set's inside), shaped like ``s``.
    """
    s = np.asarray(s, dtype=np.float64)
    floor_len = FRONT_Z - (WALL_Z + COVE_RADIUS)
    cove_len = 0.5 * math.pi * COVE_RADIUS
    th = np.clip((s - floor_len) / COVE_RADIUS, 0.0, 0.5 * math.pi)
    y = np.where(s <= floor_len, floor_y,
                 np.where(s <= floor_len + cove_len, floor_y + COVE_RADIUS * (1.0 - np.cos(th)),
                          floor_y + COVE_RADIUS + (s - floor_len - cove_len)))
    z = np.where(s <= floor_len, FRONT_Z - s,
                 np.where(s <= floor_len + cove_len, WALL_Z + COVE_RADIUS * (1.0 - np.sin(th)), WALL_Z))
    ny = np.where(s <= floor_len, 1.0, np.where(s <= floor_len + cove_len, np.cos(th), 0.0))
    nz = np.where(s <= floor_len, 0.0, np.where(s <= floor_len + cove_len, np.sin(th), 1.0))
    return y, z, ny, nz


def cyclorama_hit(origin, direction, floor_y: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where rays first meet the cyclorama from inside the set.

    Parameters
    ----------
    origin : array_like, shape (3,) or (..., 3)
        Ray origins (world, inside the set).
    direction : array_like, shape (..., 3)
        Unit ray directions.
    floor_y : float
        The floor's height.

    Returns
    -------
    t, x, s : numpy.ndarray
        The distance to the hit (``inf`` where the ray leaves the set), its ``x`` and its arc length ``s``
        along the profile (:func:`profile_point`), shaped like the rays.
    """
    o = np.broadcast_to(np.asarray(origin, dtype=np.float64), np.shape(direction))
    d = np.asarray(direction, dtype=np.float64)
    ox, oy, oz = o[..., 0], o[..., 1], o[..., 2]
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    r, zc, yc = COVE_RADIUS, WALL_Z + COVE_RADIUS, floor_y + COVE_RADIUS
    floor_len = FRONT_Z - zc
    cove_len = 0.5 * math.pi * r
    inf = np.full(dx.shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        tf = np.where(dy < 0, (floor_y - oy) / dy, np.inf)
        zf = oz + tf * dz
        tf = np.where((tf > 0) & (zf >= zc) & (zf <= FRONT_Z) & (np.abs(ox + tf * dx) <= HALF_WIDTH), tf, np.inf)
        tw = np.where(dz < 0, (WALL_Z - oz) / dz, np.inf)
        yw = oy + tw * dy
        tw = np.where((tw > 0) & (yw >= yc) & (yw <= floor_y + WALL_HEIGHT) & (np.abs(ox + tw * dx) <= HALF_WIDTH),
                      tw, np.inf)
        # the cove: the far root of the circle (y - yc)² + (z - zc)² = r² in the y-z plane (seen from inside)
        a = dy * dy + dz * dz
        b = (oy - yc) * dy + (oz - zc) * dz
        c = (oy - yc) ** 2 + (oz - zc) ** 2 - r * r
        disc = b * b - a * c
        tc = np.where((disc >= 0) & (a > 1e-12), (-b + np.sqrt(np.maximum(disc, 0.0))) / a, np.inf)
        yq, zq = oy + tc * dy, oz + tc * dz
        tc = np.where((tc > 0) & (yq <= yc) & (zq <= zc) & (np.abs(ox + tc * dx) <= HALF_WIDTH), tc, np.inf)
    t = np.minimum(np.minimum(tf, tw), tc)
    x = np.where(np.isfinite(t), ox + np.where(np.isfinite(t), t, 0.0) * dx, 0.0)
    th = np.arctan2(zc - (oz + np.where(np.isfinite(tc), tc, 0.0) * dz), yc - (oy + np.where(np.isfinite(tc), tc, 0.0) * dy))
    s = np.where(t == tf, FRONT_Z - (oz + np.where(np.isfinite(tf), tf, 0.0) * dz),
                 np.where(t == tc, floor_len + r * np.clip(th, 0.0, 0.5 * math.pi),
                          floor_len + cove_len + (oy + np.where(np.isfinite(tw), tw, 0.0) * dy) - yc))
    return np.where(np.isfinite(t), t, inf), x, np.where(np.isfinite(t), s, 0.0)


#: The lightmap's warp ``k`` (:func:`lightmap_axes`): texels ~``sinh(k)/k`` times denser at the object than at the
#: cyclorama's ends.
LIGHTMAP_WARP = 3.0


def lightmap_axes(nx: int, ns: int) -> tuple[np.ndarray, np.ndarray]:
    """The lightmap's texel centres: ``x`` and ``s`` on a sinh warp centred on the object.

    A texel coordinate ``u`` in [0, 1] maps to ``x = W sinh(k (2u − 1)) / sinh(k)`` (``W`` = :data:`HALF_WIDTH`,
    ``k`` = :data:`LIGHTMAP_WARP`); ``s`` likewise about ``s0`` = the floor under the object (``z = 0``),
    ``s = s0 + A sinh(k (2v − 1)) / sinh(k)`` with ``A = s0`` in front of it and the rest of the profile behind, so
    that ``v`` spans the whole profile. The page inverts the same maps (``asinh``).

    Parameters
    ----------
    nx, ns : int
        Texels across and along the profile.

    Returns
    -------
    x, s : numpy.ndarray
        Shapes (nx,) and (ns,), scene units.
    """
    k = LIGHTMAP_WARP
    u = (np.arange(nx) + 0.5) / nx
    v = (np.arange(ns) + 0.5) / ns
    s0 = FRONT_Z
    w = np.sinh(k * (2 * v - 1)) / math.sinh(k)
    return (HALF_WIDTH * np.sinh(k * (2 * u - 1)) / math.sinh(k),
            s0 + np.where(w < 0, s0, profile_length() - s0) * w)


def _lightmap_lookup(lightmap: np.ndarray, x: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Bilinear lookup of a lightmap (ns, nx) at world ``x`` and arc length ``s`` (the page's lookup)."""
    ns, nx = lightmap.shape
    k = LIGHTMAP_WARP
    s0 = FRONT_Z
    span = np.where(s < s0, s0, profile_length() - s0)
    u = (np.arcsinh(np.clip(x / HALF_WIDTH, -1, 1) * math.sinh(k)) / k + 1) / 2 * nx - 0.5
    v = (np.arcsinh(np.clip((s - s0) / span, -1, 1) * math.sinh(k)) / k + 1) / 2 * ns - 0.5
    u = np.clip(u, 0, nx - 1)
    v = np.clip(v, 0, ns - 1)
    i0, j0 = np.minimum(np.floor(v).astype(int), ns - 2), np.minimum(np.floor(u).astype(int), nx - 2)
    fv, fu = v - i0, u - j0
    a = lightmap[i0, j0] * (1 - fu) + lightmap[i0, j0 + 1] * fu
    b = lightmap[i0 + 1, j0] * (1 - fu) + lightmap[i0 + 1, j0 + 1] * fu
    return a * (1 - fv) + b * fv


def set_radiance(directions, floor_y: float, lightmap: np.ndarray, scale: float, boxes: bool = True) -> np.ndarray:
    """Radiance arriving at the object's centre (the origin) from ``directions``: a soft box, else the
    cyclorama (its baked radiance), else the fill.

    Parameters
    ----------
    directions : array_like, shape (..., 3)
        Unit directions, world frame (y up).
    floor_y : float
        The floor's height.
    lightmap : numpy.ndarray, shape (ns, nx)
        The cyclorama's radiance on the grid of :func:`lightmap_axes` (already multiplied by ``scale``).
    scale : float
        The render's radiance scale (a white diffuser facing up at the object, lit directly, reflects 1):
        multiplies the boxes' and the fill's radiance.
    boxes : bool, optional
        False: the set without its soft boxes (what is behind them instead; the page draws the boxes itself).

    Returns
    -------
    numpy.ndarray
        Radiance (grey), shaped like ``directions`` without its last axis.
    """
    d = np.asarray(directions, dtype=np.float64)
    t, x, s = cyclorama_hit(np.zeros(3), d, floor_y)
    L = np.where(np.isfinite(t), _lightmap_lookup(lightmap, x, s), FILL_RADIANCE * scale)
    best = t
    for frame, box in zip(box_frames() if boxes else (), SOFT_BOXES if boxes else (), strict=True):
        c, hu, hv, n = frame
        denom = d @ n
        with np.errstate(divide="ignore", invalid="ignore"):
            tb = (c @ n) / denom
        p = d * tb[..., None] - c
        a = (p @ hu) / (hu @ hu)
        b = (p @ hv) / (hv @ hv)
        hit = (denom < 0) & (tb > 0) & (np.abs(a) <= 1) & (np.abs(b) <= 1) & (tb < best)
        L = np.where(hit, box.radiance * scale, L)
        best = np.where(hit, tb, best)
    return L
