"""The pinhole camera of a swatch render (:class:`Camera`): its frame, its square window on the image
plane at distance 1, and the rays through pixel coordinates."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Camera", "unit", "FRAME_FILL"]

#: How much of the square window a framed object fills (:meth:`Camera.fitted`; the catalog page's live view
#: frames its shapes the same way, swatch.catalog.explorer.scene_data).
FRAME_FILL = 0.86


def unit(v) -> np.ndarray:
    """``v`` normalised to length 1.

    Parameters
    ----------
    v : array_like, shape (3,)
        A nonzero 3-vector.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``v`` scaled to length 1 (float64).

    Examples
    --------
    >>> unit([3.0, 0.0, 4.0]).tolist()
    [0.6, 0.0, 0.8]
    """
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


@dataclass(frozen=True)
class Camera:
    """A pinhole camera with a square window on the image plane at distance 1.

    Attributes
    ----------
    position : numpy.ndarray, shape (3,)
        The eye, in scene units (the object fits the unit sphere).
    right, up, forward : numpy.ndarray, shape (3,)
        Orthonormal frame.
    cx, cy : float
        The window's centre, tan units.
    half : float
        The window's half width, tan units.
    """

    position: np.ndarray
    right: np.ndarray
    up: np.ndarray
    forward: np.ndarray
    cx: float = 0.0
    cy: float = 0.0
    half: float = 0.5

    @classmethod
    def look_at(cls, position, target=(0.0, 0.0, 0.0), world_up=(0.0, 1.0, 0.0)) -> Camera:
        """A camera at ``position`` looking at ``target`` (``world_up`` fixes the roll).

        Parameters
        ----------
        position, target, world_up : array_like, shape (3,)
            The eye, the point looked at (scene units) and the direction that is up in the image.

        Returns
        -------
        Camera
            A pinhole camera looking from ``position`` at ``target``.
        """
        pos = np.asarray(position, dtype=np.float64)
        fwd = unit(np.asarray(target, dtype=np.float64) - pos)
        right = unit(np.cross(fwd, world_up))
        up = np.cross(right, fwd)
        return cls(pos, right, up, fwd)

    def fitted(self, points, fill: float = FRAME_FILL) -> Camera:
        """The camera with its window framing ``points``, filling ``fill`` of the square.

        Parameters
        ----------
        points : array_like, shape (N, 3)
            Points of the object (scene units) that must be in view.
        fill : float
            Fraction of the image side the points span (0–1).

        Returns
        -------
        Camera
            The same camera with its field of view narrowed to frame the points.
        """
        q = np.asarray(points, dtype=np.float64) - self.position
        z = q @ self.forward
        u = (q @ self.right) / z
        w = (q @ self.up) / z
        half = 0.5 * max(u.max() - u.min(), w.max() - w.min()) / fill
        return Camera(self.position, self.right, self.up, self.forward,
                      0.5 * (u.max() + u.min()), 0.5 * (w.max() + w.min()), half)

    def window(self, x, y, size: int, dtype=np.float32):
        """Image-plane coordinates ``(u, w)`` and ``inv = 1/|(u, w, 1)|`` for pixel coordinates (broadcast:
        a row and a column vector give the grid).

        Parameters
        ----------
        x, y : array_like
            Column and row, pixels.
        size : int
            Image side, pixels.
        dtype : numpy dtype
            Precision of the returned arrays (float32 for renders).

        Returns
        -------
        (numpy.ndarray, numpy.ndarray, numpy.ndarray)
            ``(u, w, inv)``: the rays' coordinates in the image plane (at unit distance) and 1/|(u, w, 1)|, the
            broadcast shape of ``x`` and ``y``.
        """
        s = 2.0 * self.half / size
        u = np.asarray(x, dtype=dtype) * dtype(s) + dtype(self.cx - self.half)
        w = dtype(self.cy + self.half) - np.asarray(y, dtype=dtype) * dtype(s)
        inv = dtype(1.0) / np.sqrt(u * u + (w * w + dtype(1.0)))
        return u, w, inv

    def dot(self, u, w, inv, vec) -> np.ndarray:
        """``d · vec`` for the unit rays of :meth:`window` (a broadcast sum, then one product).

        Parameters
        ----------
        u, w, inv : numpy.ndarray
            From :meth:`window`.
        vec : array_like, shape (3,)
            A direction in scene coordinates.

        Returns
        -------
        numpy.ndarray
            The dot product of each ray's unit direction with ``vec`` (the window's shape).
        """
        t = inv.dtype.type
        vec = np.asarray(vec, dtype=np.float64)
        return (u * t(self.right @ vec) + (w * t(self.up @ vec) + t(self.forward @ vec))) * inv

    def directions(self, x, y, size: int, dtype=np.float32):
        """Unit ray directions for continuous pixel coordinates (broadcast), as planar arrays.

        Parameters
        ----------
        x, y : array_like
            Pixels.
        size : int
            Image side, pixels.
        dtype : numpy dtype
            Precision of the returned arrays.

        Returns
        -------
        (numpy.ndarray, numpy.ndarray, numpy.ndarray)
            dx, dy, dz.
        """
        u, w, inv = self.window(x, y, size, dtype)
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
