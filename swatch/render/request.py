"""A render request: everything a render depends on, checked once (issue 36).

:func:`render_request` is the one place a render's inputs are checked: it raises a
:class:`swatch.core.errors.SwatchError` naming the parameter (```size_px```, ```spp```, …) and returns a
frozen :class:`RenderRequest`. Engines (:data:`swatch.render.dispatch.ENGINES`) take the request and a
progress callback and return a :class:`swatch.render.image.SwatchImage`; they render what the request
holds and check nothing again (tests/test_layers.py pins it). A series of thicknesses reuses one
request (:meth:`RenderRequest.with_thickness` checks the new thickness alone).

An option that would change nothing in the picture the request describes (``light_deg`` without the point
light, ``spp`` on the built-in engine, ``roughness_alpha`` beside a ``finish``, …) is refused, in one loop
(:data:`_ONLY_WHERE`), rather than ignored. Each default is defined once: the lighting by
:func:`swatch.render.lighting.default_environment`, the numbers in :data:`_DEFAULTS` from
:mod:`swatch.core.choices`.

Nothing here imports Mitsuba: the checks of the ``mitsuba`` engine's size, samples, seed, window and
exposure (:mod:`swatch.render.checks`) are plain arithmetic on :mod:`swatch.core.limits`.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypedDict, Unpack

from swatch.colorimetry.colorimeter import Colorimeter, check_rgb_space
from swatch.core.choices import DEFAULT_LIGHT_DEG, DEFAULT_ROUGHNESS_ALPHA, DEFAULT_SEED, DEFAULT_SPP, POINT_LIGHT
from swatch.core.errors import SwatchError
from swatch.physics import microfacet
from swatch.physics.finishes import Finish
from swatch.physics.model import check_thickness_nm
from swatch.physics.spread import NO_SPREAD, ThicknessSpread
from swatch.render.builtin import shading
from swatch.render.checks import (
    check_denoise,
    check_denoise_size,
    check_device,
    check_exposure,
    check_mitsuba_request,
    check_window_px,
)
from swatch.render.image import check_background, check_finish_lighting, check_size_px
from swatch.render.lighting import Lighting, Sun, check_engine, lighting_for
from swatch.render.metadata import coating_and_colorimeter
from swatch.render.scene import Scene, check_shape, make_scene

__all__ = ["RenderRequest", "RenderOptions", "Progress", "render_request"]

#: A progress callback: ``progress(done, total)`` after each pass (the Mitsuba engine's passes).
Progress = Callable[[int, int], None]

#: The camera's light angle of a Mitsuba render's scene (its lighting is the environment's; the point light's
#: angle only places :class:`swatch.render.scene.Scene`'s unused light).
_MITSUBA_SCENE_LIGHT_DEG = 45.0


class RenderOptions(TypedDict, total=False):
    """The keyword options of :func:`render_request` and :func:`swatch.render.render_swatch` (each
    described in full there; all optional).

    Attributes
    ----------
    light_deg : float
        Point light's polar angle, degrees from the normal (builtin, ``environment='point'``).
    roughness_alpha : float or (float, float)
        GGX/Beckmann α (dimensionless), or (α_u, α_v) (mitsuba).
    model, distribution, space : str
        Intensity model, facet distribution, RGB primaries of the linear image.
    coating, colorimeter
        The film (:class:`swatch.physics.model.Coating`) and the colorimetry of the metadata's Lab
        (default D65, CIE 1964 10°); the image's display sRGB always uses CIE 1931 2°.
    workers : int or None
        Threads of the point-light engine.
    environment
        The lighting (a name, a map's path, an Environment or a resolved Lighting; None: the engine's default,
        :func:`swatch.render.lighting.default_environment`).
    background : str or None
        ``grey``, ``white`` or ``environment``.
    view_deg, view_azimuth_deg : float
        The camera's polar angle and azimuth, degrees.
    mesh, finish
        A mesh to render instead of the shape; a named surface finish.
    engine : str
        ``builtin`` or ``mitsuba``.
    spp, seed : int
        Mitsuba's samples per pixel and seed.
    sun : Sun or None
        The sun of ``environment="sun"`` (mitsuba).
    exposure : float or None
        Mitsuba's display exposure factor (1/64–64).
    window_px : (int, int, int, int) or None
        Mitsuba's film window, pixels.
    variant : str or None
        Mitsuba variant.
    device : str or None
        Where Mitsuba renders and denoises: ``cpu`` or ``cuda`` (names the variant).
    bsdf_override : dict or None
        Another BSDF for Mitsuba (tests, benchmarks).
    denoise : bool or str
        Mitsuba: denoise with Intel Open Image Denoise (True: ``high`` quality; ``balanced``, ``fast``; False:
        the raw estimate).
    """

    light_deg: float
    roughness_alpha: float | tuple[float, float]
    model: str
    coating: Any
    colorimeter: Colorimeter | None
    space: str
    distribution: str
    workers: int | None
    environment: Any
    background: str | None
    view_deg: float | None
    view_azimuth_deg: float
    mesh: Any
    finish: Finish | None
    engine: str
    spp: int
    seed: int
    sun: Sun | None
    exposure: float | None
    window_px: tuple[int, int, int, int] | None
    variant: str | None
    device: str | None
    bsdf_override: dict | None
    denoise: bool | str


#: Each option's default (the one definition; ``environment=None`` is the engine's default lighting).
_DEFAULTS: dict[str, Any] = {
    "light_deg": DEFAULT_LIGHT_DEG, "roughness_alpha": DEFAULT_ROUGHNESS_ALPHA, "model": "microfacet", "coating": None,
    "colorimeter": None, "space": "srgb", "distribution": "ggx", "workers": None, "environment": None,
    "background": None, "view_deg": None, "view_azimuth_deg": 0.0, "mesh": None, "finish": None,
    "engine": "builtin", "spp": DEFAULT_SPP, "seed": DEFAULT_SEED, "sun": None, "exposure": None, "window_px": None,
    "variant": None, "device": None, "bsdf_override": None, "denoise": True,
}


@dataclass(frozen=True, eq=False)
class RenderRequest:
    """Everything one render depends on, checked (:func:`render_request` builds it; engines read it).

    Equality is identity (the built-in engine caches a scene's gather per lighting object).

    Attributes
    ----------
    engine : str
        The engine's name (a key of :data:`swatch.render.dispatch.ENGINES`).
    thickness_nm : float
        Oxide film thickness, nm (0 to :data:`swatch.core.limits.MAX_THICKNESS_NM`).
    shape : str
        ``flat``, ``cylinder``, ``sphere`` (:data:`swatch.core.choices.SHAPES`), or ``mesh``.
    mesh : swatch.render.mesh.MeshShape or None
        The mesh rendered when ``shape`` is ``mesh``.
    size_px : int
        Image side, pixels (each engine's range: :func:`check_size_px`, the environment renderer's,
        :func:`check_mitsuba_request`).
    scene : swatch.render.scene.Scene
        Camera, shape and point light (the point light at ``light_deg``; the Mitsuba engine uses the camera).
    light_deg : float
        Polar angle of the built-in engine's point light, degrees from the normal.
    view_deg : float or None
        The camera's polar angle, degrees from the normal (None: the shape's default view).
    view_azimuth_deg : float
        The camera's azimuth about the normal, degrees.
    lobe : tuple of float
        The microfacet roughness: ``(α,)`` isotropic, or ``(α_u, α_v)`` of an anisotropic finish
        (dimensionless, :data:`swatch.core.limits.MIN_ROUGHNESS_ALPHA` to 1).
    model : str
        Intensity model: ``microfacet`` or ``paper`` (:data:`swatch.core.choices.MODELS`).
    distribution : str
        Facet normal distribution: ``ggx`` or ``beckmann``.
    space : str
        RGB primaries of ``linear_rgb`` (:data:`swatch.core.choices.IMAGE_SPACES`).
    background : str
        Display background: ``grey``, ``white`` or ``environment``.
    lighting : swatch.render.lighting.Lighting
        The lighting, resolved for ``engine``.
    coating : swatch.physics.model.Coating
        Film, substrate, index scale, thickness spread and wavelength grid.
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the metadata's Lab (default D65, CIE 1964 10°) and the built-in engine's
        illuminant; display sRGB always from CIE 1931 2°.
    finish : swatch.physics.finishes.Finish or None
        A named surface finish (its lobe is ``lobe``); recorded in the metadata.
    workers : int or None
        Threads of the point-light engine (None: one).
    spp : int
        Mitsuba: samples per pixel (the built-in engine refuses it).
    seed : int
        Mitsuba: the sampler's seed; equal requests give byte-identical images.
    exposure : float
        Mitsuba: display exposure of the PNG (the EXR keeps scene values), 1/64 to 64.
    window_px : (int, int, int, int) or None
        Mitsuba: ``(x, y, width, height)`` pixels of the image to render alone (film crop).
    variant : str or None
        Mitsuba variant (checked; default :data:`swatch.core.choices.DEFAULT_VARIANT`, the ``device``'s).
    device : str
        Mitsuba: where it renders and denoises, ``cpu`` or ``cuda`` (:func:`swatch.render.checks.check_device`;
        the built-in engine refuses the option).
    bsdf_override : dict or None
        Mitsuba: another BSDF for the object (tests and benchmarks: Mitsuba's ``roughconductor``).
    denoise : str or None
        Mitsuba: Intel Open Image Denoise's filter quality (``high``, ``balanced``, ``fast``), or None for the raw
        path-traced estimate (:func:`swatch.render.checks.check_denoise`; the built-in engine refuses it).
    """

    engine: str
    thickness_nm: float
    shape: str
    mesh: Any
    size_px: int
    scene: Scene
    light_deg: float
    view_deg: float | None
    view_azimuth_deg: float
    lobe: tuple[float, ...]
    model: str
    distribution: str
    space: str
    background: str
    lighting: Lighting
    coating: Any
    colorimeter: Colorimeter
    finish: Finish | None = None
    workers: int | None = None
    spp: int = DEFAULT_SPP
    seed: int = DEFAULT_SEED
    exposure: float = 1.0
    window_px: tuple[int, int, int, int] | None = None
    variant: str | None = None
    bsdf_override: dict | None = None
    denoise: str | None = "high"
    device: str = "cpu"

    @property
    def roughness_alpha(self) -> float:
        """The isotropic α (an anisotropic lobe's geometric mean √(α_u α_v)), dimensionless.

        Returns
        -------
        float
            α of the metadata's ``roughness`` key.
        """
        return self.lobe[0] if len(self.lobe) == 1 else float(math.sqrt(self.lobe[0] * self.lobe[1]))

    @property
    def spread(self) -> ThicknessSpread:
        """The film's thickness spread (the coating's; none for the default coating).

        Returns
        -------
        swatch.physics.spread.ThicknessSpread
            Standard deviation of the thickness, absolute (nm) and relative parts.
        """
        return getattr(self.coating, "spread", NO_SPREAD)

    def with_thickness(self, thickness_nm: float) -> RenderRequest:
        """The same request at another thickness (checked alone: the rest was checked once).

        Parameters
        ----------
        thickness_nm : float
            Oxide film thickness, nm (0 to :data:`swatch.core.limits.MAX_THICKNESS_NM`).

        Returns
        -------
        RenderRequest
            A copy holding the new thickness.
        """
        return dataclasses.replace(self, thickness_nm=float(check_thickness_nm(float(thickness_nm))))


def _lobe(roughness_alpha, finish: Finish | None) -> tuple[float, ...]:
    """The checked lobe: a finish's (anisotropic: (α_u, α_v)), else one α or (α_u, α_v)."""
    if finish is not None:
        return (finish.alpha_u, finish.alpha_v) if finish.anisotropic else (finish.roughness_alpha,)
    alphas = tuple(roughness_alpha) if isinstance(roughness_alpha, tuple | list) else (roughness_alpha,)
    if len(alphas) not in (1, 2):
        raise SwatchError("`roughness_alpha` is one alpha or (alpha_u, alpha_v)")
    return tuple(microfacet.check_roughness_alpha(a) for a in alphas)


def _view(view_deg) -> float | None:
    """The camera's polar angle as given (checked by the scene), None for the shape's default."""
    return None if view_deg is None else float(view_deg)


def _builtin(d: float, shape: str, size_px, o: dict[str, Any]) -> RenderRequest:
    """The built-in engine's request (point light or environment)."""
    size = check_size_px(size_px)
    model = shading.check_model(o["model"])
    finish = o["finish"]
    lobe = _lobe(o["roughness_alpha"], None) if finish is None else (finish.roughness_alpha,)
    if len(lobe) != 1:
        raise SwatchError("the built-in engine renders an anisotropic lobe through a `finish` only")
    distribution = microfacet.check_distribution(o["distribution"])
    space = check_rgb_space(o["space"])
    coating, colorimeter = coating_and_colorimeter(o["coating"], o["colorimeter"])
    background = check_background("grey" if o["background"] is None else o["background"])
    light = lighting_for(o["environment"], "builtin", o["sun"], model, distribution, size, background)
    check_finish_lighting(finish, light.environment, model, distribution, size)
    scene = make_scene(shape, o["light_deg"], o["view_deg"], o["view_azimuth_deg"], o["mesh"])
    return RenderRequest(engine="builtin", thickness_nm=d, shape=shape, mesh=o["mesh"], size_px=size, scene=scene,
                         light_deg=float(o["light_deg"]), view_deg=_view(o["view_deg"]),
                         view_azimuth_deg=float(o["view_azimuth_deg"]), lobe=lobe, model=model,
                         distribution=distribution, space=space, background=background, lighting=light,
                         coating=coating, colorimeter=colorimeter, finish=finish, workers=o["workers"])


def _mitsuba(d: float, shape: str, size_px, o: dict[str, Any]) -> RenderRequest:
    """The Mitsuba engine's request (microfacet model, D65, its size and sample limits, its lightings)."""
    model = shading.check_model(o["model"])
    if model != "microfacet":
        raise SwatchError(f"the mitsuba engine renders the microfacet model; drop `model={model!r}`")
    coating, colorimeter = coating_and_colorimeter(o["coating"], o["colorimeter"])
    if getattr(colorimeter, "illuminant", "D65") not in ("D65", None):
        raise SwatchError("the mitsuba engine renders under D65 light (its emitters and film); use `illuminant='D65'`")
    if getattr(coating, "overcoats", ()):
        raise SwatchError("the mitsuba engine renders one film on the metal; drop the overcoats")
    size, spp, seed = check_mitsuba_request(size_px, o["spp"], o["seed"])
    light = lighting_for(o["environment"], "mitsuba", o["sun"])
    lobe = _lobe(o["roughness_alpha"], o["finish"])
    distribution = microfacet.check_distribution(o["distribution"])
    space = check_rgb_space(o["space"])
    photo_only = light.kind in ("studio", "sun")
    background = check_background(("environment" if photo_only else "grey") if o["background"] is None
                                  else o["background"])
    if photo_only and background != "environment":
        raise SwatchError(f"{light.kind} lighting shows its set behind the object; use `background='environment'` "
                          "(or uniform lighting or a map for a grey or white background)")
    exposure = check_exposure(1.0 if o["exposure"] is None else o["exposure"])
    window = check_window_px(o["window_px"], size)
    device, variant = check_device(o["device"], o["variant"])
    scene = make_scene(shape, _MITSUBA_SCENE_LIGHT_DEG, o["view_deg"], o["view_azimuth_deg"], o["mesh"])
    denoise = check_denoise_size(check_denoise(o["denoise"]), size if window is None else max(window[2:]))
    return RenderRequest(engine="mitsuba", thickness_nm=d, shape=shape, mesh=o["mesh"], size_px=size, scene=scene,
                         light_deg=_MITSUBA_SCENE_LIGHT_DEG, view_deg=_view(o["view_deg"]),
                         view_azimuth_deg=float(o["view_azimuth_deg"]), lobe=lobe, model=model,
                         distribution=distribution, space=space, background=background, lighting=light,
                         coating=coating, colorimeter=colorimeter, finish=o["finish"], workers=o["workers"], spp=spp,
                         seed=seed, exposure=exposure, window_px=window, variant=variant,
                         bsdf_override=o["bsdf_override"], denoise=denoise, device=device)


_BUILDERS: dict[str, Callable[[float, str, Any, dict[str, Any]], RenderRequest]] = {
    "builtin": _builtin, "mitsuba": _mitsuba}


def _mitsuba_only(name: str) -> tuple[Callable[[RenderRequest], bool], Callable[[RenderRequest], str]]:
    return (lambda r: r.engine == "mitsuba",
            lambda r: f"`{name}` is an option of the mitsuba engine; add `engine='mitsuba'`")


def _light_deg_unused(r: RenderRequest) -> str:
    if r.engine == "mitsuba":
        return "`light_deg` places the point light, and the mitsuba engine has none; drop it"
    return (f"`light_deg` places the point light, and the {r.lighting.name} lighting has none; drop it, or add "
            f"`environment='{POINT_LIGHT}'`")


#: The options that change the picture only where the request uses them: name -> (whether the checked request
#: uses it, the one-line refusal where it does not). A given option that would change nothing is refused.
_ONLY_WHERE: dict[str, tuple[Callable[[RenderRequest], bool], Callable[[RenderRequest], str]]] = {
    "light_deg": (lambda r: r.lighting.kind == POINT_LIGHT, _light_deg_unused),
    "roughness_alpha": (lambda r: r.finish is None,
                        lambda r: "`roughness_alpha` is the `finish`'s (its lobe replaces it); give one of them"),
    **{name: _mitsuba_only(name) for name in ("spp", "seed", "denoise", "exposure", "window_px", "bsdf_override",
                                                "variant", "device")},
}


def render_request(thickness_nm: float, shape: str, size_px: int = 512,
                   **options: Unpack[RenderOptions]) -> RenderRequest:
    """Check a render's inputs once and hold them in a :class:`RenderRequest`.

    Parameters
    ----------
    thickness_nm : float
        Oxide film thickness, nm.
    shape : str
        ``flat``, ``cylinder`` or ``sphere`` (:data:`swatch.core.choices.SHAPES`); ignored with ``mesh``.
    size_px : int
        Image side, pixels.
    **options
        The keywords of :func:`swatch.render.render_swatch` (:class:`RenderOptions`; each defaults as
        documented there).

    Returns
    -------
    RenderRequest
        The checked request.

    Raises
    ------
    SwatchError
        For the first input out of range, naming its parameter (one line, what is allowed), and for an
        option given where it would change nothing (``light_deg`` without the point light, the mitsuba
        engine's options on the built-in one, ``roughness_alpha`` beside a ``finish``).
    TypeError
        For an unknown keyword.
    """
    unknown = set(options) - set(_DEFAULTS)
    if unknown:
        raise TypeError(f"render_request() got unexpected keyword arguments {sorted(unknown)}")
    o: dict[str, Any] = {**_DEFAULTS, **options}
    engine = check_engine(o["engine"])
    d = float(check_thickness_nm(float(thickness_nm)))
    shape = "mesh" if o["mesh"] is not None else check_shape(shape)
    request = _BUILDERS[engine](d, shape, size_px, o)
    for name, (uses, refusal) in _ONLY_WHERE.items():
        if name in options and not uses(request):
            raise SwatchError(refusal(request))
    return request
