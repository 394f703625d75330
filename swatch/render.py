"""Angular colour maps and swatch renders (flat plate, half cylinder, sphere).

Light and colour
----------------
A directional light whose spectrum is the colorimeter's illuminant (D65 by default, as the
paper's CG) lights the swatch; the camera records CIE XYZ, converted to linear RGB. Pixel values
are scene-referred with **1.0 = a perfect white diffuser lit by the same light at normal
incidence**: a pixel is ``XYZ(F(·; d, θ_d)) · s`` (see :mod:`swatch.shading`) with
``s = π D G cos θ_l / (4 cos θ_l cos θ_v)`` for the microfacet model and ``s = 1`` (lit and
seen) for the paper's model.

The chromaticity depends only on ``θ_d`` (the half angle between light and view): with a distant
light and a distant camera it would be one colour over the whole shape. The colour shift across a
curved swatch therefore comes from perspective, as in a close product photograph: the camera
sits a few object sizes away (field of view 30–45°), so the view direction, and with it ``θ_d``,
changes across the swatch.

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

Anti-aliasing: each pixel is shaded at its centre; pixels on or next to a silhouette edge are
re-rendered with 4 × 4 stratified sub-samples (colour averaged, coverage = fraction hit), so
edges are anti-aliased at a cost proportional to the outline, not the area. ``linear_rgb`` is
premultiplied by the coverage ``alpha`` (background 0, as EXR expects); ``display_rgb`` is
composited on a neutral grey (linear 0.18, sRGB 118).

Exposure (display only; the EXR keeps the scene values): for the microfacet model, the mirror
region is far brighter than the rest. The exposure ``k`` is chosen from the geometry alone (so a
series of thicknesses shares it, like photographs taken with one camera setting): over the
off-mirror pixels (``D(h) < D(n)/2``, outside the half maximum of the specular lobe) the 95th
percentile of ``s`` (the value a white, F = 1 reflector would have) maps to 0.8. Hence the
off-mirror colours (F ≤ 1) stay below 0.8 and are shown exactly; above 0.8 a smooth per-channel
shoulder rolls the highlight off to white (``y = 0.8 + 0.2 (1 − exp(−(x − 0.8)/0.2))``), as film
or a camera does. The paper's model has no mirror peak: ``k = 1`` (reflectance shown as is).
"""
from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from swatch import __version__, geometry, microfacet, shading
from swatch.errors import SwatchError

__all__ = [
    "SHAPES",
    "MAX_SIZE_PX",
    "BACKGROUND_LINEAR",
    "SwatchImage",
    "AngularMap",
    "render_swatch",
    "render_scene",
    "angular_map",
    "angular_figure",
    "check_size_px",
    "display_encode",
    "reference_Lab",
    "file_stem",
]

SHAPES = ("flat", "cylinder", "sphere")
MAX_SIZE_PX = 8192
BACKGROUND_LINEAR = 0.18
KNEE = 0.8
SUPERSAMPLE = 4
#: Nodes of a render's cos θ_d table over the range its pixels span (refined 16× for lookups;
#: the range is narrow, so 129 nodes are far denser than the 1025 of the full [0, 1] table).
RENDER_TABLE_NODES = 129
REFERENCE_GEOMETRY = (45.0, 0.0)  # light 45°, view along the normal


# -- validation ----------------------------------------------------------------------------------
def check_size_px(size_px) -> int:
    try:
        ok = float(size_px) == int(size_px)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(size_px) <= MAX_SIZE_PX:
        raise SwatchError(f"image size must be a whole number of pixels from 1 to {MAX_SIZE_PX}, got {size_px!r}")
    return int(size_px)


def check_shape(shape: str) -> str:
    key = str(shape).strip().lower()
    if key not in SHAPES:
        raise SwatchError(f"unknown swatch shape {shape!r}; use one of {', '.join(SHAPES)}")
    return key


def _defaults(coating, colorimeter):
    if coating is None:
        from swatch.model import get_coating

        coating = get_coating()
    if colorimeter is None:
        from swatch.colorimetry import get_colorimeter

        colorimeter = get_colorimeter(coating.wavelength_nm)
    if not np.array_equal(np.asarray(colorimeter.wavelength_nm), np.asarray(coating.wavelength_nm)):
        raise SwatchError("the colorimeter and the coating must use the same wavelength grid")
    return coating, colorimeter


def file_stem(kind: str, thickness_nm: float) -> str:
    """``cylinder_050.8nm``: the kind and the thickness to 0.1 nm, zero-padded to sort."""
    return f"{kind}_{float(thickness_nm):05.1f}nm"


def reference_Lab(thickness_nm: float, coating, colorimeter) -> np.ndarray:
    """CIELAB at the reference geometry 45°:0° (the half-vector reflectance, paper's model)."""
    refl, _ = coating.half_vector(float(thickness_nm), *REFERENCE_GEOMETRY)
    return colorimeter.Lab(colorimeter.XYZ(refl.R))


# -- display encoding ----------------------------------------------------------------------------
_LUT_N = 16384
_LUT_XMAX = 16.0


def _lut() -> np.ndarray:
    if not hasattr(_lut, "table"):
        # Entry j serves indices floor(sqrt(x/16)·(N-1)) = j: its value is taken at the bucket's middle.
        x = ((np.arange(_LUT_N, dtype=np.float64) + 0.5) / (_LUT_N - 1)) ** 2 * _LUT_XMAX
        x[0] = 0.0  # exact black stays black
        y = np.where(x <= KNEE, x, KNEE + (1.0 - KNEE) * (1.0 - np.exp(-(x - KNEE) / (1.0 - KNEE))))
        y = np.clip(y, 0.0, 1.0)
        enc = np.where(y <= 0.0031308, 12.92 * y, 1.055 * np.power(y, 1.0 / 2.4) - 0.055)
        _lut.table = np.round(np.clip(enc, 0.0, 1.0) * 255.0).astype(np.uint8)
    return _lut.table


def tone(x) -> np.ndarray:
    """The display shoulder: identity up to 0.8, then a smooth roll-off to 1 (per channel)."""
    x = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    return np.where(x <= KNEE, x, KNEE + (1.0 - KNEE) * (1.0 - np.exp(-(x - KNEE) / (1.0 - KNEE))))


def display_encode(linear_srgb, exposure: float = 1.0, background=None, out=None) -> np.ndarray:
    """Linear sRGB × ``exposure`` -> tone shoulder -> sRGB-encoded uint8, via a lookup table.

    The table is indexed by ``floor(sqrt(x / 16) · 16383)`` and holds each bucket's middle value,
    so the 8-bit result equals the exact encoding to within a fraction of a code (negative values
    clip to 0, values ≥ 16 map to white).
    ``background`` = (mask (H, W), linear value): masked pixels get that value (no exposure).
    """
    n1 = np.float32(_LUT_N - 1)
    scale = np.float32(float(exposure) / _LUT_XMAX) * n1 * n1
    x = np.multiply(np.asarray(linear_srgb, dtype=np.float32), scale)
    if background is not None:
        mask, value = background
        np.copyto(x, np.float32(value / _LUT_XMAX) * n1 * n1, where=np.asarray(mask)[..., None])
    np.clip(x, np.float32(0.0), n1 * n1, out=x)
    np.sqrt(x, out=x)
    idx = x.astype(np.int32)  # floor; the table holds each bucket's middle value
    if out is None:
        return _lut()[idx]
    np.take(_lut(), idx, out=out)
    return out


# -- cameras and shapes --------------------------------------------------------------------------
def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: ``position``, orthonormal ``right``/``up``/``forward`` and a square window
    on the image plane at distance 1 (centre ``cx, cy`` and half width ``half``, tan units)."""

    position: np.ndarray
    right: np.ndarray
    up: np.ndarray
    forward: np.ndarray
    cx: float = 0.0
    cy: float = 0.0
    half: float = 0.5

    @classmethod
    def look_at(cls, position, target=(0.0, 0.0, 0.0), world_up=(0.0, 1.0, 0.0)) -> "Camera":
        pos = np.asarray(position, dtype=np.float64)
        fwd = _unit(np.asarray(target, dtype=np.float64) - pos)
        right = _unit(np.cross(fwd, world_up))
        up = np.cross(right, fwd)
        return cls(pos, right, up, fwd)

    def fitted(self, points, fill: float = 0.86) -> "Camera":
        """The camera with its window framing ``points`` (N, 3), filling ``fill`` of the square."""
        q = np.asarray(points, dtype=np.float64) - self.position
        z = q @ self.forward
        u = (q @ self.right) / z
        w = (q @ self.up) / z
        half = 0.5 * max(u.max() - u.min(), w.max() - w.min()) / fill
        return Camera(self.position, self.right, self.up, self.forward,
                      0.5 * (u.max() + u.min()), 0.5 * (w.max() + w.min()), half)

    def window(self, x, y, size: int, dtype=np.float32):
        """Image-plane coordinates (u, w) and ``inv = 1/|(u, w, 1)|`` for pixel coordinates
        ``x`` (column), ``y`` (row); broadcasting (a row and a column vector give the grid)."""
        s = 2.0 * self.half / size
        u = np.asarray(x, dtype=dtype) * dtype(s) + dtype(self.cx - self.half)
        w = dtype(self.cy + self.half) - np.asarray(y, dtype=dtype) * dtype(s)
        inv = dtype(1.0) / np.sqrt(u * u + (w * w + dtype(1.0)))
        return u, w, inv

    def dot(self, u, w, inv, vec) -> np.ndarray:
        """``d · vec`` for the unit rays of :meth:`window` (a broadcast sum, then one product)."""
        t = inv.dtype.type
        vec = np.asarray(vec, dtype=np.float64)
        return (u * t(self.right @ vec) + (w * t(self.up @ vec) + t(self.forward @ vec))) * inv

    def directions(self, x, y, size: int, dtype=np.float32):
        """Unit ray directions (dx, dy, dz), planar arrays, for continuous pixel coordinates
        ``x`` (column) and ``y`` (row) on a ``size`` × ``size`` image (pixel centres at k + 0.5).
        ``x`` and ``y`` broadcast (a row and a column vector give the full grid)."""
        s = 2.0 * self.half / size
        u = np.asarray(x, dtype=dtype) * dtype(s) + dtype(self.cx - self.half)
        w = dtype(self.cy + self.half) - np.asarray(y, dtype=dtype) * dtype(s)
        inv = dtype(1.0) / np.sqrt(u * u + (w * w + dtype(1.0)))
        out = []
        for k in range(3):
            r, up, f = dtype(self.right[k]), dtype(self.up[k]), dtype(self.forward[k])
            c = inv * f if f != 0 else np.zeros_like(inv)
            if r != 0:
                c = c + (u * r) * inv
            if up != 0:
                c = c + (w * up) * inv
            out.append(np.broadcast_to(c, inv.shape) if c.shape != inv.shape else c)
        return tuple(out)


class Sphere:
    """A unit sphere at the origin."""

    name = "sphere"

    def intersect(self, o, dx, dy, dz):
        """(hit, nx, ny, nz) for rays from ``o`` along unit (dx, dy, dz)."""
        t32 = dx.dtype.type
        ox, oy, oz = (t32(v) for v in o)
        b = dx * ox + dy * oy + dz * oz
        disc = b * b - t32(float(o @ o) - 1.0)
        hit = disc >= 0
        t = -b - np.sqrt(np.maximum(disc, t32(0)))
        return hit, ox + t * dx, oy + t * dy, oz + t * dz

    def trace(self, cam: "Camera", u, w, inv, light):
        """(hit, cos_l, cos_v) without normals: with ``n = o + t d``, ``n·d = -sqrt(disc)``."""
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
        th, ph = np.meshgrid(np.linspace(0, np.pi, 65), np.linspace(0, 2 * np.pi, 129), indexing="ij")
        return np.stack([np.sin(th) * np.cos(ph), np.cos(th), np.sin(th) * np.sin(ph)], -1).reshape(-1, 3)


class HalfCylinder:
    """A sheet bent into a half cylinder: radius 1 about the y axis, |y| <= h, the half z >= 0.

    Both faces are the same anodised metal (the outer, convex face is the one mostly seen; near
    the top corners the inner face shows through the opening)."""

    name = "cylinder"

    def __init__(self, half_height: float = 1.1):
        self.h = float(half_height)

    def intersect(self, o, dx, dy, dz):
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

    def trace(self, cam: "Camera", u, w, inv, light):
        """(hit, cos_l, cos_v) without normals. With ``p = o + t d``, ``n = ±(p_x, 0, p_z)``,
        ``b = o_xz·d_xz``, ``a = |d_xz|²``: ``n·d = ±(b + t a) = ∓sqrt(disc)`` for the near (+) and
        far (−) root, so ``cos_v = sqrt(disc)`` on both faces, and
        ``n·l = ±((o_x l_x + o_z l_z) + t (d_x l_x + d_z l_z))``."""
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
        ph, y = np.meshgrid(np.linspace(-np.pi / 2, np.pi / 2, 65), np.linspace(-self.h, self.h, 33), indexing="ij")
        return np.stack([np.sin(ph), y, np.cos(ph)], -1).reshape(-1, 3)


class Plate:
    """A flat square plate |x|, |z| <= half in the plane y = 0 (normal +y)."""

    name = "flat"

    def __init__(self, half: float = 1.0):
        self.a = float(half)

    def intersect(self, o, dx, dy, dz):
        t32 = dx.dtype.type
        ox, oy, oz = (t32(v) for v in o)
        a = t32(self.a)
        t = -oy / np.minimum(dy, t32(-1e-30))
        hit = (dy < 0) & (np.abs(ox + t * dx) <= a) & (np.abs(oz + t * dz) <= a)
        return hit, t32(0.0), t32(1.0), t32(0.0)

    def trace(self, cam: "Camera", u, w, inv, light):
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
        a = self.a
        return np.array([[-a, 0, -a], [a, 0, -a], [a, 0, a], [-a, 0, a]], dtype=np.float64)


@dataclass(frozen=True)
class Scene:
    shape: object
    camera: Camera
    light: np.ndarray  # unit vector towards the light
    description: str


def make_scene(shape: str, light_deg: float) -> Scene:
    """The camera, light and object of a swatch render (see the module documentation)."""
    shape = check_shape(shape)
    light_deg = float(geometry.check_polar_deg(light_deg, "light"))
    t = math.radians(light_deg)
    if shape == "flat":
        obj = Plate(1.0)
        cam_polar = math.radians(36.0)
        cam = Camera.look_at(3.2 * np.array([0.0, math.cos(cam_polar), math.sin(cam_polar)]))
        light = np.array([0.0, math.cos(t), -math.sin(t)])
        desc = (f"flat 2x2 plate, normal +y; light {light_deg:g} deg from the normal on the far side; "
                f"perspective camera 36 deg from the normal on the near side at 3.2 plate half-widths")
    else:
        if shape == "cylinder":
            obj, dist, what = HalfCylinder(1.1), 5.5, "half cylinder (sheet bent to radius 1, height 2.2, vertical axis)"
        else:
            obj, dist, what = Sphere(), 4.0, "unit sphere"
        el = math.radians(20.0)
        cam = Camera.look_at(dist * np.array([0.0, math.sin(el), math.cos(el)]))
        c_hat = -cam.forward
        w = _unit(-cam.right * math.cos(math.radians(30.0)) + cam.up * math.sin(math.radians(30.0)))
        light = math.cos(t) * c_hat + math.sin(t) * w
        desc = (f"{what}; perspective camera 20 deg above the horizon at {dist:g} radii; "
                f"light {light_deg:g} deg from the camera direction, from the left and 30 deg up")
    cam = cam.fitted(obj.points())
    return Scene(obj, cam, _unit(light), desc)


# -- rendering -----------------------------------------------------------------------------------
@dataclass
class SwatchImage:
    """A rendered swatch: scene-referred linear RGB (premultiplied), coverage, display sRGB, metadata."""

    linear_rgb: np.ndarray
    alpha: np.ndarray
    display_rgb: np.ndarray
    metadata: dict = field(default_factory=dict)
    exposure: float = 1.0

    @property
    def rgba(self) -> np.ndarray:
        return np.concatenate([self.linear_rgb, self.alpha[..., None]], axis=-1)


def _terms(scene: Scene, u, w, inv):
    """(hit, cos_l, cos_v, cos_h, cos_d) for the camera rays at window coordinates (u, w)."""
    cam = scene.camera
    t32 = inv.dtype.type
    hit, cos_l, cos_v = scene.shape.trace(cam, u, w, inv, scene.light)
    lv = cam.dot(u, w, inv, -scene.light)  # l·v with v = -d
    cos_d = np.sqrt(np.maximum((lv + t32(1.0)) * t32(0.5), t32(1e-12)))
    cos_h = (cos_l + cos_v) * (t32(0.5) / cos_d)  # n·(l+v)/|l+v|, |l+v| = 2 cos θ_d
    return hit, cos_l, cos_v, cos_h, cos_d


def _intensity(hit, cos_l, cos_v, cos_h, cos_d, model, roughness, distribution):
    """The render's intensity factor s (zero off the object)."""
    if model == "microfacet" and distribution == "ggx":
        s = microfacet.ggx_reflectance_factor_cos(cos_l, cos_v, cos_h, roughness)
        s *= hit
        return s
    s = shading.intensity(cos_l, cos_v, cos_h, cos_d, model, roughness, distribution, irradiance=True)
    return np.where(hit, s, s.dtype.type(0.0))


def _exposure(model: str, s: np.ndarray, cos_h: np.ndarray, seen: np.ndarray, roughness: float, distribution: str):
    """Display exposure k and a sentence saying how it was chosen (see the module doc)."""
    if model == "paper":
        return 1.0, "paper model: reflectance shown as is (k = 1); display shoulder above 0.8"
    seen = seen & (s > 0)
    off = seen & (microfacet.D_ratio(np.clip(cos_h, 0, 1), roughness, distribution) < 0.5)
    if off.sum() >= max(16, 0.01 * seen.sum()):
        p = float(np.median(s[off]))
        rule = ("k = 1 / median F=1 intensity over the off-mirror region (D(h) < D(n)/2, outside the half "
                "maximum of the specular lobe): off-mirror pixels show the half-vector reflectance colour "
                "at their own brightness; the brighter highlight rolls off to white with a smooth "
                "per-channel shoulder above 0.8")
    elif seen.any():
        p = float(np.median(s[seen]))
        rule = "no off-mirror region in view: k = 1 / median F=1 intensity; shoulder above 0.8"
    else:
        return 1.0, "nothing lit in view: k = 1"
    return (1.0 / p if p > 0 else 1.0), rule


def scene_geometry(scene: Scene, size_px: int, dtype=np.float64):
    """Per-pixel (centre) normal, view (H, W, 3), light (3,) and hit (H, W) of a scene: for tests
    and the benchmark's direct spectral path."""
    size = int(size_px)
    c = np.arange(size, dtype=dtype) + dtype(0.5)
    dx, dy, dz = scene.camera.directions(c[None, :], c[:, None], size, dtype=dtype)
    hit, nx, ny, nz = scene.shape.intersect(scene.camera.position, dx, dy, dz)
    n = np.stack([np.broadcast_to(c, hit.shape) for c in (nx, ny, nz)], -1)
    v = -np.stack([dx, dy, dz], -1)
    return n, scene.light.astype(dtype), v, hit


def _edge_pixels(hit: np.ndarray) -> np.ndarray:
    """Pixels whose centre differs from one of its 8 neighbours' (flat indices): the pixels a
    silhouette crosses (a corner clipped by less than a pixel's diagonal half is the only miss)."""
    e = np.zeros_like(hit)
    for a, b in (((slice(None), slice(1, None)), (slice(None), slice(None, -1))),
                 ((slice(1, None), slice(None)), (slice(None, -1), slice(None))),
                 ((slice(1, None), slice(1, None)), (slice(None, -1), slice(None, -1))),
                 ((slice(1, None), slice(None, -1)), (slice(None, -1), slice(1, None)))):
        d = hit[a] != hit[b]
        e[a] |= d
        e[b] |= d
    return np.flatnonzero(e)


TILE_ROWS = 64


def _fine_index(fine, cos_d) -> np.ndarray:
    """Nearest node of a refined table (linear interpolation of the coarse table, see
    :meth:`swatch.shading.ColourTable.lookup_nearest`)."""
    t32 = np.float32
    x = (cos_d - t32(fine.c0)) * t32((fine.nodes - 1) / max(fine.c1 - fine.c0, 1e-12)) + t32(0.5)
    return np.clip(x, t32(0), t32(fine.nodes - 1)).astype(np.int32)


def render_scene(scene: Scene, table, size_px: int, model: str, roughness: float, distribution: str,
                 display_table=None, workers: int | None = None):
    """Render ``scene`` with the colour ``table`` (linear RGB; the fast, table-lookup path).

    Returns (linear_rgb premultiplied (H, W, 3), alpha (H, W), display uint8 (H, W, 3), exposure,
    rule, (c0, c1)). ``table`` is an XYZ or RGB :class:`swatch.shading.ColourTable` *factory*
    ``table(c0, c1)`` called with the cos θ_d range of the image, or a ready table.
    ``display_table`` (same form) gives linear sRGB for the display when ``table`` is another space.
    """
    size = int(size_px)
    dt = np.float32
    t32 = np.float32

    # Pre-pass on every 4th pixel centre: the cos θ_d range (for the table) and the exposure.
    sub = np.arange(0, size, 4, dtype=dt) + dt(0.5)
    edge_c = np.array([0.0, size / 2, size], dtype=dt)
    xs = np.concatenate([sub, edge_c])
    hit, cl, cv, ch, cd = _terms(scene, *scene.camera.window(xs[None, :], xs[:, None], size, dtype=dt))
    s = _intensity(hit, cl, cv, ch, cd, model, roughness, distribution)
    n_sub = sub.size
    k, rule = _exposure(model, s[:n_sub, :n_sub], ch[:n_sub, :n_sub], hit[:n_sub, :n_sub], roughness, distribution)
    lo, hi = float(cd.min()), float(cd.max())
    pad = 0.05 * (hi - lo) + 2e-3
    c0, c1 = max(0.0, lo - pad), min(1.0, hi + pad)
    tab = table(c0, c1) if callable(table) else table
    fine = tab.refined(16)
    dfine = None
    if display_table is not None:
        dtab = display_table(c0, c1) if callable(display_table) else display_table
        dfine = dtab.refined(16)

    rgb = np.empty((size, size, 3), dtype=dt)
    alpha = np.empty((size, size), dtype=dt)
    display = np.empty((size, size, 3), dtype=np.uint8)
    cols = np.arange(size, dtype=dt) + dt(0.5)
    kk = t32(k)
    bg = t32(BACKGROUND_LINEAR)

    def tile(r0, r1):
        rows = (np.arange(r0, r1, dtype=dt) + dt(0.5))[:, None]
        hit, cl, cv, ch, cd = _terms(scene, *scene.camera.window(cols[None, :], rows, size, dtype=dt))
        s = _intensity(hit, cl, cv, ch, cd, model, roughness, distribution)
        idx = _fine_index(fine, cd)
        s3 = s[..., None]
        np.multiply(np.take(fine.values, idx, axis=0), s3, out=rgb[r0:r1])
        alpha[r0:r1] = hit
        src = rgb[r0:r1] if dfine is None else np.take(dfine.values, idx, axis=0) * s3
        display_encode(src, k, (~hit, BACKGROUND_LINEAR), out=display[r0:r1])

    bounds = list(range(0, size, TILE_ROWS)) + [size]
    n_workers = int(workers or 1)  # threads gain little for numpy ufuncs on 2 cores; opt-in
    if n_workers > 1 and len(bounds) > 2:
        with ThreadPoolExecutor(max_workers=n_workers) as pool:
            list(pool.map(lambda i: tile(bounds[i], bounds[i + 1]), range(len(bounds) - 1)))
    else:
        for i in range(len(bounds) - 1):
            tile(bounds[i], bounds[i + 1])

    # Anti-aliasing: re-render silhouette pixels with SUPERSAMPLE² stratified sub-samples.
    edge = _edge_pixels(alpha > 0.5)
    if edge.size:
        n = SUPERSAMPLE
        off = (np.arange(n, dtype=dt) + dt(0.5)) / dt(n)
        ox, oy = (a.reshape(-1) for a in np.meshgrid(off, off, indexing="xy"))
        ey, ex = np.divmod(edge, size)
        u, w, inv = scene.camera.window(ex[:, None].astype(dt) + ox[None, :],
                                        ey[:, None].astype(dt) + oy[None, :], size, dtype=dt)
        hit, cl, cv, ch, cd = _terms(scene, *np.broadcast_arrays(u, w, inv))
        s = _intensity(hit, cl, cv, ch, cd, model, roughness, distribution)
        idx = _fine_index(fine, cd)
        a = hit.mean(axis=1, dtype=np.float64).astype(dt)
        col = (np.take(fine.values, idx, axis=0) * s[..., None]).mean(axis=1)
        rgb.reshape(-1, 3)[edge] = col
        alpha.reshape(-1)[edge] = a
        if dfine is not None:
            col = (np.take(dfine.values, idx, axis=0) * s[..., None]).mean(axis=1)
        comp = col * kk + (t32(1.0) - a)[:, None] * bg
        display.reshape(-1, 3)[edge] = display_encode(comp)  # exposure and background already in
    return rgb, alpha, display, float(k), rule, (c0, c1)


def _common_metadata(d: float, coating, colorimeter, model: str, distribution: str, alpha_r: float) -> dict:
    """Metadata shared by renders and angular maps (the CLI replaces the voltage entries with
    the user's own voltage and growth rate)."""
    from swatch.model import thickness_to_voltage_V

    return {
        "thickness_nm": round(d, 6),
        "voltage_V": round(float(thickness_to_voltage_V(d)), 6),
        "voltage_note": "from the thickness at the default growth rate (50.8 nm at 25 V)",
        "film": coating.film,
        "substrate": coating.substrate,
        "illuminant": colorimeter.illuminant,
        "observer": f"CIE {'1964 10' if colorimeter.observer == '10' else '1931 2'} deg",
        "rgb_observer": "CIE 1931 2 deg (display RGB is defined on it; Lab uses the observer above)",
        "model": model,
        "distribution": distribution if model == "microfacet" else "none (facet probability constant)",
        "roughness": alpha_r,
        "reference_geometry": "45:0 (light 45 deg, view along the normal), paper model",
        "Lab_reference": [round(float(x), 4) for x in reference_Lab(d, coating, colorimeter)],
        "software": f"swatch {__version__}",
    }


def render_swatch(thickness_nm: float, shape: str, size_px: int = 512, light_deg: float = 45.0,
                  roughness: float = 0.3, model: str = "microfacet", coating=None, colorimeter=None,
                  space: str = "srgb", distribution: str = "ggx", workers: int | None = None) -> SwatchImage:
    """Render one swatch (see the module documentation for scene, units and exposure).

    Returns a :class:`SwatchImage`: ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in
    ``space`` (srgb or acescg), premultiplied by ``alpha`` (H, W) coverage; ``display_rgb``
    (H, W, 3) uint8 sRGB, exposure applied and composited on neutral grey; ``metadata``.
    """
    from swatch.colorimetry import RGB_SPACES
    from swatch.model import check_thickness_nm

    d = float(check_thickness_nm(float(thickness_nm)))
    shape = check_shape(shape)
    size = check_size_px(size_px)
    model = shading.check_model(model)
    alpha_r = microfacet.check_alpha(roughness)
    distribution = microfacet.check_distribution(distribution)
    space = str(space).lower()
    if space not in RGB_SPACES:
        raise SwatchError(f"unknown RGB space {space!r}; use one of {', '.join(RGB_SPACES)}")
    coating, colorimeter = _defaults(coating, colorimeter)
    scene = make_scene(shape, light_deg)

    def table(c0, c1, sp=space):
        return shading.colour_table(d, coating, colorimeter, RENDER_TABLE_NODES, (c0, c1)).to_rgb(colorimeter, sp)

    display_table = None if space == "srgb" else (lambda c0, c1: table(c0, c1, "srgb"))
    rgb, alpha, display, k, rule, crange = render_scene(scene, table, size, model, alpha_r, distribution,
                                                        display_table, workers)

    meta = _common_metadata(d, coating, colorimeter, model, distribution, alpha_r)
    meta.update({
        "shadowing": "Smith height-correlated" if model == "microfacet" else "none",
        "shape": shape,
        "geometry": scene.description,
        "light_deg": float(light_deg),
        "size_px": size,
        "rgb_space": space,
        "units": "scene-referred linear; 1.0 = perfect white diffuser lit by the same light at normal incidence; "
                 "RGB premultiplied by alpha (coverage)",
        "exposure": round(float(k), 9),
        "exposure_rule": rule,
        "cos_theta_d_range": [round(crange[0], 6), round(crange[1], 6)],
        "display": "sRGB-encoded PNG: linear x exposure, composited on grey 0.18, shoulder above 0.8",
        "wavelength_grid_nm": f"{coating.wavelength_nm[0]:g}:{coating.wavelength_nm[-1]:g}:{coating.wavelength_nm[1] - coating.wavelength_nm[0]:g}",
    })
    return SwatchImage(rgb, alpha, display, meta, float(k))


# -- angular maps --------------------------------------------------------------------------------
@dataclass
class AngularMap:
    """Colour over light angle (rows) × view angle (columns), in plane, on opposite sides."""

    thickness_nm: float
    light_deg: np.ndarray
    view_deg: np.ndarray
    theta_d_deg: np.ndarray
    XYZ: np.ndarray
    Lab: np.ndarray
    linear_rgb: np.ndarray
    display_rgb: np.ndarray
    exposure: float
    spectral: np.ndarray
    wavelength_nm: np.ndarray
    metadata: dict = field(default_factory=dict)


def angular_map(thickness_nm: float, light_deg=np.arange(0, 86), view_deg=np.arange(0, 86), coating=None,
                colorimeter=None, model: str = "paper", roughness: float = 0.3, distribution: str = "ggx",
                space: str = "srgb") -> AngularMap:
    """The colour of one thickness over all in-plane light × view angles (the paper's Fig. 5/11).

    ``spectral`` (L, V, W) is the reflectance factor per wavelength: the half-vector reflectance
    ``F`` for the paper's model, ``π D G F / (4 cos θ_l cos θ_v)`` for the microfacet model (no
    ``cos θ_l`` irradiance factor: a gonio-spectrophotometer's reflectance factor). ``XYZ``/``Lab``
    are its colour (Y = 100 for a white diffuser; L* may exceed 100 in the mirror region);
    ``linear_rgb`` in ``space``; ``display_rgb`` sRGB uint8 with ``exposure`` applied (1 for the
    paper's model; for the microfacet model chosen as in :mod:`swatch.render`'s doc).
    """
    from swatch.colorimetry import RGB_SPACES
    from swatch.model import check_thickness_nm

    d = float(check_thickness_nm(float(thickness_nm)))
    model = shading.check_model(model)
    alpha_r = microfacet.check_alpha(roughness)
    distribution = microfacet.check_distribution(distribution)
    lt = np.atleast_1d(geometry.check_polar_deg(light_deg, "light"))
    vw = np.atleast_1d(geometry.check_polar_deg(view_deg, "view"))
    if lt.ndim != 1 or vw.ndim != 1:
        raise SwatchError("light and view angles must be 1-D lists")
    if space not in RGB_SPACES:
        raise SwatchError(f"unknown RGB space {space!r}; use one of {', '.join(RGB_SPACES)}")
    coating, colorimeter = _defaults(coating, colorimeter)
    L, V = lt[:, None], vw[None, :]
    cos_d = geometry.cos_theta_d(L, V)
    theta_d = geometry.theta_d_deg(L, V)
    spectral = coating.reflectance_cos(d, cos_d).R  # (L, V, W)
    if model == "microfacet":
        cl = np.cos(np.radians(L)) + 0 * V
        cv = np.cos(np.radians(V)) + 0 * L
        ch = geometry.cos_theta_h(L, V)
        s = shading.intensity(cl, cv, ch, cos_d, model, alpha_r, distribution, irradiance=False)
        spectral = spectral * s[..., None]
        k, rule = _exposure(model, s, ch, np.ones_like(s, dtype=bool), alpha_r, distribution)
        rule = rule.replace("F=1 intensity", "F=1 reflectance factor")
    else:
        k, rule = 1.0, "paper model: reflectance shown as is (k = 1); display shoulder above 0.8"
    XYZ = colorimeter.XYZ(spectral)
    Lab = colorimeter.Lab(XYZ)
    XYZ_2 = colorimeter.display_XYZ(spectral)  # RGB from CIE 1931 2° colorimetry
    rgb = np.asarray(colorimeter.rgb_linear(XYZ_2, space), dtype=np.float32)
    srgb = rgb if space == "srgb" else np.asarray(colorimeter.rgb_linear(XYZ_2, "srgb"), dtype=np.float32)
    display = display_encode(srgb * np.float32(k))
    meta = _common_metadata(d, coating, colorimeter, model, distribution, alpha_r)
    meta.update({
        "geometry": "angular map: rows = light polar angle, columns = view polar angle, in one plane on "
                    "opposite sides of the normal (light = view is the mirror direction)",
        "light_deg": f"{lt[0]:g}:{lt[-1]:g} ({lt.size} rows)",
        "view_deg": f"{vw[0]:g}:{vw[-1]:g} ({vw.size} columns)",
        "rgb_space": space,
        "units": "reflectance factor (1.0 = perfect white diffuser); XYZ with Y = 100 for it",
        "exposure": round(float(k), 9),
        "exposure_rule": rule,
    })
    return AngularMap(d, lt, vw, theta_d, XYZ, Lab, rgb, display, float(k), spectral,
                      np.asarray(coating.wavelength_nm, dtype=np.float64), meta)


def angular_figure(amap: AngularMap, title: str | None = None, cell_px: int | None = None) -> np.ndarray:
    """A labelled display figure of an angular map: light angle up the side, view angle along the
    bottom (origin bottom-left, so the mirror diagonal runs bottom-left to top-right)."""
    from swatch import imageio

    nl, nv = amap.display_rgb.shape[:2]
    cell = int(cell_px or max(1, 516 // max(nl, nv)))
    mh, mw = nl * cell, nv * cell
    left, right, top, bottom = 78, 24, 64, 64
    H, W = top + mh + bottom, left + mw + right
    img = np.full((H, W, 3), 255, dtype=np.uint8)
    block = np.repeat(np.repeat(amap.display_rgb[::-1], cell, axis=0), cell, axis=1)  # light 0 at the bottom
    img[top:top + mh, left:left + mw] = block
    ink = (40, 40, 40)
    img = imageio.draw_rect(img, left - 1, top - 1, left + mw + 1, top + mh + 1, ink, fill=False)
    # The mirror direction (light = view), dotted over the map so it is visible whatever the model.
    lo_m = max(float(amap.light_deg[0]), float(amap.view_deg[0]))
    hi_m = min(float(amap.light_deg[-1]), float(amap.view_deg[-1]))
    if hi_m > lo_m:
        t = np.linspace(lo_m, hi_m, max(2, int(max(mw, mh))))
        xs = (left + (np.interp(t, amap.view_deg, np.arange(nv)) + 0.5) * cell).astype(int)
        ys = (top + mh - (np.interp(t, amap.light_deg, np.arange(nl)) + 0.5) * cell).astype(int)
        on = (np.arange(t.size) % 10) < 6  # dashes of ~6 px, gaps of ~4 px
        for dy, dx, shade in ((1, 1, 60), (0, 0, 255), (0, 1, 255), (1, 0, 255)):  # 2-px stroke, dark edge
            img[np.clip(ys[on] + dy, 0, H - 1), np.clip(xs[on] + dx, 0, W - 1)] = shade

    def ticks(values):
        lo, hi = float(values[0]), float(values[-1])
        step = 15.0 if hi - lo >= 45 else (5.0 if hi - lo >= 10 else 1.0)
        t = np.arange(math.ceil(lo / step) * step, hi + 1e-9, step)
        return t

    for t in ticks(amap.view_deg):  # x axis: view
        j = float(np.interp(t, amap.view_deg, np.arange(nv)))
        x = int(left + (j + 0.5) * cell)
        img = imageio.draw_line(img, x, top + mh, x, top + mh + 6, ink)
        img = imageio.draw_text(img, f"{t:g}", x, top + mh + 22, 15, ink, align="center")
    for t in ticks(amap.light_deg):  # y axis: light (upwards)
        i = float(np.interp(t, amap.light_deg, np.arange(nl)))
        y = int(top + mh - (i + 0.5) * cell)
        img = imageio.draw_line(img, left - 7, y, left - 1, y, ink)
        img = imageio.draw_text(img, f"{t:g}", left - 11, y + 5, 15, ink, align="right")
    img = imageio.draw_text(img, "view angle (deg from normal, opposite side); dashed: mirror", left + mw // 2,
                            H - 14, 16, ink, align="center")
    # Vertical axis label: draw horizontally into a strip, rotate it, paste it.
    label = "light angle (deg)"
    lw = imageio.text_width(label, 16) + 8
    strip = np.full((24, lw, 3), 255, dtype=np.uint8)
    strip = imageio.draw_text(strip, label, 4, 17, 16, ink)
    rot = np.rot90(strip)  # reads bottom to top
    y0 = top + mh // 2 - rot.shape[0] // 2
    if rot.shape[0] <= H - max(0, y0):
        img[max(0, y0):max(0, y0) + rot.shape[0], 6:6 + rot.shape[1]] = rot
    meta = amap.metadata
    volts = meta.get("voltage_V")
    head = title or (f"{amap.thickness_nm:.1f} nm" + (f" (~{volts:.1f} V)" if volts is not None else "")
                     + f"  {meta.get('film')} on {meta.get('substrate')}")
    img = imageio.draw_text(img, head, left, 26, 19, (0, 0, 0))
    sub = (f"{meta.get('model')} model" + (f", {meta.get('distribution')} a={meta.get('roughness'):g}"
                                             if meta.get("model") == "microfacet" else "")
           + f"; {meta.get('illuminant')}, {meta.get('observer')}; exposure x{amap.exposure:.3g}")
    img = imageio.draw_text(img, sub, left, 50, 14, (70, 70, 70))
    return img
