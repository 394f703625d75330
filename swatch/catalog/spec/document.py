"""The catalog spec as a document: :class:`CatalogSpec`, parsed from a TOML file and validated strictly.

A spec names the catalog, the film and substrate, the thicknesses (or anodising voltages), the colorimetry, the
geometries, the render options, the tolerance grade and the sheet layout. Every key is checked: an unknown key, a
wrong type or an impossible value raises :class:`~swatch.core.errors.SwatchError` naming the file, the key and what
is allowed, e.g. ``catalog/x.toml: key thickness.step_nm: must be a number > 0 (got 'a')``.

This module is light (no colour-science import) so that a no-op rebuild starts quickly; the format: docs/catalog.md.
"""
from __future__ import annotations

import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path

from swatch.catalog.chip_size import CHIP_DPI, CHIP_SIZE_MM, chip_px
from swatch.catalog.spec.checks import SpecChecker, spec_material, spec_process, spec_range
from swatch.catalog.spec.render import parse_render
from swatch.colorimetry import tolerance
from swatch.colorimetry.geometry import DEFAULT_ASPECULAR_DEG, Geometry, geometry_name
from swatch.colorimetry.tolerance import get_tolerance
from swatch.core.choices import MODELS, SHAPES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_CHIP_PX, MAX_SPEC_BYTES, MAX_THICKNESS_NM, MAX_VOLTAGE_V, read_text_capped
from swatch.physics.finishes import get_finish
from swatch.physics.growth import growth_law_nm, thickness_to_voltage_V
from swatch.physics.process import DEFAULT_PROCESS
from swatch.physics.spread import ThicknessSpread

__all__ = ["spec_summary", "CatalogSpec", "load_spec", "parse_spec", "RENDER_SHAPES", "RENDER_MODELS"]

#: Shapes and shading models a tile can show (swatch.render.render_swatch accepts these).
RENDER_SHAPES, RENDER_MODELS = SHAPES, MODELS


@dataclass(frozen=True)
class CatalogSpec:
    """A validated catalog spec (:func:`parse_spec`); frozen. See docs/catalog.md for the TOML format.

    Attributes
    ----------
    source : str
        The file's name, for messages.
    name, description : str
        The catalog's title and its one-paragraph description (on the page and the sheets).
    film, substrate : str
        Optical table names (the process's, or the spec's overrides).
    nm_per_V, offset_nm, knee_V, nm_per_V_above_knee : float or None
        The growth law: ``thickness_nm = offset_nm + nm_per_V × voltage_V`` (two slopes with a knee);
        ``nm_per_V`` None when the profile has no rate.
    thickness_nm : tuple of float
        The swatches' thicknesses, nm.
    voltage_V : tuple of float or None
        The voltages given (None when thicknesses were given).
    illuminant, observer, wavelength_step_nm : str, str, float
        The colorimetry (``observer`` ``"2"`` or ``"10"``) and its grid's step: 1, 5 or 10 nm (ASTM E308).
    reference : swatch.colorimetry.geometry.Geometry
        The reference geometry (default 45:0).
    multi_angle : tuple of swatch.colorimetry.geometry.Geometry
        The multi-angle geometries (default 45as-15 … 45as110, ASTM E2194 / E2539).
    shapes, size_px, model, roughness, angular_map, finish, hero
        The tiles' renders (``roughness`` is GGX α; a named ``finish`` sets it: the first of ``finishes``).
    finishes : tuple of str
        The finishes offered (the page's live view and the heroes), the first shown first and used by the sheets
        and chips; ``(finish,)`` for ``finish = X`` alone; empty with a bare ``roughness``.
    mesh, mesh_path, mesh_sha256 : str or None
        The designer's part (``[render] mesh``): the name as given, its resolved path and the SHA-256 of its
        bytes (None without one; the path is not part of :meth:`canonical`).
    hero_size_px, hero_spp, hero_cover_px, denoise
        The hero renders' side (pixels), samples per pixel, the page's cover's side (0: no cover), denoised or not.
    scheme, grade, metric, max_delta_E : str or None, str or None, str, float
        The tolerance: a named grade (None for a written bound), the colour difference it bounds (``dEab``
        or ``dE00``) and its bound, in that metric.
    search_nm, columns, rows : float, int, int
        The process window's search span (nm); tiles per sheet across and down.
    process, process_origin, film_index_scale, spread_nm, spread_fraction : str, str, float, float, float
        The profile's name and where it came from, its factor on the film's real index (dimensionless), and
        its thickness spread: 1σ = spread_nm + spread_fraction × d (nm).
    chips, chip_size_mm, chip_dpi
        Print chips: on/off, side (mm), resolution (dpi).
    presets : bool
        Whether the build fits and writes the 3-D material presets (``[presets] enabled``).
    ar : bool
        Whether the page offers "see it in your room" (``[presets] ar``, default on with the presets): the
        ``<model-viewer>`` files and script (swatch.catalog.ar).
    presets_usd, presets_physicallybased : bool
        ``[presets] usd``: a ``.usdz`` per swatch (swatch.catalog.presets_usd; default off); ``[presets]
        physicallybased``: one physicallybased.info document for the catalog (default off). Both need the presets.
    presets_physicallybased_base_url : str or None
        ``[presets] physicallybased_base_url``: the http(s) address the catalog's ``presets/`` folder is served
        from; the document's picture URLs are then absolute under it (None: relative references).
    scheduler : str or None
        ``[build] scheduler``: the address of the Dask scheduler the build's work is sent to (None: local
        processes); not part of :meth:`canonical` (the files do not depend on where they were made).
    """
    source: str  # file name, for messages
    name: str
    description: str
    film: str
    substrate: str
    nm_per_V: float | None  # growth rate (None: the profile has none; thicknesses only)
    thickness_nm: tuple[float, ...]
    voltage_V: tuple[float, ...] | None  # given voltages (None when thicknesses were given)
    illuminant: str
    observer: str
    wavelength_step_nm: float
    reference: Geometry
    multi_angle: tuple[Geometry, ...]
    shapes: tuple[str, ...]
    size_px: int
    model: str
    roughness: float
    angular_map: bool
    scheme: str | None  # a named grade's scheme and name (None for a written tolerance)
    grade: str | None
    metric: str  # the colour difference the tolerance bounds (swatch.colorimetry.tolerance.METRICS)
    max_delta_E: float  # its bound, in that metric
    search_nm: float
    columns: int
    rows: int
    process: str = "titanium-fujii2019"  # the profile's name
    offset_nm: float = 0.0  # growth law: thickness_nm = offset_nm + nm_per_V × voltage_V
    film_index_scale: float = 1.0
    process_origin: str = "preset"
    spread_nm: float = 0.0  # the profile's thickness spread (swatch.physics.spread): 1σ = spread_nm + spread_fraction × d
    spread_fraction: float = 0.0
    knee_V: float | None = None  # a two-slope growth law: nm_per_V up to knee_V, nm_per_V_above_knee beyond
    nm_per_V_above_knee: float | None = None
    chips: bool = True  # per-swatch print chips (PNG and TIFF, 16-bit)
    chip_size_mm: float = 50.0
    chip_dpi: int = 300
    finish: str | None = None  # a named finish (swatch.physics.finishes); it sets ``roughness``
    hero: bool = False  # per-swatch hero renders through Mitsuba (swatch.catalog.hero)
    hero_size_px: int = 256  # a hero's side in pixels (a 128 CSS px picture on a 2x display)
    hero_spp: int = 16  # its samples per pixel
    hero_cover_px: int = 0  # the page's first view: the most vivid swatch's hero at this side (0: none)
    denoise: bool = True  # heroes denoised (Intel Open Image Denoise, swatch.render.mitsuba.denoise)
    presets: bool = True  # per-swatch 3-D material presets (swatch.catalog.presets)
    ar: bool = True  # the page's "see it in your room" (<model-viewer>, swatch.catalog.ar); needs presets
    presets_usd: bool = False  # a .usdz per swatch (swatch.catalog.presets_usd); needs presets
    presets_physicallybased: bool = False  # one physicallybased.info document (swatch.catalog.presets_usd)
    presets_physicallybased_base_url: str | None = None  # where presets/ is served from (absolute picture URLs)
    finishes: tuple[str, ...] = ()  # the finishes offered, the first shown first (= finish); () with a bare roughness
    mesh: str | None = None  # the designer's part, as the spec names it (relative to the spec's folder)
    mesh_sha256: str | None = None  # its bytes' hash (in the fingerprint: an edited part rebuilds)
    mesh_path: str | None = field(default=None, compare=False)  # where it was read (not hashed: a moved folder)
    scheduler: str | None = field(default=None, compare=False)  # where the work runs, not what it makes

    @property
    def finish_spec(self):
        """The :class:`swatch.physics.finishes.Finish` of ``finish`` (None without one).

        Returns
        -------
        swatch.physics.finishes.Finish or None
            The named finish (its GGX α, and α_u/α_v when brushed).
        """
        return None if self.finish is None else get_finish(self.finish)

    @property
    def tile_renders(self) -> tuple[str, ...]:
        """What a sheet tile shows rendered, in order: the spec's shapes, then the part (``mesh``) when it names one.

        Returns
        -------
        tuple of str
            ``shapes``, plus ``"mesh"`` with a part.
        """
        return self.shapes + (("mesh",) if self.mesh else ())

    @property
    def tolerance(self):
        """The spec's tolerance: the named grade, or the written bound in its metric.

        Returns
        -------
        swatch.colorimetry.tolerance.Tolerance
            Its metric (``dEab`` / ``dE00``) and bound, and the grade's name when one was named.
        """
        if self.grade is not None:
            return get_tolerance(self.scheme, self.grade)
        return get_tolerance(metric=self.metric, max=self.max_delta_E)

    def voltage_of(self, thickness_nm):
        """Voltage that grows ``thickness_nm`` by the spec's growth law (one slope, or two with a knee).

        Parameters
        ----------
        thickness_nm : array_like
            nm.

        Returns
        -------
        numpy.ndarray or None
            V, the shape of ``thickness_nm``; None without a rate.
        """
        if self.nm_per_V is None:
            return None
        return thickness_to_voltage_V(thickness_nm, self.nm_per_V, self.offset_nm, self.knee_V,
                                      self.nm_per_V_above_knee)

    @property
    def per_sheet(self) -> int:
        """Tiles per sheet (columns × rows).

        Returns
        -------
        int
            ``columns * rows``.
        """
        return self.columns * self.rows

    @property
    def spread(self):
        """The film's thickness spread.

        Returns
        -------
        swatch.physics.spread.ThicknessSpread
            1σ = ``spread_nm`` + ``spread_fraction`` × d (zero: a uniform film).
        """
        return ThicknessSpread(self.spread_nm, self.spread_fraction)

    def coating(self, wavelength_nm):
        """The spec's coating on a wavelength grid: film, substrate, index scale, spread.

        Parameters
        ----------
        wavelength_nm : array_like, shape (W,)
            nm.

        Returns
        -------
        swatch.physics.model.Coating
            Film and substrate indices on the grid (the film's real index scaled), with the spread.
        """
        from swatch.physics.model import get_coating  # lazy: see tests/test_layers.py

        return get_coating(self.film, self.substrate, wavelength_nm, self.film_index_scale, self.spread)

    def canonical(self) -> dict:
        """Everything that affects the outputs, JSON-ready (the build's content hashes; keys a uniform film or
        a one-slope law does not use are left out, so the hashes of before stay).

        Returns
        -------
        dict
            The fields as JSON values, less ``source``, ``mesh_path`` (the part counts by its bytes' hash) and the
            unused keys named above.
        """
        d = asdict(self)
        d.pop("source")
        if d["spread_nm"] == 0.0 and d["spread_fraction"] == 0.0:  # a uniform film: the hashes of before
            d.pop("spread_nm")
            d.pop("spread_fraction")
        if d["knee_V"] is None:  # a linear law: the hashes of before
            d.pop("knee_V")
            d.pop("nm_per_V_above_knee")
        d.pop("mesh_path")
        d.pop("scheduler")  # where the build runs: the same bytes either way
        if len(d["finishes"]) <= 1:  # one finish (it is ``finish``) or none: the hashes of before
            d.pop("finishes")
        if d["ar"] == d["presets"]:  # AR as the presets (its default): the hashes of before
            d.pop("ar")
        for key, default in (("presets", True), ("hero_cover_px", 0), ("mesh", None), ("mesh_sha256", None),
                             ("presets_usd", False), ("presets_physicallybased", False),
                             ("presets_physicallybased_base_url", None)):
            if d[key] == default:  # the hashes of before
                d.pop(key)
        return d


def parse_spec(data: dict, source: str = "<spec>", base_dir: Path | None = None) -> CatalogSpec:
    """Validate a decoded TOML document into a :class:`CatalogSpec` (every key checked).

    Parameters
    ----------
    data : dict
        The decoded document.
    source : str
        Names it in messages.
    base_dir : pathlib.Path, optional
        The spec's folder: a ``process`` file is looked up inside it.

    Returns
    -------
    CatalogSpec
        The checked spec, with the process's values where the spec gives none.

    Raises
    ------
    swatch.core.errors.SwatchError
        An unknown key, a wrong type or an impossible value, in one line naming the file, the key and
        what is allowed.

    Examples
    --------
    >>> s = parse_spec({"name": "Demo", "voltage": {"list_V": [10, 20]}})
    >>> s.thickness_nm == tuple(s.offset_nm + s.nm_per_V * v for v in (10.0, 20.0)), s.per_sheet, s.metric
    (True, 12, 'dEab')
    """
    c = SpecChecker(source)
    top = ("name", "description", "process", "film", "substrate", "nm_per_V", "growth_nm_per_V", "thickness",
           "voltage", "colour", "geometry", "render", "tolerance", "sheet", "chips", "presets", "build")
    c.table(data, "", top)
    if "name" not in data:
        raise SwatchError(f"{source}: missing key name (the catalog's name, a text)")
    name = c.string(data["name"], "name", 120)
    description = c.string(data["description"], "description", 1000, multiline=True) if "description" in data else ""
    proc = spec_process(c, data.get("process", DEFAULT_PROCESS), base_dir)
    film = spec_material(c, data["film"], "film", "film") if "film" in data else None
    substrate = spec_material(c, data["substrate"], "substrate", "substrate") if "substrate" in data else None
    if "nm_per_V" in data and "growth_nm_per_V" in data:
        raise SwatchError(f"{source}: give nm_per_V or its old name growth_nm_per_V, not both")
    rate_key = "growth_nm_per_V" if "growth_nm_per_V" in data else "nm_per_V"
    rate = c.number(data[rate_key], rate_key, 0.1, 10.0) if rate_key in data else None
    proc = proc.with_overrides(film, substrate, rate)
    rate = proc.nm_per_V

    if ("thickness" in data) == ("voltage" in data):
        raise SwatchError(f"{source}: give exactly one of the tables [thickness] (nm) or [voltage] (V)")
    if "thickness" in data:
        d = spec_range(c, data["thickness"], "thickness", "nm", MAX_THICKNESS_NM)
        volts = None
    else:
        if rate is None:
            raise SwatchError(f"{source}: process {proc.name} has no growth rate, so the catalog needs a "
                              "[thickness] table (or nm_per_V, or a calibrated profile)")
        volts = spec_range(c, data["voltage"], "voltage", "V", MAX_VOLTAGE_V)
        d = growth_law_nm(volts, rate, proc.offset_nm, proc.knee_V, proc.nm_per_V_above_knee).tolist()
        for v, t in zip(volts, d, strict=True):
            if not 0 <= t <= MAX_THICKNESS_NM:
                c.fail("voltage", f"{v:g} V gives {t:g} nm at {rate:g} nm/V + {proc.offset_nm:g} nm; "
                       f"from 0 to {MAX_THICKNESS_NM:g} nm allowed", v)

    col = c.table(data.get("colour", {}), "colour", ("illuminant", "observer", "wavelength_step_nm"))
    illuminant = c.string(col.get("illuminant", "D65"), "colour.illuminant", 40)
    observer = col.get("observer", "10")
    if isinstance(observer, int) and not isinstance(observer, bool):
        observer = str(observer)
    observer = c.string(observer, "colour.observer", 10, choices=("10", "2"))
    wl_step = c.number(col.get("wavelength_step_nm", 5), "colour.wavelength_step_nm")
    if wl_step not in (1.0, 5.0, 10.0):
        c.fail("colour.wavelength_step_nm", "must be 1, 5 or 10 (ASTM E308 intervals)", col["wavelength_step_nm"])

    geo = c.table(data.get("geometry", {}), "geometry", ("reference", "multi_angle"))
    ref = c.table(geo.get("reference", {}), "geometry.reference", ("light_deg", "view_deg"))
    ref_light = c.number(ref.get("light_deg", 45.0), "geometry.reference.light_deg", 0, 90, hi_open=True)
    ref_view = c.number(ref.get("view_deg", 0.0), "geometry.reference.view_deg", 0, 90, hi_open=True)
    reference = Geometry(f"{ref_light:g}:{ref_view:g}", ref_light, ref_view, "opposite")
    ma = c.table(geo.get("multi_angle", {}), "geometry.multi_angle", ("light_deg", "aspecular_deg"))
    ma_light = c.number(ma.get("light_deg", 45.0), "geometry.multi_angle.light_deg", 0, 90, hi_open=True)
    asp = ma.get("aspecular_deg", list(DEFAULT_ASPECULAR_DEG))
    empty = isinstance(asp, list) and not asp
    asp_vals = [] if empty else c.numbers(asp, "geometry.multi_angle.aspecular_deg", -180, 180, max_len=24)
    multi = []
    for i, g in enumerate(asp_vals):
        v = ma_light - g  # swatch.physics.geometry.aspecular_view_deg: signed, negative = light's side
        if not abs(v) < 90:
            c.fail(f"geometry.multi_angle.aspecular_deg[{i}]",
                   f"puts the view at {abs(v):g}° from the normal with light at {ma_light:g}°; "
                   f"aspecular angles must lie in ({ma_light - 90:g}, {ma_light + 90:g})", g)
        multi.append(Geometry(geometry_name(ma_light, g), ma_light, abs(v),
                              "opposite" if v >= 0 else "light", g))
    if len({g.name for g in multi}) != len(multi):
        c.fail("geometry.multi_angle.aspecular_deg", "must not repeat an angle", asp)

    render = parse_render(c, data.get("render", {}), base_dir)

    tol = c.table(data.get("tolerance", {}), "tolerance", ("scheme", "grade", "metric", "max", "search_nm"))

    if "metric" in tol or "max" in tol:
        if "scheme" in tol or "grade" in tol:
            c.fail("tolerance", "give scheme and grade, or metric and max (as coating specifications write "
                   "it: { metric = \"dE00\", max = 2.0 }), not both", tol, show_got=False)
        if "metric" not in tol or "max" not in tol:
            c.fail("tolerance", "a written tolerance needs both metric and max", tol, show_got=False)
        metric = c.string(tol["metric"], "tolerance.metric", 10, tuple(tolerance.METRICS))
        max_dE = c.number(tol["max"], "tolerance.max", 0.0, tolerance.MAX_TOLERANCE, lo_open=True)
        scheme, grade = None, None
    else:
        scheme = c.string(tol.get("scheme", "csaj"), "tolerance.scheme", 20, tuple(tolerance.schemes()))
        grade_names = tuple(g.name for g in tolerance.grades(scheme))
        grade = c.string(tol.get("grade", "C"), "tolerance.grade", 20, grade_names)
        metric, max_dE = tolerance.grade_metric(scheme), tolerance.grade_bound(grade, scheme)
    search = c.number(tol.get("search_nm", 50.0), "tolerance.search_nm", 1.0, 200.0)

    sh = c.table(data.get("sheet", {}), "sheet", ("columns", "rows"))
    columns = c.integer(sh.get("columns", 4), "sheet.columns", 1, 8)
    rows = c.integer(sh.get("rows", 3), "sheet.rows", 1, 8)
    ch = c.table(data.get("chips", {}), "chips", ("enabled", "size_mm", "dpi"))
    chips = c.boolean(ch.get("enabled", True), "chips.enabled")
    chip_size = c.number(ch.get("size_mm", CHIP_SIZE_MM), "chips.size_mm", 5.0, 300.0)
    chip_dpi = c.integer(ch.get("dpi", CHIP_DPI), "chips.dpi", 72, 1200)
    if chip_px(chip_size, chip_dpi) > MAX_CHIP_PX:
        c.fail("chips", f"size_mm × dpi must give at most {MAX_CHIP_PX} pixels per side "
               f"({chip_size:g} mm at {chip_dpi} dpi is {chip_px(chip_size, chip_dpi)})", show_got=False)

    pr = c.table(data.get("presets", {}), "presets",
                 ("enabled", "ar", "usd", "physicallybased", "physicallybased_base_url"))
    presets = c.boolean(pr.get("enabled", True), "presets.enabled")
    ar = c.boolean(pr.get("ar", presets), "presets.ar")
    if ar and not presets:
        c.fail("presets.ar", "needs the presets (presets.enabled = true): the viewer shows a fitted preset", True)
    presets_usd = c.boolean(pr.get("usd", False), "presets.usd")
    presets_pb = c.boolean(pr.get("physicallybased", False), "presets.physicallybased")
    for key, on in (("presets.usd", presets_usd), ("presets.physicallybased", presets_pb)):
        if on and not presets:
            c.fail(key, "needs the presets (presets.enabled = true): it is written from the fitted presets", True)
    pb_url = c.base_url(pr["physicallybased_base_url"], "presets.physicallybased_base_url") if (
        "physicallybased_base_url" in pr) else None
    if pb_url is not None and not presets_pb:
        c.fail("presets.physicallybased_base_url", "applies to presets.physicallybased = true", True)
    bu = c.table(data.get("build", {}), "build", ("scheduler",))
    scheduler = c.string(bu["scheduler"], "build.scheduler", 200) if "scheduler" in bu else None
    return CatalogSpec(
        source=source, name=name, description=description, film=proc.film, substrate=proc.substrate,
        nm_per_V=rate, thickness_nm=tuple(float(x) for x in d),
        voltage_V=None if volts is None else tuple(float(v) for v in volts),
        illuminant=illuminant, observer=observer, wavelength_step_nm=wl_step,
        reference=reference, multi_angle=tuple(multi), scheme=scheme, grade=grade, metric=metric, max_delta_E=max_dE,
        search_nm=search, columns=columns, rows=rows, chips=chips, chip_size_mm=chip_size, chip_dpi=chip_dpi,
        process=proc.name, offset_nm=proc.offset_nm, film_index_scale=proc.film_index_scale,
        process_origin=proc.origin, spread_nm=proc.spread.spread_nm, spread_fraction=proc.spread.spread_fraction,
        knee_V=proc.knee_V, nm_per_V_above_knee=proc.nm_per_V_above_knee,
        presets=presets, ar=ar, presets_usd=presets_usd, presets_physicallybased=presets_pb,
        presets_physicallybased_base_url=pb_url, scheduler=scheduler,
        **render)


def load_spec(path) -> tuple[CatalogSpec, bytes]:
    """Read and validate a spec file (size-capped, UTF-8, TOML).

    Parameters
    ----------
    path : str or path-like
        At most :data:`swatch.core.limits.MAX_SPEC_BYTES`.

    Returns
    -------
    (CatalogSpec, bytes)
        The spec and the file's bytes.

    Raises
    ------
    swatch.core.errors.SwatchError
        The file is too big, not UTF-8, not TOML, nested too deeply, or not a valid spec.
    """
    p = Path(path)
    source = str(path)
    text = read_text_capped(p, MAX_SPEC_BYTES, "catalog spec", "TOML", source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SwatchError(f"{source}: not valid TOML: {exc}") from None
    except RecursionError:
        raise SwatchError(f"{source}: tables or lists nested too deeply; a catalog spec nests at most "
                          "three levels") from None
    return parse_spec(data, source, p.parent), text.encode("utf-8")  # valid UTF-8: the file's bytes again


def spec_summary(s: CatalogSpec) -> str:
    """One line: name, swatches, thickness range, sheets, materials, colorimetry, geometries, tolerance, the
    finishes offered and the part.

    Parameters
    ----------
    s : CatalogSpec
        The checked spec.

    Returns
    -------
    str
        ``'NAME': N swatches, A–B nm, S sheet(s) of C×R; film on substrate; D65/10°; …; tolerance …``, then
        ``; finishes polished, satin`` and ``; part part.glb`` when the spec offers them.
    """
    d, per = s.thickness_nm, s.per_sheet
    nm = f"{round(d[0], 1):g}–{round(d[-1], 1):g} nm"  # as the sheets print them (0.1 nm)
    if s.voltage_V:
        nm += f" ({s.voltage_V[0]:g}–{s.voltage_V[-1]:g} V)"
    tol = (f"tolerance {s.metric} ≤ {s.max_delta_E:g}" if s.grade is None
           else f"grade {s.scheme} {s.grade} ({s.metric} ≤ {s.max_delta_E:g})")
    return (f"{s.name!r}: {len(d)} swatches, {nm}, "
            f"{(len(d) + per - 1) // per} sheet(s) of {s.columns}×{s.rows}; {s.film} on {s.substrate}; "
            f"{s.illuminant}/{s.observer}°; reference {s.reference.name}; "
            f"{len(s.multi_angle)} multi-angle geometries; {tol}"
            + (f"; finishes {', '.join(s.finishes)}" if len(s.finishes) > 1 else f"; finish {s.finish}" if s.finish else "")
            + (f"; part {s.mesh}" if s.mesh else ""))
