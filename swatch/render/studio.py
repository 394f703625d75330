"""The built-in studio's radiance (``--environment studio``): soft boxes over dark walls and a light floor.

A photographic studio for metal, defined in code; :mod:`swatch.render.environment` samples it into
its octahedral map (:func:`swatch.render.environment.get_environment`).
"""
from __future__ import annotations

import numpy as np

__all__ = ["studio_radiance"]


# -- the studio -----------------------------------------------------------------------------------
#: Rectangular soft boxes (a plane ``axis = at`` and the box's extent on two axes) and their
#: radiance, in units before normalisation; see :func:`studio_radiance`. The camera of a render
#: is on the +z side, 20° above the horizon for the curved shapes and 36° from the zenith for the
#: plate.
_BOXES = (
    # overhead key: a 2.0 × 1.8 panel 2 units above, over the object and towards the back: the
    # plate mirrors it in its near half and the dark ceiling beyond (its edge crosses the plate)
    ("y", 2.0, ("x", -1.0, 1.0), ("z", -1.0, 0.4), 6.0),
    # tall strip on the camera's left (−x), floor to above head height: a bright vertical band on
    # the cylinder and the sphere (they mirror the horizon band)
    ("x", -2.0, ("z", -0.4, 0.4), ("y", -1.2, 2.0), 6.0),
    # weaker strip on the right (+x), a little behind
    ("x", 2.0, ("z", -0.9, -0.1), ("y", -1.2, 1.6), 3.5),
)
#: Walls and ceiling: dark grey at the zenith, lighter towards the horizon (spill from the boxes).
_WALL_ZENITH = 0.2
_WALL_HORIZON = 0.3
#: The floor: a sweep, brightest under the object (the key's pool of light), darker far away,
#: with a step at the horizon (lighter floor, darker wall above it).
_FLOOR_NEAR = 0.9
_FLOOR_FAR = 0.5
#: Width of a soft box's edge (0 to full radiance, in the box's plane; ~4° seen from the object):
#: diffusers fall off at their rims, and a hard edge would show the fixed samples' pattern.
_EDGE = 0.15


def studio_radiance(directions) -> np.ndarray:
    """Radiance of the built-in studio in unit ``directions`` (before normalisation).

    A photographic studio for metal: dark-grey walls and ceiling (0.15 at the zenith, 0.45 at the
    horizon), a light floor (0.7 at the horizon to 1.1 straight down) that meets the walls in a
    visible horizon, and three soft boxes (:data:`_BOXES`): a large overhead key (8) whose edge
    crosses the plate's mirror directions, a tall strip on the camera's left (6) and a weaker one
    on the right (3.5), both standing on the floor, so that curved shapes show vertical bright
    bands and the horizon. Neutral (grey) throughout, so the finish shows its own colour.

    Parameters
    ----------
    directions : array_like, shape (..., 3)
        Unit vectors (z up, the plate's normal).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Linear RGB radiance, relative (the environment normalises it).

    Examples
    --------
    >>> bool(studio_radiance([0.0, 0.0, -1.0])[0] > studio_radiance([0.0, 0.6, 0.8])[0])  # the floor is lighter
    True
    """
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    up = np.clip(y, 0.0, 1.0)
    down = np.clip(-y, 0.0, 1.0)
    L = np.where(y >= 0, _WALL_ZENITH + (_WALL_HORIZON - _WALL_ZENITH) * (1.0 - up) ** 2,
                 _FLOOR_FAR + (_FLOOR_NEAR - _FLOOR_FAR) * np.sqrt(down))
    comp = {"x": x, "y": y, "z": z}
    for axis, at, (a1, lo1, hi1), (a2, lo2, hi2), value in _BOXES:
        c = comp[axis]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = at / c
            p1 = comp[a1] * t
            p2 = comp[a2] * t
            cover = (_ramp((p1 - lo1) / _EDGE) * _ramp((hi1 - p1) / _EDGE)
                     * _ramp((p2 - lo2) / _EDGE) * _ramp((hi2 - p2) / _EDGE))
        cover = np.where(t > 0, np.nan_to_num(cover), 0.0)
        L = L + cover * (value - L)
    return np.repeat(L[..., None], 3, axis=-1)


def _ramp(x):
    """0 below −1/2, 1 above 1/2, smoothstep between (a soft box's diffuser edge)."""
    u = np.clip(np.asarray(x) + 0.5, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)
