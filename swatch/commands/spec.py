"""``swatch spec``: a finish specification (spec.json and a one-page PDF spec card) from a target."""
from __future__ import annotations

import json
from pathlib import Path

import click

from swatch.commands import common
from swatch.core.errors import SwatchError


@click.command()
@click.option("--hex", "hex_code", default=None,
              help="target sRGB colour RRGGBB (defined on CIE 1931 2°; brought into --observer through its smoothest "
                   "reflectance, docs/processes.md) matched at 45:0")
@click.option("--lab", "lab", default=None, help="target CIELAB L,a,b (under --illuminant/--observer, at 45:0)")
@click.option("--thickness", type=float, default=None, help="nominal oxide thickness in nm")
@click.option("--voltage", type=float, default=None, help="nominal anodising voltage in V (through the process's growth law)")
@common.process_options
@click.option("--roughness", type=float, default=None,
              help="the finish's GGX roughness, recorded with the spec [default: the process profile's, else 0.3]")
@click.option("--tolerance", "tolerance", default="dE00:2", show_default=True, metavar="METRIC:MAX|SCHEME:GRADE",
              help="the tolerance, judged in its own metric at 45:0 (e.g. dE00:2, dEab:3.2, csaj:C)")
@common.colour_options
@click.option("--angles", default=None, metavar="L:V,...|LasA,...",
              help="for --hex/--lab: the geometries the colour must hold at (e.g. 45:0,45:60); the nominal is the "
                   "thickness with the smallest worst difference over them")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False, path_type=str),
              help="folder for spec.json and spec.pdf")
@click.option("--accept-closest", "accept_closest", is_flag=True,
              help="a colour target out of reach within the tolerance: accept the closest reachable colour "
                   "deliberately (exit 0; the card says so) [default: exit 1, the card stamped NOT REACHABLE]")
@click.option("--force", is_flag=True, help="overwrite an existing spec.json / spec.pdf")
@click.option("--json", "as_json", is_flag=True, help="also print spec.json")
def spec(hex_code, lab, thickness, voltage, process, nm_per_volt, roughness, tolerance, illuminant, observer,
         angles, out_dir, accept_closest, force, as_json):
    """A finish specification for a fabricator: nominal thickness and voltage, CIELAB at 45:0 and the
    ASTM E2194 / E2539 multi-angle geometries, the flop (ΔE00 view 0° vs 60°), the tolerance and the
    process window it allows (nm, V); for a colour target, the closest reachable colour and how far.
    Writes DIR/spec.json (stable keys, README) and DIR/spec.pdf (one page: chips, multi-angle table,
    window, process profile, how to measure, sign-off box). Exit status 1 when a colour target cannot
    be reached within the tolerance (the files are written, the card stamped) unless --accept-closest.
    """
    from swatch.colorimetry.colorimeter import get_colorimeter, parse_Lab
    from swatch.colorimetry.observers import hex_display, hex_to_document_Lab
    from swatch.colorimetry.tolerance import parse_tolerance
    from swatch.core.fileio import atomic_path, atomic_write_text, check_new, check_writable_dir
    from swatch.fit.multi_match import parse_angles
    from swatch.physics.materials import wavelength_grid
    from swatch.physics.model import check_thickness_nm
    from swatch.production.card import write_spec_card
    from swatch.production.spec import finish_spec

    given = [n for n, v in (("--hex", hex_code), ("--lab", lab), ("--thickness", thickness), ("--voltage", voltage))
             if v is not None]
    if len(given) != 1:
        raise SwatchError("give exactly one of --hex, --lab, --thickness or --voltage")
    if not str(out_dir).strip():
        raise SwatchError("--out is an empty string; give a folder path")
    tol = parse_tolerance(tolerance)
    geoms = parse_angles(angles) if angles is not None else None
    if geoms is not None and hex_code is None and lab is None:
        raise SwatchError("--angles applies to a colour target (--hex or --lab)")
    if accept_closest and hex_code is None and lab is None:
        raise SwatchError("--accept-closest applies to a colour target (--hex or --lab)")
    proc = common.resolve_process(process, None, None, nm_per_volt)
    rough = roughness if roughness is not None else (proc.roughness if proc.roughness is not None else 0.3)
    if not 0.01 <= rough <= 1.0:
        raise SwatchError(f"--roughness must be from 0.01 to 1 (got {rough:g})")
    wl = wavelength_grid(380.0, 780.0, 5.0)
    cm = get_colorimeter(wl, illuminant, observer)
    target: dict[str, object]
    if hex_code is not None:
        target = {"kind": "hex", "value": hex_display(hex_code),
                  "Lab": [float(v) for v in hex_to_document_Lab(hex_code, cm)]}
    elif lab is not None:
        target = {"kind": "lab", "value": lab, "Lab": [float(v) for v in parse_Lab(lab, "--lab")]}
    elif thickness is not None:
        target = {"kind": "thickness", "value": thickness,
                  "thickness_nm": float(check_thickness_nm([thickness])[0])}
    else:
        if proc.nm_per_V is None:
            raise SwatchError(f"process {proc.name} has no growth rate; give --thickness or --nm-per-volt")
        target = {"kind": "voltage", "value": voltage,
                  "thickness_nm": float(proc.thickness_nm([voltage])[0])}  # checked by the growth law
    out = Path(out_dir)
    paths = [out / "spec.json", out / "spec.pdf"]
    check_new([p for p in paths if out.exists()], force)
    made = finish_spec(target, proc, tol, illuminant=illuminant, observer=observer, wavelength_nm=wl,
                       roughness=rough, angles=geoms, accept_closest=accept_closest)
    data = made.document
    text = json.dumps(data, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    check_writable_dir(out)
    with atomic_path(paths[1]) as tmp:
        write_spec_card(made, tmp)
    atomic_write_text(paths[0], text)
    reach = data["reach"]
    unreachable = made.reach is not None and not made.reach.within_tolerance
    status = 1 if made.reach is not None and unreachable and not made.reach.accepted_closest else 0
    if as_json:
        common.echo_json_text(text)
        return status
    nom, pw = data["nominal"], data["process_window"]
    col = data["colorimetry"]
    volts = f" at {nom['voltage_V']} V" if nom["voltage_V"] is not None else ""
    click.echo(f"nominal {nom['thickness_nm']} nm{volts}; window -{pw['thickness_minus_nm']}/+{pw['thickness_plus_nm']} nm "
               f"({pw['metric']} <= {pw['max']:g} at {pw['geometry']}); flop dE00 {data['flop']['delta_E_00']}; CIELAB under "
               f"{col['illuminant']}, {col['observer']}° observer")
    vb = nom["voltage"]
    if not vb["calibrated"]:
        click.echo(f"note: {vb['note']} (swatch calibrate coupons.csv --out line.toml; swatch spec … "
                   "--process line.toml)")
    if unreachable:
        where = reach["colorimetry"]["geometry"]
        click.echo(f"{'accepted' if reach['accepted_closest'] else 'NOT REACHABLE'}: the target cannot be reached within "
                   f"the tolerance; closest {reach['closest_thickness_nm']} nm, {reach['metric']} {reach['delta_E']} "
                   f"from the target ({'worst over ' + where + '; ' if reach.get('delta_E_per_geometry') else ''}at "
                   f"{reach['closest_Lab_geometry']}: Lab {' '.join(map(str, reach['closest_Lab']))} against the "
                   f"target's {' '.join(map(str, data['target']['Lab']))}, {col['illuminant']} {col['observer']}°)"
                   + ("; accepted deliberately (--accept-closest)" if reach["accepted_closest"] else
                      "; exit status 1 (give --accept-closest to accept the closest colour deliberately)"))
    click.echo(f"written {paths[0]} and {paths[1]}")
    return status
