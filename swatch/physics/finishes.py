"""Named surface finishes: the microfacet roughness of polished, satin, bead-blasted and brushed
metal, defined once (#23 item 3).

A finish is the GGX roughness ``α`` of the metal under the film (the oxide follows the metal's
micro-relief: the paper's §2.2), isotropic or, for ``brushed``, two values: ``alpha_u`` along the
brushing direction (the grooves; small) and ``alpha_v`` across it (large). What each number
means, and what it is based on:

* **The lobe width.** GGX ``D`` falls to half its peak at ``tan θh = α sqrt((√2 − 1)/(1 − √2 α²))``
  (≈ 0.644 α for small α), so a reflected edge (a soft box's rim, the horizon) is blurred over
  about ``±2 θh`` around the mirror direction (:func:`highlight_half_width_deg`). Polished ±3°
  (reflections sharp), satin ±15° (recognisable but soft), bead-blasted ±44° (no image, a
  sheen), brushed ±9° along the grain and ±33° across it (the highlight is drawn out across the
  grooves).
* **A profilometer's slope.** For small α the GGX lobe is that of Beckmann with RMS slope
  ``m = α``, whose facet slopes are Gaussian with a variance of ``α²/2`` per direction; a stylus
  profile's RMS slope ``Rdq`` (ISO 4287 ``Δq``, radians) along one direction is then
  ``α / √2``, i.e. ``α ≈ √2 · Rdq`` (Beckmann & Spizzichino 1963; for an isotropic Gaussian
  surface). The table's values correspond to ``Rdq`` ≈ 1.6° (polished), 8° (satin), 20°
  (bead-blasted), 5° along / 16° across (brushed): the ranges profilometry gives for mirror-
  polished, fine-abrasive (satin), glass-bead blasted and grained (brushed, Scotch-Brite / No. 4
  style) sheet. They are **typical values, not a fit to measured anodised titanium** (none is
  shipped): with a measured ``Rdq``, give ``--roughness √2·Rdq`` instead. (``Ra``, the height
  roughness that the paper measured, 268 nm, sets whether the surface is optically rough, the
  Rayleigh criterion of :mod:`swatch.physics.rayleigh`, not the lobe width, which needs slopes.)

The brushing direction on a render: the plate's x axis (left–right in the image), the
cylinder's axis and, for the sphere and meshes, the vertical (+y) projected onto the surface
(x where the surface faces up); see :func:`brush_tangent`.

References
----------
.. [1] :cite:`Walter2007`: GGX.
.. [2] :cite:`Beckmann1963`: RMS slope of a Gaussian surface.
.. [3] :cite:`Fujii2019`: §2.2, the oxide following the metal's relief.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swatch.core.choices import FINISHES
from swatch.core.errors import SwatchError

__all__ = ["FINISHES", "Finish", "get_finish", "finish_or_roughness", "highlight_half_width_deg", "brush_tangent",
           "isotropic_finish", "HAIRLINE_SLOPE", "HAIRLINE_OCTAVES", "HAIRLINE_STRETCH", "hairline_slope",
           "brush_coordinates", "tilt_normals"]


@dataclass(frozen=True)
class Finish:
    """A finish: GGX ``alpha_u`` along the brushing direction and ``alpha_v`` across it (equal
    when isotropic), what it looks like and what the numbers are based on.

    Parameters
    ----------
    name : str
        The finish's name (one of ``swatch.core.choices.FINISHES``, or ``roughness α`` for
        :func:`isotropic_finish`).
    alpha_u, alpha_v : float
        GGX roughness α (dimensionless) along and across the grain.
    description : str
        What it looks like.

    References
    ----------
    :cite:`Walter2007` (GGX).
    """

    name: str
    alpha_u: float
    alpha_v: float
    description: str

    @property
    def anisotropic(self) -> bool:
        """Whether the lobe differs along and across the grain (``alpha_u != alpha_v``: brushed).

        Returns
        -------
        bool
            True for a brushed lobe (``alpha_u != alpha_v``), False for an isotropic one.
        """
        return self.alpha_u != self.alpha_v

    @property
    def roughness_alpha(self) -> float:
        """The isotropic GGX α of the same lobe area: ``sqrt(alpha_u alpha_v)`` (α itself when isotropic).

        Returns
        -------
        float
            Rounded to 6 decimals.
        """
        return round(math.sqrt(self.alpha_u * self.alpha_v), 6)

    def metadata(self) -> dict:
        """The ``finish`` entry of an output's metadata.

        Returns
        -------
        dict
            Name and description; the two α and the grain's direction when anisotropic, else the α.
        """
        out: dict = {"name": self.name, "description": self.description}
        if self.anisotropic:
            out.update({"alpha_along": self.alpha_u, "alpha_across": self.alpha_v,
                        "direction": "along the plate's x axis, the cylinder's axis, the sphere's and a mesh's "
                                     "vertical projected on the surface (GGX anisotropic, Smith height-correlated)"})
        else:
            out["alpha"] = self.alpha_u
        out["basis"] = ("typical profilometer slopes for the finish (alpha ~ sqrt(2) Rdq), not a fit to measured "
                        "anodised titanium; docs/finishes.md")
        return out

    def label(self) -> str:
        """A short label for sheet headers.

        Returns
        -------
        str
            ``satin (GGX 0.2)``, ``brushed (GGX 0.12 along, 0.4 across the grain)``.
        """
        if self.anisotropic:
            return f"{self.name} (GGX {self.alpha_u:g} along, {self.alpha_v:g} across the grain)"
        return f"{self.name} (GGX {self.alpha_u:g})"


_TABLE = {
    "polished": Finish("polished", 0.04, 0.04, "mirror polish: sharp reflections (highlight ±3°)"),
    "satin": Finish("satin", 0.2, 0.2, "satin (fine abrasive): soft but recognisable reflections (±15°)"),
    "bead-blasted": Finish("bead-blasted", 0.5, 0.5, "glass-bead blasted: no reflected image, an even sheen (±44°)"),
    "brushed": Finish("brushed", 0.12, 0.4, "brushed (grained): highlights drawn out across the grain "
                                            "(±9° along, ±33° across)"),
}
assert tuple(_TABLE) == FINISHES, "choices.FINISHES names the table's finishes"


def get_finish(name: str) -> Finish:
    """The finish of a name (case-insensitive), or SwatchError naming the choices.

    Parameters
    ----------
    name : str
        One of ``swatch.core.choices.FINISHES``; surrounding blanks and case are ignored.

    Returns
    -------
    Finish
        The finish's name, GGX ``alpha_u`` / ``alpha_v`` (dimensionless, along / across the grain) and description.

    Raises
    ------
    SwatchError
        For an unknown name.
    """
    key = str(name).strip().lower()
    if key not in _TABLE:
        raise SwatchError(f"unknown finish {name!r}; use one of {', '.join(FINISHES)}")
    return _TABLE[key]


def isotropic_finish(roughness_alpha: float) -> Finish:
    """An unnamed isotropic finish of a given GGX α (``--roughness``).

    Parameters
    ----------
    roughness_alpha : float
        GGX α (dimensionless), used for both ``alpha_u`` and ``alpha_v`` (not range-checked here).

    Returns
    -------
    Finish
        Named ``roughness <α>``.
    """
    a = float(roughness_alpha)
    return Finish(f"roughness {a:g}", a, a, "GGX roughness given directly")


def finish_or_roughness(finish: str | None, roughness: float | None) -> Finish | None:
    """The finish of ``--finish`` (or a spec's ``finish``); SwatchError when a roughness is given
    too (one of the two); None when neither.

    Parameters
    ----------
    finish : str or None
        A finish's name (:func:`get_finish`).
    roughness : float or None
        A GGX α given instead (only checked for being given).

    Returns
    -------
    Finish or None
        None when ``finish`` is None (whatever ``roughness`` is).

    Raises
    ------
    SwatchError
        When both are given, or for an unknown finish.
    """
    if finish is None:
        return None
    if roughness is not None:
        raise SwatchError("give either a finish or a roughness, not both (a finish sets the roughness)")
    return get_finish(finish)


def highlight_half_width_deg(roughness_alpha) -> np.ndarray:
    """Half width (degrees) of the reflected highlight of a GGX lobe: ``2 θh`` with
    ``tan θh = α sqrt((√2 − 1)/(1 − √2 α²))``, the half-vector angle at which ``D`` is half its
    peak (from ``D(θh)/D(0) = α⁴ / (cos²θh (α² + tan²θh))²``).

    Parameters
    ----------
    roughness_alpha : array_like
        GGX α (> 0).

    Returns
    -------
    numpy.ndarray
        Degrees, the shape of the input.
    """
    a = np.asarray(roughness_alpha, dtype=np.float64)
    return np.degrees(2.0 * np.arctan(a * np.sqrt((np.sqrt(2.0) - 1.0) / (1.0 - np.sqrt(2.0) * a * a))))


#: World direction a shape is brushed along (projected onto its surface).
_BRUSH_AXIS = {"flat": (1.0, 0.0, 0.0), "cylinder": (0.0, 1.0, 0.0), "sphere": (0.0, 1.0, 0.0),
               "mesh": (0.0, 1.0, 0.0)}


def brush_axis(shape: str) -> tuple[float, float, float]:
    """The world axis a shape is brushed along (projected onto each point's tangent plane by
    :func:`brush_tangent`): x for ``flat``, y for ``cylinder``, ``sphere``, ``mesh`` and any other name.

    Parameters
    ----------
    shape : str
        A shape name (:data:`swatch.core.choices.SHAPES`) or ``mesh``.

    Returns
    -------
    tuple of float
        The unit axis (x, y, z) in world space (y up).
    """
    return tuple(float(c) for c in _BRUSH_AXIS.get(shape, (0.0, 1.0, 0.0)))  # type: ignore[return-value]


def brush_tangent(shape: str, normals) -> np.ndarray:
    """Unit tangents (P, 3) along the brushing direction at unit ``normals`` (P, 3) of a shape:
    its world axis (:data:`_BRUSH_AXIS`) projected onto the tangent plane; where that axis is
    within ~1° of the normal, x is projected instead.

    Parameters
    ----------
    shape : str
        ``flat`` (brushed along x), ``cylinder``, ``sphere`` or ``mesh`` (along y); any other
        name is brushed along y.
    normals : array_like, shape (..., 3)
        Unit surface normals (world space); reshaped to (P, 3).

    Returns
    -------
    numpy.ndarray, float32, shape (P, 3)
        Unit tangents.
    """
    n = np.asarray(normals, dtype=np.float32).reshape(-1, 3)
    axis = np.asarray(brush_axis(shape), dtype=np.float32)
    t = axis - (n @ axis)[:, None] * n
    norm = np.linalg.norm(t, axis=1)
    bad = norm < 0.02
    if bad.any():
        x = np.array([1.0, 0.0, 0.0], dtype=np.float32)
        alt = x - (n[bad] @ x)[:, None] * n[bad]
        t[bad] = alt
        norm[bad] = np.linalg.norm(alt, axis=1)
    return t / np.maximum(norm, np.float32(1e-12))[:, None]


# -- hairlines ------------------------------------------------------------------------------------------------
# A brushed sheet shows fine lines along the grain: bands across it where the abrasive cut a little deeper or
# shallower, so the facets there lean a little more one way or the other. The finish's alpha_u / alpha_v are the
# slopes finer than a pixel; the hairlines are the part of the relief the eye resolves. They are drawn as a tilt
# of the facet normal about the grain (a slope across it), a procedural field that varies quickly across the
# grain and slowly along it: the film's colour still comes from the film model at each facet's own geometry.

#: Bound of the slope (tan of the tilt across the grain) of the hairline field: ±0.2 (±11°), RMS about 0.05 (2.9°);
#: small beside the finish's across-grain RMS slope (alpha_v / sqrt 2 = 0.28): the lines are a visible part of
#: the relief, not a new finish. A typical value chosen for appearance, not a fit to a measured profile.
HAIRLINE_SLOPE = 0.2
#: The field's octaves: (lines per object unit across the grain, weight); the weights sum to 1. The shapes are
#: about 2 units across, so the finest octave gives lines ~1/300 of the part wide.
HAIRLINE_OCTAVES = ((40.0, 0.45), (95.0, 0.35), (160.0, 0.20))
#: How much longer a line's cell is along the grain than across (a line's length / width).
HAIRLINE_STRETCH = 60.0


def _lattice_hash(i, j) -> np.ndarray:
    """A value in [-1, 1) per integer lattice point (i, j): an integer hash (uint32 arithmetic, wrapping), the same
    bits as the live view's GLSL ``hairHash`` (swatch/catalog/web/view.js)."""
    h = ((np.asarray(i, dtype=np.int64) & 0xFFFFFFFF).astype(np.uint32) * np.uint32(0x27D4EB2D)
         ^ (np.asarray(j, dtype=np.int64) & 0xFFFFFFFF).astype(np.uint32) * np.uint32(0x165667B1))
    h = (h ^ (h >> np.uint32(15))) * np.uint32(0x2C1B3C6D)
    h = (h ^ (h >> np.uint32(12))) * np.uint32(0x297A2D39)
    h = h ^ (h >> np.uint32(15))
    return (h >> np.uint32(8)).astype(np.float64) * (2.0 / 16777216.0) - 1.0


def _value_noise(x, y) -> np.ndarray:
    """Smooth value noise: the lattice's hash values, interpolated with the smoothstep weight ``3f² − 2f³``."""
    i0, j0 = np.floor(x), np.floor(y)
    fx, fy = x - i0, y - j0
    sx, sy = fx * fx * (3.0 - 2.0 * fx), fy * fy * (3.0 - 2.0 * fy)
    i, j = i0.astype(np.int64), j0.astype(np.int64)
    a = _lattice_hash(i, j) + sx * (_lattice_hash(i + 1, j) - _lattice_hash(i, j))
    b = _lattice_hash(i, j + 1) + sx * (_lattice_hash(i + 1, j + 1) - _lattice_hash(i, j + 1))
    return a + sy * (b - a)


def hairline_slope(across, along) -> np.ndarray:
    """The hairline field: the facets' slope across the grain (tan of their tilt about the brushing direction) at
    surface coordinates ``across`` and ``along`` the grain (object units), a sum of the value-noise octaves of
    :data:`HAIRLINE_OCTAVES` stretched :data:`HAIRLINE_STRETCH` times along the grain, scaled to
    :data:`HAIRLINE_SLOPE`. Deterministic (a fixed integer hash): the same point has the same slope in every run.

    Parameters
    ----------
    across, along : array_like
        Surface coordinates (object units; broadcast together).

    Returns
    -------
    numpy.ndarray, float64
        Slopes in [−HAIRLINE_SLOPE, HAIRLINE_SLOPE], the broadcast shape.
    """
    a, b = np.broadcast_arrays(np.asarray(across, dtype=np.float64), np.asarray(along, dtype=np.float64))
    out = np.zeros(a.shape, dtype=np.float64)
    for k, (freq, weight) in enumerate(HAIRLINE_OCTAVES):
        out += weight * _value_noise(a * freq + 17.0 * k, b * (freq / HAIRLINE_STRETCH) + 31.0 * k)
    return HAIRLINE_SLOPE * out


def brush_coordinates(shape: str, points) -> tuple[np.ndarray, np.ndarray] | None:
    """Surface coordinates across and along the grain of points on a shape (object units), for
    :func:`hairline_slope`: the plate (brushed along x) ``(z, x)``; the cylinder and the sphere (brushed along
    the vertical y) the arc ``atan2(x, z)`` about the vertical (their radius is 1) and ``y``. None for other
    shapes (a mesh has no such parameterisation here: no hairlines).

    Parameters
    ----------
    shape : str
        ``flat``, ``cylinder`` or ``sphere`` (any other: None).
    points : array_like, shape (..., 3)
        Points on the surface (render world, y up).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray) or None
        ``across``, ``along``, the points' shape less its last axis.
    """
    p = np.asarray(points, dtype=np.float64)
    if shape == "flat":
        return p[..., 2], p[..., 0]
    if shape in ("cylinder", "sphere"):
        return np.arctan2(p[..., 0], p[..., 2]), p[..., 1]
    return None


def tilt_normals(normals, tangents, slope) -> np.ndarray:
    """Unit normals tilted across the grain: ``normalize(n + s (n × t))`` for unit normals ``n``, unit brushing
    tangents ``t`` (perpendicular to ``n``, :func:`brush_tangent`) and slopes ``s``; ``t`` stays a tangent of the
    tilted normal.

    Parameters
    ----------
    normals, tangents : array_like, shape (P, 3)
        Unit surface normals and unit brushing tangents (perpendicular to them), one per point.
    slope : array_like, shape (P,)
        tan of the tilt (:func:`hairline_slope`).

    Returns
    -------
    numpy.ndarray, float32, shape (P, 3)
        The tilted unit normals.
    """
    n = np.asarray(normals, dtype=np.float32).reshape(-1, 3)
    t = np.asarray(tangents, dtype=np.float32).reshape(-1, 3)
    s = np.asarray(slope, dtype=np.float32).reshape(-1, 1)
    m = n + s * np.cross(n, t)
    return m / np.maximum(np.linalg.norm(m, axis=1, keepdims=True), np.float32(1e-12))
