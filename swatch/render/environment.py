"""Environment lighting: distant radiance over all directions, as a normalised octahedral map.

An environment gives the radiance arriving from every direction (world frame: **y up**, the
camera of a swatch render on the +z side). Three kinds:

* ``uniform``: radiance 1 from every direction (the furnace test's light);
* ``studio``: a photographic studio for metal, defined in code: a large overhead soft box,
  two tall strip boxes at the sides standing on the floor, dark-grey walls and a light floor
  meeting them in a horizon (:func:`swatch.render.studio.studio_radiance`), so that metal shows reflections;
* a user's **equirectangular** (latitude–longitude) EXR or Radiance HDR, read and checked by
  :mod:`swatch.render.hdri` (orientation, caps and primaries are described there).

**Units.** Every map is scaled so that a perfect white diffuser facing up (+y, the plate's
normal) reflects radiance 1 (Y of the RGB, Rec.709 weights): ``E_up / π = 1``. Rendered
pixels are then scene-referred with 1.0 = that white diffuser under the same lighting; a
constant map of any value equals ``uniform``.

**Representation.** Maps are stored as an octahedral projection of the sphere
(:mod:`swatch.render.octahedral`: ``RES × RES`` texels, y is the octahedron's pole), which needs no
trigonometry to look up, padded with its octahedral neighbours for bilinear lookups across the
folded edges. :meth:`Environment.filtered` returns the map blurred on the sphere by a Gaussian of
a given angular width (a dense convolution with the texels' solid angles as weights), and
:func:`levels` a stack of such blurs, used by :mod:`swatch.render.builtin.env_shading` so that a fixed set
of samples per pixel gives a smooth image.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from swatch.core.choices import POINT_LIGHT, lightings_of
from swatch.core.errors import SwatchError
from swatch.render.hdri import MAP_RES, equirect_to_octa, read_equirect
from swatch.render.octahedral import (
    LevelMaps,
    PaddedMap,
    octa_decode,
    octa_encode,
    texel_directions,
    texel_solid_angles,
)
from swatch.render.studio import studio_radiance
from swatch.render.studio_set import set_radiance

__all__ = [
    "BUILTIN",
    "LEVELS",
    "Environment",
    "get_environment",
    "levels",
    "set_environment",
]

#: The built-in environments: the lightings of :data:`swatch.core.choices.LIGHTINGS` that the built-in engine
#: renders as a map (all its lightings but the point light).
BUILTIN = tuple(n for n in lightings_of("builtin") if n != POINT_LIGHT)
_REC709_Y = np.array([0.2126, 0.7152, 0.0722])


# -- the environment -----------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Environment:
    """Radiance on an octahedral map, linear Rec.709 RGB, normalised (module doc).

    Parameters
    ----------
    name : str
        ``uniform``, ``studio`` or the file name of a user's map.
    radiance : numpy.ndarray
        The normalised map, shape ``(res, res, 3)`` float32 (texel order of
        :func:`swatch.render.octahedral.texel_directions`); 1.0 = the radiance a white diffuser
        facing +y reflects.
    description : str
        One line for metadata and reports.
    scale : float, optional
        The factor applied to the source values (``1 / (E_up/π)``), dimensionless.

    Examples
    --------
    >>> env = get_environment("uniform")
    >>> env.res, env.is_constant, env.radiance_at([[0.0, 1.0, 0.0]]).tolist()
    (8, True, [[1.0, 1.0, 1.0]])
    """

    name: str
    radiance: np.ndarray
    description: str
    scale: float = 1.0  # the factor applied to the source values (1 / (E_up/π))
    _cache: dict = field(default_factory=dict, repr=False, compare=False, hash=False)

    @property
    def res(self) -> int:
        """Texels per side of the map.

        Returns
        -------
        int
            Side of the octahedral map, texels.
        """
        return int(self.radiance.shape[0])

    @property
    def is_constant(self) -> bool:
        """Whether every texel has the same radiance (a blur is then the map itself).

        Returns
        -------
        bool
            True for a map of one radiance everywhere (``uniform``).
        """
        r = self.radiance.reshape(-1, 3)
        return bool(np.all(r == r[0]))

    def padded(self) -> PaddedMap:
        """The unblurred map with its octahedral border, for lookups (cached).

        Returns
        -------
        swatch.render.octahedral.PaddedMap
            The map's linear RGB radiance with a one-texel octahedral border (bilinear lookups wrap correctly).
        """
        if "padded" not in self._cache:
            self._cache["padded"] = PaddedMap(self.radiance.astype(np.float32))
        return self._cache["padded"]

    def downsampled(self, res: int) -> np.ndarray:
        """The map averaged (solid-angle weighted) onto a coarser map.

        Each texel goes to the coarse texel its centre falls in.

        Parameters
        ----------
        res : int
            Texels per side of the result; at or above the map's own, the map itself is returned.

        Returns
        -------
        numpy.ndarray
            Radiance, shape ``(min(res, self.res),) * 2 + (3,)`` float64.
        """
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
        normalised with the source texels' solid angles, so a constant map stays constant (cached).

        Parameters
        ----------
        sigma_deg : float
            The blur's width σ in degrees (> 0 unless the map is constant).
        res : int, optional
            Texels per side of the blurred map (at most the map's own).

        Returns
        -------
        swatch.render.octahedral.PaddedMap
            The blurred map, padded for lookups.

        Raises
        ------
        ValueError
            For ``sigma_deg <= 0`` or ``res`` above the map's resolution (a programming error).
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
        """Radiance in given directions, bilinear on the unfiltered map.

        Parameters
        ----------
        directions : array_like
            Unit directions, shape ``S + (3,)`` (y up).

        Returns
        -------
        numpy.ndarray
            Normalised radiance, shape ``S + (3,)`` float32.
        """
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


def _octa_mean(radiance_fn, res: int, sub: int) -> np.ndarray:
    """An octahedral map of ``radiance_fn(directions)``, each texel the solid-angle-weighted mean of
    ``sub × sub`` points (shape ``(res, res, 3)``)."""
    c = (np.arange(res * sub) + 0.5) / (res * sub)
    s, t = np.meshgrid(c, c, indexing="xy")
    d = octa_decode(s, t)
    x = d / np.abs(d).sum(-1, keepdims=True)
    w = np.linalg.norm(x, axis=-1) ** -3  # dω ∝ 1/|p|³ (p on the octahedron)
    L = radiance_fn(d) * w[..., None]
    num = L.reshape(res, sub, res, sub, 3).sum(axis=(1, 3))
    den = w.reshape(res, sub, res, sub).sum(axis=(1, 3))[..., None]
    return num / den


def _studio(res: int = MAP_RES, sub: int = 4) -> Environment:
    """The studio map, each texel the solid-angle-weighted mean of ``sub × sub`` points."""
    return _normalised("studio", _octa_mean(studio_radiance, res, sub),
                       "studio (built in): overhead soft box, tall strip boxes left and right, dark-grey walls, "
                       "light floor with a horizon; neutral")


def set_environment(name: str, floor_y: float, lightmap: np.ndarray, scale: float, res: int = MAP_RES,
                    sub: int = 4) -> Environment:
    """The path tracer's studio set seen from the object's centre without its soft boxes
    (:func:`swatch.render.studio_set.set_radiance`; the page meets the boxes along each sample's own ray), as an
    environment in the renders' own units (not renormalised: the set's radiance scale is the hero's).

    Parameters
    ----------
    name : str
        Its name (the shape it was baked around).
    floor_y : float
        The floor's height under that shape.
    lightmap : numpy.ndarray, shape (ns, nx)
        The cyclorama's radiance (:func:`swatch.render.dispatch.studio_lightmap`).
    scale : float
        The render's radiance scale (multiplies the soft boxes and the fill).
    res, sub : int, optional
        The map's side in texels and the points averaged per texel along each side.

    Returns
    -------
    Environment
        Neutral radiance, 1 = a white diffuser facing up at the object, lit directly by the set's emitters, reflects 1.
    """
    def radiance(d):
        return np.repeat(set_radiance(d, floor_y, lightmap, scale, boxes=False)[..., None], 3, axis=-1)

    return Environment(name, _octa_mean(radiance, res, sub).astype(np.float32),
                       "the path tracer's studio set without its soft boxes (cyclorama, fill) from the object's centre", 1.0)


@functools.lru_cache(maxsize=4)
def _builtin(name: str) -> Environment:
    if name == "uniform":
        return Environment("uniform", np.ones((8, 8, 3), dtype=np.float32),
                           "uniform (built in): radiance 1 from every direction", 1.0)
    return _studio()


def get_environment(name_or_path) -> Environment | None:
    """An environment by name or file: None for ``point``, a built-in, or a user's map.

    Parameters
    ----------
    name_or_path : str, path-like or Environment
        ``point``, ``uniform``, ``studio``, or the path of an equirectangular EXR (y up, Rec.709
        primaries, at most ``MAX_ENV_PIXELS``; checked from its header before pixels are read).

    Returns
    -------
    Environment or None
        Normalised so that a white diffuser facing up reflects 1.0; None for ``point`` (the point light).

    Raises
    ------
    SwatchError
        For an unknown name, or a file that is not a usable map (one line, what is allowed).
    """
    key = str(name_or_path).strip()
    if key.lower() == POINT_LIGHT:
        return None
    if key.lower() in BUILTIN:
        return _builtin(key.lower())
    if not key.lower().endswith((".exr", ".hdr")):
        raise SwatchError(f"unknown environment {key!r}; use one of {POINT_LIGHT}, {', '.join(BUILTIN)} "
                          "or an equirectangular .exr or .hdr file")
    img = read_equirect(key)
    octa = equirect_to_octa(img)
    return _normalised(Path(key).name, octa, f"equirectangular map {Path(key).name} ({img.shape[1]}x{img.shape[0]}), "
                       "y up, Rec.709 primaries assumed")


#: Blur levels of :func:`levels`: (σ in degrees, map resolution). Level 0 is the
#: map itself (texels of ~1.6°).
LEVELS = ((0.0, MAP_RES), (4.0, 48), (8.0, 48), (16.0, 32), (32.0, 16), (64.0, 16))


def levels(env: Environment) -> LevelMaps:
    """The :data:`LEVELS` blurred copies of an environment, in one array (cached on it).

    Parameters
    ----------
    env : Environment
        The environment.

    Returns
    -------
    swatch.render.octahedral.LevelMaps
        Level ``k`` is ``env`` blurred by ``LEVELS[k][0]`` degrees at ``LEVELS[k][1]`` texels per side.
    """
    if "levels" not in env._cache:
        maps = [env.padded() if s == 0 else env.filtered(s, r) for s, r in LEVELS]
        env._cache["levels"] = LevelMaps(maps, [s for s, _ in LEVELS])
    return env._cache["levels"]
