"""Shading a thin-film surface: a per-thickness colour table over cos θ_d, and the direct spectral path.

Why a table works: in both intensity models the spectrum enters only through the thin-film
reflectance ``F(λ; d, θ_d)`` on the half-vector facet, and ``θ_d`` (``cos θ_d = h·l``) is the only
angle it depends on. The rest is a wavelength-independent scalar:

* ``paper``: the published model, ``colour = XYZ(F(·; d, θ_d))`` (facet probability constant);
* ``microfacet``: ``f = D(h) G(l, v) F / (4 cos θ_l cos θ_v)``, so
  ``XYZ = XYZ(F(·; d, θ_d)) · s`` with ``s = π D G / (4 cos θ_l cos θ_v)`` (the reflectance factor,
  1 for a perfect white diffuser), times ``cos θ_l`` when shading a render (irradiance of a
  directional light on the tilted surface).

So a render builds, once per thickness, the tristimulus values of ``F`` on a uniform grid of
``cos θ_d`` (:func:`facet_colour_table`: by default 1025 nodes on [0, 1]; a render uses 129 nodes over
the range of ``cos θ_d`` its pixels span; linear interpolation) and shades each pixel by a lookup
times the scalar (:func:`shade`). Because XYZ → linear RGB is linear, the same
table can hold RGB (:meth:`FacetColourTable.to_rgb`) and the render never leaves RGB.

:func:`shade_direct` is the reference: it evaluates the full spectrum ``F(λ)`` for every pixel's
own ``θ_d`` (vectorised over pixel chunks) and integrates it with the colorimeter's weights.

XYZ scale: Y = 100 for the perfect white diffuser (colour-science's convention), as
:class:`swatch.colorimetry.colorimeter.Colorimeter` gives it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from swatch.core.choices import MODELS
from swatch.core.errors import SwatchError
from swatch.physics import microfacet

__all__ = [
    "MODELS",
    "TABLE_NODES",
    "FacetColourTable",
    "facet_colour_table",
    "check_model",
    "geometry_terms",
    "intensity",
    "shade",
    "shade_direct",
]

#: Nodes of the cos θ_d table (uniform on [0, 1]). 1025 keeps linear interpolation far inside
#: ΔE00 0.05 even at 1000 nm (checked in tests/test_render.py against the direct path).
TABLE_NODES = 1025


def check_model(model: str) -> str:
    key = str(model).strip().lower()
    if key not in MODELS:
        raise SwatchError(f"unknown intensity model {model!r}; use one of {', '.join(MODELS)}")
    return key


@dataclass(frozen=True)
class FacetColourTable:
    """Colour of the facet reflectance ``F(·; d, θ_d)`` on a uniform grid of ``cos θ_d``.

    ``cos_d`` (N,) is uniform on ``[c0, c1]`` (default [0, 1]); ``values`` (N, C) are XYZ (Y = 100
    for R = 1) under the colorimeter's observer or, after :meth:`to_rgb`, linear RGB (1 = white).
    ``display_XYZ`` (N, 3): the CIE 1931 2° XYZ of the same nodes, from which :meth:`to_rgb`
    derives RGB (display RGB is defined on 2° colorimetry). Lookups clamp to the grid's range.
    """

    thickness_nm: float
    cos_d: np.ndarray
    values: np.ndarray
    kind: str = "XYZ"
    _delta: np.ndarray = field(init=False, repr=False, compare=False)
    display_XYZ: np.ndarray | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        v = np.ascontiguousarray(self.values)
        object.__setattr__(self, "values", v)
        object.__setattr__(self, "_delta", np.ascontiguousarray(np.diff(v, axis=0)))

    @property
    def nodes(self) -> int:
        return int(self.cos_d.size)

    @property
    def c0(self) -> float:
        return float(self.cos_d[0])

    @property
    def c1(self) -> float:
        return float(self.cos_d[-1])

    def _position(self, cos_d):
        dtype = self.values.dtype.type
        c = np.asarray(cos_d)
        scale = dtype((self.nodes - 1) / (self.c1 - self.c0)) if self.c1 > self.c0 else dtype(0.0)
        return np.clip((c.astype(dtype, copy=False) - dtype(self.c0)) * scale, dtype(0.0), dtype(self.nodes - 1))

    def lookup(self, cos_d) -> np.ndarray:
        """Linearly interpolated values (..., C) at ``cos_d``."""
        x = self._position(cos_d)
        i = np.minimum(x.astype(np.int32), self.nodes - 2)
        f = (x - i)[..., None]
        return np.take(self.values, i, axis=0) + f * np.take(self._delta, i, axis=0)

    def lookup_nearest(self, cos_d) -> np.ndarray:
        """Values at the nearest node (use on a :meth:`refined` table: linear interpolation of the
        coarse table to within 1/(2·factor) of a coarse node, at the cost of one gather)."""
        x = self._position(cos_d)
        x += self.values.dtype.type(0.5)
        return np.take(self.values, x.astype(np.int32), axis=0)

    def refined(self, factor: int = 16) -> FacetColourTable:
        """The table linearly interpolated onto a ``factor`` times finer grid (same range)."""
        n = (self.nodes - 1) * int(factor) + 1
        grid = np.linspace(self.c0, self.c1, n)

        def interp(v):
            return None if v is None else np.stack([np.interp(grid, self.cos_d, v[:, k]) for k in range(v.shape[1])], -1)

        return FacetColourTable(self.thickness_nm, grid, interp(self.values).astype(self.values.dtype), kind=self.kind,
                           display_XYZ=interp(self.display_XYZ))

    def to_rgb(self, colorimeter, space: str = "srgb", dtype=np.float32) -> FacetColourTable:
        """The same table in linear RGB of ``space`` (1.0 = white), as ``dtype``, from the nodes'
        CIE 1931 2° XYZ (``display_XYZ``; the values themselves when the table is 2°)."""
        if self.kind != "XYZ":
            rgb = self.values
        else:
            if self.display_XYZ is None and colorimeter.observer != "2":
                raise SwatchError("this XYZ table has no CIE 1931 2° values to derive display RGB from")
            rgb = colorimeter.rgb_linear(self.values if self.display_XYZ is None else self.display_XYZ, space)
        return FacetColourTable(self.thickness_nm, self.cos_d, np.asarray(rgb, dtype=dtype), kind=f"RGB:{space}")

    def astype(self, dtype) -> FacetColourTable:
        return FacetColourTable(self.thickness_nm, self.cos_d, self.values.astype(dtype), kind=self.kind,
                           display_XYZ=self.display_XYZ)


def facet_colour_table(thickness_nm: float, coating, colorimeter, nodes: int = TABLE_NODES,
                       cos_range=(0.0, 1.0)) -> FacetColourTable:
    """XYZ of the thin-film reflectance over ``cos θ_d`` in ``cos_range`` (``nodes`` uniform samples).

    A render passes the range of ``cos θ_d`` its pixels span (perspective makes it narrow), so a
    small table is very dense; the default covers every geometry.
    """
    if int(nodes) < 2:
        raise SwatchError("a colour table needs at least 2 nodes")
    c0, c1 = (float(x) for x in cos_range)
    if not (0.0 <= c0 <= c1 <= 1.0):
        raise SwatchError("cos θ_d range must satisfy 0 <= c0 <= c1 <= 1")
    cos_d = np.linspace(c0, c1, int(nodes))
    R = coating.reflectance_cos(float(thickness_nm), cos_d).R  # (N, W)
    XYZ = colorimeter.XYZ(R)
    XYZ_2 = XYZ if colorimeter.observer == "2" else colorimeter.display_XYZ(R)
    return FacetColourTable(float(thickness_nm), cos_d, XYZ, kind="XYZ", display_XYZ=XYZ_2)


def _dot(a, b) -> np.ndarray:
    a = np.asarray(a)
    b = np.asarray(b)
    if b.ndim == 1:
        return a @ b
    if a.ndim == 1:
        return b @ a
    return np.einsum("...i,...i->...", a, b)


def geometry_terms(normal, light, view):
    """``(cos_l, cos_v, cos_h, cos_d)`` for unit normal, light and view vectors (..., 3).

    ``light`` and ``view`` point away from the surface; any of them may be a single (3,) vector.
    ``cos_d = h·l = sqrt((1 + l·v)/2)``; ``cos_h = n·h``.
    """
    n = np.asarray(normal)
    l = np.asarray(light)
    v = np.asarray(view)
    cos_l = _dot(n, l)
    cos_v = _dot(n, v)
    lv = _dot(l, v) if (l.ndim > 1 or v.ndim > 1) else np.asarray(l @ v)
    one = np.asarray(1.0, dtype=np.result_type(lv, np.float32))
    s = np.maximum(one + lv, 1e-12)  # |l + v|^2 / 2
    cos_d = np.sqrt(0.5 * s)
    cos_h = (cos_l + cos_v) / np.sqrt(2.0 * s)  # n·(l + v)/|l + v|
    return cos_l, cos_v, cos_h, cos_d


def intensity(cos_l, cos_v, cos_h, cos_d, model: str = "microfacet", roughness_alpha: float = 0.3,
              distribution: str = "ggx", irradiance: bool = True) -> np.ndarray:
    """The wavelength-independent factor ``s`` multiplying the table colour (see module doc).

    ``paper``: 1 where the surface is lit and seen (``cos θ_l, cos θ_v > 0``), else 0.
    ``microfacet``: ``π D G / (4 cos θ_l cos θ_v)``, times ``cos θ_l`` when ``irradiance``.
    """
    model = check_model(model)
    cl = np.asarray(cos_l)
    cv = np.asarray(cos_v)
    if model == "paper":
        return ((cl > 0) & (cv > 0)).astype(np.result_type(cl, np.float32))
    s = np.pi * microfacet.brdf_scale(cl, cv, cos_h, cos_d, roughness_alpha, distribution)
    if irradiance:
        s = s * np.maximum(cl, 0)
    return s


def shade(normal, light, view, table: FacetColourTable, model: str = "microfacet", roughness_alpha: float = 0.3,
          distribution: str = "ggx", irradiance: bool = True) -> np.ndarray:
    """Colour per pixel (..., C) by table lookup × intensity (the fast path)."""
    cos_l, cos_v, cos_h, cos_d = geometry_terms(normal, light, view)
    s = intensity(cos_l, cos_v, cos_h, cos_d, model, roughness_alpha, distribution, irradiance)
    out = table.lookup(cos_d)
    out *= np.asarray(s, dtype=out.dtype)[..., None]
    return out


def shade_direct(normal, light, view, thickness_nm: float, coating, colorimeter, model: str = "microfacet",
                 roughness_alpha: float = 0.3, distribution: str = "ggx", irradiance: bool = True,
                 chunk: int = 4096) -> np.ndarray:
    """XYZ per pixel (..., 3) from the full spectrum at each pixel's own θ_d (the reference path).

    The Airy reflectance is evaluated for every pixel on the whole wavelength grid (vectorised
    over chunks of ``chunk`` pixels to bound memory), weighted by the colorimeter and scaled by
    the same intensity factor as :func:`shade`.
    """
    cos_l, cos_v, cos_h, cos_d = (np.asarray(t, dtype=np.float64) for t in geometry_terms(normal, light, view))
    s = intensity(cos_l, cos_v, cos_h, cos_d, model, roughness_alpha, distribution, irradiance)
    shape = np.broadcast(cos_d, s).shape
    cd = np.broadcast_to(cos_d, shape).reshape(-1)
    flat_s = np.broadcast_to(s, shape).reshape(-1)
    out = np.zeros((cd.size, 3), dtype=np.float64)
    lit = np.flatnonzero(flat_s != 0)
    for start in range(0, lit.size, int(chunk)):
        idx = lit[start:start + int(chunk)]
        R = coating.reflectance_cos(float(thickness_nm), np.clip(cd[idx], 0.0, 1.0)).R  # (n, W)
        out[idx] = colorimeter.XYZ(R) * flat_s[idx, None]
    return out.reshape((*shape, 3))
