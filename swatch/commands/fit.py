"""``swatch fit`` (thickness from measurements, ΔE report) and ``swatch match`` (thickness from a colour)."""
from __future__ import annotations

from pathlib import Path

import click
from click.core import ParameterSource

from swatch.commands import common
from swatch.core import choices
from swatch.core.errors import SwatchError
from swatch.core.ranges import parse_pair
from swatch.physics.growth import DEFAULT_NM_PER_V

_RANGE_DEFAULT = "{:g}:{:g}".format(*choices.DEFAULT_THICKNESS_RANGE_NM)


# -- fit --------------------------------------------------------------------------------------------
@click.command()
@click.argument("measurements", nargs=-1, required=True, type=click.Path(dir_okay=False, path_type=str))
@common.unit_options("reflectance is in percent (0–100) [default: percent if any value > 1.5, else fraction]")
@click.option("--scale", type=click.Choice(choices.SCALE_MODES), default="energy", show_default=True,
              help="intensity correction: energy = the paper's (match each geometry's mean energy), "
                   "lsq = least-squares scale per geometry, global = one scale, none = absolute")
@click.option("--exclude-mirror", "exclude_mirror", type=float, default=choices.DEFAULT_EXCLUDE_MIRROR_DEG, show_default=True,
              help="leave out geometries whose view is within this many degrees of the mirror direction (0: keep all)")
@click.option("--range", "thickness_range", default=_RANGE_DEFAULT, show_default=True, help="thickness search range A:B in nm")
@click.option("--step", type=float, default=choices.DEFAULT_FIT_STEP_NM, show_default=True, help="global search step in nm")
@common.geometry_options
@common.material_options
@common.colour_options
@common.grid_option
@click.option("--scheme", default="csaj", show_default=True, help="tolerance scheme for the grade (csaj, nbs; any case)")
@common.process_options
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of text")
@click.option("--report", "report_dir", type=click.Path(file_okay=False, path_type=str), default=None,
              help="write delta_e_map.png/.exr, summary.csv/.md and geometries.csv into this folder")
@click.option("--force", is_flag=True, help="overwrite existing report files")
def fit(measurements, percent, scale, exclude_mirror, thickness_range, step, light, view, light_azimuth,
        view_azimuth, film, substrate, illuminant, observer, wavelengths, scheme, process, nm_per_volt, as_json,
        report_dir, force):
    """Estimate oxide thickness from measured spectra (or CIELAB) and report ΔE per geometry.

    MEASUREMENTS: CxF3 or CGATS files as instruments export them (each sample fitted; the file's
    geometry, illuminant and observer are used and must agree with options given), or CSV files
    (',', ';' or tab separated; decimal commas with ';' or tab), with the columns of one of: wavelength_nm,
    reflectance (one spectrum at --light/--view); light_deg, view_deg, [light_azimuth_deg,
    view_azimuth_deg,] wavelength_nm, reflectance (sBRDF set, long form; negative view_deg = on the
    light's side); light_deg, view_deg, L, a, b (CIELAB: fitted by ΔE2000); an id column splits a file
    into samples.
    The fit minimises the mean squared spectral error over all geometries outside the mirror region
    (global search over the range, then local refinement) and reports the best thickness, an
    uncertainty, the next-best minimum, ΔE*ab and ΔE2000 per geometry, their means and the grade.
    """
    from swatch.fit.spectral_fit import fit_measurement
    from swatch.io.instrument_files import read_instrument_file
    from swatch.report import text as report

    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    film, substrate = proc.film, proc.substrate
    rng = parse_pair(thickness_range, "--range")
    request = common.instrument_request(percent)
    options = dict(scale=scale, exclude_mirror_deg=exclude_mirror, thickness_range=rng, step_nm=step,
                   scheme=scheme, wavelength_nm=common.resolve_grid(wavelengths),
                   film_index_scale=proc.film_index_scale, spread=proc.spread)
    given = click.get_current_context().get_parameter_source("wavelengths") != ParameterSource.DEFAULT
    files = [read_instrument_file(p, request) for p in measurements]
    # one map per sample: a file of several samples names them <file stem>_<sample id>
    names = [p if len(f.samples) == 1 else f"{Path(p).with_suffix('')}_{s.id}.csv"
             for p, f in zip(measurements, files, strict=True) for s in f.samples]
    paths = report.report_paths(report_dir, names, force) if report_dir is not None else None
    results = [fit_measurement(s.measurement, film, substrate, grid_given=given, source=p,
                               illuminant=f.illuminant, observer=f.observer, **options)
               for p, f in zip(measurements, files, strict=True) for s in f.samples]
    dicts = [report.with_process(r.to_dict(proc.nm_per_V or DEFAULT_NM_PER_V), proc) for r in results]
    if paths:
        from swatch.core.fileio import output_batch

        # created only once every measurement has been read and fitted; all its files or none (a full disk)
        with output_batch(report_dir):
            report.write_report(results, dicts, paths)
    if as_json:
        common.echo_json(dicts[0] if len(dicts) == 1 else report.multi_summary(dicts, scheme))
        return
    for d in dicts:
        click.echo("\n".join(report.fit_text(d)))
    if len(dicts) > 1:
        click.echo("\n" + report.multi_text(report.multi_summary(dicts, scheme)))
    if paths:
        click.echo(f"report written to {report_dir}")


# -- match ------------------------------------------------------------------------------------------
@click.command()
@click.option("--lab", "lab", default=None, help="target CIELAB L,a,b (under --illuminant/--observer)")
@click.option("--hex", "hex_code", default=None,
              help="target sRGB colour RRGGBB (CIE 1931 2°; brought into --observer through its smoothest "
                   "reflectance, docs/processes.md)")
@common.geometry_options
@common.material_options
@common.colour_options
@common.grid_option
@click.option("--range", "thickness_range", default=_RANGE_DEFAULT, show_default=True, help="thickness range A:B in nm")
@click.option("--step", type=float, default=choices.DEFAULT_MATCH_STEP_NM, show_default=True, help="search step in nm")
@click.option("--top", type=int, default=5, show_default=True, help="number of candidates")
@click.option("--grade", default="C", show_default=True,
              help="tolerance grade a candidate must meet, judged in the scheme's metric (CSAJ: ΔE*ab)")
@click.option("--scheme", default="csaj", show_default=True, help="tolerance scheme (csaj, nbs; any case)")
@click.option("--tolerance", "tolerance", default=None, metavar="METRIC:MAX",
              help="a tolerance as coating specifications write it, e.g. dE00:2.0 or dEab:3.2 (instead of --grade)")
@common.process_options
@click.option("--match-lightness", is_flag=True,
              help="scale the simulated colour to the target's lightness (compare hue and chroma only)")
@click.option("--angles", default=None, metavar="L:V,...|LasA,...",
              help="match at several geometries, e.g. 45:0,45:60 or 45as15,45as45,45as110 (ASTM E2194 aspecular); "
                   "candidates ranked by --rank over them")
@click.option("--rank", type=click.Choice(("worst", "mean")), default="worst", show_default=True,
              help="with --angles or --measurement: rank by the worst or the mean ΔE2000 over the geometries")
@click.option("--measurement", "measurement", default=None, type=click.Path(dir_okay=False, path_type=str),
              help="a multi-angle measurement (CxF3, CGATS or CSV; its first sample) as the target, one colour per "
                   "geometry")
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def match(lab, hex_code, light, view, light_azimuth, view_azimuth, film, substrate, illuminant, observer,
          wavelengths, thickness_range, step, top, grade, scheme, tolerance, process, nm_per_volt, match_lightness,
          angles, rank, measurement, as_json):
    """Thicknesses (and voltages) whose colour matches a target, across interference orders.

    The geometry defaults to the catalog's reference 45°:0° (light at 45°, view along the normal).
    Candidates are ranked by ΔE2000; each says whether it is within the tolerance (--grade of
    --scheme, or --tolerance), judged in the tolerance's own metric.
    """
    from swatch.colorimetry.colorimeter import get_colorimeter, parse_Lab
    from swatch.colorimetry.observers import HEX_CONVENTION, hex_display, hex_to_document_Lab
    from swatch.colorimetry.tolerance import check_scheme, get_tolerance, parse_tolerance
    from swatch.fit.matching import judge_candidates, match_colour
    from swatch.report.text import match_text

    scheme = check_scheme(scheme)
    tol = parse_tolerance(tolerance) if tolerance is not None else get_tolerance(scheme, grade)

    if angles is not None or measurement is not None:
        return _match_angles(lab, hex_code, measurement, angles, rank, tol, process, film, substrate, nm_per_volt,
                             wavelengths, illuminant, observer, thickness_range, step, top, as_json)
    if (lab is None) == (hex_code is None):
        raise SwatchError("give exactly one of --lab L,a,b or --hex RRGGBB")
    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    coating = proc.coating(common.resolve_grid(wavelengths))
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    # a hex is sRGB (CIE 1931 2°): brought into --illuminant/--observer through its smoothest reflectance,
    # as spec and the catalog page do (docs/processes.md)
    target = parse_Lab(lab, "--lab") if lab is not None else hex_to_document_Lab(hex_code, cm)
    res = match_colour(target, coating, cm, light, view, light_azimuth, view_azimuth,
                       thickness_range=parse_pair(thickness_range, "--range"), step_nm=step, top=top,
                       grade=f"{scheme}:{grade}", match_lightness=match_lightness)
    judge_candidates(res, proc.voltage_V, tol)
    out = res.to_dict()
    out["process"] = proc.metadata()
    out["tolerance"] = tol.to_json()
    if hex_code is not None:
        out["target_hex"] = hex_display(hex_code)
        out["target_conversion"] = HEX_CONVENTION
    if as_json:
        common.echo_json(out)
        return
    click.echo("\n".join(match_text(res, out.get("target_hex"), thickness_range, cm, coating, proc.label, tol)))


def _match_angles(lab, hex_code, measurement, angles, rank, tol, process, film, substrate, nm_per_volt, wavelengths,
                  illuminant, observer, thickness_range, step, top, as_json):
    """``swatch match --angles`` / ``--measurement``: ranked by the worst or mean ΔE2000 over the geometries."""
    from swatch.colorimetry.colorimeter import get_colorimeter, parse_Lab
    from swatch.colorimetry.observers import hex_to_document_Lab
    from swatch.fit.multi_match import match_angles, parse_angles
    from swatch.fit.resampling import resampling_note
    from swatch.fit.result import colour_grid, interp_rows
    from swatch.io.instrument_files import read_instrument_file
    from swatch.io.measurements import LabMeasurement

    if sum(x is not None for x in (lab, hex_code, measurement)) != 1:
        raise SwatchError("give exactly one of --lab L,a,b, --hex RRGGBB or --measurement FILE")
    notes: list[str] = []
    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    coating = proc.coating(common.resolve_grid(wavelengths))
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    if measurement is not None:
        f = read_instrument_file(measurement, common.instrument_request())
        m = f.samples[0].measurement
        cm = get_colorimeter(coating.wavelength_nm, f.illuminant, f.observer)
        side = (m.view_azimuth_deg == m.light_azimuth_deg) & (m.view_deg > 0)
        geoms = [(f"{lt:g}:{-v if s else v:g}", float(lt), float(-v if s else v))
                 for lt, v, s in zip(m.light_deg, m.view_deg, side, strict=True)]
        if angles is not None:
            raise SwatchError("--measurement gives its own geometries; leave out --angles")
        if isinstance(m, LabMeasurement):
            target = m.Lab
        else:
            wl, interp = colour_grid(m.wavelength_nm)
            R = interp_rows(wl, m.wavelength_nm, m.reflectance) if interp else m.reflectance
            mcm = get_colorimeter(wl, f.illuminant, f.observer)
            target = mcm.Lab(mcm.XYZ(R))
            notes = [n for n in [resampling_note(f.source, m.wavelength_nm)] if n is not None]
    else:
        geoms = parse_angles(angles)
        target = parse_Lab(lab, "--lab") if lab is not None else hex_to_document_Lab(hex_code, cm)
    out = match_angles(target, geoms, coating, cm, tol, rank=rank, thickness_range=parse_pair(thickness_range, "--range"),
                       step_nm=step, top=top, voltage_of=proc.voltage_V)
    out.update({"illuminant": cm.illuminant, "observer": cm.observer, "tolerance": tol.to_json(),
                "process": proc.metadata(), "notes": notes})
    if as_json:
        common.echo_json(out)
        return
    names = [g["name"] for g in out["geometries"]]
    click.echo(f"# ranked by the {rank} ΔE2000 over {', '.join(names)}; {cm.illuminant}, {cm.observer}° observer; "
               f"process {proc.name}; within = every geometry within {tol.text}")
    for note in notes:
        click.echo(f"note: {note}")
    click.echo(f"{'rank':>4} {'d_nm':>8} {'volt_V':>7} {'worst':>6} {'mean':>6}  " + " ".join(f"{n:>9}" for n in names)
               + "  within")
    for k, c in enumerate(out["candidates"], start=1):
        volts = "" if c["voltage_V"] is None else f"{c['voltage_V']:7.1f}"
        per = " ".join(f"{c['geometries'][n]['delta_E_00']:9.2f}" for n in names)
        click.echo(f"{k:4d} {c['thickness_nm']:8.2f} {volts:>7} {c['worst_delta_E_00']:6.2f} {c['mean_delta_E_00']:6.2f}  "
                   f"{per}  {'yes' if c['within_tolerance'] else 'no'}")
