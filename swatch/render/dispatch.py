"""The render layer's one entry point: :func:`render_swatch` checks a render request once
(:func:`swatch.render.request.render_request`) and hands it to an engine of :data:`ENGINES`.

Engines
-------
An engine is a function ``engine(request, progress) -> SwatchImage`` of a checked
:class:`swatch.render.request.RenderRequest` and an optional ``progress(done, total)`` callback; it
renders what the request holds and checks nothing again. :data:`ENGINES` maps a name to it:

``builtin`` (the default) is the table-lookup renderer of this package (:func:`render_builtin`):
:mod:`swatch.render.builtin.pointlight` for one directional light, :mod:`swatch.render.builtin.env_render` when an
environment lights the swatch. ``mitsuba`` is Mitsuba 3's spectral path tracer with the exact thin-film
BSDF (:func:`swatch.render.mitsuba.engine.render_mitsuba`), imported only when it is asked for (Mitsuba
and Dr.Jit are an optional dependency that takes seconds to load); where it runs (the CPU, or an NVIDIA GPU) is
its ``device`` option, not another engine. A further engine is one entry here and one builder in
:mod:`swatch.render.request` (docs/DEVNOTES.md).
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Unpack

from swatch.core.choices import ENGINES
from swatch.core.errors import SwatchError
from swatch.core.procguard import signals_held
from swatch.core.version import __version__
from swatch.render.builtin import env_render
from swatch.render.builtin.pointlight import render_pointlight
from swatch.render.image import SwatchImage, finish_meta
from swatch.render.metadata import common_metadata
from swatch.render.request import Progress, RenderOptions, RenderRequest, render_request

__all__ = ["ENGINES", "Engine", "render_builtin", "render_swatch", "engine_unavailable", "engine_version", "set_engine_threads",
           "studio_lightmap"]

#: An engine: a checked request and an optional progress callback in, a :class:`SwatchImage` out.
Engine = Callable[[RenderRequest, Progress | None], SwatchImage]


def render_builtin(request: RenderRequest, progress: Progress | None = None) -> SwatchImage:
    """The ``builtin`` engine: one directional light (:mod:`swatch.render.builtin.pointlight`) or an environment
    (:mod:`swatch.render.builtin.env_render`), by the request's lighting.

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        A request built for ``engine="builtin"``.
    progress : callable(done, total), optional
        Unused (the built-in engine renders in one pass).

    Returns
    -------
    SwatchImage
        ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in ``request.space``, premultiplied by the
        ``coverage`` (H, W); ``display_rgb`` (H, W, 3) uint8 sRGB, exposure applied and composited on the
        background; ``metadata``.
    """
    meta = common_metadata(request.thickness_nm, request.coating, request.colorimeter, request.model,
                           request.distribution, request.roughness_alpha)
    if request.lighting.environment is not None:
        return env_render.render_swatch_environment(request, meta | finish_meta(request.finish))
    img = render_pointlight(request, meta)
    img.metadata |= finish_meta(request.finish)
    return img


def _render_mitsuba(request: RenderRequest, progress: Progress | None = None) -> SwatchImage:
    """The ``mitsuba`` engine, imported on first use (:func:`swatch.render.mitsuba.engine.render_mitsuba`)."""
    return _mitsuba_engine().render_mitsuba(request, progress)


def _mitsuba_engine():
    """The Mitsuba engine's module (Mitsuba and Dr.Jit load here, once, only when asked for; with the stop
    signals held: a KeyboardInterrupt raised inside a nanobind module's initialisation aborts the interpreter)."""
    with signals_held():
        from swatch.render.mitsuba import engine
    return engine


def engine_unavailable(engine: str) -> str | None:
    """Why an engine cannot render here (one line: what to install), or None when it can.

    Parameters
    ----------
    engine : str
        A name of :data:`ENGINES`.

    Returns
    -------
    str or None
        The reason (Mitsuba not installed, no usable libLLVM for its JIT), or None.
    """
    if engine == "builtin":
        return None
    try:
        _mitsuba_engine().use_variant()
    except ImportError as exc:
        return f"Mitsuba is not installed ({exc.name}); pip install mitsuba (docs/mitsuba.md)"
    except SwatchError as exc:
        return str(exc)
    return None


def engine_version(engine: str) -> str:
    """The version of the renderer behind an engine (cache keys of its renders).

    Parameters
    ----------
    engine : str
        A name of :data:`ENGINES`.

    Returns
    -------
    str
        swatch's version for ``builtin``, Mitsuba's for ``mitsuba``.
    """
    if engine == "builtin":
        return __version__
    return str(_mitsuba_engine().mi.__version__)


def set_engine_threads(engine: str, threads: int) -> None:
    """The number of threads an engine renders with, for the whole process (Mitsuba: Dr.Jit's thread pool; the
    built-in engine's NumPy needs none): a cluster's worker gives it the cores Dask gave the worker.

    Parameters
    ----------
    engine : str
        A name of :data:`ENGINES`.
    threads : int
        Threads, at least 1.

    Returns
    -------
    None
        Returns when set.
    """
    if engine == "mitsuba":
        _mitsuba_engine().dr.set_thread_count(max(1, int(threads)))


def studio_lightmap(shape: str, mesh=None) -> tuple:
    """The path tracer's studio set baked around ``shape`` (:func:`swatch.render.mitsuba.bake.cyclorama_lightmap`:
    the cyclorama's radiance with the object's shadow, and what the object throws onto it); Mitsuba loads here.

    Parameters
    ----------
    shape : str
        ``flat``, ``cylinder``, ``sphere`` or ``mesh``.
    mesh : swatch.render.mesh.MeshShape, optional
        With ``shape="mesh"``.

    Returns
    -------
    shadow, bounce : numpy.ndarray, shape (ns, nx), float32
        Radiance on the grid of :func:`swatch.render.studio_set.lightmap_axes` (renders' units).
    scale, floor_y : float
        The render's radiance scale and the floor's height.
    """
    with signals_held():  # (as _mitsuba_engine)
        from swatch.render.mitsuba import bake
    return bake.cyclorama_lightmap(shape, mesh)


# The engines by name: swatch.core.choices.ENGINES (names, descriptions) holds each function, registered here.
ENGINES.implement("builtin", render_builtin)
ENGINES.implement("mitsuba", _render_mitsuba)


def render_swatch(thickness_nm: float, shape: str, size_px: int = 512, progress: Progress | None = None,
                  **options: Unpack[RenderOptions]) -> SwatchImage:
    """Render one swatch: the request checked once (:func:`swatch.render.request.render_request`), then
    rendered by its engine (:data:`ENGINES`).

    Parameters
    ----------
    thickness_nm : float
        Oxide film thickness, nm (0 to :data:`swatch.core.limits.MAX_THICKNESS_NM`).
    shape : str
        ``flat``, ``cylinder`` or ``sphere`` (:data:`swatch.core.choices.SHAPES`); ``"mesh"`` with ``mesh``.
    size_px : int
        Image side, pixels (builtin: 1 to ``MAX_SIZE_PX``, under an environment ``MIN_ENV_RENDER_PX`` to
        ``MAX_ENV_RENDER_PX``; mitsuba: to ``MAX_MITSUBA_PX``).
    progress : callable(done, total), optional
        mitsuba: called after each pass with the passes done and their number.
    **options
        The request's keywords (:class:`swatch.render.request.RenderOptions`):

        light_deg : float
            Polar angle of the builtin engine's point light (``environment='point'`` only), degrees from the
            normal (default :data:`swatch.core.choices.DEFAULT_LIGHT_DEG`, 45).
        roughness_alpha : float or (float, float)
            Microfacet roughness α (GGX or Beckmann), dimensionless, 0.001 to 1 (default 0.3); mitsuba also
            takes (α_u, α_v).
        model, distribution : str
            The intensity model (``microfacet``, the default, or ``paper``) and the facet normal distribution
            (``ggx``, the default, or ``beckmann``).
        coating, colorimeter
            A :class:`swatch.physics.model.Coating` (film, substrate, index scale, thickness spread) and a
            :class:`swatch.colorimetry.colorimeter.Colorimeter` (defaults: TiO2 on Ti; D65 and the CIE 1964
            10° observer for the metadata's XYZ and Lab, the colorimeter's default); the image's display
            sRGB always comes from the CIE 1931 2° observer.
        space : str
            RGB primaries of ``linear_rgb``: ``srgb`` (default) or ``acescg``.
        workers : int, optional
            Threads of the point-light engine.
        environment
            The lighting: a :class:`swatch.render.lighting.Lighting` resolved for ``engine`` (reuse one
            across thicknesses), or what :func:`swatch.render.lighting.resolve_lighting` takes (a name, a
            map's path, an :class:`swatch.render.environment.Environment`). None: the engine's default,
            :func:`swatch.render.lighting.default_environment` (the studio; the point light for the paper
            model or the Beckmann distribution), as ``swatch render`` without ``--environment``.
        background : str, optional
            ``grey``, ``white`` or (with an environment) ``environment``; default grey (mitsuba under
            studio and sun: environment, the only choice there).
        view_deg, view_azimuth_deg : float
            The camera's polar angle from the normal and azimuth about it, degrees
            (:func:`swatch.render.scene.make_scene`; default: the shape's view, azimuth 0).
        mesh
            A :class:`swatch.render.mesh.MeshShape` rendered instead of ``shape`` (which is then ``"mesh"``).
        finish
            A :class:`swatch.physics.finishes.Finish`: its roughness replaces ``roughness_alpha``; an
            anisotropic one (brushed) is rendered under an environment only by the builtin engine.
        engine : str
            ``builtin`` (default) or ``mitsuba`` (:data:`swatch.core.choices.ENGINES`).
        spp, seed : int
            mitsuba: samples per pixel (default :data:`swatch.core.choices.DEFAULT_SPP`, 64) and the seed
            (default 0; the same values give byte-identical images).
        sun : swatch.render.lighting.Sun, optional
            mitsuba: the sun of ``environment="sun"``.
        exposure : float, optional
            mitsuba: display exposure of the PNG, 1/64 to 64 (default 1: the white diffuser is display white).
        window_px : (int, int, int, int), optional
            mitsuba: ``(x, y, width, height)`` pixels of the image to render alone (the image returned).
        variant : str, optional
            mitsuba: the Mitsuba variant (default ``llvm_ad_spectral``).
        device : str, optional
            mitsuba: where it renders and denoises, ``cpu`` (the default) or ``cuda`` (an NVIDIA GPU: the
            ``cuda_ad_spectral`` variant and the denoiser's CUDA device; refused where there is none, and beside a
            variant of the other device: :data:`swatch.core.choices.DEVICES`).
        bsdf_override : dict, optional
            mitsuba: another BSDF for the object (tests and benchmarks).
        denoise : bool or str
            mitsuba: denoise with Intel Open Image Denoise guided by the render's albedo and normal buffers
            (True, the default: ``high`` quality; ``balanced``, ``fast``), or False: the raw path-traced estimate
            (:mod:`swatch.render.mitsuba.denoise`).

    Returns
    -------
    SwatchImage
        ``linear_rgb`` (H, W, 3) float32 scene-referred linear RGB in ``space``, premultiplied by the
        ``coverage`` (H, W); ``display_rgb`` (H, W, 3) uint8 sRGB, exposure applied and composited on
        the background; ``metadata``.

    Raises
    ------
    swatch.core.errors.SwatchError
        For an input out of range, naming its parameter, or an option given where it would change nothing
        (``light_deg`` without the point light, ``spp`` on the builtin engine; before anything is rendered).
    """
    request = render_request(thickness_nm, shape, size_px, **options)
    return ENGINES[request.engine](request, progress)
