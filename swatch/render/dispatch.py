"""The render layer's one entry point: :func:`render_swatch` checks a render request once and hands it
to an engine.

Engines
-------
``builtin`` (the default) is the table-lookup renderer of this package: :mod:`swatch.render.pointlight`
for one directional light, :mod:`swatch.render.env_render` when an environment lights the swatch.
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
from swatch.render.metadata import coating_and_colorimeter, common_metadata
from swatch.render.pointlight import render_pointlight
from swatch.render.scene import check_shape, make_scene

__all__ = ["DISPATCHED_ENGINES", "render_swatch"]

#: Engines :func:`render_swatch` runs (of :data:`swatch.core.choices.ENGINES`; ``mitsuba`` is reached
#: through :mod:`swatch.mitsuba.engine` for now).
DISPATCHED_ENGINES = ("builtin",)


def render_swatch(thickness_nm: float, shape: str, size_px: int = 512, light_deg: float = 45.0,
                  roughness_alpha: float = 0.3, model: str = "microfacet", coating=None, colorimeter=None,
                  space: str = "srgb", distribution: str = "ggx", workers: int | None = None,
                  environment=None, background: str = "grey", view_deg: float | None = None,
                  view_azimuth_deg: float = 0.0, mesh=None, finish=None, engine: str = "builtin") -> SwatchImage:
    """Render one swatch (see :mod:`swatch.render.pointlight` for scene, units and exposure).

    Parameters
    ----------
    thickness_nm : float
        Oxide thickness (nm).
    shape : str
        ``plate``, ``cylinder`` or ``sphere`` (:data:`swatch.core.choices.SHAPES`); ``"mesh"`` with ``mesh``.
    size_px : int
        Image size, pixels per side.
    light_deg : float
        Polar angle of the light (degrees from the normal).
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
        None (the point light) or an environment (name, path or
        :class:`swatch.render.environment.Environment`).
    background : str
        ``grey``, ``white`` or (with an environment) ``environment``.
    view_deg, view_azimuth_deg : float
        The camera (:func:`swatch.render.scene.make_scene`; degrees).
    mesh
        A :class:`swatch.render.mesh.MeshShape` rendered instead of ``shape`` (which is then ``"mesh"``).
    finish
        A :class:`swatch.physics.finishes.Finish`: its roughness replaces ``roughness_alpha``; an
        anisotropic one (brushed) is rendered under an environment only.
    engine : str
        One of :data:`DISPATCHED_ENGINES`.

    Returns
    -------
    SwatchImage
        ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in ``space``, premultiplied by the
        ``coverage`` (H, W); ``display_rgb`` (H, W, 3) uint8 sRGB, exposure applied and composited on
        the background; ``metadata``.
    """
    if engine not in DISPATCHED_ENGINES:
        raise SwatchError(f"render engine {engine!r} is not run by render_swatch; use one of "
                          f"{', '.join(DISPATCHED_ENGINES)}")
    d = float(check_thickness_nm(float(thickness_nm)))
    shape = "mesh" if mesh is not None else check_shape(shape)
    size = check_size_px(size_px)
    if finish is not None:
        roughness_alpha = finish.roughness_alpha
        check_finish_lighting(finish, environment, model, distribution, size)
    model = shading.check_model(model)
    roughness_alpha = microfacet.check_roughness_alpha(roughness_alpha)
    distribution = microfacet.check_distribution(distribution)
    space = check_rgb_space(space)
    coating, colorimeter = coating_and_colorimeter(coating, colorimeter)
    scene = make_scene(shape, light_deg, view_deg, view_azimuth_deg, mesh)
    background = check_background(background)
    meta = common_metadata(d, coating, colorimeter, model, distribution, roughness_alpha)
    if environment is not None:
        return env_render.render_swatch_environment(
            d, shape, scene, size, environment, background, roughness_alpha, model, distribution, coating, colorimeter,
            space, meta | finish_meta(finish), (light_deg, view_deg, view_azimuth_deg), finish)
    img = render_pointlight(d, shape, scene, size, background, roughness_alpha, model, distribution, coating,
                            colorimeter, space, meta, light_deg, workers, mesh)
    img.metadata |= finish_meta(finish)
    return img
