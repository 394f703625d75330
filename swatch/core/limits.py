"""Caps on untrusted input, defined once: sizes and counts are checked before memory is spent.

Every limit here is quoted in the error that enforces it (what is allowed), so a user who hits
one learns the bound. Light module (no numpy), importable from anywhere.
"""
from __future__ import annotations

import os
import stat

from swatch.core.errors import SwatchError

__all__ = ["MIN_ENV_RENDER_PX", "MIN_ROUGHNESS_ALPHA", "MAX_FIT_GEOMETRIES", "MAX_OVERCOATS", "MAX_ERROR_CHARS",
           "MAX_ERROR_WORD_CHARS", "MAX_PROFILE_NAME_CHARS", "plan_rows", "MAX_METADATA_BYTES", "MAX_NAME_CHARS",
           "MAX_CACHE_ENTRY_BYTES", "MAX_WAVELENGTHS", "MAX_RANGE_POINTS", "MAX_MEASUREMENT_BYTES",
           "MAX_SPEC_BYTES", "MAX_CSV_FIELD_CHARS", "MAX_LAB_AB", "MIN_PEAK_REFLECTANCE", "MAX_RUN_BYTES",
           "MAX_THICKNESS_NM", "MAX_VOLTAGE_V", "MAX_SPREAD_NM", "MAX_SPREAD_FRACTION", "MAX_SIZE_PX",
           "MAX_ANGULAR_SAMPLES", "MAX_ENV_PIXELS", "MAX_ENV_SIDE", "MAX_ENV_FILE_BYTES", "MAX_ENV_RENDER_PX",
           "MAX_SWATCHES", "MAX_CHIP_PX", "MAX_GRID_NODES", "MAX_SEARCH_POINTS", "MAX_RA_NM", "MAX_COUPON_BYTES",
           "MAX_COUPON_ROWS", "MAX_COUPONS", "MAX_PROFILE_BYTES", "MAX_PROFILE_TEXT_CHARS", "MAX_TOLERANCE",
           "MAX_REFLECTANCE", "MIN_REFLECTANCE", "MAX_MESH_BYTES", "MAX_MESH_TRIANGLES", "MAX_PAGE_MESH_TRIANGLES", "MAX_MESH_COORDINATE",
           "MIN_MESH_EXTENT", "MAX_MESH_VERTICES", "MAX_MESH_NODES", "MAX_MESH_NODE_DEPTH", "MAX_MESH_JSON_ITEMS",
           "MAX_INSTRUMENT_SAMPLES",
           "MAX_INSTRUMENT_FIELDS", "MAX_HEADER_COUNT_CHARS", "MIN_MEASURED_WAVELENGTH_NM", "MAX_MEASURED_WAVELENGTH_NM",
           "MAX_INSTRUMENT_GEOMETRIES", "MAX_SPP", "MAX_SEED", "MAX_MITSUBA_PX",
           "MAX_MITSUBA_SAMPLES", "MAX_DENOISE_PX", "MAX_DENOISE_MEMORY_MB", "MAX_PASS_LANES", "MAX_PASS_SPP",
           "MIN_YEAR", "MAX_YEAR", "MIN_TURBIDITY", "MAX_TURBIDITY", "SCHEDULER_TIMEOUT_S", "CLUSTER_TASK_RETRIES",
           "read_capped", "read_text_capped", "MAX_ANISO_RENDER_PX", "MIN_FILM_INDEX_SCALE", "MAX_FILM_INDEX_SCALE",
           "MAX_DISPLAY_EXPOSURE", "MAX_FIGURE_ROWS", "MAX_USD_PART_TRIANGLES", "MAX_BASE_URL_CHARS"]

#: A catalog's own metadata files (``.swatch-catalog/manifest.json``, ``journal.json``); a 400-swatch
#: catalog's manifest is ~20 kB.
MAX_METADATA_BYTES = 16 * 1024 * 1024
#: How long a distributed catalog build waits for its Dask scheduler to answer (``--scheduler``), seconds:
#: an unreachable one is an error after this, with nothing written.
SCHEDULER_TIMEOUT_S = 10.0
#: How many times the cluster runs a unit of work of a catalog build again after it raised (a worker that
#: dies is handled by Dask itself: its tasks go to the others, up to ``distributed.scheduler.allowed-failures``).
CLUSTER_TASK_RETRIES = 2
#: A file name read back from metadata (the usual file-system limit).
MAX_NAME_CHARS = 255
#: One cached tile (``.swatch-catalog/cache/*.npz``); the largest spec (two 512 px renders and a map)
#: needs ~5 MB.
MAX_CACHE_ENTRY_BYTES = 64 * 1024 * 1024
#: Points in a wavelength grid (380–780 nm at 0.04 nm; colorimetry itself needs 1–20 nm steps).
MAX_WAVELENGTHS = 10_001
#: Values in one ``A:B:STEP`` range of the command line (thicknesses, voltages, angles).
MAX_RANGE_POINTS = 100_000
#: A measurement file (CSV, CGATS, CxF3): an sBRDF set of ~7000 geometries at 5 nm (86 × 86 angles) is ~15 MB, and
#: reading and fitting it peaks near 1 GB.
MAX_MEASUREMENT_BYTES = 16 * 1024 * 1024
#: A catalog spec (TOML; the shipped ones are ~1 kB).
MAX_SPEC_BYTES = 1024 * 1024
#: One CSV field (Python's csv module default).
MAX_CSV_FIELD_CHARS = 131_072
#: Largest |a*| and |b*| accepted as a colour (real surface colours stay within about ±130).
MAX_LAB_AB = 200.0
#: A measured spectrum whose largest reflectance (fraction) is below this is not a measurement.
MIN_PEAK_REFLECTANCE = 1e-4


def _lowered_budget(default: int, variable: str = "SWATCH_MAX_RUN_BYTES", floor: int = 64 * 1024 ** 2) -> int:
    """``default``, or the smaller budget (bytes, at least ``floor``) that the environment variable
    ``variable`` names; a larger or unreadable value is ignored (a run may be told to plan for less
    memory, never for more)."""
    try:
        asked = int(os.environ.get(variable, ""))
    except ValueError:
        return default
    return min(default, max(asked, floor))


#: Working memory one run may plan for; large jobs are done in chunks or refused beyond it.
#: ``SWATCH_MAX_RUN_BYTES`` (bytes, 64 MiB at least) lowers it for a run: the memory-cap tests plan the
#: chunked commands against a small budget under a matching address-space limit (issue 17 item 7).
MAX_RUN_BYTES = _lowered_budget(2 * 1024 ** 3)
#: Distinct geometries in one measurement to fit (an 86 × 86 sBRDF set has 7,396): one thickness of the
#: search sweep at the cap (~20k facet angles × the wavelengths) stays well inside MAX_RUN_BYTES.
MAX_FIT_GEOMETRIES = 20_000
#: Largest film thickness accepted (anodic films are 10–300 nm; interference orders beyond a
#: micrometre are not colours any more).
MAX_THICKNESS_NM = 1000.0
#: Longest error line the CLI prints, and longest word in it (a message that quotes a huge input
#: has the quote cut, not what it says is allowed).
MAX_ERROR_CHARS = 4000
MAX_ERROR_WORD_CHARS = 200
#: Clear layers over the oxide (``--overcoat``); their total thickness is capped at MAX_THICKNESS_NM too.
MAX_OVERCOATS = 10
#: Largest anodising voltage accepted.
MAX_VOLTAGE_V = 300.0
#: A film's thickness spread (1σ of the local thickness, swatch.physics.spread): the absolute part, nm, and the part
#: proportional to the thickness. Beyond them every interference colour is washed out to grey.
MAX_SPREAD_NM = 50.0
MAX_SPREAD_FRACTION = 0.3
#: Largest render size (pixels per side): a 4096² render peaks at ~1.2 GB (8192² would need ~4.5 GB).
MAX_SIZE_PX = 4096
#: Smallest render size under an environment (pixels per side): its shading grid needs 8
#: (a point-light render takes any size from 1).
MIN_ENV_RENDER_PX = 8
#: Smallest microfacet roughness alpha: below it alpha² underflows in the distributions' terms
#: (1e-300 gave NaN pixels); 0.001 is already a mirror at any render size.
MIN_ROUGHNESS_ALPHA = 1e-3
#: Range of a film's real-index factor (a process profile's ``film_index_scale``, the Mitsuba plugin's
#: property): a deposited oxide's index is within ±50 % of the tabulated film's (dimensionless).
MIN_FILM_INDEX_SCALE = 0.5
MAX_FILM_INDEX_SCALE = 1.5
#: Largest display exposure factor of a render's PNG (and 1/it the smallest): 6 stops either way.
MAX_DISPLAY_EXPOSURE = 64.0
#: Largest angular map, in cells × wavelengths: its spectral array (8 bytes a sample) and the
#: spectral EXR (4) stay near 0.6 GB within MAX_RUN_BYTES (e.g. 700 × 700 cells at 81 wavelengths).
MAX_ANGULAR_SAMPLES = 40_000_000
#: A user's environment map (equirectangular EXR), checked from its header before pixels are read.
MAX_ENV_PIXELS = 8192 * 4096
MAX_ENV_SIDE = 16384
MAX_ENV_FILE_BYTES = 512 * 1024 * 1024
#: Largest environment-lit render (pixels per side): a 2048² render peaks at ~0.7 GB (the
#: gathered environment samples of the shading points), within MAX_RUN_BYTES.
MAX_ENV_RENDER_PX = 2048
#: Side of an environment-lit render of an anisotropic (brushed) finish: four bins gathered per
#: shading point (swatch.render.builtin.env_aniso), so a quarter of the pixels for the same memory.
MAX_ANISO_RENDER_PX = 1024

#: Swatches in one catalog (a spec's thickness or voltage list or range).
MAX_SWATCHES = 400
#: Largest print-chip side in pixels (a 16-bit RGB chip of 4096² is 100 MB in memory).
MAX_CHIP_PX = 4096
#: Thickness nodes of either explorer table (a 1000 nm range at 0.1 nm).
MAX_GRID_NODES = 10_001
#: Largest thickness search grid (``swatch match``/``fit`` ``--step`` over ``--range``).
MAX_SEARCH_POINTS = 200_000
#: Largest roughness Ra accepted by the Rayleigh criterion (nm; a millimetre).
MAX_RA_NM = 1e6
#: A coupon CSV (``swatch calibrate``): bytes, non-comment rows and coupons. A cap bounds time as well as
#: memory: the search grows linearly with the coupons (the leave-one-out folds are Newton steps, a bounded number
#: refitted: swatch.fit.calibration.leave_one_out); 1,000 at 0–300 V take ~20 s of CPU and 0.8 GB peak
#: (``calibrate_1000_cpu_s``, ``calibrate_1000_peak_mb`` in ``python3 dev.py bench calibrate``); a line is
#: calibrated from tens.
MAX_COUPON_BYTES = 8 * 1024 * 1024
MAX_COUPON_ROWS = 200_000
MAX_COUPONS = 1000
#: Parts drawn in ``swatch check --report``'s check.png (check.json has them all): a figure stays a page.
MAX_FIGURE_ROWS = 60
#: A process profile (TOML; the shipped ones are ~1 kB) and one of its text fields.
MAX_PROFILE_BYTES = 64 * 1024
MAX_PROFILE_TEXT_CHARS = 2000
MAX_PROFILE_NAME_CHARS = 80
#: Largest colour tolerance (ΔE, any metric) a spec or a grade may state.
MAX_TOLERANCE = 100.0
#: Largest reflectance factor accepted in a measurement (fraction). Near the mirror direction a
#: glossy sample's reflectance factor (relative to a white diffuser) can reach the hundreds;
#: beyond this a value is an error in the file.
MAX_REFLECTANCE = 1e5
#: Most negative reflectance (as a fraction) accepted as measurement noise.
MIN_REFLECTANCE = -0.05
#: A mesh file (``swatch render --mesh``): bytes (a binary STL of 64 MB is 1.3 M triangles) and
#: triangles (Embree's scene and the per-corner normals stay near 0.3 GB).
MAX_MESH_BYTES = 64 * 1024 * 1024
MAX_MESH_TRIANGLES = 2_000_000
#: A catalog's part on its page (the live view's WebGL2 triangles, embedded as float32 corners and normals:
#: 72 bytes a triangle in the page, 14 MB at the cap; software GL draws 200 000 in about a frame's time).
MAX_PAGE_MESH_TRIANGLES = 200_000
#: A USD preset's part (``swatch preset --format usd|usdz --mesh``): each triangle keeps its own corners and
#: normals, 72 bytes a triangle in the .usdz's binary layer (14 MB at the cap), several times that as .usda text.
MAX_USD_PART_TRIANGLES = 200_000
#: The address a physicallybased.info document's pictures are served from (``--base-url``, ``[presets]
#: physicallybased_base_url``): every picture's URL starts with it.
MAX_BASE_URL_CHARS = 1000
#: A mesh vertex coordinate's magnitude (the file's units; the mesh is placed in the unit sphere):
#: beyond it the areas and normals overflow float64 (1e300 made "every triangle is degenerate").
MAX_MESH_COORDINATE = 1e15
#: A mesh's smallest size (its bounding box's largest side, the file's units). A smaller mesh is scaled up by a
#: power of two (exact) before it is placed, so any size renders alike; what this bounds is the file's own
#: precision: glTF, binary STL and PLY store float32, whose normal numbers end at 1.2e-38, so a mesh of 1e-30
#: keeps its detail down to a millionth of its size, and Mitsuba traces float32. (Placing a mesh under ~1e-290
#: overflowed: 10^digits of trimesh's vertex merge.)
MIN_MESH_EXTENT = 1e-30
#: A mesh's vertices (a triangle soup's corners: three a triangle), the triangle cap's companion: a glTF's
#: nodes place a copy of their mesh's vertices each, however few triangles use them.
MAX_MESH_VERTICES = 3 * MAX_MESH_TRIANGLES
#: A glTF's scene graph, checked in its JSON before the reader builds anything: nodes (with the primitives of
#: each placed mesh that has several: a frame each in trimesh's scene, 10 000 flatten in ~3 s and ~0.2 GB) and
#: the depth of its node trees (trimesh multiplies each node's transforms from its root with numpy's multi_dot,
#: whose chain ordering is cubic in the depth: 10 000 nodes 20 deep take ~11 s of CPU, 64 deep ~90 s).
MAX_MESH_NODES = 10_000
MAX_MESH_NODE_DEPTH = 20
#: Objects and lists in a glTF's JSON, counted (its ``{`` and ``[``) before it is parsed: a 64 MB JSON of empty
#: objects parses into 22 M dicts, 1.9 GB; a part at the caps above has tens of thousands.
MAX_MESH_JSON_ITEMS = 1_000_000
#: An instrument file (CGATS text, CxF3 XML, CSV; ``fit``, ``calibrate``, ``check``; its bytes are
#: capped by MAX_MEASUREMENT_BYTES): samples, fields of a CGATS table (a 1 nm spectrum 360–830 nm
#: has 471) and geometries of one sample.
MAX_INSTRUMENT_SAMPLES = 10_000
MAX_INSTRUMENT_FIELDS = 2_000
MAX_INSTRUMENT_GEOMETRIES = 32
#: A count in a measurement file's header (CGATS ``NUMBER_OF_SETS``, ``NUMBER_OF_FIELDS``, ``SPECTRAL_BANDS``):
#: characters read before it is converted (the largest count allowed, MAX_WAVELENGTHS, has 5 digits).
MAX_HEADER_COUNT_CHARS = 12
#: The wavelengths a measured spectrum may hold, nm: a UV–visible–NIR spectrophotometer's span and the
#: optical tables' (a spectral fit uses what the film's and substrate's tables cover; colorimetry uses
#: 360–830 nm of it).
MIN_MEASURED_WAVELENGTH_NM = 200.0
MAX_MEASURED_WAVELENGTH_NM = 2500.0

#: ``swatch render --engine mitsuba``: samples per pixel, the seed, the image side, and the total
#: samples (size² × spp), which bound the time: the studio sphere traces about 4e6 samples a second on
#: 2 cores (512² at 256 spp, 6.7e7 samples, 16.8 s), the plate (more bounces) about 2.2e6 (loaded: 1024² at
#: 128 spp, 1.3e8 samples, denoised, took 140 s at load 4.7; 2048² at 32 spp, 102 s), so 2**26 (6.7e7) samples
#: keeps a render within the minute it is promised (256² at 16384 spp, 1.1e9 samples, ran past 180 s).
MAX_SPP = 16384
MAX_SEED = 2**31 - 1
#: The side: at 4096² one sample a pixel took 57 s and 2.1 GB without denoising (the film, its develop and the
#: EXR and PNG of 16.7e6 pixels), 7.4 GB denoised; 2048² at 16 spp (the sample cap) 0.73 GB.
MAX_MITSUBA_PX = 2048
MAX_MITSUBA_SAMPLES = 2**26
#: The largest side Intel Open Image Denoise is run on (a Mitsuba render's ``denoise``; its default quality
#: ``high``): at 2048² the filter alone took 95 s (``balanced``: 8.7 s) on a loaded 2-core machine and the render
#: 1.7 GB; at 1024² a quarter of that. Larger renders are made without denoising (more samples instead).
MAX_DENOISE_PX = 1024
#: The denoiser's working memory, MB (OIDN's ``maxMemoryMB``: above it OIDN filters the image in tiles, the
#: same bytes for an image that fits: the 256 px heroes are unchanged; 2.6 GB at 2048² without it).
MAX_DENOISE_MEMORY_MB = 512
#: Samples one Mitsuba pass traces at once, and samples per pixel in one pass: a render is split into
#: passes of at most these. Mitsuba's loops are symbolic (one kernel per path, its state in registers), so a
#: pass's memory hardly grows with its lanes (peak RSS of a whole render, llvm_ad_spectral, studio sphere:
#: 273 MB at 2**20 lanes, 296 MB at 2**24, 385 MB at 2**26); what bounds a pass is how long a stop waits
#: for it (a stop is taken between passes: 2**24 lanes is ~9 s on 2 cores) and, for the low-discrepancy
#: sampler, how many samples of a pixel are stratified together (each pass is its own sequence: at 2**20
#: lanes a 512 px render was stratified in fours and a 1024 px one not at all).
MAX_PASS_LANES = 1 << 24
MAX_PASS_SPP = 256
#: ``--sun-date``: the years the solar-position model is stated for (and sane), and the sky
#: model's turbidity range (Hosek–Wilkie's fit covers 1–10).
MIN_YEAR, MAX_YEAR = 1900, 2100
MIN_TURBIDITY, MAX_TURBIDITY = 1.0, 10.0


def plan_rows(bytes_per_row: int, what: str, hint: str = "", budget: int = MAX_RUN_BYTES // 2) -> int:
    """Rows one chunk of work may hold (``bytes_per_row`` each) within half the run's memory budget
    (the rest is the interpreter, the libraries and the inputs); SwatchError when not even one fits.

    Parameters
    ----------
    bytes_per_row : int
        Memory one row needs, bytes (at least 1 is assumed).
    what : str
        The work, for the message.
    hint : str
        What to do instead, appended to the message (default none).
    budget : int
        Bytes the chunk may hold (default half of ``MAX_RUN_BYTES``).

    Returns
    -------
    int
        ``budget // bytes_per_row`` (≥ 1).

    Raises
    ------
    SwatchError
        When one row needs more than ``budget``.
    """

    per = max(1, int(bytes_per_row))
    if per > budget:
        raise SwatchError(f"{what} needs {per / 1024 ** 3:.1f} GB at once, more than a run may plan for "
                          f"({MAX_RUN_BYTES / 1024 ** 3:g} GB){'; ' + hint if hint else ''}")
    return budget // per


def read_capped(path, limit: int, what: str) -> bytes:
    """The bytes of ``path``, refused (SwatchError) beyond ``limit`` bytes before they are all read.

    Works for devices too (``/dev/zero``): at most ``limit + 1`` bytes are read. A pipe or socket
    is refused before it is opened (reading one blocks until a writer comes, maybe never).

    Parameters
    ----------
    path : str or os.PathLike
        The file to read (a regular file or a device; a pipe or socket is refused).
    limit : int
        Largest size allowed, bytes.
    what : str
        What the file is, for the messages.

    Returns
    -------
    bytes
        The file's content, at most ``limit`` bytes.

    Raises
    ------
    SwatchError
        For a pipe or socket, or more than ``limit`` bytes.
    OSError
        When it cannot be opened or read (FileNotFoundError, IsADirectoryError, ...).
    """

    try:
        mode = os.stat(path).st_mode
    except OSError:
        mode = 0  # (open reports it)
    if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):  # opening a pipe would wait for a writer forever
        raise SwatchError(f"{path}: a pipe or socket, not a file; a {what} must be a regular file")
    with open(path, "rb") as fh:
        st = os.fstat(fh.fileno())
        data = b"x" * (limit + 1) if stat.S_ISREG(st.st_mode) and st.st_size > limit else fh.read(limit + 1)
    if len(data) > limit:
        raise SwatchError(f"{path}: larger than {_size(limit)}; a {what} is at most {_size(limit)}")
    return data


def read_text_capped(path, limit: int, what: str, kind: str, source: str | None = None,
                     encoding: str = "utf-8-sig") -> str:
    """The text of ``path`` through :func:`read_capped`, with the one-line errors of a user's file:
    missing, a folder (``give a .{kind} file``), unreadable, or not UTF-8 (``a {what} is a {kind}
    file``). ``source`` names the file in the messages (default ``path``). A UTF-8 byte-order mark
    (Windows editors write one) is dropped.

    Parameters
    ----------
    path : str or os.PathLike
        The user's file to read.
    limit : int
        Largest size allowed, bytes.
    what, kind : str
        What the file is (``measurement file``) and its format (``CSV``), for the messages.
    source : str or None
        The file's name in the messages (default ``path``).
    encoding : str
        Default ``utf-8-sig``.

    Returns
    -------
    str
        The text decoded with ``encoding`` (the default drops a leading byte-order mark); newlines as in the file.

    Raises
    ------
    SwatchError
        For every failure above, and those of :func:`read_capped`.
    """

    source = str(path) if source is None else source
    try:
        raw = read_capped(path, limit, what)
    except FileNotFoundError:
        raise SwatchError(f"{what} {source} does not exist") from None
    except IsADirectoryError:
        raise SwatchError(f"{what} {source} is a folder; give a .{kind.lower()} file") from None
    except OSError as exc:
        raise SwatchError(f"cannot read {what} {source}: {exc.strerror}") from None
    try:
        return raw.decode(encoding)
    except UnicodeDecodeError:
        raise SwatchError(f"{source}: not UTF-8 text; a {what} is a {kind} file") from None


def _size(n: int) -> str:
    return f"{n // (1024 * 1024)} MB" if n >= 1024 * 1024 else f"{n // 1024} kB"
