"""The octahedral map of the sphere: directions ↔ texels, texel solid angles, padded lookups.

An environment's radiance (:mod:`swatch.render.environment`) is stored on an octahedral projection
of the unit sphere (``res × res`` texels; **y up** is the octahedron's pole, the upper hemisphere
is the inner diamond), which needs no trigonometry to look up. A direction ``d`` goes to
``p = d / (|x| + |y| + |z|)`` on the octahedron; the lower half (``y < 0``) is folded over the
diamond's edges. :class:`PaddedMap` keeps a one-texel border of the octahedral neighbours so that
a bilinear lookup is continuous across the folds; :class:`LevelMaps` stacks several blurred
copies of one map for per-sample filtered lookups (the renders' fixed samples,
:mod:`swatch.render.builtin.env_shading`).

References
----------
.. [1] Cigolle, Donow, Evangelakos, Mara, McGuire, Meyer, "A Survey of Efficient Representations
   for Independent Unit Vectors", Journal of Computer Graphics Techniques 3(2), 2014
   (https://jcgt.org/published/0003/02/01/).
"""
from __future__ import annotations

import functools

import numpy as np

__all__ = [
    "octa_uw",
    "octa_encode",
    "octa_decode",
    "texel_directions",
    "texel_solid_angles",
    "PaddedMap",
    "LevelMaps",
]


def octa_uw(x, y, z):
    """Octahedron coordinates of directions, before the shift to texture space.

    Parameters
    ----------
    x, y, z : numpy.ndarray
        The components of directions (planar arrays of one shape, any length; need not be unit,
        not all zero). float32 input stays float32.

    Returns
    -------
    u, w : numpy.ndarray
        Coordinates in [-1, 1]² (same shape as ``x``): ``u`` along x, ``w`` along z; the lower
        hemisphere (``y < 0``) folded onto the outer triangles.
    """
    one = np.asarray(1.0, dtype=np.result_type(x, np.float32)).dtype.type(1.0)
    inv = one / (np.abs(x) + np.abs(y) + np.abs(z))
    px = x * inv
    pz = z * inv
    lower = y < 0
    u = np.where(lower, np.copysign(one - np.abs(pz), px), px)
    w = np.where(lower, np.copysign(one - np.abs(px), pz), pz)
    return u, w


def octa_encode(x, y, z):
    """Map coordinates of unit directions; +y is the pole (the map's centre).

    Parameters
    ----------
    x, y, z : numpy.ndarray
        The components of directions (planar arrays of one shape).

    Returns
    -------
    s, t : numpy.ndarray
        Map coordinates in [0, 1]² (``s`` the column, ``t`` the row), same shape as ``x``.

    Examples
    --------
    >>> import numpy as np
    >>> [float(c) for c in octa_encode(np.array(0.0), np.array(1.0), np.array(0.0))]
    [0.5, 0.5]
    """
    u, w = octa_uw(x, y, z)
    return 0.5 * (u + 1.0), 0.5 * (w + 1.0)


def octa_decode(s, t):
    """Unit directions of map coordinates (the inverse of :func:`octa_encode`).

    Parameters
    ----------
    s, t : array_like
        Map coordinates in [0, 1]² (column, row), broadcast together.

    Returns
    -------
    numpy.ndarray
        Unit directions, shape ``broadcast(s, t).shape + (3,)``, float64.

    Examples
    --------
    >>> import numpy as np
    >>> d = np.array([[0.6, 0.0, -0.8], [0.0, -1.0, 0.0]])
    >>> bool(np.allclose(octa_decode(*octa_encode(d[:, 0], d[:, 1], d[:, 2])), d))
    True
    """
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
    """Unit directions of the texel centres of a ``res × res`` map (cached).

    Parameters
    ----------
    res : int
        Texels per side.

    Returns
    -------
    numpy.ndarray
        Directions, shape ``(res·res, 3)``, float64; texel ``(row t, column s)`` at index ``t·res + s``.
    """
    c = (np.arange(res) + 0.5) / res
    s, t = np.meshgrid(c, c, indexing="xy")
    return octa_decode(s, t).reshape(-1, 3)


@functools.lru_cache(maxsize=8)
def texel_solid_angles(res: int, sub: int = 8) -> np.ndarray:
    """Solid angle of each texel of a ``res × res`` map (cached).

    With the octahedron point ``p = (u, 1 − |u| − |w|, w)`` (folded below), ``dω = du dw / |p|³``
    (the Jacobian of ``p/|p|``; ``p · (∂p/∂u × ∂p/∂w) = −1``), integrated on ``sub × sub`` points.

    Parameters
    ----------
    res : int
        Texels per side.
    sub : int, optional
        Integration points per texel side.

    Returns
    -------
    numpy.ndarray
        Solid angles in sr, shape ``(res·res,)`` (texel order of :func:`texel_directions`); they sum to 4π.

    Examples
    --------
    >>> import numpy as np
    >>> round(float(texel_solid_angles(16).sum() / np.pi), 6)
    4.0
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
    """An octahedral RGB map with a one-texel border of its octahedral neighbours.

    Stored as RGBA float32 so that one 16-byte gather fetches a texel (viewed as complex128).

    Parameters
    ----------
    rgb : numpy.ndarray
        The map, shape ``(res, res, 3)`` (linear RGB; any float dtype, stored as float32).

    Attributes
    ----------
    res : int
        Texels per side of the map (without the border).
    rgba : numpy.ndarray
        The padded map, shape ``(res + 2, res + 2, 4)`` float32 (alpha 0).
    flat : numpy.ndarray
        ``rgba`` viewed as one complex128 per texel, shape ``((res + 2)²,)``.
    """

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

    def bilinear(self, x, y, z) -> np.ndarray:
        """The map bilinear across texels and folded edges, in each direction.

        Parameters
        ----------
        x, y, z : numpy.ndarray
            Direction components (planar float32 arrays of one shape ``S``).

        Returns
        -------
        numpy.ndarray
            RGB, shape ``S + (3,)`` float32.
        """
        u, w = octa_uw(x, y, z)
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


class LevelMaps:
    """Several blurred copies of one map in one flat texel array, for per-sample filtered lookups.

    Sample ``i`` reads level ``k_i`` (chosen by its footprint, :meth:`level_for`) bilinearly;
    ``res`` and ``offset`` of that level are passed per sample.

    Parameters
    ----------
    maps : list of PaddedMap
        The levels, least blurred first.
    sigmas_deg : list of float
        Each level's Gaussian blur in degrees (0 for the unblurred map), ascending.

    Attributes
    ----------
    sigma_deg : numpy.ndarray
        The levels' blurs in degrees, shape ``(K,)``.
    res : numpy.ndarray
        The levels' texels per side, shape ``(K,)`` int64.
    offset : numpy.ndarray
        Each level's first texel in ``flat``, shape ``(K,)`` int64.
    flat : numpy.ndarray
        All levels' padded texels (RGBA float32 viewed as complex128), concatenated.
    """

    def __init__(self, maps: list[PaddedMap], sigmas_deg: list[float]):
        self.sigma_deg = np.asarray(sigmas_deg, dtype=np.float64)
        self.res = np.array([m.res for m in maps], dtype=np.int64)
        sizes = (self.res + 2) ** 2
        self.offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.flat = np.concatenate([m.flat for m in maps])

    def level_for(self, sigma_deg) -> np.ndarray:
        """The least blurred level whose blur is at least ``sigma_deg``.

        Parameters
        ----------
        sigma_deg : array_like
            Each sample's footprint, in degrees (any shape ``S``).

        Returns
        -------
        numpy.ndarray
            Level indices, shape ``S`` int32: level 0 (the map itself, texels of ~1.6°) below the
            first blur, the most blurred level beyond the last.
        """
        s = np.asarray(sigma_deg, dtype=np.float64)
        ref = np.where(self.sigma_deg > 0, self.sigma_deg, 1.0)
        k = np.searchsorted(ref, s, side="left")
        return np.minimum(k, ref.size - 1).astype(np.int32)

    def bilinear(self, x, y, z, res, offset) -> np.ndarray:
        """Each sample's level, bilinear within it.

        Parameters
        ----------
        x, y, z : numpy.ndarray
            Direction components (planar float32 arrays, shape ``S``).
        res : numpy.ndarray
            Each sample's level resolution (float32, broadcast with ``x``).
        offset : numpy.ndarray
            Each sample's level offset into ``flat`` (int32 or float32, broadcast with ``x``).

        Returns
        -------
        numpy.ndarray
            RGB, shape ``S + (3,)`` float32.
        """
        u, w = octa_uw(x, y, z)
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

        def fetch(k):  # RGBA texels: the blend runs on contiguous rows of four (2× faster than on an RGB view)
            return np.take(f, k).view(np.float32).reshape((*k.shape, 4))

        c00 = fetch(i)
        top = c00 + ax * (fetch(i + 1) - c00)
        i += stride
        c10 = fetch(i)
        bot = c10 + ax * (fetch(i + 1) - c10)
        return (top + ay * (bot - top))[..., :3]
