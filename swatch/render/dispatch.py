"""The render layer's one entry point: :func:`render_swatch` checks a render request once and hands it
to an engine.

Engines
-------
``builtin`` (the default) is the table-lookup renderer of this package: :mod:`swatch.render.pointlight`
for one directional light, :mod:`swatch.render.env_render` when an environment lights the swatch.
``mitsuba`` is Mitsuba 3's spectral path tracer with the exact thin-film BSDF
(:mod:`swatch.render.mitsuba.engine`), imported only when it is asked for (Mitsuba and Dr.Jit are an
optional dependency that takes seconds to load). The lighting of either is resolved once
(:func:`swatch.render.lighting.resolve_lighting`) into one :class:`swatch.render.lighting.Lighting`.
Every engine returns a :class:`swatch.render.image.SwatchImage`. How a further engine plugs in is
described in docs/DEVNOTES.md.
"""
from __future__ import annotations

from swatch.colorimetry.colorimeter import check_rgb_space
from swatch.core.errors import SwatchError
from swatch.physics import microfacet
from swatch.physics.model import check_thickness_nm
from swatch.render import env_render, shading
from swatch.render.image import SwatchImage, check_background, check_finish_lighting, check_size_px, finish_meta
from swatch.render.lighting import Sun, check_engine, resolve_lighting
from swatch.render.metadata import coating_and_colorimeter, common_metadata
from swatch.render.pointlight import render_pointlight
from swatch.render.scene import check_shape, make_scene

__all__ = ["DISPATCHED_ENGINES", "render_swatch"]

#: Engines :func:`render_swatch` runs (of :data:`swatch.core.choices.ENGINES`; ``mitsuba`` is reached
#: through :mod:`swatch.render.mitsuba.engine` for now).
DISPATCHED_ENGINES = ("builtin",)


def render_swatch(thickness_nm: float, shape: str, size_px: int = 512, light_deg: float = 45.0,
                  roughness_alpha: float = 0.3, model: str = "microfacet", coating=None, colorimeter=None,
                  space: str = "srgb", distribution: str = "ggx", workers: int | None = None,
                  environment=None, background: str | None = None, view_deg: float | None = None,
                  view_azimuth_deg: float = 0.0, mesh=None, finish=None, engine: str = "builtin",
                  spp: int = 64, seed: int = 0, sun: Sun | None = None, progress=None,
                  denoise: bool = True) -> SwatchImage:
    """Render one swatch with an engine (builtin: :mod:`swatch.render.pointlight` and
    :mod:`swatch.render.env_render` for scene, units and exposure; mitsuba:
    :mod:`swatch.render.mitsuba.engine`).

    Parameters
    ----------
    thickness_nm : float
        Oxide thickness (nm).
    shape : str
        ``plate``, ``cylinder`` or ``sphere`` (:data:`swatch.core.choices.SHAPES`); ``"mesh"`` with ``mesh``.
    size_px : int
        Image size, pixels per side.
    light_deg : float
        Polar angle of the builtin engine's point light (degrees from the normal).
    roughness_alpha : float
        Microfacet roughness α (GGX or Beckmann).
    model, distribution : str
        The intensity model (``microfacet`` or the paper's) and the facet distribution.
    coating, colorimeter
        A :class:`swatch.physics.model.Coating` and a :class:`swatch.colorimetry.colorimeter.Colorimeter`
        (defaults: TiO2 on Ti, D65 and CIE 1931 2°).
    space : str
        RGB space of ``linear_rgb``: ``srgb`` or ``acescg``.
    workers : int, optional
        Threads for the point-light engine.
    environment
        The lighting: a :class:`swatch.render.lighting.Lighting` resolved for ``engine`` (reuse one
        across thicknesses), or what :func:`swatch.render.lighting.resolve_lighting` takes (a name, a
        map's path, an :class:`swatch.render.environment.Environment`). None: builtin's point light,
        mitsuba's studio.
    background : str, optional
        ``grey``, ``white`` or (with an environment) ``environment``; default grey (mitsuba under
        studio and sun: environment, the only choice there).
    view_deg, view_azimuth_deg : float
        The camera (:func:`swatch.render.scene.make_scene`; degrees).
    mesh
        A :class:`swatch.render.mesh.MeshShape` rendered instead of ``shape`` (which is then ``"mesh"``).
    finish
        A :class:`swatch.physics.finishes.Finish`: its roughness replaces ``roughness_alpha``; an
        anisotropic one (brushed) is rendered under an environment only.
    engine : str
        ``builtin`` or ``mitsuba`` (:data:`swatch.core.choices.ENGINES`).
    spp, seed : int
        mitsuba: samples per pixel and the seed (the same values give byte-identical images).
    sun : swatch.render.lighting.Sun, optional
        mitsuba: the sun of ``environment="sun"``.
    progress : callable(done, total), optional
        mitsuba: called after each pass with the passes done and their number.
    denoise : bool
        mitsuba: denoise the image (Intel Open Image Denoise guided by the render's albedo and normal
        buffers; the default) or keep the raw path-traced estimate (:mod:`swatch.render.mitsuba.denoise`).

    Returns
    -------
    SwatchImage
        ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in ``space``, premultiplied by the
        ``coverage`` (H, W); ``display_rgb`` (H, W, 3) uint8 sRGB, exposure applied and composited on
        the background; ``metadata``.
    """
    engine = check_engine(engine)
    d = float(check_thickness_nm(float(thickness_nm)))
    shape = "mesh" if mesh is not None else check_shape(shape)
    if engine == "mitsuba":
        return _render_mitsuba(d, shape, size_px, roughness_alpha, model, coating, colorimeter, space, distribution,
                               environment, background, view_deg, view_azimuth_deg, mesh, finish, spp, seed, sun,
                               progress, denoise)
    size = check_size_px(size_px)
    if finish is not None:
        roughness_alpha = finish.roughness_alpha
        check_finish_lighting(finish, environment, model, distribution, size)
    model = shading.check_model(model)
    roughness_alpha = microfacet.check_roughness_alpha(roughness_alpha)
    distribution = microfacet.check_distribution(distribution)
    space = check_rgb_space(space)
    coating, colorimeter = coating_and_colorimeter(coating, colorimeter)
    background = check_background("grey" if background is None else background)
    light = resolve_lighting("none" if environment is None else environment, "builtin", sun, model, distribution,
                             size, background, view_deg, view_azimuth_deg)
    scene = make_scene(shape, light_deg, view_deg, view_azimuth_deg, mesh)
    meta = common_metadata(d, coating, colorimeter, model, distribution, roughness_alpha)
    if light.environment is not None:
        return env_render.render_swatch_environment(
            d, scene, light.environment, shape=shape, size=size, background=background,
            roughness_alpha=roughness_alpha, coating=coating, colorimeter=colorimeter, space=space,
            meta=meta | finish_meta(finish), camera=(light_deg, view_deg, view_azimuth_deg), finish=finish)
    img = render_pointlight(d, shape, scene, size, background, roughness_alpha, model, distribution, coating,
                            colorimeter, space, meta, light_deg, workers, mesh)
    img.metadata |= finish_meta(finish)
    return img


def _render_mitsuba(d: float, shape: str, size_px, roughness_alpha, model, coating, colorimeter, space, distribution,
                    environment, background, view_deg, view_azimuth_deg, mesh, finish, spp, seed, sun,
                    progress, denoise=True) -> SwatchImage:
    """The ``mitsuba`` branch of :func:`render_swatch` (thickness and shape checked there)."""
    from swatch.render.mitsuba.engine import render_swatch_mitsuba  # Mitsuba loads only when asked for

    if model != "microfacet":
        raise SwatchError("the mitsuba engine renders the microfacet model; use `model='microfacet'`")
    if finish is not None:
        lobe = (finish.alpha_u, finish.alpha_v) if finish.anisotropic else finish.roughness_alpha
    else:
        lobe = microfacet.check_roughness_alpha(roughness_alpha)
    coating, colorimeter = coating_and_colorimeter(coating, colorimeter)
    if getattr(coating, "overcoats", ()):
        raise SwatchError("the mitsuba engine renders one film on the metal; drop the overcoats")
    light = resolve_lighting(environment, "mitsuba", sun, view_deg=view_deg, view_azimuth_deg=view_azimuth_deg)
    img = render_swatch_mitsuba(d, shape, size_px, spp, seed, light, None, lobe, distribution, coating.film,
                                coating.substrate, coating.film_index_scale, coating, colorimeter, space, background,
                                view_deg, view_azimuth_deg, mesh, progress=progress, spread=coating.spread,
                                denoise=denoise)
    img.metadata |= finish_meta(finish)
    return img
