"""Hairlines of a brushed finish for the ``anodic_film`` plugin (issue 37): fine lines along the brush axis.

A brushed surface is not a uniform anisotropic lobe: the abrasive leaves grooves of varying depth along
the brushing direction, so the width of the reflected highlight across the grain varies from line to
line, and a highlight drawn across the grain breaks into fine streaks along it. The plugin models this
as a perturbation of the across-grain roughness: ``α_v(p) = α_v · (1 + depth · (2 g(p) − 1))`` with
``g`` a value noise in [0, 1] of the position **across** the grain only (the point projected onto the
plane perpendicular to the brush axis), so it is constant along the axis: lines, not grain or glitter.
Two octaves (:data:`LINES_PER_UNIT`, per unit of scene length: the unit sphere's radius) give lines
1–4 px wide on a 256 px sphere. The lobe's mean roughness is unchanged (``g`` averages 1/2), and so is
its energy balance (each point is a normal GGX lobe).

Everything here is Dr.Jit arithmetic on the lanes of a render: an integer hash of the lattice
(no texture, no Python loop over points).
"""
from __future__ import annotations

import drjit as dr
import mitsuba as mi
import numpy as np

__all__ = ["LINES_PER_UNIT", "OCTAVE_WEIGHTS", "HAIRLINE_DEPTH", "across_basis", "line_noise"]

#: Lattice frequencies of the two octaves, cells per unit length across the grain.
LINES_PER_UNIT = (40.0, 110.0)
#: Their weights (sum 1).
OCTAVE_WEIGHTS = (0.6, 0.4)
#: The engine's ``hairline_depth`` for a brushed finish: the across-grain roughness varies by ±45 %.
HAIRLINE_DEPTH = 0.45


def across_basis(axis) -> tuple[list[float], list[float]]:
    """Two unit vectors perpendicular to ``axis`` and to each other (world space).

    Parameters
    ----------
    axis : array_like
        The brush axis (3 floats, unit length).

    Returns
    -------
    (list of float, list of float)
        The two unit vectors ``e1, e2`` (3 floats each, world space; ``e1 × e2`` along ``axis``).
    """
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    helper = np.array([0.0, 0.0, 1.0]) if abs(a[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = np.cross(a, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    return e1.tolist(), e2.tolist()


def _hash01(ix, iy, salt: int):
    """A hash of two lattice coordinates (UInt32) to [0, 1)."""
    h = ix * 0x8DA6B343 + iy * 0xD8163841 + salt
    h = h ^ (h >> 16)
    h = h * 0x7FEB352D
    h = h ^ (h >> 15)
    h = h * 0x846CA68B
    h = h ^ (h >> 16)
    return mi.Float(h >> 8) * (1.0 / 16777216.0)


def line_noise(p, e1, e2):
    """Value noise in [0, 1] of the position across the grain: a function of ``(p·e1, p·e2)`` only.

    Parameters
    ----------
    p : mitsuba.Point3f
        World positions.
    e1, e2 : list of float
        :func:`across_basis` of the brush axis.

    Returns
    -------
    mitsuba.Float
        Mean 1/2 over the surface; constant along the brush axis.
    """
    q1 = p.x * e1[0] + p.y * e1[1] + p.z * e1[2]
    q2 = p.x * e2[0] + p.y * e2[1] + p.z * e2[2]
    total = mi.Float(0.0)
    for k, (freq, weight) in enumerate(zip(LINES_PER_UNIT, OCTAVE_WEIGHTS, strict=True)):
        x, y = q1 * freq + 1000.5, q2 * freq + 1000.5  # (positive lattice coordinates)
        fx, fy = dr.floor(x), dr.floor(y)
        tx, ty = x - fx, y - fy
        sx, sy = tx * tx * (3.0 - 2.0 * tx), ty * ty * (3.0 - 2.0 * ty)
        ix, iy = mi.UInt32(fx), mi.UInt32(fy)
        v00, v10 = _hash01(ix, iy, k), _hash01(ix + 1, iy, k)
        v01, v11 = _hash01(ix, iy + 1, k), _hash01(ix + 1, iy + 1, k)
        top = v00 + (v10 - v00) * sx
        bottom = v01 + (v11 - v01) * sx
        total = total + weight * (top + (bottom - top) * sy)
    return total
