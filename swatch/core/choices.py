"""Every choice list (and the fits' defaults) of the library, defined once (no numpy: the spec
parser imports it). The limits are in :mod:`swatch.core.limits`.

The CLI builds its ``click.Choice`` lists from these, and the library's checks raise
:class:`swatch.core.errors.SwatchError` naming them, so a new choice is added in one place.
"""
from __future__ import annotations

__all__ = [
    "SHAPES",
    "MESH_FORMATS",
    "MODELS",
    "DISTRIBUTIONS",
    "FINISHES",
    "IMAGE_SPACES",
    "ENVIRONMENTS",
    "BACKGROUNDS",
    "ENGINES",
    "MITSUBA_LIGHTINGS",
    "LIGHTINGS",
    "SCALE_MODES",
    "DEFAULT_THICKNESS_RANGE_NM",
    "DEFAULT_FIT_STEP_NM",
    "DEFAULT_MATCH_STEP_NM",
    "DEFAULT_EXCLUDE_MIRROR_DEG",
    "DENOISE_QUALITIES",
]

#: Swatch shapes of a render: flat plate, half cylinder (a bent sheet), sphere.
SHAPES = ("flat", "cylinder", "sphere")
#: Mesh files a render can show instead (``--mesh``; a .gltf only with embedded buffers).
MESH_FORMATS = ("obj", "ply", "stl", "glb", "gltf")
#: Intensity models: ``paper`` (the half-vector reflectance alone, facet probability constant) and
#: ``microfacet`` (D G F / (4 cos θ_l cos θ_v)).
MODELS = ("paper", "microfacet")
#: Microfacet normal distributions.
DISTRIBUTIONS = ("ggx", "beckmann")
#: Named surface finishes (their roughness: :mod:`swatch.physics.finishes`); ``brushed`` is anisotropic.
FINISHES = ("polished", "satin", "bead-blasted", "brushed")
#: RGB primaries of the EXR images of renders and angular maps (the colorimeter knows more spaces,
#: :data:`swatch.colorimetry.colorimeter.RGB_SPACES`; these are the ones with an EXR ``chromaticities`` tag).
IMAGE_SPACES = ("srgb", "acescg")
#: Built-in lighting of renders (``--environment``; a path to an equirectangular .exr also works):
#: ``none`` (one directional light), ``uniform`` (radiance 1 everywhere), ``studio`` (a photographic
#: studio: soft boxes, dark walls, a floor and horizon).
ENVIRONMENTS = ("none", "uniform", "studio")
#: Lighting of the catalog page's live view: ``point`` (its one directional light, ``none`` above)
#: and the built-in environments.
LIGHTINGS = ("point", *(e for e in ENVIRONMENTS if e != "none"))
#: Display backgrounds of renders (``environment``: the map seen behind the object, also in the EXR).
BACKGROUNDS = ("grey", "white", "environment")
#: Render engines: ``builtin`` (the table-lookup renderer, the default and the sheets' fast path) and
#: ``mitsuba`` (Mitsuba 3's spectral path tracer with the ``anodic_film`` plugin, docs/mitsuba.md).
ENGINES = ("builtin", "mitsuba")
#: Built-in lightings of the ``mitsuba`` engine (a path to an .exr or .hdr map also works): ``studio``
#: (cyclorama and soft boxes), ``sun`` (Mitsuba's ``sunsky``), ``uniform`` (radiance 1).
MITSUBA_LIGHTINGS = ("studio", "sun", "uniform")
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
