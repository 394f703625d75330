"""A designer's object as a swatch shape: a triangle mesh (OBJ, PLY, STL, glTF binary) ray-cast
with the same shading as the built-in shapes.

Functions
---------
* :func:`load_mesh`: read a mesh file (untrusted input: size-capped, its bytes checked by
  :func:`swatch.render.mesh_checks.check_mesh_bytes` before trimesh reads them, parsed from memory so the
  file cannot make the reader open anything else), check it, and place it: the bounding box's
  centre at the origin, scaled so the farthest vertex is at distance 1 (the unit sphere's frame),
  +y up as written (the glTF convention; most OBJ and PLY exports agree). A mesh smaller than
  :data:`_SMALL_SIZE` is scaled up by a power of two first (exact), so any size down to
  :data:`swatch.core.limits.MIN_MESH_EXTENT` renders alike.
* :class:`MeshShape`: the :class:`swatch.render.scene.Shape` protocol for a mesh: ``intersect`` (hit and
  the shading normal per ray) and ``trace`` (hit, ``cos θ_l``, ``cos θ_v``, with the point light
  shadowed by the object itself), ray-cast by Embree through trimesh; ``surface`` and ``blocked``
  (the directions the object hides from its own points: the environment renderer's self-occlusion).

Shading normals: the vertex normals (from the file where it has them, otherwise trimesh's
area-weighted ones over the triangles sharing a position: vertices at one position are merged
unless their normals or texture coordinates differ) interpolated barycentrically, except where a vertex normal is more than
:data:`SMOOTH_ANGLE_DEG` from its face's normal (a crease), where the face normal is used (the
"auto smooth" rule of 3-D tools). Both faces of every triangle are the same anodised metal: the
normal is turned towards the viewer (as the bent sheet's inner face).

References
----------
* Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), 2014
  (through the ``embreex`` binding and ``trimesh.ray.ray_pyembree``).
* trimesh (https://trimesh.org): file readers, ``triangles.points_to_barycentric``.
"""
from __future__ import annotations

import hashlib
import io
import math
import warnings
from pathlib import Path

import numpy as np

from swatch.core.choices import MESH_FORMATS
from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_MESH_BYTES,
    MAX_MESH_COORDINATE,
    MAX_MESH_TRIANGLES,
    MAX_MESH_VERTICES,
    MIN_MESH_EXTENT,
    read_capped,
)
from swatch.core.procguard import signals_held
from swatch.render.mesh_checks import check_mesh_bytes

# trimesh catches BaseException around its own imports (scipy, PIL, rtree, whose finder prints "rtree.finder ...
# unexpected error"): a Ctrl-C there was printed and lost. Held over the import, it is raised once trimesh is in.
with signals_held():
    import trimesh
    from trimesh.ray.ray_pyembree import RayMeshIntersector
    from trimesh.triangles import points_to_barycentric

__all__ = ["MESH_FORMATS", "SMOOTH_ANGLE_DEG", "MeshShape", "load_mesh"]

#: Vertex normals further than this from their face's normal are creases (face normal used), degrees.
SMOOTH_ANGLE_DEG = 30.0
#: Shadow-ray origins are lifted off the surface by this distance (the mesh is scaled to unit radius).
_SHADOW_OFFSET = 1e-4
#: A mesh smaller than this (its bounding box's largest side, the file's units) is scaled up by a power of two
#: before its vertices are merged and its normals computed (larger ones as read: a part in metres is 1 mm or more).
_SMALL_SIZE = 2.0 ** -10


def load_mesh(path) -> MeshShape:
    """Read and place a mesh file (see the module documentation).

    Parameters
    ----------
    path : str or pathlib.Path
        An ``.obj``, ``.ply``, ``.stl``, ``.glb`` or ``.gltf`` (embedded buffers) file, at most
        :data:`swatch.core.limits.MAX_MESH_BYTES` bytes, :data:`swatch.core.limits.MAX_MESH_TRIANGLES`
        triangles and :data:`swatch.core.limits.MAX_MESH_VERTICES` vertices (a glTF's as its nodes place
        them), at least :data:`swatch.core.limits.MIN_MESH_EXTENT` across.

    Returns
    -------
    MeshShape
        Placed in the unit sphere (bounding-box centre at the origin, farthest vertex at 1).
    """
    p = Path(path)
    fmt = p.suffix.lower().lstrip(".")
    if fmt not in MESH_FORMATS:
        raise SwatchError(f"{p.name}: unknown mesh format {p.suffix or '(none)'!r}; use one of "
                          f"{', '.join('.' + f for f in MESH_FORMATS)}")
    if not p.is_file():
        raise SwatchError(f"mesh {p} is not a file")
    data = check_mesh_bytes(read_capped(p, MAX_MESH_BYTES, "mesh file"), fmt, p.name)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):  # the error below says it in one line
            warnings.simplefilter("ignore")
            mesh = trimesh.load(io.BytesIO(data), file_type=fmt, force="mesh", process=False)
    except Exception as exc:  # the readers raise many kinds; any of them means an unreadable file
        raise SwatchError(f"{p.name}: cannot read the {fmt.upper()} mesh ({type(exc).__name__}: "
                          f"{str(exc).splitlines()[0][:120] if str(exc) else 'no detail'})") from None
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))))
    vertices = np.asarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=np.float64)
    if faces.ndim != 2 or faces.shape[0] == 0 or not isinstance(mesh, trimesh.Trimesh):
        raise SwatchError(f"{p.name}: the file has no triangles; a mesh needs at least one")
    if faces.shape[0] > MAX_MESH_TRIANGLES or vertices.shape[0] > MAX_MESH_VERTICES:
        raise SwatchError(f"{p.name}: {faces.shape[0]} triangles and {vertices.shape[0]} vertices; a mesh may have "
                          f"at most {MAX_MESH_TRIANGLES} triangles and {MAX_MESH_VERTICES} vertices")
    if not np.isfinite(vertices).all():
        raise SwatchError(f"{p.name}: vertex coordinates must be finite numbers (found NaN or infinity)")
    if vertices.size and np.abs(vertices).max() > MAX_MESH_COORDINATE:
        raise SwatchError(f"{p.name}: a vertex coordinate is {np.abs(vertices).max():.3g} in magnitude; "
                          f"coordinates may be at most {MAX_MESH_COORDINATE:.0e} (scale the mesh down)")
    if faces.min() < 0 or faces.max() >= vertices.shape[0]:
        raise SwatchError(f"{p.name}: a triangle refers to a vertex that does not exist")
    _place_small(mesh, vertices, p.name)
    # vertices at one position are merged unless their normals or texture coordinates differ (an
    # STL stores every triangle's corners apart: merged, its normals can be smoothed); trimesh compares
    # coordinates rounded to 10^-digits in int64: 8 digits overflowed beyond ~1e11 (a triangle at
    # ±1e11…1e15, within MAX_MESH_COORDINATE, collapsed to one point), so fewer digits for large ones
    largest = float(np.abs(mesh.vertices).max())
    digits = min(8, int(np.floor(np.log10(2.0 ** 62 / largest)))) if largest > 0 else 8
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        mesh.merge_vertices(digits_vertex=digits)
    return MeshShape(mesh, p.name, hashlib.sha256(data).hexdigest())


def _place_small(mesh, vertices: np.ndarray, file_name: str) -> None:
    """Refuse a mesh with no size or smaller than MIN_MESH_EXTENT; scale one smaller than
    :data:`_SMALL_SIZE` up by a power of two (exact: no coordinate's digits change) to a size in [0.5, 1), in
    place, so that trimesh's vertex merge (to 10^-8) and its normals (zero for a triangle under
    ~1e-13 in area) see it as a mesh of unit size: a part drawn in kilometres renders as in millimetres."""
    size = float((vertices.max(axis=0) - vertices.min(axis=0)).max())  # (no squares: they underflow)
    if size == 0:
        raise SwatchError(f"{file_name}: all vertices are at one point; a mesh needs an extent")
    if size < MIN_MESH_EXTENT:
        raise SwatchError(f"{file_name}: the mesh is {size:.3g} across (its bounding box's largest side); a mesh "
                          f"is at least {MIN_MESH_EXTENT:.0e} across in the file's units (scale the mesh up)")
    if size < _SMALL_SIZE:
        mesh.apply_scale(2.0 ** -math.frexp(size)[1])


class MeshShape:
    """A placed triangle mesh behind the :class:`swatch.render.scene.Shape` protocol (arrays planar, in the rays' precision).

    Placement: the bounding box's centre at the origin, the farthest vertex at distance 1; shading
    normals are the vertex normals interpolated, the face normal across creases over
    :data:`SMOOTH_ANGLE_DEG`; zero-area triangles are dropped. Rays go through trimesh's Embree
    intersector. ``key`` (``mesh:<sha256>``) identifies it for caches.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The loaded mesh (:func:`load_mesh`).
    file_name : str
        For messages and metadata.
    digest : str
        SHA-256 of the file's bytes.

    Raises
    ------
    swatch.core.errors.SwatchError
        All vertices at one point, or every triangle of zero area.
    """

    name = "mesh"

    def __init__(self, mesh, file_name: str, digest: str):
        v = np.asarray(mesh.vertices, dtype=np.float64)
        lo, hi = v.min(axis=0), v.max(axis=0)
        v = v - 0.5 * (lo + hi)
        radius = float(np.linalg.norm(v, axis=1).max())
        if not radius > 0:
            raise SwatchError(f"{file_name}: all vertices are at one point; a mesh needs an extent")
        normals = np.asarray(mesh.vertex_normals, dtype=np.float64)  # the file's, else area-weighted
        placed = trimesh.Trimesh(vertices=v / radius, faces=np.asarray(mesh.faces), process=False, validate=False)
        area = placed.area_faces
        keep = area > 1e-14 * max(float(area.max()), 1e-300)
        if not keep.any():
            raise SwatchError(f"{file_name}: every triangle has zero area (its corners on one line); a mesh "
                              "needs at least one triangle with an area")
        self._mesh = trimesh.Trimesh(vertices=placed.vertices, faces=placed.faces[keep], process=False,
                                     validate=False)
        fn = self._mesh.face_normals
        vn = normals[self._mesh.faces]  # (F, 3, 3)
        vn = vn / np.maximum(np.linalg.norm(vn, axis=-1, keepdims=True), 1e-300)
        crease = np.einsum("fkc,fc->fk", vn, fn) < np.cos(np.radians(SMOOTH_ANGLE_DEG))
        self._corner_normals = np.where(crease[..., None], fn[:, None, :], vn)
        self._face_normals = fn
        self._rays = RayMeshIntersector(self._mesh)
        self.file_name, self.key = file_name, f"mesh:{digest}"
        self.triangles = int(self._mesh.faces.shape[0])

    def _cast(self, o, d):
        """First hits of rays from ``o`` (3,) along unit ``d`` (N, 3): hit (N,), shading normal
        (N, 3) turned towards the ray's origin, geometric normal (N, 3) likewise, and the point."""

        n_rays = d.shape[0]
        origins = np.broadcast_to(np.asarray(o, dtype=np.float64), (n_rays, 3))
        tri, ray, loc = self._rays.intersects_id(origins, d, multiple_hits=False, return_locations=True)
        hit = np.zeros(n_rays, dtype=bool)
        hit[ray] = True
        shade = np.zeros((n_rays, 3))
        geo = np.zeros((n_rays, 3))
        point = np.zeros((n_rays, 3))
        if ray.size:
            bary = points_to_barycentric(self._mesh.triangles[tri], loc)
            ns = np.einsum("rk,rkc->rc", bary, self._corner_normals[tri])
            ns /= np.maximum(np.linalg.norm(ns, axis=1, keepdims=True), 1e-300)
            ng = self._face_normals[tri]
            side = np.where(np.einsum("rc,rc->r", ng, d[ray]) > 0, -1.0, 1.0)[:, None]  # face the viewer
            ns *= side
            ng = ng * side
            # a shading normal facing away from the viewer (interpolation at a silhouette) is bent
            # back to the visible hemisphere: the geometric normal's side decides what is seen
            back = np.einsum("rc,rc->r", ns, d[ray]) > 0
            ns[back] = ng[back]
            shade[ray], geo[ray], point[ray] = ns, ng, loc
        return hit, shade, geo, point

    def intersect(self, o, dx, dy, dz):
        """First hits of rays and the shading normals there (facing the ray's origin).

        Parameters
        ----------
        o : array_like, shape (3,)
            The rays' origin.
        dx, dy, dz : numpy.ndarray
            Unit directions (broadcast together).

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, nx, ny, nz)``, the broadcast shape.
        """
        bx, by, bz = np.broadcast_arrays(dx, dy, dz)
        shape, t = bx.shape, np.result_type(bx.dtype, np.float32).type
        d = np.stack([bx.reshape(-1), by.reshape(-1), bz.reshape(-1)], -1).astype(np.float64)
        hit, n, _, _ = self._cast(o, d)
        return (hit.reshape(shape), *(n[:, k].astype(t).reshape(shape) for k in range(3)))

    def trace(self, cam, u, w, inv, light):
        """Camera rays at window coordinates: hit and the cosines to light and view, with shadows.

        Parameters
        ----------
        cam : swatch.render.scene.Camera
            The camera whose rays are traced (position and window).
        u, w : numpy.ndarray
            Window coordinates.
        inv : numpy.ndarray
            1/|ray| of each window point.
        light : array_like, shape (3,)
            Unit direction to the point light.

        Returns
        -------
        tuple of numpy.ndarray
            ``(hit, cos_l, cos_v)``; ``cos_l`` is 0 where the object shadows the light.
        """
        bu, bw, binv = np.broadcast_arrays(u, w, inv)
        shape, t = bu.shape, binv.dtype.type
        d = (bu.reshape(-1, 1).astype(np.float64) * cam.right + bw.reshape(-1, 1) * cam.up + cam.forward) \
            * binv.reshape(-1, 1)
        hit, n, geo, point = self._cast(cam.position, d)
        light = np.asarray(light, dtype=np.float64)
        cos_l = n @ light
        cos_v = -np.einsum("rc,rc->r", n, d)
        lit = np.flatnonzero(hit & (cos_l > 0))
        if lit.size:
            start = point[lit] + _SHADOW_OFFSET * geo[lit]
            blocked = self._rays.intersects_any(start, np.broadcast_to(light, start.shape))
            cos_l[lit[blocked]] = 0.0
        return hit.reshape(shape), cos_l.astype(t).reshape(shape), cos_v.astype(t).reshape(shape)

    def surface(self, o, d) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where rays from ``o`` first meet the mesh: the points and the geometric normals there (turned
        towards the ray's origin), for :meth:`blocked`.

        Parameters
        ----------
        o : array_like, shape (3,)
            The rays' origin (the camera).
        d : array_like, shape (N, 3)
            Unit directions.

        Returns
        -------
        (numpy.ndarray, numpy.ndarray, numpy.ndarray)
            Hit (N,) bool, points (N, 3) and unit geometric normals (N, 3), float64 (zeros where missed).
        """
        hit, _, geo, point = self._cast(o, np.asarray(d, dtype=np.float64).reshape(-1, 3))
        return hit, point, geo

    def blocked(self, points, normals, directions) -> np.ndarray:
        """Which directions the mesh itself hides from surface points (rays started just off the surface, along
        its geometric normal; a direction below the surface is hidden).

        Parameters
        ----------
        points, normals : array_like, shape (P, 3)
            Surface points and their geometric normals on the viewer's side (:meth:`surface`).
        directions : array_like, shape (P, K, 3)
            Unit directions from each point.

        Returns
        -------
        numpy.ndarray of bool, shape (P, K)
            True where a ray from the point along the direction meets the mesh.
        """
        dirs = np.asarray(directions, dtype=np.float64)
        p, k = dirs.shape[:2]
        start = np.asarray(points, dtype=np.float64) + _SHADOW_OFFSET * np.asarray(normals, dtype=np.float64)
        origins = np.broadcast_to(start[:, None, :], (p, k, 3)).reshape(-1, 3)
        if origins.shape[0] == 0:
            return np.zeros((p, k), dtype=bool)
        return np.asarray(self._rays.intersects_any(origins, dirs.reshape(-1, 3)), dtype=bool).reshape(p, k)

    def triangle_soup(self) -> tuple[np.ndarray, np.ndarray]:
        """The placed triangles' corners and their shading normals (creases split), for renderers that take a
        mesh of their own (``--engine mitsuba``).

        Returns
        -------
        (numpy.ndarray, numpy.ndarray)
            Corners (F, 3, 3) and normals (F, 3, 3).
        """
        return np.asarray(self._mesh.triangles), self._corner_normals

    def points(self) -> np.ndarray:
        """Vertices (at most about 50 000, evenly strided) to frame the camera.

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            Vertex positions, scene units (placed in the unit sphere).
        """
        v = np.asarray(self._mesh.vertices)
        return v[:: max(1, v.shape[0] // 50_000)]
