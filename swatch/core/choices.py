"""Every choice list (and the fits' defaults) of the library, defined once (no numpy: the spec
parser imports it). The limits are in :mod:`swatch.core.limits`.

The CLI builds its ``click.Choice`` lists from these, and the library's checks raise
:class:`swatch.core.errors.SwatchError` naming them, so a new choice is added in one place.
"""
from __future__ import annotations

from swatch.core.registry import Registry

__all__ = [
    "SHAPES",
    "MESH_FORMATS",
    "MODELS",
    "DISTRIBUTIONS",
    "FINISHES",
    "IMAGE_SPACES",
    "BACKGROUNDS",
    "ENGINES",
    "LIGHTINGS",
    "lightings_of",
    "POINT_LIGHT",
    "DEFAULT_LIGHT_DEG",
    "DEFAULT_ROUGHNESS_ALPHA",
    "DEFAULT_SPP",
    "DEFAULT_SEED",
    "SCALE_MODES",
    "DEFAULT_THICKNESS_RANGE_NM",
    "DEFAULT_FIT_STEP_NM",
    "DEFAULT_MATCH_STEP_NM",
    "DEFAULT_EXCLUDE_MIRROR_DEG",
    "DENOISE_QUALITIES",
    "DEVICES",
]

#: Swatch shapes of a render: flat plate, half cylinder (a bent sheet), sphere.
SHAPES = ("flat", "cylinder", "sphere")
#: Mesh files a render can show instead (``--mesh``; a .gltf only with embedded buffers).
MESH_FORMATS = ("obj", "ply", "stl", "glb", "gltf")
#: Intensity models (``model``); each intensity factor is registered by :mod:`swatch.render.builtin.shading`.
MODELS: Registry = Registry.declare("intensity model", "model", {
    "paper": "the half-vector reflectance alone, facet probability constant",
    "microfacet": "D G F / (4 cos θ_l cos θ_v)"})
#: Microfacet normal distributions (``distribution``); each ``D`` and Smith ``Λ`` registered by
#: :mod:`swatch.physics.microfacet`.
DISTRIBUTIONS: Registry = Registry.declare("microfacet distribution", "distribution", {
    "ggx": "GGX (Trowbridge-Reitz)", "beckmann": "Beckmann"})
#: Named surface finishes (their roughness: :mod:`swatch.physics.finishes`); ``brushed`` is anisotropic.
FINISHES = ("polished", "satin", "bead-blasted", "brushed")
#: RGB primaries of the EXR images of renders and angular maps (the colorimeter knows more spaces,
#: :data:`swatch.colorimetry.colorimeter.RGB_SPACES`; these are the ones with an EXR ``chromaticities`` tag).
IMAGE_SPACES = ("srgb", "acescg")
#: The point light's name (``environment='point'``): one directional light at ``light_deg``.
POINT_LIGHT = "point"
#: Lightings by name (``environment``; a path to an equirectangular .exr or .hdr map also works), each with the
#: engines that render it; the catalog page's live view offers the built-in engine's, in this order. The
#: default lighting is :func:`swatch.render.lighting.default_environment`'s.
LIGHTINGS: Registry[tuple[str, ...]] = Registry("lighting", "environment", {
    POINT_LIGHT: (("builtin",), "one directional light at the light angle"),
    "uniform": (("builtin", "mitsuba"), "white, radiance 1 from every direction"),
    "studio": (("builtin", "mitsuba"), "a photographic studio: soft boxes, cyclorama, floor and horizon"),
    "sun": (("mitsuba",), "Mitsuba's sun and sky (sunsky, Hosek-Wilkie; the mitsuba engine only)")})


def lightings_of(engine: str) -> tuple[str, ...]:
    """The names of :data:`LIGHTINGS` that ``engine`` renders, in their order (the built-in engine's are the
    catalog page's live view's: ``point``, ``uniform``, ``studio``).

    Parameters
    ----------
    engine : str
        A name of :data:`ENGINES`, lower case.

    Returns
    -------
    tuple of str
        The lighting names.
    """
    return tuple(name for name, engines in LIGHTINGS.items() if engine in engines)

#: Display backgrounds of renders (``environment``: the map seen behind the object, also in the EXR).
BACKGROUNDS = ("grey", "white", "environment")
#: Render engines (``engine``); each engine function is registered by :mod:`swatch.render.dispatch`
#: (``swatch.render.ENGINES`` is this registry).
ENGINES: Registry = Registry.declare("render engine", "engine", {
    "builtin": "the table-lookup renderer (fast; the default and the sheets' path)",
    "mitsuba": "Mitsuba 3's spectral path tracer with the anodic_film plugin (docs/mitsuba.md)"})
#: The point light's default angle (degrees from the normal), the Mitsuba engine's samples per pixel and seed,
#: the microfacet roughness α of a render without one (a process profile's or a catalog spec's comes first).
DEFAULT_LIGHT_DEG = 45.0
DEFAULT_ROUGHNESS_ALPHA = 0.3
DEFAULT_SPP = 64
DEFAULT_SEED = 0
#: Intensity corrections of the thickness fit: ``energy`` (the paper's mean-energy match per
#: geometry), ``lsq`` (least-squares scale per geometry), ``global`` (one scale), ``none``.
SCALE_MODES = ("energy", "lsq", "global", "none")

#: Thickness fits and colour matches: the search range, its steps and the mirror exclusion.
DEFAULT_THICKNESS_RANGE_NM = (0.0, 400.0)
DEFAULT_FIT_STEP_NM = 1.0
DEFAULT_MATCH_STEP_NM = 0.1
DEFAULT_EXCLUDE_MIRROR_DEG = 10.0

#: The Mitsuba variants the thin-film plugin runs in (it needs the sampled wavelengths), and the default.
SPECTRAL_VARIANTS = ("llvm_ad_spectral", "scalar_spectral", "cuda_ad_spectral")
#: Intel Open Image Denoise's filter qualities a Mitsuba render may ask for (``denoise=``), best first;
#: ``high`` is the engine's default, ``balanced`` the catalog heroes' (about half the filter's time at 256²,
#: block ΔE00 5–10 % higher on the accuracy tests' 96 px renders).
DENOISE_QUALITIES = ("high", "balanced", "fast")
DEFAULT_VARIANT = "llvm_ad_spectral"
#: Where a Mitsuba render runs (``device``), each with the spectral variant it renders in; Intel Open Image Denoise
#: runs on the same device. The default, ``cpu``, is :data:`DEFAULT_VARIANT`'s (``scalar_spectral`` runs there too).
DEVICES: Registry[str] = Registry("render device", "device", {
    "cpu": (DEFAULT_VARIANT, "the processor: Mitsuba's LLVM variant, the denoiser on the CPU"),
    "cuda": ("cuda_ad_spectral", "an NVIDIA GPU: Mitsuba's CUDA variant, the denoiser's CUDA device")})
