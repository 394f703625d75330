"""The ``anodic_film`` BSDF for Mitsuba 3: the exact thin film on a rough metal.

A rough conductor whose facets carry the anodic film: on the facet of the half vector ``m``, the
Fresnel factor is the Airy reflectance (:func:`swatch.render.mitsuba.film.airy_reflectance`) of air /
film / substrate with the tables' complex dispersive indices at each sampled wavelength (the
film's real part times ``film_index_scale``), s and p averaged — the physics of
:mod:`swatch.physics.optics` and the built-in renderer. The microfacet part is Mitsuba's own
:class:`mitsuba.MicrofacetDistribution` (GGX or Beckmann, isotropic or anisotropic, visible-normal
sampling), with Smith shadowing either height-correlated (``shadowing = "correlated"``, the
default: the built-in renderer's ``G₂ = 1 / (1 + Λ_i + Λ_o)``, with ``Λ = 1/G₁ − 1`` from Mitsuba's
own ``G₁``) or separable (``"separable"``: ``G₁(i) G₁(o)``, what Mitsuba's ``roughconductor`` uses).

The scene-dictionary keys are :data:`PARAMETERS`, one row each (the key, Mitsuba's property type, the
default, what it means, and whether ``traverse`` exposes it and whether it is differentiable, as Mitsuba's
own plugin tables say); docs/mitsuba.md's table is generated from it (docs/conf.py).

The tables are looked up at the sampled wavelengths in one shared grid (:mod:`swatch.render.mitsuba.tables`:
``np.interp`` of each table, in constant time); wavelengths outside a table's range are clamped to its end
(the tables cover the visible range that matters; Mitsuba samples 360–830 nm). Directions below the
horizon (either side, of the surface or of the facet) give 0, never NaN.
"""
from __future__ import annotations

import math
from typing import Any

import drjit as dr
import mitsuba as mi
import numpy as np

from swatch.core.choices import DISTRIBUTIONS
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_FILM_INDEX_SCALE, MAX_THICKNESS_NM, MIN_FILM_INDEX_SCALE, MIN_ROUGHNESS_ALPHA
from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, load_material
from swatch.physics.spread import SIGMA_CAP_OF_THICKNESS, ThicknessSpread, node_count, spread_nodes
from swatch.render.mitsuba.film import airy_reflectance
from swatch.render.mitsuba.hairlines import across_basis, line_noise
from swatch.render.mitsuba.setup import SPECTRAL_VARIANTS
from swatch.render.mitsuba.tables import SpectralTables

__all__ = ["PLUGIN_NAME", "SHADOWING", "PARAMETERS", "register", "index_tables", "check_parameters"]

PLUGIN_NAME = "anodic_film"
SHADOWING = ("correlated", "separable")
#: The plugin's scene-dictionary keys: ``keys`` (one row may name keys given together), Mitsuba's property
#: ``type``, the ``default``, the ``description`` (Markdown), and ``exposed`` / ``differentiable``: whether
#: ``traverse`` puts the key in ``mi.traverse``'s parameters and without ``mi.ParamFlags.NonDifferentiable``
#: (tests/mitsuba/test_mitsuba_parameters.py reads both from Mitsuba). A literal, so that the docs read it
#: without importing Mitsuba (docs/conf.py writes docs/generated/mitsuba_parameters.md from it).
PARAMETERS: tuple[dict, ...] = (
    {"keys": ("thickness_nm",), "type": "float or texture", "default": "0", "exposed": True, "differentiable": False,
     "description": "film thickness in nm, 0 to 1000; a texture (`eval_1`: give bitmaps `\"raw\": True`) for "
                    "spatially varying films"},
    {"keys": ("film", "substrate"), "type": "string", "default": "TiO2-Siefke, Ti-Johnson", "exposed": False,
     "differentiable": False, "description": "table names as in `swatch materials list`"},
    {"keys": ("film_index_scale",), "type": "float", "default": "1", "exposed": False, "differentiable": False,
     "description": "factor on the film's real index, 0.5–1.5 (a process profile's `film_index_scale`)"},
    {"keys": ("distribution",), "type": "string", "default": "ggx", "exposed": False, "differentiable": False,
     "description": "`\"ggx\"` or `\"beckmann\"` (Mitsuba's `MicrofacetDistribution`, visible-normal sampling)"},
    {"keys": ("alpha",), "type": "float or texture", "default": "0.3", "exposed": False, "differentiable": False,
     "description": "isotropic roughness, 0.001–1"},
    {"keys": ("alpha_u", "alpha_v"), "type": "float or texture", "default": "none (`alpha`)", "exposed": False,
     "differentiable": False,
     "description": "anisotropic roughness, given together instead of `alpha` (brushed: along the surface's "
                    "tangent `dp_du` and bitangent, or along `brush_axis`)"},
    {"keys": ("brush_axis",), "type": "vector", "default": "none (`dp_du`)", "exposed": False,
     "differentiable": False,
     "description": "a world direction (3 floats) an anisotropic lobe's `alpha_u` follows, projected onto the "
                    "tangent plane at each point (world x where it is within ~1° of the normal), as the built-in "
                    "engine's `brush_tangent`; `--engine mitsuba` sets it for brushed finishes (x on the plate, y "
                    "elsewhere); ignored by an isotropic lobe"},
    {"keys": ("hairline_depth",), "type": "float", "default": "0 (a uniform lobe)", "exposed": False,
     "differentiable": False,
     "description": "brushed hairlines, with `brush_axis` and an anisotropic lobe: the across-grain roughness "
                    "varies by ± `hairline_depth` (0 to 0.9) from line to line along the axis"},
    {"keys": ("shadowing",), "type": "string", "default": "correlated", "exposed": False, "differentiable": False,
     "description": "`\"correlated\"` (height-correlated Smith, the built-in renderer's) or `\"separable\"` "
                    "(G₁·G₁, what `roughconductor` uses)"},
    {"keys": ("spread_nm", "spread_fraction"), "type": "float", "default": "0, 0 (a uniform film)",
     "exposed": False, "differentiable": False,
     "description": "the film's thickness spread (issue 19): F averaged incoherently over a normal distribution "
                    "of local thickness, σ = min(spread_nm + spread_fraction × d, d/3), by the built-in model's "
                    "Gauss–Hermite nodes (the node count from the phase spread at 360 nm, the shortest "
                    "wavelength Mitsuba samples; docs/processes.md)"},
    {"keys": ("two_sided",), "type": "boolean", "default": "false (one-sided, like Mitsuba's conductors)",
     "exposed": False, "differentiable": False,
     "description": "`true`: both faces carry the film, as `{\"type\": \"twosided\", \"material\": …}` around "
                    "the plugin gives it (the same values, pdf and samples, tested), but traced once: "
                    "`--engine mitsuba` uses it, and its render kernels are about a third smaller and compile "
                    "about 0.5 s sooner"},
)
#: The span of the tables kept around the wavelengths Mitsuba samples (360–830 nm), in nm.
_TABLE_SPAN_NM = (300.0, 900.0)
#: The shortest wavelength a spectral Mitsuba variant samples (nm): it sets the spread's node count.
_SHORTEST_SAMPLED_NM = 360.0
_REGISTERED: set[str] = set()


def index_tables(film: str, substrate: str, film_index_scale: float = 1.0) -> SpectralTables:
    """The film's (real part scaled) and the substrate's n and k on one grid, for lookups at sampled wavelengths.

    Parameters
    ----------
    film, substrate : str
        Table names (:func:`swatch.physics.materials.load_material`).
    film_index_scale : float, optional
        Multiplies the film's real index.

    Returns
    -------
    swatch.render.mitsuba.tables.SpectralTables
        ``(n_film, k_film, n_substrate, k_substrate)`` over the wavelengths both tables cover within
        :data:`_TABLE_SPAN_NM` (lookups outside are clamped to it).

    Raises
    ------
    SwatchError
        For a table of the wrong role.
    """
    f, s = load_material(film), load_material(substrate)
    for mat, role in ((f, "film"), (s, "substrate")):
        if mat.role != role:
            raise SwatchError(f"{mat.name} is a {mat.role} table, not a {role}; see `swatch materials list`")
    lo = max(f.wavelength_range_nm[0], s.wavelength_range_nm[0], _TABLE_SPAN_NM[0])
    hi = min(f.wavelength_range_nm[1], s.wavelength_range_nm[1], _TABLE_SPAN_NM[1])
    return SpectralTables([(f.wavelength_nm, f.n * film_index_scale), (f.wavelength_nm, f.k),
                           (s.wavelength_nm, s.n), (s.wavelength_nm, s.k)], lo, hi)


def _flag(props, name: str) -> bool:
    """A boolean scene-dictionary entry (default False)."""
    value = props.get(name, False)
    if not isinstance(value, bool):
        raise SwatchError(f"anodic_film: {name} must be true or false, got {value!r}")
    return value


def check_parameters(thickness_nm: float, film_index_scale: float, distribution: str, shadowing: str) -> None:
    """Check the plugin's parameters (a scene file's, untrusted).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm, from 0 to ``MAX_THICKNESS_NM``.
    film_index_scale : float
        Factor on the film's real index, ``MIN_FILM_INDEX_SCALE`` to ``MAX_FILM_INDEX_SCALE`` (0.5–1.5).
    distribution, shadowing : str
        One of :data:`swatch.core.choices.DISTRIBUTIONS`, one of :data:`SHADOWING`.

    Raises
    ------
    SwatchError
        Naming the plugin's parameter out of range.
    """
    if not (math.isfinite(thickness_nm) and 0.0 <= thickness_nm <= MAX_THICKNESS_NM):
        raise SwatchError(f"anodic_film: thickness_nm must be from 0 to {MAX_THICKNESS_NM:g}, got {thickness_nm!r}")
    if not (math.isfinite(film_index_scale) and MIN_FILM_INDEX_SCALE <= film_index_scale <= MAX_FILM_INDEX_SCALE):
        raise SwatchError(f"anodic_film: film_index_scale must be from {MIN_FILM_INDEX_SCALE:g} to "
                          f"{MAX_FILM_INDEX_SCALE:g}, got {film_index_scale!r}")
    if distribution not in DISTRIBUTIONS.names():  # the plugin's properties: as spelt
        raise SwatchError(f"anodic_film: distribution must be one of {', '.join(DISTRIBUTIONS)}, got {distribution!r}")
    if shadowing not in SHADOWING:
        raise SwatchError(f"anodic_film: shadowing must be one of {', '.join(SHADOWING)}, got {shadowing!r}")


def _float_or_texture(props, name: str, default: float):
    """A float property as a texture (validated when it is a number), or the texture given."""
    if name in props:
        value = props.get(name)
        if isinstance(value, int | float):
            return float(value), props.get_unbounded_texture(name, float(value))
        return None, props.get_unbounded_texture(name, default)
    return default, props.get_unbounded_texture(name, default)


def _define_class():
    """The plugin class for the current variant (Mitsuba's base classes are per variant)."""

    class AnodicFilmBSDF(mi.BSDF):
        """See the module documentation of :mod:`swatch.render.mitsuba.bsdf`."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            film = str(props.get("film", DEFAULT_FILM))
            substrate = str(props.get("substrate", DEFAULT_SUBSTRATE))
            scale = float(props.get("film_index_scale", 1.0))
            distribution = str(props.get("distribution", "ggx")).lower()
            shadowing = str(props.get("shadowing", "correlated")).lower()
            d0, self.thickness = _float_or_texture(props, "thickness_nm", 0.0)
            check_parameters(0.0 if d0 is None else d0, scale, distribution, shadowing)
            if ("alpha_u" in props) or ("alpha_v" in props):
                if not (("alpha_u" in props) and ("alpha_v" in props)) or ("alpha" in props):
                    raise SwatchError("anodic_film: give alpha, or both alpha_u and alpha_v")
                a_u, self.alpha_u = _float_or_texture(props, "alpha_u", 0.3)
                a_v, self.alpha_v = _float_or_texture(props, "alpha_v", 0.3)
                alphas = [a for a in (a_u, a_v) if a is not None]
            else:
                a, self.alpha_u = _float_or_texture(props, "alpha", 0.3)
                self.alpha_v = self.alpha_u
                alphas = [] if a is None else [a]
            for a in alphas:
                if not (math.isfinite(a) and MIN_ROUGHNESS_ALPHA <= a <= 1.0):
                    raise SwatchError(f"anodic_film: roughness alpha must be from {MIN_ROUGHNESS_ALPHA:g} to 1, "
                                      f"got {a!r}")
            self.tables = index_tables(film, substrate, scale)
            try:
                self.spread = ThicknessSpread(float(props.get("spread_nm", 0.0)),
                                              float(props.get("spread_fraction", 0.0)))
            except (TypeError, ValueError):
                raise SwatchError("anodic_film: spread_nm and spread_fraction must be numbers") from None
            self.spread_nodes = None
            if not self.spread.is_zero:
                d_max = MAX_THICKNESS_NM if d0 is None else d0
                sigma_max = min(self.spread.spread_nm + self.spread.spread_fraction * d_max,
                                SIGMA_CAP_OF_THICKNESS * d_max)
                n_max = float(np.max(load_material(film).n)) * scale
                z, w = spread_nodes(node_count(sigma_max, n_max, _SHORTEST_SAMPLED_NM))
                self.spread_nodes = [(float(zi), float(wi)) for zi, wi in zip(z, w, strict=True)]
                if dr.is_jit_v(mi.Float):
                    self.spread_arrays = (mi.Float([zi for zi, _ in self.spread_nodes]),
                                          mi.Float([wi for _, wi in self.spread_nodes]))
            self.brush_axis = None
            if "brush_axis" in props:
                axis = np.asarray(props.get("brush_axis"), dtype=np.float64).reshape(-1)
                if axis.size != 3 or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) == 0:
                    raise SwatchError("anodic_film: brush_axis must be three finite numbers, not all 0")
                isotropic = "alpha" in props or (len(alphas) == 2 and alphas[0] == alphas[1])
                if not isotropic:  # an isotropic lobe has no direction (and keeps its code path)
                    self.brush_axis = (axis / np.linalg.norm(axis)).tolist()
            self.hairlines = None
            depth = float(props.get("hairline_depth", 0.0))
            if not (math.isfinite(depth) and 0.0 <= depth <= 0.9):
                raise SwatchError(f"anodic_film: hairline_depth must be from 0 to 0.9, got {depth!r}")
            if depth > 0 and self.brush_axis is not None:
                self.hairlines = (depth, *across_basis(self.brush_axis))
            self.two_sided = _flag(props, "two_sided")
            self.film, self.substrate, self.scale = film, substrate, scale
            self.type = mi.MicrofacetType.GGX if distribution == "ggx" else mi.MicrofacetType.Beckmann
            self.distribution_name, self.shadowing = distribution, shadowing
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            if self.two_sided:
                flags = flags | mi.BSDFFlags.BackSide
            self.m_components = [flags]
            self.m_flags = flags

        # -- the pieces ---------------------------------------------------------------------------
        def _lit_side(self, si):
            """``si`` seen from its lit side, and where that is the back face (None: one-sided). A two-sided
            film's back face is its front face mirrored, as Mitsuba's ``twosided`` does it (``wi.z`` and
            ``wo.z`` negated together), traced once rather than once a side."""
            if not self.two_sided:
                return si, None
            back = mi.Frame3f.cos_theta(si.wi) < 0
            si = mi.SurfaceInteraction3f(si)
            si.wi = mi.Vector3f(si.wi.x, si.wi.y, dr.abs(si.wi.z))
            return si, back

        @staticmethod
        def _mirror(back, w):
            """A local direction mirrored through the surface where ``back`` (no-op for a one-sided film)."""
            if back is None:
                return w
            return mi.Vector3f(w.x, w.y, dr.select(back, -w.z, w.z))

        def _distr(self, si, active):
            alpha_v = self.alpha_v.eval_1(si, active)
            if self.hairlines is not None:  # across-grain roughness varying from line to line along the axis
                depth, e1, e2 = self.hairlines
                alpha_v = alpha_v * (1.0 + depth * (2.0 * line_noise(si.p, e1, e2) - 1.0))
            return mi.MicrofacetDistribution(self.type, self.alpha_u.eval_1(si, active), alpha_v, True)

        def _fresnel(self, si, cos_m, active):
            """Airy reflectance on the facet at the sampled wavelengths (clamped into the tables)."""
            n1, k1, n2, k2 = self.tables.eval(si.wavelengths, active)
            d = dr.maximum(self.thickness.eval_1(si, active), 0.0)
            cos = mi.UnpolarizedSpectrum(cos_m)
            if self.spread_nodes is None:
                return airy_reflectance(cos, si.wavelengths, n1, k1, n2, k2, d)
            sigma = dr.minimum(self.spread.spread_nm + self.spread.spread_fraction * d, SIGMA_CAP_OF_THICKNESS * d)
            wl = si.wavelengths
            if not dr.is_jit_v(mi.Float):  # scalar variants: a plain loop over the quadrature's nodes
                R = 0.0
                for z, w in self.spread_nodes:
                    R = R + w * airy_reflectance(cos, wl, n1, k1, n2, k2, dr.maximum(d + z * sigma, 0.0))
                return R
            # JIT variants: one symbolic loop over the nodes (the Airy formula is traced and compiled once,
            # not once per node: an unrolled loop of ~20 nodes took ~60 s to compile, this ~2 s)
            zs, ws = self.spread_arrays

            def body(i, R):
                z = dr.gather(mi.Float, zs, i, active)
                w = dr.gather(mi.Float, ws, i, active)
                term = airy_reflectance(cos, wl, n1, k1, n2, k2, dr.maximum(d + z * sigma, 0.0))
                return i + 1, mi.UnpolarizedSpectrum(R + w * term)

            count, lanes = len(self.spread_nodes), dr.width(cos_m)
            state: tuple[Any, Any] = (dr.zeros(mi.UInt32, lanes), dr.zeros(mi.UnpolarizedSpectrum, lanes))
            _, R = dr.while_loop(state, lambda i, R: i < count, body, labels=("i", "R"), label="anodic_film_spread")
            return R

        def _brush(self, si):
            """(cos, sin) of the brushing tangent's angle in the shading frame (None: the frame's own s)."""
            if self.brush_axis is None:
                return None
            a = si.sh_frame.to_local(mi.Vector3f(*self.brush_axis))
            x = si.sh_frame.to_local(mi.Vector3f(1.0, 0.0, 0.0))
            ok = a.x * a.x + a.y * a.y >= 0.02 * 0.02  # brush_tangent's fallback to world x
            tx, ty = dr.select(ok, a.x, x.x), dr.select(ok, a.y, x.y)
            len2 = tx * tx + ty * ty
            inv = dr.rsqrt(dr.maximum(len2, 1e-30))
            unset = len2 < 1e-12  # no shading frame (a bare BSDF query): the frame's own s
            return dr.select(unset, 1.0, tx * inv), dr.select(unset, 0.0, ty * inv)

        @staticmethod
        def _to_brush(rot, w):
            """A local vector in the brushing frame (x along the tangent)."""
            if rot is None:
                return w
            c, s = rot
            return mi.Vector3f(c * w.x + s * w.y, c * w.y - s * w.x, w.z)

        @staticmethod
        def _from_brush(rot, w):
            if rot is None:
                return w
            c, s = rot
            return mi.Vector3f(c * w.x - s * w.y, s * w.x + c * w.y, w.z)

        def _shadowing(self, distr, wi, wo, m):
            g_i, g_o = distr.smith_g1(wi, m), distr.smith_g1(wo, m)
            if self.shadowing == "separable":
                return g_i * g_o, g_i
            den = g_i + g_o - g_i * g_o  # 1 / (1 + Λi + Λo) with Λ = 1/G1 − 1
            return dr.select(den > 0, g_i * g_o * dr.rcp(dr.maximum(den, 1e-30)), 0.0), g_i

        # -- the interface ------------------------------------------------------------------------
        def sample(self, ctx, si, sample1, sample2, active=True):
            si, back = self._lit_side(si)
            cos_i = mi.Frame3f.cos_theta(si.wi)
            active = mi.Bool(active) & (cos_i > 0)
            bs = dr.zeros(mi.BSDFSample3f)
            distr = self._distr(si, active)
            rot = self._brush(si)
            wi_b = self._to_brush(rot, si.wi)
            m_b, pdf = distr.sample(wi_b, sample2)
            m = self._from_brush(rot, m_b)
            bs.wo = mi.reflect(si.wi, m)
            bs.eta = 1.0  # type: ignore[assignment]
            bs.sampled_component = 0  # type: ignore[assignment]
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)  # type: ignore[assignment]
            dot_om = dr.dot(bs.wo, m)
            active &= (pdf > 0) & (mi.Frame3f.cos_theta(bs.wo) > 0) & (dot_om > 0)
            bs.pdf = dr.select(active, pdf * dr.rcp(dr.maximum(4.0 * dot_om, 1e-30)), 0.0)
            G, g_i = self._shadowing(distr, wi_b, self._to_brush(rot, bs.wo), m_b)
            weight = dr.select(g_i > 0, G * dr.rcp(dr.maximum(g_i, 1e-30)), 0.0)  # G / G1(wi) (VNDF)
            F = self._fresnel(si, dr.dot(si.wi, m), active)
            enabled = ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            bs.wo = self._mirror(back, bs.wo)
            return bs, dr.select(active & enabled, mi.Spectrum(F * weight), mi.Spectrum(0.0))

        def _eval_pdf(self, si, wo, active):
            si, back = self._lit_side(si)
            wo = self._mirror(back, wo)
            cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            active = mi.Bool(active) & (cos_i > 0) & (cos_o > 0)
            m = dr.normalize(wo + si.wi)
            active &= (dr.dot(si.wi, m) > 0) & (dr.dot(wo, m) > 0)
            distr = self._distr(si, active)
            rot = self._brush(si)
            m_b = self._to_brush(rot, m)
            D = distr.eval(m_b)
            G, g_i = self._shadowing(distr, self._to_brush(rot, si.wi), self._to_brush(rot, wo), m_b)
            inv4 = dr.rcp(dr.maximum(4.0 * cos_i, 1e-30))
            F = self._fresnel(si, dr.dot(si.wi, m), active)
            value = dr.select(active, mi.Spectrum(F * (D * G * inv4)), mi.Spectrum(0.0))
            pdf = dr.select(active, D * g_i * inv4, 0.0)
            return value, pdf

        def eval(self, ctx, si, wo, active=True):
            value, _ = self._eval_pdf(si, wo, active)
            return dr.select(ctx.is_enabled(mi.BSDFFlags.GlossyReflection), value, mi.Spectrum(0.0))

        def pdf(self, ctx, si, wo, active=True):
            _, pdf = self._eval_pdf(si, wo, active)
            return dr.select(ctx.is_enabled(mi.BSDFFlags.GlossyReflection), pdf, 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            value, pdf = self._eval_pdf(si, wo, active)
            on = ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            return dr.select(on, value, mi.Spectrum(0.0)), dr.select(on, pdf, 0.0)

        def eval_diffuse_reflectance(self, si, active=True):
            """The film's directional reflectance colour for denoising buffers (Mitsuba's ``aov`` integrator's
            ``albedo``): the Airy reflectance of the film on its metal at the incidence angle ``|cos θ_i|``
            (the facet along the normal). Smooth over the surface and free of sampling noise; it carries the
            interference colour, so a denoiser guided by it keeps the colour boundaries of the film; with
            hairlines, their pattern at a third of their roughness contrast."""
            cos_i = dr.abs(mi.Frame3f.cos_theta(si.wi))
            active = mi.Bool(active)
            F = self._fresnel(si, cos_i, active)
            if self.hairlines is not None:  # the lines' contrast, so that the denoiser keeps them as texture
                depth, e1, e2 = self.hairlines
                F = F * (1.0 + (depth / 3.0) * (2.0 * line_noise(si.p, e1, e2) - 1.0))
            return dr.select(active, mi.Spectrum(F), mi.Spectrum(0.0))

        def traverse(self, callback):
            callback.put("thickness_nm", self.thickness, mi.ParamFlags.NonDifferentiable)

        def to_string(self):
            return (f"AnodicFilmBSDF[film={self.film}, substrate={self.substrate}, film_index_scale={self.scale:g}, "
                    f"distribution={self.distribution_name}, shadowing={self.shadowing}, "
                    f"spread_nm={self.spread.spread_nm:g}, spread_fraction={self.spread.spread_fraction:g}, "
                    f"two_sided={str(self.two_sided).lower()}]")

    return AnodicFilmBSDF


def register() -> None:
    """Register BSDF type ``anodic_film`` for Mitsuba's current variant (a spectral one; idempotent).

    Call after ``mitsuba.set_variant(...)``; registering again after switching variants defines
    the plugin for the new variant.

    Raises
    ------
    SwatchError
        When the current variant is not spectral.
    """
    variant = mi.variant()
    if variant not in SPECTRAL_VARIANTS:
        raise SwatchError(f"anodic_film needs a spectral Mitsuba variant ({', '.join(SPECTRAL_VARIANTS)}); "
                          f"the current one is {variant!r}: call mitsuba.set_variant('llvm_ad_spectral') first")
    if variant in _REGISTERED:
        return
    cls = _define_class()
    mi.register_bsdf(PLUGIN_NAME, cls)
    _REGISTERED.add(variant)
