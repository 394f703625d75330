"""Environment lighting: distant radiance over all directions, as an octahedral map.

An environment gives the radiance arriving from every direction (world frame: **y up**, the
camera of a swatch render on the +z side). Three kinds:

* ``uniform``: radiance 1 from every direction (the furnace test's light);
* ``studio``: a photographic studio for metal, defined here in code: a large overhead soft box,
  two tall strip boxes at the sides standing on the floor, dark-grey walls and a light floor
  meeting them in a horizon (:func:`studio_radiance`), so that metal shows reflections;
* a user's **equirectangular** (latitude–longitude) EXR or Radiance HDR, read with OpenImageIO: row 0 is the
  zenith (+y), the centre column looks along −z (away from the camera) and longitude grows
  towards +x (``u = 0.5 + atan2(x, −z)/2π``, ``v = acos(y)/π``). Untrusted input: the size
  is checked from the header before any pixel is read (:data:`MAX_ENV_PIXELS`), the values must
  be finite and ≥ 0, and RGB is taken as linear Rec.709/sRGB primaries (1 or 2 channels: grey).

**Units.** Every map is scaled so that a perfect white diffuser facing up (+y, the plate's
normal) reflects radiance 1 (Y of the RGB, Rec.709 weights): ``E_up / π = 1``. Rendered
pixels are then scene-referred with 1.0 = that white diffuser under the same lighting; a
constant map of any value equals ``uniform``.

**Representation.** Maps are stored as an octahedral projection of the sphere (``RES × RES``
texels, y is the octahedron's pole: the upper hemisphere is the inner diamond), which needs no
trigonometry to look up; :func:`lookup` interpolates bilinearly across the folded edges (the
map is padded with its octahedral neighbours). :meth:`Environment.filtered` returns the map
blurred on the sphere by a Gaussian of a given angular width (a dense convolution with the
texels' solid angles as weights), used by :mod:`swatch.render.env_shading` so that a fixed set of
samples per pixel gives a smooth image.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import OpenImageIO as oiio

from swatch.core.choices import ENVIRONMENTS
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_ENV_FILE_BYTES, MAX_ENV_PIXELS, MAX_ENV_SIDE
from swatch.render.studio import studio_radiance

__all__ = [
    "BUILTIN",
    "ENVIRONMENT_CHOICES",
    "MAX_ENV_PIXELS",
    "MAX_ENV_SIDE",
    "MAP_RES",
    "Environment",
    "get_environment",
    "octa_encode",
    "octa_decode",
    "texel_directions",
    "texel_solid_angles",
    "PaddedMap",
    "studio_radiance",
    "read_equirect",
]

#: Built-in environments (``none`` = no environment: the single directional light).
ENVIRONMENT_CHOICES = ENVIRONMENTS
BUILTIN = tuple(e for e in ENVIRONMENTS if e != "none")
#: Octahedral map resolution (texels per side) of an environment's radiance.
MAP_RES = 128
_REC709_Y = np.array([0.2126, 0.7152, 0.0722])


# -- octahedral mapping -----------------------------------------------------------------------
def _octa_uw(x, y, z):
    """Octahedron coordinates (u, w) in [-1, 1]² of directions (planar arrays, any length)."""
    one = np.asarray(1.0, dtype=np.result_type(x, np.float32)).dtype.type(1.0)
    inv = one / (np.abs(x) + np.abs(y) + np.abs(z))
    px = x * inv
    pz = z * inv
    lower = y < 0
    u = np.where(lower, np.copysign(one - np.abs(pz), px), px)
    w = np.where(lower, np.copysign(one - np.abs(px), pz), pz)
    return u, w


def octa_encode(x, y, z):
    """Map coordinates ``(s, t)`` in [0, 1]² of unit directions (planar arrays); +y is the pole."""
    u, w = _octa_uw(x, y, z)
    return 0.5 * (u + 1.0), 0.5 * (w + 1.0)


def octa_decode(s, t):
    """Unit directions (..., 3) of map coordinates ``(s, t)`` in [0, 1]²."""
    u = 2.0 * np.asarray(s, dtype=np.float64) - 1.0
    w = 2.0 * np.asarray(t, dtype=np.float64) - 1.0
    y = 1.0 - np.abs(u) - np.abs(w)
    lower = y < 0
    x = np.where(lower, np.copysign(1.0 - np.abs(w), u), u)
    z = np.where(lower, np.copysign(1.0 - np.abs(u), w), w)
    d = np.stack([x, y, z], -1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


@functools.lru_cache(maxsize=8)
def texel_directions(res: int) -> np.ndarray:
    """Unit directions (res·res, 3) of the texel centres (row = t, column = s)."""
    c = (np.arange(res) + 0.5) / res
    s, t = np.meshgrid(c, c, indexing="xy")
    return octa_decode(s, t).reshape(-1, 3)


@functools.lru_cache(maxsize=8)
def texel_solid_angles(res: int, sub: int = 8) -> np.ndarray:
    """Solid angle (res·res,) of each texel (sr; they sum to 4π).

    With the octahedron point ``p = (u, 1 − |u| − |w|, w)`` (folded below), ``dω = du dw / |p|³``
    (the Jacobian of ``p/|p|``; ``p · (∂p/∂u × ∂p/∂w) = −1``), integrated on ``sub × sub`` points.
    """
    c = (np.arange(res * sub) + 0.5) / (res * sub)
    u = 2.0 * c - 1.0
    U, W = np.meshgrid(u, u, indexing="xy")
    y = 1.0 - np.abs(U) - np.abs(W)
    x = np.where(y < 0, 1.0 - np.abs(W), U)  # |x|, |z| on the folded half (signs do not matter)
    z = np.where(y < 0, 1.0 - np.abs(U), W)
    dens = (x * x + y * y + z * z) ** -1.5 * (2.0 / (res * sub)) ** 2
    return dens.reshape(res, sub, res, sub).sum(axis=(1, 3)).reshape(-1)


class PaddedMap:
    """An octahedral RGB map with a one-texel border of its octahedral neighbours, stored as
    RGBA float32 so that one 16-byte gather fetches a texel (viewed as complex128)."""

    def __init__(self, rgb: np.ndarray):
        n = rgb.shape[0]
        p = np.zeros((n + 2, n + 2, 4), dtype=np.float32)
        p[1:-1, 1:-1, :3] = rgb
        p[0, 1:-1] = p[1, -2:0:-1]
        p[-1, 1:-1] = p[-2, -2:0:-1]
        p[1:-1, 0] = p[-2:0:-1, 1]
        p[1:-1, -1] = p[-2:0:-1, -2]
        p[0, 0], p[0, -1], p[-1, 0], p[-1, -1] = p[-2, -2], p[-2, 1], p[1, -2], p[1, 1]
        self.res = n
        self.rgba = p
        self.flat = p.reshape(-1).view(np.complex128)

    def _fetch(self, idx) -> np.ndarray:
        return np.take(self.flat, idx).view(np.float32).reshape((*idx.shape, 4))

    def nearest(self, x, y, z) -> np.ndarray:
        """RGBA (..., 4) of the texel containing each direction (planar float32 arrays)."""
        u, w = _octa_uw(x, y, z)
        n = self.res
        h = np.float32(n / 2)
        c = np.float32(n / 2 + 1)
        ix = np.minimum((u * h + c).astype(np.int32), n)
        iy = np.minimum((w * h + c).astype(np.int32), n)
        return self._fetch(iy * (n + 2) + ix)

    def bilinear(self, x, y, z) -> np.ndarray:
        """RGB (..., 3), bilinear across texels and folded edges."""
        u, w = _octa_uw(x, y, z)
        n = self.res
        t = np.float32
        fx = np.clip(u * t(n / 2) + t(n / 2 + 0.5), t(0), t(n + 1) - t(1e-3))
        fy = np.clip(w * t(n / 2) + t(n / 2 + 0.5), t(0), t(n + 1) - t(1e-3))
        ix = fx.astype(np.int32)
        iy = fy.astype(np.int32)
        ax = (fx - ix)[..., None]
        ay = (fy - iy)[..., None]
        i = iy * (n + 2) + ix
        c00, c01, c10, c11 = (self._fetch(i + k) for k in (0, 1, n + 2, n + 3))
        top = c00 + ax * (c01 - c00)
        return (top + ay * ((c10 + ax * (c11 - c10)) - top))[..., :3]


# -- the environment -----------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Environment:
    """Radiance on an octahedral map (res, res, 3), linear Rec.709 RGB, normalised (module doc)."""

    name: str
    radiance: np.ndarray
    description: str
    scale: float = 1.0  # the factor applied to the source values (1 / (E_up/π))
    _cache: dict = field(default_factory=dict, repr=False, compare=False, hash=False)

    @property
    def res(self) -> int:
        return int(self.radiance.shape[0])

    @property
    def is_constant(self) -> bool:
        r = self.radiance.reshape(-1, 3)
        return bool(np.all(r == r[0]))

    def padded(self) -> PaddedMap:
        if "padded" not in self._cache:
            self._cache["padded"] = PaddedMap(self.radiance.astype(np.float32))
        return self._cache["padded"]

    def downsampled(self, res: int) -> np.ndarray:
        """The map averaged (solid-angle weighted) onto ``res`` ≤ its own texels per side: each
        texel goes to the coarse texel its centre falls in."""
        if int(res) >= self.res:
            return self.radiance.astype(np.float64)
        d = texel_directions(self.res)
        s, t = octa_encode(d[:, 0], d[:, 1], d[:, 2])
        idx = np.minimum((t * res).astype(np.int64), res - 1) * res + np.minimum((s * res).astype(np.int64), res - 1)
        w = texel_solid_angles(self.res)
        src = self.radiance.reshape(-1, 3).astype(np.float64)
        num = np.stack([np.bincount(idx, w * src[:, k], res * res) for k in range(3)], -1)
        return (num / np.bincount(idx, w, res * res)[:, None]).reshape(res, res, 3)

    def filtered(self, sigma_deg: float, res: int = 64) -> PaddedMap:
        """The map blurred by a Gaussian of ``sigma_deg`` on the sphere, at ``res``, padded.

        ``exp(−(1 − cos γ)/σ²)`` (γ the angle between directions; ≈ a Gaussian in γ of width σ),
        normalised with the source texels' solid angles, so a constant map stays constant.
        """
        key = ("filtered", round(float(sigma_deg), 6), int(res))
        if key not in self._cache:
            if self.is_constant:
                out = np.broadcast_to(self.radiance.reshape(-1, 3)[0], (res * res, 3))
            elif sigma_deg <= 0 or res > self.res:
                raise ValueError("a filtered level needs a blur > 0 and at most the map's resolution")
            else:
                src = self.downsampled(res).reshape(-1, 3)
                sd = texel_directions(res).astype(np.float32)
                sw = texel_solid_angles(res).astype(np.float32)
                inv2 = np.float32(1.0 / np.radians(float(sigma_deg)) ** 2)
                out = np.empty((sd.shape[0], 3))
                for a in range(0, sd.shape[0], 1024):  # 1024 × res² weights at a time
                    k = np.exp((sd[a:a + 1024] @ sd.T - np.float32(1.0)) * inv2) * sw
                    out[a:a + 1024] = (k @ src.astype(np.float32)) / k.sum(axis=1, keepdims=True)
            self._cache[key] = PaddedMap(out.reshape(res, res, 3).astype(np.float32))
        return self._cache[key]

    def radiance_at(self, directions) -> np.ndarray:
        """Radiance (..., 3) in unit ``directions`` (..., 3), bilinear on the unfiltered map."""
        d = np.asarray(directions, dtype=np.float32)
        return self.padded().bilinear(d[..., 0], d[..., 1], d[..., 2])


def _normalised(name: str, rgb_map: np.ndarray, description: str) -> Environment:
    """Scale a map so that a white diffuser facing +y reflects Y = 1 (module doc)."""
    res = rgb_map.shape[0]
    d = texel_directions(res)
    w = texel_solid_angles(res) * np.maximum(d[:, 1], 0.0)
    E = float((rgb_map.reshape(-1, 3).astype(np.float64) @ _REC709_Y) @ w)
    if not np.isfinite(E) or E <= 0:
        raise SwatchError(f"environment {name!r} sends no light onto an upward-facing surface; "
                          "give a map with positive radiance above the horizon")
    scale = float(w.sum()) / E  # Σw = the same sum for radiance 1 (π up to the discretisation)
    return Environment(name, (rgb_map * scale).astype(np.float32), description, float(scale))


def _studio(res: int = MAP_RES, sub: int = 4) -> Environment:
    """The studio map, each texel the solid-angle-weighted mean of ``sub × sub`` points."""
    c = (np.arange(res * sub) + 0.5) / (res * sub)
    s, t = np.meshgrid(c, c, indexing="xy")
    d = octa_decode(s, t)
    x = d / np.abs(d).sum(-1, keepdims=True)
    w = np.linalg.norm(x, axis=-1) ** -3  # dω ∝ 1/|p|³ (p on the octahedron)
    L = studio_radiance(d) * w[..., None]
    num = L.reshape(res, sub, res, sub, 3).sum(axis=(1, 3))
    den = w.reshape(res, sub, res, sub).sum(axis=(1, 3))[..., None]
    return _normalised("studio", num / den,
                       "studio (built in): overhead soft box, tall strip boxes left and right, dark-grey walls, "
                       "light floor with a horizon; neutral")


# -- user maps -----------------------------------------------------------------------------------
def read_equirect(path) -> np.ndarray:
    """An equirectangular EXR or Radiance HDR (H, W, 3) float32, checked (module doc); SwatchError on bad input."""

    p = Path(path)
    if not p.is_file():
        raise SwatchError(f"environment map {str(p)!r} is not a file; give an equirectangular .exr or .hdr "
                          f"or one of {', '.join(ENVIRONMENT_CHOICES)}")
    if p.stat().st_size > MAX_ENV_FILE_BYTES:
        raise SwatchError(f"environment map {p.name!r} is larger than {MAX_ENV_FILE_BYTES >> 20} MiB")
    inp = oiio.ImageInput.open(str(p))
    if inp is None:
        raise SwatchError(f"cannot read environment map {p.name!r}: {oiio.geterror().strip() or 'unknown format'}")
    try:
        if inp.format_name() not in ("openexr", "hdr"):
            raise SwatchError(f"environment map {p.name!r} is not an OpenEXR or Radiance HDR file; give an "
                              "equirectangular .exr or .hdr")
        spec = inp.spec()
        w, h, nch = int(spec.width), int(spec.height), int(spec.nchannels)
        if w < 2 or h < 1 or w > MAX_ENV_SIDE or h > MAX_ENV_SIDE or w * h > MAX_ENV_PIXELS:
            raise SwatchError(f"environment map {p.name!r} is {w}x{h}; allowed up to {MAX_ENV_SIDE} per side "
                              f"and {MAX_ENV_PIXELS} pixels")
        if abs(w - 2 * h) > 1:
            raise SwatchError(f"environment map {p.name!r} is {w}x{h}; an equirectangular map is twice as wide as tall")
        if nch < 1 or nch > 64:
            raise SwatchError(f"environment map {p.name!r} has {nch} channels; give 1 or 2 (grey; a second channel is ignored) or 3 or more (RGB)")
        pix = inp.read_image(0, 0, 0, min(nch, 3), "float")
    finally:
        inp.close()
    if pix is None:
        raise SwatchError(f"cannot read the pixels of environment map {p.name!r}")
    a = np.asarray(pix, dtype=np.float32).reshape(h, w, -1)
    if a.shape[-1] < 3:
        a = np.repeat(a[..., :1], 3, axis=-1)
    if not np.all(np.isfinite(a)) or a.min() < 0:
        raise SwatchError(f"environment map {p.name!r} has negative, infinite or NaN values; radiance must be "
                          "finite and >= 0")
    return a


def _equirect_to_octa(img: np.ndarray, res: int = MAP_RES) -> np.ndarray:
    """Resample a lat-long map onto the octahedral map by splatting: every source pixel (split
    into sub-pixels when the source is small) adds radiance × solid angle to the texel its
    direction falls in; each texel is the solid-angle-weighted mean (energy is kept, a constant
    map stays constant). Texels that receive nothing take their bilinear value."""
    h, w, _ = img.shape
    sub = max(1, int(np.ceil(np.sqrt(8.0 * res * res / (h * w)))))
    out_num = np.zeros((res * res, 3))
    out_den = np.zeros(res * res)
    for r0 in range(0, h, max(1, 262144 // (w * sub * sub))):  # bounded memory per block of rows
        r1 = min(h, r0 + max(1, 262144 // (w * sub * sub)))
        rows = (np.arange(r0 * sub, r1 * sub) + 0.5) / (h * sub)
        cols = (np.arange(w * sub) + 0.5) / (w * sub)
        theta = np.pi * rows[:, None]
        phi = 2.0 * np.pi * (cols[None, :] - 0.5)
        st = np.sin(theta)
        x, y, z = st * np.sin(phi), np.cos(theta) + 0 * phi, -st * np.cos(phi)
        s, t = octa_encode(x, y, z)
        idx = (np.minimum((t * res).astype(np.int64), res - 1) * res
               + np.minimum((s * res).astype(np.int64), res - 1)).reshape(-1)
        om = np.broadcast_to(st, x.shape).reshape(-1)  # dω ∝ sin θ
        vals = np.repeat(np.repeat(img[r0:r1], sub, axis=0), sub, axis=1).reshape(-1, 3)
        out_num += np.stack([np.bincount(idx, om * vals[:, k], res * res) for k in range(3)], -1)
        out_den += np.bincount(idx, om, res * res)
    empty = out_den <= 0
    out = out_num / np.where(empty, 1.0, out_den)[:, None]
    if empty.any():
        d = texel_directions(res)[empty]
        th = np.arccos(np.clip(d[:, 1], -1, 1))
        ph = np.arctan2(d[:, 0], -d[:, 2])
        fy = np.clip(th / np.pi * h - 0.5, 0, h - 1)
        fx = (ph / (2 * np.pi) + 0.5) * w - 0.5
        out[empty] = _bilinear_wrap(img, fy, fx)
    return out.reshape(res, res, 3)


def _bilinear_wrap(img, fy, fx):
    h, w, _ = img.shape
    y0 = np.floor(fy).astype(int)
    x0 = np.floor(fx).astype(int)
    ay, ax = (fy - y0)[:, None], (fx - x0)[:, None]
    y1 = np.minimum(y0 + 1, h - 1)
    x0w, x1w = x0 % w, (x0 + 1) % w
    top = img[y0, x0w] * (1 - ax) + img[y0, x1w] * ax
    bot = img[y1, x0w] * (1 - ax) + img[y1, x1w] * ax
    return top * (1 - ay) + bot * ay


@functools.lru_cache(maxsize=4)
def _builtin(name: str) -> Environment:
    if name == "uniform":
        return Environment("uniform", np.ones((8, 8, 3), dtype=np.float32),
                           "uniform (built in): radiance 1 from every direction", 1.0)
    return _studio()


def get_environment(name_or_path) -> Environment | None:
    """An environment by name or file: None for ``none``, a built-in, or a user's map.

    Parameters
    ----------
    name_or_path : str, path-like or Environment
        ``none``, ``uniform``, ``studio``, or the path of an equirectangular EXR (y up, Rec.709
        primaries, at most ``MAX_ENV_PIXELS``; checked from its header before pixels are read).

    Returns
    -------
    Environment or None
        Normalised so that a white diffuser facing up reflects 1.0; None for ``none`` (the point light).

    Raises
    ------
    SwatchError
        For an unknown name, or a file that is not a usable map (one line, what is allowed).
    """
    key = str(name_or_path).strip()
    if key.lower() == "none":
        return None
    if key.lower() in BUILTIN:
        return _builtin(key.lower())
    if not key.lower().endswith((".exr", ".hdr")):
        raise SwatchError(f"unknown environment {key!r}; use one of {', '.join(ENVIRONMENT_CHOICES)} "
                          "or an equirectangular .exr or .hdr file")
    img = read_equirect(key)
    octa = _equirect_to_octa(img)
    return _normalised(Path(key).name, octa, f"equirectangular map {Path(key).name} ({img.shape[1]}x{img.shape[0]}), "
                       "y up, Rec.709 primaries assumed")


#: Blur levels of :meth:`Environment.levels`: (σ in degrees, map resolution). Level 0 is the
#: map itself (texels of ~1.6°).
LEVELS = ((0.0, MAP_RES), (4.0, 48), (8.0, 48), (16.0, 32), (32.0, 16), (64.0, 16))


class LevelMaps:
    """Several blurred copies of one environment in one flat texel array, for per-sample
    filtered lookups: sample ``i`` reads level ``k_i`` (its footprint) at its nearest texel."""

    bilinear: Any  # the filtered lookup, bound below (_levels_bilinear)

    def __init__(self, maps: list[PaddedMap], sigmas_deg: list[float]):
        self.sigma_deg = np.asarray(sigmas_deg, dtype=np.float64)
        self.res = np.array([m.res for m in maps], dtype=np.int64)
        sizes = (self.res + 2) ** 2
        self.offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.flat = np.concatenate([m.flat for m in maps])

    def level_for(self, sigma_deg) -> np.ndarray:
        """The least blurred level whose blur is at least ``sigma_deg`` (level 0, the map itself
        with texels of ~1.6°, below 1°; the most blurred level beyond the last)."""
        s = np.asarray(sigma_deg, dtype=np.float64)
        ref = np.where(self.sigma_deg > 0, self.sigma_deg, 1.0)
        k = np.searchsorted(ref, s, side="left")
        return np.minimum(k, ref.size - 1).astype(np.int32)

    def nearest(self, x, y, z, res, offset) -> np.ndarray:
        """RGB (..., 3) at the nearest texel of each sample's level (``res``, ``offset`` per
        sample: float32 resolution and int32/float32 offset, broadcast with the directions)."""
        u, w = _octa_uw(x, y, z)
        h = res * np.float32(0.5)
        c = h + np.float32(1.0)
        ix = np.minimum((u * h + c).astype(np.int32), res.astype(np.int32))
        iy = np.minimum((w * h + c).astype(np.int32), res.astype(np.int32))
        idx = offset.astype(np.int32) + iy * (res.astype(np.int32) + 2) + ix
        return np.take(self.flat, idx).view(np.float32).reshape((*idx.shape, 4))[..., :3]


def levels(env: Environment) -> LevelMaps:
    """The :data:`LEVELS` blurred copies of ``env`` (cached on it)."""
    if "levels" not in env._cache:
        maps = [env.padded() if s == 0 else env.filtered(s, r) for s, r in LEVELS]
        env._cache["levels"] = LevelMaps(maps, [s for s, _ in LEVELS])
    return env._cache["levels"]


def _levels_bilinear(self, x, y, z, res, offset) -> np.ndarray:
    """RGB (..., 3), bilinear within each sample's level (``res``, ``offset`` per sample)."""
    u, w = _octa_uw(x, y, z)
    t = np.float32
    h = res * t(0.5)
    c = h + t(0.5)
    top_ = res + t(1.0) - t(1e-3)
    fx = np.minimum(np.maximum(u * h + c, t(0)), top_)
    fy = np.minimum(np.maximum(w * h + c, t(0)), top_)
    ix = fx.astype(np.int32)
    iy = fy.astype(np.int32)
    ax = (fx - ix)[..., None]
    ay = (fy - iy)[..., None]
    stride = res.astype(np.int32) + 2
    i = offset.astype(np.int32) + iy * stride + ix
    f = self.flat

    def fetch(k):
        return np.take(f, k).view(np.float32).reshape((*k.shape, 4))[..., :3]

    c00 = fetch(i)
    top = c00 + ax * (fetch(i + 1) - c00)
    i += stride
    c10 = fetch(i)
    bot = c10 + ax * (fetch(i + 1) - c10)
    return top + ay * (bot - top)


LevelMaps.bilinear = _levels_bilinear
