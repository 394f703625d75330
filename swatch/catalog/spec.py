"""Catalog specs: TOML files describing one catalog, parsed and validated strictly.

A spec names the catalog, the film and substrate, the thicknesses (or anodising voltages), the
colorimetry, the geometries, the render options, the tolerance grade and the sheet layout.
Every key is checked: an unknown key, a wrong type or an impossible value raises
:class:`~swatch.core.errors.SwatchError` naming the file, the key and what is allowed, e.g.
``catalog/x.toml: key thickness.step_nm: must be a number > 0 (got 'a')``.

This module is light (no colour-science import) so that a no-op rebuild starts quickly.
See ``docs/catalog.md`` for the format.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import NoReturn

import numpy as np

from swatch.catalog.chip_size import CHIP_DPI, CHIP_SIZE_MM, chip_px
from swatch.colorimetry import tolerance
from swatch.colorimetry.tolerance import get_tolerance
from swatch.core.choices import FINISHES, MODELS, SHAPES
from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_CHIP_PX,
    MAX_SPEC_BYTES,
    MAX_SWATCHES,
    MAX_THICKNESS_NM,
    MAX_VOLTAGE_V,
    read_text_capped,
)
from swatch.physics.finishes import get_finish
from swatch.physics.materials import list_materials, load_material
from swatch.physics.process import DEFAULT_PROCESS, load_process, preset_names
from swatch.physics.spread import ThicknessSpread

__all__ = ["spec_summary", "CatalogSpec", "Geometry", "load_spec", "parse_spec", "RENDER_SHAPES", "RENDER_MODELS"]

#: Shapes and shading models a tile can show (swatch.render.render_swatch accepts these).
RENDER_SHAPES = SHAPES
RENDER_MODELS = MODELS
#: Default multi-angle set: illumination 45°, aspecular -15°, 15°, 25°, 45°, 75°, 110° (ASTM E2194 / E2539).
DEFAULT_ASPECULAR_DEG = (-15.0, 15.0, 25.0, 45.0, 75.0, 110.0)


@dataclass(frozen=True)
class Geometry:
    """One in-plane light/view geometry.

    ``view_deg`` is the view's polar angle from the normal; ``view_side`` is ``"opposite"`` (the
    usual side, across the normal from the light) or ``"light"`` (the same side as the light).
    """

    name: str
    light_deg: float
    view_deg: float
    view_side: str = "opposite"
    aspecular_deg: float | None = None

    @property
    def view_azimuth_deg(self) -> float | None:
        """For swatch.physics.geometry: None = opposite side (azimuth + 180), 0 = the light's side."""
        return None if self.view_side == "opposite" else 0.0

    @property
    def theta_d_deg(self) -> float:
        """Incidence angle on the half-vector facet (in plane): half the angle between l and v."""
        if self.view_side == "opposite":
            return 0.5 * (self.light_deg + self.view_deg)
        return 0.5 * abs(self.light_deg - self.view_deg)

    def to_json(self) -> dict:
        out = {"name": self.name, "light_deg": self.light_deg, "view_deg": self.view_deg,
               "view_side": self.view_side}
        if self.aspecular_deg is not None:
            out["aspecular_deg"] = self.aspecular_deg
        out["theta_d_deg"] = self.theta_d_deg
        return out


@dataclass(frozen=True)
class CatalogSpec:
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
    extra: dict = field(default_factory=dict)
    chips: bool = True  # per-swatch print chips (PNG and TIFF, 16-bit)
    chip_size_mm: float = 50.0
    chip_dpi: int = 300
    finish: str | None = None  # a named finish (swatch.physics.finishes); it sets ``roughness``
    hero: bool = False  # per-swatch hero renders through Mitsuba (swatch.catalog.hero)

    @property
    def finish_spec(self):
        """The :class:`swatch.physics.finishes.Finish` of ``finish`` (None without one)."""

        return None if self.finish is None else get_finish(self.finish)

    @property
    def tolerance(self):
        if self.grade is not None:
            return get_tolerance(self.scheme, self.grade)
        return get_tolerance(metric=self.metric, max=self.max_delta_E)

    def voltage_of(self, thickness_nm):
        """Voltage, V, growing ``thickness_nm`` by the spec's growth law; None without a rate."""
        from swatch.physics.model import thickness_to_voltage_V  # lazy: see tests/test_layers.py

        if self.nm_per_V is None:
            return None
        if self.knee_V is None:
            return (np.asarray(thickness_nm, dtype=np.float64) - self.offset_nm) / self.nm_per_V
        return thickness_to_voltage_V(thickness_nm, self.nm_per_V, self.offset_nm, self.knee_V,
                                      self.nm_per_V_above_knee)

    @property
    def per_sheet(self) -> int:
        return self.columns * self.rows

    @property
    def spread(self):
        """The film's :class:`swatch.physics.spread.ThicknessSpread`."""

        return ThicknessSpread(self.spread_nm, self.spread_fraction)

    def coating(self, wavelength_nm):
        """The spec's :class:`swatch.physics.model.Coating` on a wavelength grid (nm): film, substrate, index scale, spread."""
        from swatch.physics.model import get_coating  # lazy: see tests/test_layers.py

        return get_coating(self.film, self.substrate, wavelength_nm, self.film_index_scale, self.spread)

    def canonical(self) -> dict:
        """Everything that affects the outputs, JSON-ready (used for content hashes)."""
        d = asdict(self)
        d.pop("source")
        if d["spread_nm"] == 0.0 and d["spread_fraction"] == 0.0:  # a uniform film: the hashes of before
            d.pop("spread_nm")
            d.pop("spread_fraction")
        if d["knee_V"] is None:  # a linear law: the hashes of before
            d.pop("knee_V")
            d.pop("nm_per_V_above_knee")
        return d


# -- validation helpers --------------------------------------------------------------------

class _Checker:
    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, what: str, got=None, show_got: bool = True) -> NoReturn:
        msg = f"{self.source}: key {key}: {what}"
        if show_got:
            msg += f" (got {_show(got)})"
        raise SwatchError(msg)

    def table(self, data, key: str, allowed: tuple[str, ...]) -> dict:
        if not isinstance(data, dict):
            self.fail(key, "must be a table", data)
        for k in data:
            if k not in allowed:
                where = f"{key}.{k}" if key else k
                scope = f" in [{key}]" if key else ""
                raise SwatchError(f"{self.source}: unknown key {where}; allowed{scope}: {', '.join(allowed)}")
        return data

    def number(self, value, key: str, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        if ok:
            v = float(value)
            ok = (lo is None or (v > lo if lo_open else v >= lo)) and (hi is None or (v < hi if hi_open else v <= hi))
        if not ok:
            self.fail(key, f"must be a number {_bounds(lo, hi, lo_open, hi_open)}", value)
        return float(value)

    def integer(self, value, key: str, lo: int, hi: int) -> int:
        if not (isinstance(value, int) and not isinstance(value, bool) and lo <= value <= hi):
            self.fail(key, f"must be a whole number from {lo} to {hi}", value)
        return int(value)

    def string(self, value, key: str, max_len: int = 200, choices=None, multiline: bool = False) -> str:
        if not isinstance(value, str) or not value.strip() or len(value) > max_len:
            self.fail(key, f"must be a non-empty text of at most {max_len} characters", value)
        allowed = "\t\n\r" if multiline else ""
        if any(_is_control(ch) and ch not in allowed for ch in value):
            self.fail(key, "must not contain control characters"
                      + (" (other than tab and line breaks)" if multiline else ""), value)
        if choices is not None:
            for c in choices:
                if c.lower() == value.strip().lower():
                    return c
            self.fail(key, f"must be one of {', '.join(choices)}", value)
        return value.strip()

    def boolean(self, value, key: str) -> bool:
        if not isinstance(value, bool):
            self.fail(key, "must be true or false", value)
        return value

    def numbers(self, value, key: str, lo, hi, max_len: int = MAX_SWATCHES) -> list[float]:
        if not isinstance(value, list) or not value:
            self.fail(key, "must be a non-empty list of numbers", value)
        if len(value) > max_len:
            self.fail(key, f"must have at most {max_len} entries", f"{len(value)} entries", True)
        return [self.number(v, f"{key}[{i}]", lo, hi) for i, v in enumerate(value)]


def _is_control(ch: str) -> bool:
    """C0/C1 controls, DEL and the XML non-characters (the exports are XML: CxF3)."""
    o = ord(ch)
    return o < 32 or 127 <= o < 160 or o in (0xFFFE, 0xFFFF) or 0xD800 <= o < 0xE000


def _show(v) -> str:
    if isinstance(v, str):
        return repr(v if len(v) <= 60 else v[:57] + "...")
    if isinstance(v, dict):
        return "a table"
    if isinstance(v, list):
        return "a list"
    if isinstance(v, bool):
        return "true" if v else "false"
    return repr(v)


def _bounds(lo, hi, lo_open, hi_open) -> str:
    if lo is not None and hi is not None:
        return f"{'>' if lo_open else '>='} {lo:g} and {'<' if hi_open else '<='} {hi:g}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if hi_open else '<='} {hi:g}"
    return ""


def _range(c: _Checker, tbl: dict, key: str, unit: str, hi: float) -> list[float]:
    """start_/stop_/step_ or list_ (unit nm or V) -> sorted values."""
    suffix = "nm" if unit == "nm" else "V"
    names = (f"start_{suffix}", f"stop_{suffix}", f"step_{suffix}", f"list_{suffix}")
    c.table(tbl, key, names)
    has_list = f"list_{suffix}" in tbl
    has_range = any(n in tbl for n in names[:3])
    if has_list == has_range:
        raise SwatchError(
            f"{c.source}: [{key}]: give either start_{suffix}, stop_{suffix}, step_{suffix} or list_{suffix}")
    if has_list:
        vals = c.numbers(tbl[f"list_{suffix}"], f"{key}.list_{suffix}", 0.0, hi)
        if len(set(vals)) != len(vals):
            c.fail(f"{key}.list_{suffix}", "must not repeat a value", tbl[f"list_{suffix}"])
        return sorted(vals)
    for n in names[:3]:
        if n not in tbl:
            raise SwatchError(f"{c.source}: [{key}]: missing key {key}.{n} (a number in {unit})")
    start = c.number(tbl[names[0]], f"{key}.{names[0]}", 0.0, hi)
    stop = c.number(tbl[names[1]], f"{key}.{names[1]}", 0.0, hi)
    step = c.number(tbl[names[2]], f"{key}.{names[2]}", 0.0, None, lo_open=True)
    if stop < start:
        c.fail(f"{key}.{names[1]}", f"must be >= {names[0]} ({start:g})", tbl[names[1]])
    span = (stop - start) / step  # inf for a subnormal step: compared before any conversion
    if not span + 1 <= MAX_SWATCHES:
        n = f"{math.floor(span + 1e-9) + 1}" if math.isfinite(span) else "too many"
        c.fail(f"{key}.{names[2]}", f"gives {n} swatches; at most {MAX_SWATCHES} per catalog", tbl[names[2]])
    count = math.floor(span + 1e-9) + 1
    # start + i*step, rounded to 1e-9 to keep decimal steps exact in the outputs
    return [round(start + i * step, 9) for i in range(count)]


def _material(c: _Checker, value, key: str, role: str) -> str:
    name = c.string(value, key)
    try:
        mat = load_material(name)
    except SwatchError:
        names = [m.name for m in list_materials(role)]
        c.fail(key, f"unknown {role} table; use one of {', '.join(names)}", value)
    if mat.role != role:
        names = [m.name for m in list_materials(role)]
        c.fail(key, f"{mat.name} is a {mat.role} table, not a {role}; use one of {', '.join(names)}", value)
    if mat.wavelength_range_nm[0] > 380 or mat.wavelength_range_nm[1] < 780:
        c.fail(key, f"{mat.name} does not cover 380–780 nm", value)
    return mat.name


def _geometry_name(light: float, aspecular: float) -> str:
    return f"{light:g}as{aspecular:g}"


def _process(c: _Checker, value, base_dir: Path | None):
    """The spec's ``process``: a preset name, or a profile .toml inside the spec's folder."""

    text = c.string(value, "process", 200)
    if text in preset_names() or base_dir is None:
        try:
            return load_process(text)
        except SwatchError as exc:
            c.fail("process", str(exc), value, show_got=False)
    root = base_dir.resolve()
    path = (root / text).resolve()
    if not path.is_relative_to(root):
        c.fail("process", "a profile file must lie inside the spec's folder", value)
    if path.suffix.lower() != ".toml" or not path.is_file():
        c.fail("process", f"is neither a preset ({', '.join(preset_names())}) nor a .toml file next to the spec",
               value)
    return load_process(str(path))


def parse_spec(data: dict, source: str = "<spec>", base_dir: Path | None = None) -> CatalogSpec:
    """Validate a decoded TOML document (``source`` names it in error messages; a ``process`` file is
    looked up inside ``base_dir``, the spec's folder)."""

    c = _Checker(source)
    top = ("name", "description", "process", "film", "substrate", "nm_per_V", "growth_nm_per_V", "thickness",
           "voltage", "colour", "geometry", "render", "tolerance", "sheet", "chips")
    c.table(data, "", top)
    if "name" not in data:
        raise SwatchError(f"{source}: missing key name (the catalog's name, a text)")
    name = c.string(data["name"], "name", 120)
    description = c.string(data["description"], "description", 1000, multiline=True) if "description" in data else ""
    proc = _process(c, data.get("process", DEFAULT_PROCESS), base_dir)
    film = _material(c, data["film"], "film", "film") if "film" in data else None
    substrate = _material(c, data["substrate"], "substrate", "substrate") if "substrate" in data else None
    if "nm_per_V" in data and "growth_nm_per_V" in data:
        raise SwatchError(f"{source}: give nm_per_V or its old name growth_nm_per_V, not both")
    rate_key = "growth_nm_per_V" if "growth_nm_per_V" in data else "nm_per_V"
    rate = c.number(data[rate_key], rate_key, 0.1, 10.0) if rate_key in data else None
    proc = proc.with_overrides(film, substrate, rate)
    rate = proc.nm_per_V

    if ("thickness" in data) == ("voltage" in data):
        raise SwatchError(f"{source}: give exactly one of the tables [thickness] (nm) or [voltage] (V)")
    if "thickness" in data:
        d = _range(c, data["thickness"], "thickness", "nm", MAX_THICKNESS_NM)
        volts = None
    else:
        if rate is None:
            raise SwatchError(f"{source}: process {proc.name} has no growth rate, so the catalog needs a "
                              "[thickness] table (or nm_per_V, or a calibrated profile)")
        volts = _range(c, data["voltage"], "voltage", "V", MAX_VOLTAGE_V)
        d = [proc.offset_nm + v * rate for v in volts] if proc.knee_V is None else [
            proc.offset_nm + rate * min(v, proc.knee_V) + proc.nm_per_V_above_knee * max(v - proc.knee_V, 0.0)
            for v in volts]
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
        multi.append(Geometry(_geometry_name(ma_light, g), ma_light, abs(v),
                              "opposite" if v >= 0 else "light", g))
    if len({g.name for g in multi}) != len(multi):
        c.fail("geometry.multi_angle.aspecular_deg", "must not repeat an angle", asp)

    ren = c.table(data.get("render", {}), "render",
                  ("shapes", "size_px", "model", "roughness", "finish", "angular_map", "hero"))
    shapes = ren.get("shapes", ["flat", "cylinder"])
    if not isinstance(shapes, list) or not 1 <= len(shapes) <= 2:
        c.fail("render.shapes", f"must be a list of one or two of {', '.join(RENDER_SHAPES)}", shapes)
    shapes = tuple(c.string(s, f"render.shapes[{i}]", 20, RENDER_SHAPES) for i, s in enumerate(shapes))
    if len(set(shapes)) != len(shapes):
        c.fail("render.shapes", "must not repeat a shape", ren["shapes"])
    size = c.integer(ren.get("size_px", 192), "render.size_px", 64, 512)
    model = c.string(ren.get("model", "microfacet"), "render.model", 20, RENDER_MODELS)
    rough = c.number(ren.get("roughness", 0.3), "render.roughness", 0.01, 1.0)
    finish = None
    if "finish" in ren:
        if "roughness" in ren:
            c.fail("render.finish", "give either finish or roughness, not both (a finish sets the roughness)", ren["finish"])
        finish = c.string(ren["finish"], "render.finish", 20, FINISHES)
        rough = get_finish(finish).roughness_alpha
        if get_finish(finish).anisotropic and model != "microfacet":
            c.fail("render.finish", f"{finish} is anisotropic: it needs model = \"microfacet\"", finish)
    amap = c.boolean(ren.get("angular_map", True), "render.angular_map")
    if (hero := c.boolean(ren.get("hero", False), "render.hero")) and model != "microfacet":
        c.fail("render.hero", "hero renders are of the microfacet model (Mitsuba); set model = \"microfacet\"", True)

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

    return CatalogSpec(
        source=source, name=name, description=description, film=proc.film, substrate=proc.substrate,
        nm_per_V=rate, thickness_nm=tuple(float(x) for x in d),
        voltage_V=None if volts is None else tuple(float(v) for v in volts),
        illuminant=illuminant, observer=observer, wavelength_step_nm=wl_step,
        reference=reference, multi_angle=tuple(multi), shapes=shapes, size_px=size, model=model,
        roughness=rough, angular_map=amap, scheme=scheme, grade=grade, metric=metric, max_delta_E=max_dE,
        search_nm=search, columns=columns, rows=rows, chips=chips, chip_size_mm=chip_size, chip_dpi=chip_dpi,
        process=proc.name, offset_nm=proc.offset_nm, film_index_scale=proc.film_index_scale,
        process_origin=proc.origin, spread_nm=proc.spread.spread_nm, spread_fraction=proc.spread.spread_fraction,
        knee_V=proc.knee_V, nm_per_V_above_knee=proc.nm_per_V_above_knee,
        finish=finish, hero=hero,
    )


def load_spec(path) -> tuple[CatalogSpec, bytes]:
    """Read and validate a spec file; returns the spec and the file's bytes."""
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
    """One line: name, swatches, thickness range, sheets, materials, colorimetry, geometries, grade."""
    d, per = s.thickness_nm, s.per_sheet
    nm = f"{round(d[0], 1):g}–{round(d[-1], 1):g} nm"  # as the sheets print them (0.1 nm)
    if s.voltage_V:
        nm += f" ({s.voltage_V[0]:g}–{s.voltage_V[-1]:g} V)"
    tol = (f"tolerance {s.metric} ≤ {s.max_delta_E:g}" if s.grade is None
           else f"grade {s.scheme} {s.grade} ({s.metric} ≤ {s.max_delta_E:g})")
    return (f"{s.name!r}: {len(d)} swatches, {nm}, "
            f"{(len(d) + per - 1) // per} sheet(s) of {s.columns}×{s.rows}; {s.film} on {s.substrate}; "
            f"{s.illuminant}/{s.observer}°; reference {s.reference.name}; "
            f"{len(s.multi_angle)} multi-angle geometries; {tol}")
