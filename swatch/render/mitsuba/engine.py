"""``swatch render --engine mitsuba``: a swatch rendered by Mitsuba 3's spectral path tracer.

The object (plate, bent sheet, sphere, mesh) wears the ``anodic_film`` BSDF (the exact thin film,
:mod:`swatch.render.mitsuba.bsdf`) and is seen by the built-in renderer's camera
(:mod:`swatch.render.mitsuba.scene`), under ``studio``, ``sun``, ``uniform`` or a user's HDRI, with
Mitsuba's ``path`` integrator (up to :data:`PATH_BOUNCES` bounces: meshes shadow and reflect
themselves). Rendering is split into passes of at most :data:`swatch.core.limits.MAX_PASS_LANES`
samples and :data:`swatch.core.limits.MAX_PASS_SPP` per pixel (progress reported after each pass,
Ctrl-C/SIGTERM between passes; a pixel's samples within a pass are stratified together), each with its own
seed derived from ``seed``: the same seed and spp give byte-identical images. Samples are low-discrepancy
(:data:`SAMPLER`), and the image is denoised by default with Intel Open Image Denoise guided by the
albedo and normal buffers of the same scene (:mod:`swatch.render.mitsuba.denoise`; ``denoise=False``
keeps the raw estimate).

Units: linear Rec.709/sRGB (Mitsuba's film: CIE 1931 2° XYZ to sRGB), scaled so that **1.0 = a
perfect white diffuser facing up (+y) at the origin under the same lighting** (the built-in
environment renders' unit): for ``studio`` lit directly by the emitters (each emitter's own
direction sampling on a fixed grid, averaged in numpy: deterministic), by quadrature of the map
for an HDRI; ``uniform`` is radiance 1; every ``sun`` shares one scale (:data:`SUN_SCALE`: the
sun at 45°), so a low sun is darker. Emitters are D65 white (the sun
and sky are their own spectra); the display PNG is exposure 1 through the renderer's shoulder.

Devices: ``device="cpu"`` (the default) renders in ``llvm_ad_spectral`` and denoises on the CPU;
``device="cuda"`` in ``cuda_ad_spectral`` on an NVIDIA GPU, denoised on OIDN's CUDA device. Where Dr.Jit or
OIDN finds no CUDA device, :func:`device_unavailable` says so in one line and nothing is rendered. A CUDA
render is not byte-identical to a CPU one (other kernels, other orders of sums); each is byte-identical on
rerun on its own device.
"""
from __future__ import annotations

import math
import os
from typing import Unpack

import colour
import drjit as dr
import mitsuba as mi
import numpy as np

from swatch.colorimetry.colorimeter import RGB_SPACES
from swatch.core.choices import DEFAULT_SEED, DEFAULT_SPP
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_PASS_LANES, MAX_PASS_SPP
from swatch.core.procguard import raise_if_signalled
from swatch.physics.finishes import brush_axis
from swatch.render.display import BACKGROUND_LINEAR, display_encode
from swatch.render.image import SwatchImage, finish_meta, mesh_metadata
from swatch.render.lighting import Lighting, Sun, resolve_lighting
from swatch.render.metadata import common_metadata
from swatch.render.mitsuba import denoise as oidn
from swatch.render.mitsuba.bsdf import PLUGIN_NAME, register
from swatch.render.mitsuba.hairlines import HAIRLINE_DEPTH
from swatch.render.mitsuba.scene import camera_dict, jit_float, lighting, load_scene, object_shapes
from swatch.render.mitsuba.setup import (
    DEFAULT_VARIANT,
    ENV_VAR,
    INSTALL_HINT,
    OLDEST_LLVM_MAJOR,
    check_variant,
    llvm_major,
)
from swatch.render.request import Progress, RenderOptions, RenderRequest, render_request

__all__ = ["PATH_BOUNCES", "SUN_SCALE", "SUN_Y_UP", "reference_sun_y_up", "Sun", "use_variant", "device_unavailable",
           "mitsuba_lighting",
           "render_swatch_mitsuba", "render_mitsuba", "Lighting", "studio_scale", "floor_y"]

PATH_BOUNCES = 12
#: Sun and sky: 1.0 = a white diffuser facing up under the reference sun (45° elevation, azimuth 0,
#: turbidity 3) and its sky, lit directly: π / E_up of that sunsky emitter, Y-weighted, by the same
#: deterministic quadrature as the studio's (:func:`_irradiance_scale`, 96² stratified directions per
#: 4 wavelengths: Y_up = 0.336484 of radiance 1; computing it takes seconds, so it is stored here and
#: tests/mitsuba/test_mitsuba_render.py recomputes it). Every sun render shares it: a low sun is darker. (It was
#: 1 / 0.338, a 256 spp render's estimate, 0.45 % darker.)
SUN_Y_UP = 0.336484
SUN_SCALE = 1.0 / SUN_Y_UP
#: Mitsuba's sampler: low-discrepancy (Sobol'-like, scrambled by the pass's seed), in passes of a power of 4
#: samples (it rounds other counts up). At 32 spp it cuts the error of a 4 × 4-pixel block against a converged
#: render by a third against the ``independent`` sampler (sphere, studio, 96 px: mean ΔE00 1.48 → 0.98); the
#: expected image is the same (#37).
SAMPLER = "ldsampler"
_WHITE_BG = 2.0  # the built-in renderer's white background (display white)
_REC709_Y = np.array([0.2126, 0.7152, 0.0722])


def use_variant(variant: str = DEFAULT_VARIANT) -> str:
    """Set Mitsuba's ``variant`` (spectral) and register the plugin.

    Parameters
    ----------
    variant : str, optional
        A spectral variant (:data:`swatch.render.mitsuba.setup.SPECTRAL_VARIANTS`).

    Returns
    -------
    str
        The variant set.

    Raises
    ------
    SwatchError
        When the variant cannot run here (no usable libLLVM for an ``llvm_*`` one, no CUDA GPU for a ``cuda_*``
        one), with what to install.
    """

    return _set_variant(check_variant(variant))


def device_unavailable(device: str, denoise: bool = True) -> str | None:
    """Why a Mitsuba render cannot run on ``device`` here (one line: what is missing, what to do), or None.

    Parameters
    ----------
    device : str
        ``cpu`` or ``cuda`` (:data:`swatch.core.choices.DEVICES`; the CPU's libLLVM is :func:`use_variant`'s check).
    denoise : bool
        Whether the render is denoised (then OIDN needs the device too).

    Returns
    -------
    str or None
        For ``cuda``: Dr.Jit without its CUDA backend (no NVIDIA GPU or driver), or OIDN without a CUDA device;
        None when both have one.
    """
    if device == "cpu":
        return None
    if not dr.has_backend(dr.JitBackend.CUDA):
        return ("`device='cuda'`: Dr.Jit finds no CUDA GPU here (no NVIDIA GPU, or no driver: libcuda.so); render "
                "on a machine with an NVIDIA GPU and its driver, or use `device='cpu'`")
    return oidn.device_unavailable(device) if denoise else None


def _set_variant(variant: str) -> str:
    """:func:`use_variant` of a variant already checked (a render request's)."""
    if variant.startswith("cuda"):
        why = device_unavailable("cuda", denoise=False)
        if why is not None:
            raise SwatchError(why)
    if variant.startswith("llvm"):
        path = os.environ.get(ENV_VAR)
        if not path:
            raise SwatchError(INSTALL_HINT)
        major = llvm_major(path)
        if 0 < major < OLDEST_LLVM_MAJOR:
            raise SwatchError(f"{ENV_VAR} points at {os.path.basename(path)}; libLLVM {major} fails in Mitsuba's "
                              "JIT. " + INSTALL_HINT)
    try:
        mi.set_variant(variant)
    except (ImportError, AttributeError) as exc:
        raise SwatchError(f"Mitsuba variant {variant} is unavailable ({str(exc).splitlines()[0][:120]}). "
                          + INSTALL_HINT) from None
    mi.set_log_level(mi.LogLevel.Error)  # warnings are said as SwatchError lines where they matter
    register()
    return variant


def mitsuba_lighting(lighting_name: str | None = "studio", sun: Sun | None = None) -> Lighting:
    """The :class:`swatch.render.lighting.Lighting` of this engine: ``studio`` (default), ``sun`` (with
    ``sun``, default 45° elevation), ``uniform``, or an .exr/.hdr map (read and checked once; reuse the
    result across thicknesses).

    Parameters
    ----------
    lighting_name : str or None, optional
        ``studio`` (None too), ``sun``, ``uniform`` or a map's path.
    sun : swatch.render.lighting.Sun, optional
        The sun by angles or by place and time, for ``sun`` lighting (None: 45° elevation); ignored otherwise.

    Returns
    -------
    swatch.render.lighting.Lighting
        The lighting resolved and checked for the ``mitsuba`` engine (a map read into memory).
    """
    return resolve_lighting(lighting_name, "mitsuba", sun)


def _description(light: Lighting) -> str:
    """The metadata's words for a Mitsuba lighting."""
    if light.kind == "studio":
        return ("photographic studio (Mitsuba): grey cyclorama (albedo 0.45), overhead key soft box, strip "
                "boxes left and right (rectangular area lights, D65), ambient fill 0.05")
    if light.kind == "sun":
        assert light.sun is not None
        return light.sun.description() + "; mid-grey ground (albedo 0.2)"
    if light.kind == "uniform":
        return "uniform: radiance 1 (D65) from every direction"
    assert light.hdri is not None
    return (f"equirectangular map {light.name} ({light.hdri.shape[1]}x{light.hdri.shape[0]}), y up, Rec.709 "
            "primaries assumed (Mitsuba envmap)")


def _map_scale(img: np.ndarray) -> float:
    """π / E_up of an equirectangular map (the white diffuser facing up reflects 1), by the midpoint rule."""
    h, w, _ = img.shape
    theta = (np.arange(h) + 0.5) * (math.pi / h)
    weight = np.sin(theta) * np.maximum(np.cos(theta), 0.0) * (math.pi / h) * (2.0 * math.pi / w)
    E = float((img.astype(np.float64) @ _REC709_Y).sum(axis=1) @ weight)
    if not (math.isfinite(E) and E > 0):
        raise SwatchError("the environment map sends no light onto an upward-facing surface; give a map with "
                          "positive radiance above the horizon")
    return math.pi / E


def _irradiance_scale(light_entries: dict, grid: int = 96) -> float:
    """π / E_up at the origin: a white diffuser facing up there, lit directly by the emitters (no occlusion,
    no bounce), reflects 1. Each emitter's own direction sampling on a fixed stratified grid of
    ``grid``² points, at 5 nm steps weighted by CIE 1931 ȳ, relative to a D65 radiance 1 (whose white
    diffuser reflects 1); averaged in numpy, so the same scene always gives the same scale. The wavelengths
    are opaque to Dr.Jit and the grid is uploaded once, aligned (:func:`jit_float`): one kernel per emitter
    for all 21 groups of wavelengths, the same from process to process (with the wavelengths as constants,
    each group compiled its own: ~100 kernels, ~5 s with an empty kernel cache)."""
    scene = load_scene({"type": "scene", **light_entries})
    wl = np.arange(380.0, 781.0, 5.0)
    ybar = np.asarray(colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"][wl])[:, 1]
    u = (np.arange(grid) + 0.5) / grid
    su, sv = (a.ravel() for a in np.meshgrid(u, u, indexing="ij"))
    n = su.size
    sample = mi.Point2f(jit_float(su), jit_float(sv))
    reference = mi.load_dict({"type": "constant", "radiance": 1.0})
    E = np.zeros(wl.size)
    L1 = np.zeros(wl.size)
    for k in range(0, wl.size, 4):
        lam = np.resize(wl[k:k + 4], 4)
        it = dr.zeros(mi.SurfaceInteraction3f, n)
        it.p = mi.Point3f(0.0, 1e-3, 0.0)
        it.wavelengths = mi.Spectrum(*(dr.opaque(mi.Float, float(x)) for x in lam))  # type: ignore[assignment]
        for em in scene.emitters():
            ds, w = em.sample_direction(it, sample, True)
            cos = np.maximum(np.asarray(ds.d)[1], 0.0)
            E[k:k + 4] += (np.nan_to_num(np.asarray(w, dtype=np.float64)) * cos).mean(axis=1)[:len(wl[k:k + 4])]
        it.wi = mi.Vector3f(0.0, -1.0, 0.0)
        L1[k:k + 4] += np.asarray(reference.eval(it), dtype=np.float64)[:, 0][:len(wl[k:k + 4])]
    E_y, L_y = float(E @ ybar), float(L1 @ ybar)
    if not (math.isfinite(E_y) and E_y > 0 and L_y > 0):
        raise SwatchError("the lighting sends no light onto an upward-facing surface at the object")
    return math.pi * L_y / E_y


_SCALES: dict[str, float] = {}


def studio_scale(light_entries: dict) -> float:
    """The radiance scale of a lighting's scene entries (π / E_up: a white diffuser facing up at the object, lit
    directly by the emitters, reflects 1; :func:`_irradiance_scale`), kept for the process (a catalog's hero renders
    and a series of thicknesses share one studio: the quadrature took ~0.3–0.6 s of each render). Keyed by the
    entries' text (plain values and transforms) and the variant (a CUDA quadrature's sums differ in the last bits).

    Parameters
    ----------
    light_entries : dict
        Scene entries of :func:`swatch.render.mitsuba.scene.lighting`.

    Returns
    -------
    float
        The factor on Mitsuba's radiance, dimensionless.
    """
    key = str(mi.variant()) + repr(sorted((name, repr(entry)) for name, entry in light_entries.items()))
    if key not in _SCALES:
        if len(_SCALES) >= 8:
            _SCALES.pop(next(iter(_SCALES)))
        _SCALES[key] = _irradiance_scale(light_entries)
    return _SCALES[key]


def reference_sun_y_up(grid: int = 96) -> float:
    """Y of the irradiance over π on an upward white diffuser under the reference sun of :data:`SUN_SCALE`
    (45° elevation, turbidity 3), lit directly, relative to radiance 1 (the quadrature of :func:`_irradiance_scale`).

    Parameters
    ----------
    grid : int, optional
        Quadrature nodes per axis.

    Returns
    -------
    float
        Dimensionless.
    """
    entries = lighting("sun", -1.0, Sun(), None)
    return 1.0 / _irradiance_scale({"light": entries["light"]}, grid)


def _sun_above_horizon(entry: dict) -> None:
    emitter = mi.load_dict(entry)
    world = np.asarray(mi.traverse(emitter)["sun_direction"], dtype=np.float64).reshape(-1)[:3]  # world frame
    if world[1] <= 0.0:
        raise SwatchError("the sun is below the horizon at that place, date and time; choose a daytime hour "
                          "(local time of the sun's time zone, `timezone_h`)")


def floor_y(shape: str, mesh) -> float:
    """The floor's height under a shape (the object stands on it).

    Parameters
    ----------
    shape : str
        ``flat``, ``cylinder``, ``sphere`` or ``mesh``.
    mesh : swatch.render.mesh.MeshShape or None
        With ``shape="mesh"``.

    Returns
    -------
    float
        World y of the floor, scene units.
    """
    if shape == "flat":
        return -0.02
    if shape == "cylinder":
        return -1.1
    if shape == "sphere":
        return -1.0
    return float(mesh.points()[:, 1].min())


def _pass_seeds(seed: int, passes: int) -> list[int]:
    return [int((seed * 2654435761 + 97 * i + 1) % (2**32)) for i in range(passes)]


def render_swatch_mitsuba(  # type: ignore[misc]  # spp and seed: named here, options of render_swatch
        thickness_nm: float, shape: str = "sphere", size_px: int = 256, spp: int = DEFAULT_SPP,
        seed: int = DEFAULT_SEED, lighting_name: str | Lighting | None = None, progress: Progress | None = None,
        **options: Unpack[RenderOptions]) -> SwatchImage:
    """Render one swatch with Mitsuba (module documentation): ``render_swatch(..., engine="mitsuba")`` with
    this engine's defaults (a 256 px sphere at :data:`swatch.core.choices.DEFAULT_SPP` spp in its default
    lighting, the studio).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm, 0 to :data:`swatch.core.limits.MAX_THICKNESS_NM`.
    shape : str
        ``flat``, ``cylinder`` or ``sphere`` (ignored with ``mesh``).
    size_px, spp, seed : int
        Image side (≤ :data:`swatch.core.limits.MAX_MITSUBA_PX`), samples per pixel (≤ MAX_SPP; size² × spp ≤
        MAX_MITSUBA_SAMPLES) and the seed (0 … MAX_SEED): equal values give byte-identical images.
    lighting_name : str or Lighting or None
        ``studio`` (None: the default), ``sun``, ``uniform``, an .exr/.hdr path, or a :class:`Lighting` from
        :func:`resolve_lighting` (reuse it across thicknesses: the map is read once).
    progress : callable(done, total), optional
        Called after each pass with the passes done and their number (the CLI draws its bar from it:
        :class:`swatch.commands.progress.PassBar`).
    **options
        The other keywords of :func:`swatch.render.render_swatch` (``roughness_alpha``, ``coating``,
        ``sun``, ``window_px``, ``exposure``, ``bsdf_override``, ``denoise``, …). ``denoise``: Intel Open
        Image Denoise guided by the albedo and normal buffers of the same render (True: its ``high``
        quality, or ``balanced``, ``fast``; the default True), the raw image and the buffers kept in
        ``layers`` (``raw``, ``albedo``, ``normal``), the metadata's ``denoise`` saying how; False: the raw
        path-traced estimate (references, and the samples' own statistics).

    Returns
    -------
    swatch.render.SwatchImage
        ``linear_rgb`` (H, W, 3) float32 (module units), ``coverage`` (H, W), ``display_rgb`` uint8, metadata.
    """
    request = render_request(thickness_nm, shape, size_px, engine="mitsuba", spp=spp, seed=seed,
                             environment=lighting_name, **options)
    return render_mitsuba(request, progress)


def render_mitsuba(request: RenderRequest, progress: Progress | None = None) -> SwatchImage:
    """The ``mitsuba`` engine of :data:`swatch.render.dispatch.ENGINES`: render a checked request.

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        A request built for ``engine="mitsuba"`` (:func:`swatch.render.request.render_request`): the
        thickness, shape or mesh and camera, size, spp, seed, lobe (α or α_u, α_v), distribution, coating
        (film, substrate, index scale, thickness spread), colorimeter, space, background, lighting,
        exposure, film window, variant.
    progress : callable(done, total), optional
        Called after each pass with the passes done and their number.

    Returns
    -------
    swatch.render.SwatchImage
        ``linear_rgb`` (H, W, 3) float32 (module units), ``coverage`` (H, W), ``display_rgb`` uint8, metadata
        (the finish's entry too).

    Raises
    ------
    SwatchError
        When the variant cannot run here, or the sun is below the horizon.
    """
    d, shape, size, spp, seed = request.thickness_nm, request.shape, request.size_px, request.spp, request.seed
    mesh, window, alphas, distribution = request.mesh, request.window_px, request.lobe, request.distribution
    coating, colorimeter, space, background = request.coating, request.colorimeter, request.space, request.background
    light, exposure, spread, bsdf_override = request.lighting, request.exposure, request.spread, request.bsdf_override
    film, substrate, film_index_scale = coating.film, coating.substrate, coating.film_index_scale
    variant = DEFAULT_VARIANT if request.variant is None else request.variant  # (a request's is checked)
    quality = request.denoise  # OIDN's quality, or None (checked in the request)
    why = device_unavailable(request.device, quality is not None)
    if why is not None:
        raise SwatchError(why)
    variant = _set_variant(variant)

    scene_geo = request.scene
    bsdf = {"type": PLUGIN_NAME, "thickness_nm": d, "film": film, "substrate": substrate,
            "film_index_scale": float(film_index_scale), "distribution": distribution}
    if not spread.is_zero:
        bsdf["spread_nm"], bsdf["spread_fraction"] = float(spread.spread_nm), float(spread.spread_fraction)
    if len(alphas) == 1:
        bsdf["alpha"] = alphas[0]
    else:
        bsdf["alpha_u"], bsdf["alpha_v"] = alphas
        if alphas[0] != alphas[1]:  # brushed along the built-in engine's axis, whatever the surface's uv
            bsdf["brush_axis"] = list(brush_axis("mesh" if shape == "mesh" else shape))
            bsdf["hairline_depth"] = HAIRLINE_DEPTH
    if bsdf_override is not None:
        bsdf = bsdf_override
    lights = lighting(light.kind, floor_y(shape, mesh), light.sun, light.hdri)
    if light.kind == "sun":
        _sun_above_horizon(lights["light"])
    if light.kind == "uniform":
        scale = 1.0
    elif light.hdri is not None:
        scale = _map_scale(light.hdri)
    elif light.kind == "sun":
        scale = SUN_SCALE  # one scale for every sun: a low sun is darker, as it is
    else:
        scale = studio_scale(lights)
    # Samples per pass: a power of two dividing spp (so a pixel's samples, laid out together, never straddle
    # two of Dr.Jit's power-of-two thread blocks: the film's box-filter sums then run in one order, and the
    # image is byte-identical from run to run), and at most MAX_PASS_LANES samples and MAX_PASS_SPP per pixel a pass.
    width, height = (size, size) if window is None else window[2:]
    per = spp & -spp
    while per > 1 and (width * height * per > MAX_PASS_LANES or per > MAX_PASS_SPP
                       or (SAMPLER == "ldsampler" and per & 0x55555555 == 0)):
        per //= 2
    passes = spp // per
    sensor = camera_dict(scene_geo.camera, size, per, window, SAMPLER)
    integrator = {"type": "path", "max_depth": PATH_BOUNCES, "hide_emitters": background != "environment"}
    scene = load_scene({"type": "scene", "integrator": integrator, "sensor": sensor,
                        **object_shapes(shape, bsdf, mesh), **lights})
    raise_if_signalled()  # (a stop raised in the plugin while Mitsuba loaded the scene was swallowed there)
    acc = np.zeros((height, width, 4), dtype=np.float64)
    for i, s in enumerate(_pass_seeds(seed, passes)):
        acc += np.asarray(mi.render(scene, seed=s, spp=per), dtype=np.float64)  # type: ignore[arg-type]
        dr.sync_thread()
        raise_if_signalled()  # (... or while it traced the kernels)
        if progress is not None:
            progress(i + 1, passes)
    acc /= passes
    layers: dict[str, np.ndarray] = {}
    if quality is not None:
        albedo, normal = oidn.render_buffers(scene, width, height, seed, MAX_PASS_LANES)
        raise_if_signalled()
        raw = (acc[..., :3] * scale).astype(np.float32)
        rgb = oidn.denoise_rgb(raw, albedo, normal, quality, request.device)
        layers = {"raw": raw, "albedo": albedo, "normal": normal}
    else:
        rgb = (acc[..., :3] * scale).astype(np.float32)
    alpha = np.clip(acc[..., 3], 0.0, 1.0).astype(np.float32)
    if background == "environment":
        coverage = np.ones((height, width), dtype=np.float32)
        display = display_encode(rgb, exposure)
    else:
        coverage = alpha
        bg = BACKGROUND_LINEAR if background == "grey" else _WHITE_BG
        display = display_encode(rgb * np.float32(exposure) + (1.0 - coverage)[..., None] * np.float32(bg), 1.0)
    linear = rgb
    if space != "srgb":
        m = np.asarray(colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["sRGB"],
                                                colour.RGB_COLOURSPACES[RGB_SPACES[space]], "Bradford"))
        linear = np.einsum("ij,...j->...i", m.astype(np.float32), rgb).astype(np.float32)
        if "raw" in layers:
            layers["raw"] = np.einsum("ij,...j->...i", m.astype(np.float32), layers["raw"]).astype(np.float32)

    rough = alphas[0] if len(alphas) == 1 else float(math.sqrt(alphas[0] * alphas[1]))
    meta = common_metadata(d, coating, colorimeter, "microfacet", distribution, rough)
    meta.update({
        "engine": f"mitsuba {mi.__version__} {variant}",
        "bsdf": (f"{PLUGIN_NAME} (swatch.mitsuba): Airy film {film} (index scale {float(film_index_scale):g}) on "
                 f"{substrate}, per sampled wavelength on the half-vector facet; {distribution} "
                 + (f"alpha {alphas[0]:g}" if len(alphas) == 1 else f"alpha_u {alphas[0]:g}, alpha_v {alphas[1]:g}")
                 + (f" along the {'xyz'[int(np.argmax(np.abs(brush_axis(shape))))]} axis projected"
                     f", hairlines (across-grain alpha +-{HAIRLINE_DEPTH:g}, lines along the axis)"
                    if len(alphas) == 2 and alphas[0] != alphas[1] else "")
                 + ", visible-normal sampling"
                 + ("" if spread.is_zero else f"; thickness spread{spread.text()}, incoherent Gauss-Hermite average"))
        if bsdf_override is None else f"override: {bsdf['type']}",
        "shadowing": "Smith height-correlated",
        "shape": shape,
        "geometry": scene_geo.camera_description,
        "size_px": size,
        "spp": spp,
        "seed": seed,
        "integrator": f"Mitsuba path tracer, up to {PATH_BOUNCES} bounces, {passes} pass(es) of {per} spp",
        "rgb_space": space,
        "denoise": oidn.describe(quality, request.device),
        "lighting": _description(light),
        "environment": light.kind if light.kind != "map" else light.name,
        "units": ("scene-referred linear; 1.0 = perfect white diffuser facing up (+y) at the origin under the same "
                  "lighting; " + ("the scene behind the object included (opaque)" if background == "environment"
                                  else "RGB premultiplied by alpha (coverage)")),
        "colour": "Mitsuba spectral film: CIE 1931 2 deg XYZ to linear sRGB; emitters D65 (sun and sky: their own)",
        "exposure": exposure,
        "exposure_rule": "k = 1: the white diffuser under the same lighting is display white" if exposure == 1.0
        else f"k = {exposure:g} (given)",
        "display": f"sRGB-encoded PNG: linear x {exposure:g}, composited on {background}, shoulder above 0.8",
    })
    if alphas and len(alphas) == 2:
        meta["roughness_alpha_uv"] = [alphas[0], alphas[1]]
    if window is not None:
        meta["window_px"] = list(window)
    return SwatchImage(linear, coverage, display, meta | mesh_metadata(mesh) | finish_meta(request.finish),
                       exposure, layers)
