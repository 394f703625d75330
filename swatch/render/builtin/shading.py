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
#: ΔE00 0.05 even at 1000 nm (checked in tests/render/test_render.py against the direct path).
TABLE_NODES = 1025


def check_model(model: str) -> str:
    """A shading model's name of :data:`swatch.core.choices.MODELS` (case-insensitive).

    Parameters
    ----------
    model : str
        ``paper`` or ``microfacet``.

    Returns
    -------
    str
        The model's name, lower case.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other name.
    """
    return MODELS.validate(model)


@dataclass(frozen=True)
class FacetColourTable:
    """Colour of the facet reflectance ``F(·; d, θ_d)`` on a uniform grid of ``cos θ_d``.

    Lookups clamp to the grid's range.

    Parameters
    ----------
    thickness_nm : float
        Oxide thickness, nm.
    cos_d : numpy.ndarray, shape (N,)
        Uniform on ``[c0, c1]`` (default [0, 1]).
    values : numpy.ndarray, shape (N, C)
        XYZ (Y = 100 for R = 1) under the colorimeter's observer or, after :meth:`to_rgb`, linear RGB (1 = white).
    kind : str
        ``"XYZ"`` or ``"RGB:<space>"``.
    display_XYZ : numpy.ndarray, shape (N, 3), optional
        CIE 1931 2° XYZ of the same nodes, from which :meth:`to_rgb` derives RGB (display RGB is
        defined on 2° colorimetry).
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
        """N, the number of nodes.

        Returns
        -------
        int
            Number of cos θ_d nodes.
        """
        return int(self.cos_d.size)

    @property
    def c0(self) -> float:
        """The grid's first ``cos θ_d``.

        Returns
        -------
        float
            The table's first cos θ_d.
        """
        return float(self.cos_d[0])

    @property
    def c1(self) -> float:
        """The grid's last ``cos θ_d``.

        Returns
        -------
        float
            The table's last cos θ_d.
        """
        return float(self.cos_d[-1])

    def _position(self, cos_d):
        dtype = self.values.dtype.type
        c = np.asarray(cos_d)
        scale = dtype((self.nodes - 1) / (self.c1 - self.c0)) if self.c1 > self.c0 else dtype(0.0)
        return np.clip((c.astype(dtype, copy=False) - dtype(self.c0)) * scale, dtype(0.0), dtype(self.nodes - 1))

    def lookup(self, cos_d) -> np.ndarray:
        """Linearly interpolated values at ``cos_d``.

        Parameters
        ----------
        cos_d : array_like, shape S
            Facet incidence cosines (clamped to the grid).

        Returns
        -------
        numpy.ndarray, shape S + (C,)
            The table's C values (XYZ or linear RGB, as :attr:`kind`) at each cosine.
        """
        x = self._position(cos_d)
        i = np.minimum(x.astype(np.int32), self.nodes - 2)
        f = (x - i)[..., None]
        return np.take(self.values, i, axis=0) + f * np.take(self._delta, i, axis=0)

    def refined(self, factor: int = 16) -> FacetColourTable:
        """The table linearly interpolated onto a ``factor`` times finer grid (same range).

        Parameters
        ----------
        factor : int
            Nodes per original interval.

        Returns
        -------
        FacetColourTable
            The table linearly interpolated onto ``factor`` times as many nodes.
        """
        n = (self.nodes - 1) * int(factor) + 1
        grid = np.linspace(self.c0, self.c1, n)

        def interp(v):
            return None if v is None else np.stack([np.interp(grid, self.cos_d, v[:, k]) for k in range(v.shape[1])], -1)

        return FacetColourTable(self.thickness_nm, grid, interp(self.values).astype(self.values.dtype), kind=self.kind,
                           display_XYZ=interp(self.display_XYZ))

    def to_rgb(self, colorimeter, space: str = "srgb", dtype=np.float32) -> FacetColourTable:
        """The same table in linear RGB of ``space`` (1.0 = white), from the nodes' CIE 1931 2° XYZ.

        Parameters
        ----------
        colorimeter : swatch.colorimetry.colorimeter.Colorimeter
            Its illuminant's white is adapted to the space's (Bradford).
        space : str
            An RGB space (``srgb``, ``display-p3``, ``rec2020`` …).
        dtype : numpy dtype
            Precision of the returned table.

        Returns
        -------
        FacetColourTable
            Kind ``RGB:<space>``.

        Raises
        ------
        swatch.core.errors.SwatchError
            A 10° XYZ table without its 2° values.
        """
        if self.kind != "XYZ":
            rgb = self.values
        else:
            if self.display_XYZ is None and colorimeter.observer != "2":
                raise SwatchError("this XYZ table has no CIE 1931 2° values to derive display RGB from")
            rgb = colorimeter.rgb_linear(self.values if self.display_XYZ is None else self.display_XYZ, space)
        return FacetColourTable(self.thickness_nm, self.cos_d, np.asarray(rgb, dtype=dtype), kind=f"RGB:{space}")

    def astype(self, dtype) -> FacetColourTable:
        """The table with its values cast to ``dtype``.

        Parameters
        ----------
        dtype : numpy dtype
            Precision of the returned table.

        Returns
        -------
        FacetColourTable
            The same table in ``dtype``.
        """
        return FacetColourTable(self.thickness_nm, self.cos_d, self.values.astype(dtype), kind=self.kind,
                           display_XYZ=self.display_XYZ)


def facet_colour_table(thickness_nm: float, coating, colorimeter, nodes: int = TABLE_NODES,
                       cos_range=(0.0, 1.0)) -> FacetColourTable:
    """XYZ of the thin-film reflectance over ``cos θ_d`` in ``cos_range`` (``nodes`` uniform samples).

    A render passes the range of ``cos θ_d`` its pixels span (perspective makes it narrow), so a
    small table is very dense; the default covers every geometry.

    Parameters
    ----------
    thickness_nm : float
        Oxide thickness, nm.
    coating : swatch.physics.model.Coating
        The film on its substrate.
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the XYZ table.
    nodes : int
        At least 2.
    cos_range : (float, float)
        ``0 ≤ c0 ≤ c1 ≤ 1``.

    Returns
    -------
    FacetColourTable
        XYZ of the film's reflectance over cos θ_d (one thickness), for lookups.

    Raises
    ------
    swatch.core.errors.SwatchError
        Fewer than 2 nodes or a range outside [0, 1].

    References
    ----------
    :cite:`Fujii2019` (the half-vector model, eqs. 2–5).

    Examples
    --------
    >>> from swatch.colorimetry.colorimeter import get_colorimeter
    >>> from swatch.physics.model import get_coating
    >>> c = get_coating()
    >>> t = facet_colour_table(140.0, c, get_colorimeter(c.wavelength_nm), nodes=5)
    >>> t.nodes, t.values.shape, t.to_rgb(get_colorimeter(c.wavelength_nm)).kind
    (5, (5, 3), 'RGB:srgb')
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
    """The cosines the shading needs, for unit normal, light and view vectors.

    ``cos_d = h·l = sqrt((1 + l·v)/2)`` (the facet's incidence angle, Fujii et al. eq. 5); ``cos_h = n·h``.

    Parameters
    ----------
    normal, light, view : array_like, shape (..., 3) or (3,)
        Unit vectors; ``light`` and ``view`` point away from the surface.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray, numpy.ndarray)
        ``cos_l``, ``cos_v``, ``cos_h``, ``cos_d``, broadcast.

    Examples
    --------
    >>> [round(float(x), 4) for x in geometry_terms([0, 0, 1], [0, 0, 1], [0, 0, 1])]
    [1.0, 1.0, 1.0, 1.0]
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
    """The wavelength-independent factor ``s`` multiplying the table colour (see the module doc).

    Parameters
    ----------
    cos_l, cos_v, cos_h, cos_d : array_like
        From :func:`geometry_terms`.
    model : str
        ``paper``: 1 where the surface is lit and seen, else 0. ``microfacet``:
        ``π D G / (4 cos θ_l cos θ_v)`` (the reflectance factor; 1 for a white diffuser).
    roughness_alpha : float
        Microfacet α.
    distribution : str
        ``ggx`` or ``beckmann``.
    irradiance : bool
        Times ``cos θ_l`` (irradiance of a directional light on the tilted surface).

    Returns
    -------
    numpy.ndarray
        The intensity factor s (dimensionless; zero where unlit or unseen), the broadcast shape.

    References
    ----------
    :cite:`Walter2007`.
    """
    return MODELS[model](np.asarray(cos_l), np.asarray(cos_v), cos_h, cos_d, roughness_alpha, distribution, irradiance)


def _paper_intensity(cl, cv, cos_h, cos_d, roughness_alpha, distribution, irradiance) -> np.ndarray:
    """The ``paper`` model's :func:`intensity`: 1 where the surface is lit and seen (facet probability constant)."""
    return ((cl > 0) & (cv > 0)).astype(np.result_type(cl, np.float32))


def _microfacet_intensity(cl, cv, cos_h, cos_d, roughness_alpha, distribution, irradiance) -> np.ndarray:
    """The ``microfacet`` model's :func:`intensity`: ``π D G / (4 cos θ_l cos θ_v)``, times ``cos θ_l``."""
    s = np.pi * microfacet.brdf_scale(cl, cv, cos_h, cos_d, roughness_alpha, distribution)
    if irradiance:
        s = s * np.maximum(cl, 0)
    return s


MODELS.implement("paper", _paper_intensity)
MODELS.implement("microfacet", _microfacet_intensity)


def shade(normal, light, view, table: FacetColourTable, model: str = "microfacet", roughness_alpha: float = 0.3,
          distribution: str = "ggx", irradiance: bool = True) -> np.ndarray:
    """Colour per pixel by table lookup × intensity (the fast path).

    Parameters
    ----------
    normal, light, view : array_like, shape (..., 3)
        Unit vectors; ``light`` and ``view`` point away from the surface.
    table : FacetColourTable
        The thickness's colour over cos θ_d (:func:`facet_colour_table`).
    model, roughness_alpha, distribution, irradiance
        As :func:`intensity`.

    Returns
    -------
    numpy.ndarray, shape (..., C)
        The table's kind (XYZ or linear RGB).
    """
    cos_l, cos_v, cos_h, cos_d = geometry_terms(normal, light, view)
    s = intensity(cos_l, cos_v, cos_h, cos_d, model, roughness_alpha, distribution, irradiance)
    out = table.lookup(cos_d)
    out *= np.asarray(s, dtype=out.dtype)[..., None]
    return out


def shade_direct(normal, light, view, thickness_nm: float, coating, colorimeter, model: str = "microfacet",
                 roughness_alpha: float = 0.3, distribution: str = "ggx", irradiance: bool = True,
                 chunk: int = 4096) -> np.ndarray:
    """XYZ per pixel from the full spectrum at each pixel's own θ_d (the reference path).

    The Airy reflectance is evaluated for every pixel on the whole wavelength grid (vectorised over
    chunks of ``chunk`` pixels to bound memory), weighted by the colorimeter and scaled by the same
    intensity factor as :func:`shade`.

    Parameters
    ----------
    normal, light, view : array_like, shape (..., 3)
        Unit vectors; ``light`` and ``view`` point away from the surface.
    thickness_nm : float
        Film thickness, nm.
    coating : swatch.physics.model.Coating
        Film, substrate, index scale and wavelength grid.
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the XYZ, on the coating's grid.
    model, roughness_alpha, distribution, irradiance
        As :func:`intensity`.
    chunk : int
        Pixels per chunk.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        XYZ (Y = 100 for a white diffuser).
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
