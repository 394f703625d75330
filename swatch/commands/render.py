"""Render commands: ``swatch angular`` (colour over light × view angles) and ``swatch render`` (swatches)."""
from __future__ import annotations

import sys
from contextlib import nullcontext
from pathlib import Path

import click
import numpy as np

from swatch.commands import common
from swatch.commands.progress import PassBar
from swatch.commands.terminal import unescaped
from swatch.core.choices import (
    BACKGROUNDS,
    DEFAULT_LIGHT_DEG,
    DEFAULT_ROUGHNESS_ALPHA,
    DEFAULT_SEED,
    DEFAULT_SPP,
    DEVICES,
    DISTRIBUTIONS,
    ENGINES,
    FINISHES,
    IMAGE_SPACES,
    LIGHTINGS,
    MESH_FORMATS,
    MODELS,
    POINT_LIGHT,
    SHAPES,
)
from swatch.core.errors import SwatchError
from swatch.core.escapes import printable

ORIENTATION = ("rows: light angle, first value at the bottom row; columns: view angle, first value at the "
               "left (as the PNG figure and the catalog sheets)")


def _iterate(items, label: str):
    """Items with a progress bar on stderr when it is a terminal and there is more than one."""
    if len(items) > 1 and sys.stderr.isatty():
        return click.progressbar(items, label=printable(label), file=unescaped(sys.stderr), show_pos=True)
    return nullcontext(items)


def _setup(thickness, voltage, process, nm_per_volt, film, substrate, illuminant, observer, wavelengths):
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.render.metadata import voltage_note

    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    d, v = common.resolve_thickness(thickness, voltage, proc, multiple=True)
    coating = proc.coating(common.resolve_grid(wavelengths))
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    volts = v if v is not None else proc.voltage_V(d)
    note = voltage_note(proc, given=v is not None, known=volts is not None)
    volts = np.full(d.shape, np.nan) if volts is None else np.asarray(volts, dtype=float)
    return d, volts, note, coating, cm, proc


def _roughness(roughness: float | None, process: str | None) -> float:
    """``--roughness``, else the process profile's ``roughness``, else the default α; checked."""
    from swatch.physics.microfacet import check_roughness_alpha

    profile = None if roughness is not None else common.resolve_process(process).roughness
    return check_roughness_alpha(roughness if roughness is not None else
                                 (DEFAULT_ROUGHNESS_ALPHA if profile is None else profile))


def _image_options(f):
    """The options renders and angular maps share: intensity model, roughness, distribution, EXR
    primaries, --force, materials, colorimetry and the wavelength grid."""
    for deco in (
        common.grid_option, common.colour_options, common.material_options,
        click.option("--force", is_flag=True, help="overwrite existing files"),
        click.option("--space", type=click.Choice(IMAGE_SPACES), default="srgb", show_default=True,
                     help="EXR RGB primaries"),
        click.option("--distribution", type=click.Choice(DISTRIBUTIONS.names(), case_sensitive=False), default="ggx", show_default=True,
                     help="microfacet normal distribution D (the microfacet model; environment lighting: ggx)"),
        click.option("--roughness", type=float, default=None,
                     help="microfacet roughness alpha in (0, 1] [default: the process profile's, else "
                          f"{DEFAULT_ROUGHNESS_ALPHA:g}]"),
        click.option("--model", type=click.Choice(MODELS.names(), case_sensitive=False), default="microfacet",
                     show_default=True, help=MODELS.help()),
    ):
        f = deco(f)
    return f


@click.command()
@common.thickness_options(multiple=True)
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False), help="output folder")
@click.option("--light-range", default="0:85:1", show_default=True, help="light polar angles A:B:STEP or N,N,... (deg)")
@click.option("--view-range", default="0:85:1", show_default=True, help="view polar angles A:B:STEP or N,N,... (deg)")
@_image_options
def angular(thickness, voltage, process, nm_per_volt, out_dir, light_range, view_range, model, roughness, distribution,
            space, force, film, substrate, illuminant, observer, wavelengths):
    """Colour over light × view angle (in plane, opposite sides) for each thickness.

    Writes per thickness: angular_<d>nm.exr (linear RGB), .png (labelled display figure),
    _spectral.exr (R, G, B preview and reflectance per wavelength, Fichet et al. 2021 channels, 32-bit),
    .csv and .json (Lab per cell). Images: light angle up, view angle to the right.
    """
    from swatch.core.fileio import atomic_write_text, check_new, check_writable_dir
    from swatch.io import imageio, spectral_exr
    from swatch.io.pngmeta import image_xmp
    from swatch.physics import geometry
    from swatch.render.angular import angular_map, check_angular_size
    from swatch.render.metadata import file_stems, with_voltage
    from swatch.report.figures import angular_figure
    from swatch.report.text import angular_lab_csv, angular_lab_json

    roughness = _roughness(roughness, process)
    lights, views = geometry.check_light_view_deg(common.parse_range(light_range, "light angle", "deg"),
                                                  common.parse_range(view_range, "view angle", "deg"))
    d, volts, note, coating, cm, proc = _setup(thickness, voltage, process, nm_per_volt, film, substrate, illuminant,
                                               observer, wavelengths)
    check_angular_size(lights.size, views.size, coating.wavelength_nm.size)
    stems = file_stems("angular", d)
    suffixes = (".exr", ".png", "_spectral.exr", ".csv", ".json")
    check_new([Path(out_dir) / (st + suf) for st in stems for suf in suffixes], force)
    out = check_writable_dir(out_dir)  # created only once every input has been checked
    written = []
    with _iterate(list(range(d.size)), "angular maps") as it:
        for i in it:
            amap = angular_map(d[i], lights, views, coating, cm, model, roughness, distribution, space=space)
            meta = with_voltage(amap.metadata, volts[i], note, proc)
            amap.metadata = meta
            path = {suf: out / (stems[i] + suf) for suf in suffixes}  # (not with_suffix: "050.8nm")
            meta["orientation"] = ORIENTATION
            # Rows flipped: light angle grows upwards, as in the PNG figure and the catalog sheets.
            imageio.write_exr(path[".exr"], amap.linear_rgb[::-1], meta, space=space)
            imageio.write_png(path[".png"], angular_figure(amap), meta,
                              xmp=image_xmp(f"Angular colour map, {d[i]:g} nm", meta))
            spectral_exr.write_spectral_exr(path["_spectral.exr"], amap.spectral[::-1], amap.wavelength_nm, meta,
                                       rgb=amap.linear_rgb[::-1], space=space)
            atomic_write_text(path[".csv"], angular_lab_csv(amap))
            atomic_write_text(path[".json"], angular_lab_json(amap))
            written += [str(path[suf]) for suf in suffixes]
    for p in written:
        click.echo(p)


def _sun_options(f):
    """The sun of ``--engine mitsuba --environment sun``: by angles, or by place, date and time."""
    for deco in (
        click.option("--turbidity", type=float, default=None, help="sun: sky turbidity 1-10 [default: 3]"),
        click.option("--sun-timezone", type=float, default=None, help="sun: hours from UTC of --sun-time [default: 0]"),
        click.option("--sun-time", default=None, metavar="HH:MM", help="sun: local time [default: 12:00]"),
        click.option("--sun-date", default=None, metavar="YYYY-MM-DD", help="sun: date [default: 2026-06-21]"),
        click.option("--sun-place", default=None, metavar="LAT,LON",
                     help="sun: latitude and longitude in degrees (north, east positive); with --sun-date/--sun-time"),
        click.option("--sun-azimuth", type=float, default=None,
                     help="sun: azimuth in degrees about the vertical, from the camera side (+z) towards +x [default: 0]"),
        click.option("--sun-elevation", type=float, default=None,
                     help="sun: elevation above the horizon in degrees [0, 90] [default: 45]"),
    ):
        f = deco(f)
    return f


def _sun(elevation, azimuth, place, date, time, timezone, turbidity):
    """The :class:`swatch.render.lighting.Sun` of the sun options, or None when none is given (checked later)."""
    if all(v is None for v in (elevation, azimuth, place, date, time, timezone, turbidity)):
        return None
    import re

    from swatch.render.lighting import Sun

    kw: dict = {"turbidity": 3.0 if turbidity is None else turbidity, "azimuth_deg": azimuth or 0.0}
    if place is None:
        if date is not None or time is not None or timezone is not None:
            raise SwatchError("--sun-date, --sun-time and --sun-timezone need --sun-place LAT,LON")
        return Sun(elevation_deg=45.0 if elevation is None else elevation, **kw)
    if elevation is not None or azimuth is not None:
        raise SwatchError("give the sun by --sun-elevation/--sun-azimuth or by --sun-place, not both")
    try:
        lat, lon = (float(x) for x in place.split(","))
    except ValueError:
        raise SwatchError(f"--sun-place {place!r}: give LAT,LON in degrees, e.g. 48.86,2.35") from None
    m = re.fullmatch(r"(\d{4})-(\d{1,2})-(\d{1,2})", (date or "2026-06-21").strip())
    if m is None:
        raise SwatchError(f"--sun-date {date!r}: give YYYY-MM-DD")
    t = re.fullmatch(r"(\d{1,2}):(\d{2})", (time or "12:00").strip())
    if t is None or int(t.group(2)) > 59:
        raise SwatchError(f"--sun-time {time!r}: give HH:MM from 00:00 to 23:59")
    return Sun(elevation_deg=None, latitude_deg=lat, longitude_deg=lon, timezone_h=timezone or 0.0,
               year=int(m.group(1)), month=int(m.group(2)), day=int(m.group(3)),
               hour=int(t.group(1)) + int(t.group(2)) / 60.0, **kw)


@click.command()
@common.thickness_options(multiple=True)
@click.option("--shape", type=click.Choice(SHAPES), default="flat", show_default=True,
              help="flat plate, half cylinder (bent sheet) or sphere")
@click.option("--mesh", "mesh_file", default=None, metavar="FILE", help="render this mesh instead of --shape ("
              + ", ".join("." + f for f in MESH_FORMATS) + "; placed in the unit sphere, seen like the sphere)")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False), help="output folder")
@click.option("--size", "size_px", type=int, default=512, show_default=True, help="image size in pixels (square)")
@click.option("--light", "light_deg", type=float, default=None,
              help=f"the point light's angle in degrees [0, 90) (--environment {POINT_LIGHT} only) "
                   f"[default: {DEFAULT_LIGHT_DEG:g}]")
@click.option("--environment", default=None, metavar="NAME|FILE.exr",
              help="lighting: " + LIGHTINGS.help() + "; or an equirectangular .exr/.hdr map "
                   f"[default: studio; {POINT_LIGHT} for the paper model or the beckmann distribution]")
@click.option("--view", "view_deg", type=float, default=None,
              help="camera angle from the plate's normal in degrees [0, 90) (default 36 flat, 70 cylinder/sphere)")
@click.option("--view-azimuth", "view_azimuth_deg", type=float, default=0.0, show_default=True,
              help="camera azimuth about the normal in degrees")
@click.option("--background", type=click.Choice(BACKGROUNDS), default=None,
              help="display background (environment: the map behind the object, also in the EXR) [default: grey; "
                   "mitsuba: environment under studio and sun]")
@click.option("--engine", type=click.Choice(ENGINES.names(), case_sensitive=False), default="builtin",
              show_default=True, help=ENGINES.help())
@click.option("--spp", type=int, default=None, help=f"mitsuba: samples per pixel [default: {DEFAULT_SPP}]")
@click.option("--seed", type=int, default=None,
              help=f"mitsuba: random seed (same seed, same image) [default: {DEFAULT_SEED}]")
@click.option("--denoise/--no-denoise", default=None,
              help="mitsuba: denoise with Intel Open Image Denoise, guided by the render's albedo and normal buffers "
                   "(--no-denoise: the raw path-traced estimate) [default: denoise]")
@click.option("--device", type=click.Choice(DEVICES.names(), case_sensitive=False), default=None,
              help="mitsuba: where it renders and denoises: " + DEVICES.help() + " [default: cpu]")
@click.option("--keep-raw", is_flag=True, help="mitsuba, denoised: also write the raw image and the albedo and normal "
              "buffers into the EXR as layers raw.RGB, albedo.RGB, normal.XYZ (for compositing)")
@click.option("--finish", "finish_name", type=click.Choice(FINISHES), default=None,
              help="a named surface finish (its GGX roughness; brushed is anisotropic: the built-in engine renders "
                   "it under an environment); instead of --roughness (docs/finishes.md)")
@_sun_options
@_image_options
def render(thickness, voltage, process, nm_per_volt, shape, mesh_file, out_dir, size_px, light_deg, environment, view_deg,
           view_azimuth_deg, background, engine, spp, seed, denoise, device, keep_raw, finish_name, sun_elevation, sun_azimuth, sun_place, sun_date,
           sun_time, sun_timezone, turbidity, model, roughness, distribution, space, force, film, substrate, illuminant,
           observer, wavelengths):
    """Render swatches: <shape>_<d>nm.exr (linear RGBA, half) and .png (display sRGB); mesh_<d>nm with --mesh.

    --engine mitsuba path-traces them with Mitsuba 3 and the exact thin-film BSDF (lighting studio, sun,
    uniform, or an .exr/.hdr map; --spp, --seed), denoised by default (--no-denoise, --keep-raw; docs/mitsuba.md),
    on the CPU or an NVIDIA GPU (--device cuda).
    """
    from swatch.core.fileio import check_new, check_writable_dir
    from swatch.io import imageio
    from swatch.io.pngmeta import image_xmp
    from swatch.physics.finishes import finish_or_roughness
    from swatch.render import ENGINES
    from swatch.render.image import layered_pixels
    from swatch.render.mesh import load_mesh
    from swatch.render.metadata import file_stems, with_voltage
    from swatch.render.request import render_request

    finish = finish_or_roughness(finish_name, roughness)
    if keep_raw and (engine != "mitsuba" or denoise is False):
        raise SwatchError("--keep-raw keeps the mitsuba engine's raw image beside the denoised one; "
                          "add --engine mitsuba (denoised)")
    sun = _sun(sun_elevation, sun_azimuth, sun_place, sun_date, sun_time, sun_timezone, turbidity)
    mesh = None if mesh_file is None else load_mesh(mesh_file)
    shape = "mesh" if mesh is not None else shape
    d, volts, note, coating, cm, proc = _setup(thickness, voltage, process, nm_per_volt, film, substrate, illuminant,
                                               observer, wavelengths)
    # every input checked once, before anything is written (a series reuses the request and its lighting)
    # the options given, or that the process profile sets (the library refuses one that would change nothing)
    given = {"light_deg": light_deg, "spp": spp, "seed": seed, "denoise": denoise, "device": device,
             "roughness_alpha": None if finish is not None else _roughness(roughness, process)}
    request = render_request(d[0], shape, size_px, model=model, coating=coating, colorimeter=cm, space=space,
                             distribution=distribution, environment=environment, background=background,
                             view_deg=view_deg, view_azimuth_deg=view_azimuth_deg, mesh=mesh, finish=finish,
                             engine=engine, sun=sun, **{k: v for k, v in given.items() if v is not None})
    mitsuba = request.engine == "mitsuba"
    stems = file_stems(shape, d)
    check_new([Path(out_dir) / (st + suf) for st in stems for suf in (".exr", ".png")], force)
    # builtin: every input is checked; mitsuba: the first render checks the scene (the sun above the horizon)
    out = None if mitsuba else check_writable_dir(out_dir)
    written = []
    items = list(range(d.size))  # mitsuba: a bar of passes per render instead
    with nullcontext(items) if mitsuba else _iterate(items, f"{shape} swatches") as it:
        for i in it:
            with PassBar(f"mitsuba {shape}") if mitsuba else nullcontext() as passes:
                img = ENGINES[request.engine](request.with_thickness(d[i]), passes)
            out = out or check_writable_dir(out_dir)
            meta = with_voltage(img.metadata, volts[i], note, proc)
            exr, png = out / (stems[i] + ".exr"), out / (stems[i] + ".png")
            pixels, names = img.rgba, ("R", "G", "B", "A")  # type: tuple[np.ndarray, tuple[str, ...]]
            if keep_raw and img.layers:
                pixels, names = layered_pixels(img)
            imageio.write_exr(exr, pixels, meta, channel_names=names, space=space)
            title = f"{shape} swatch, {d[i]:g} nm" + (" (Mitsuba)" if mitsuba else "")
            imageio.write_png(png, img.display_rgb, meta, xmp=image_xmp(title, meta))
            written += [str(exr), str(png)]
    for p in written:
        click.echo(p)
