"""``swatch check``: measured parts against a finish specification; exit 0 all pass, 1 any fails."""
from __future__ import annotations

import click

from swatch.commands import common


def _spec_on_the_fly(thickness, voltage, process, tolerance, illuminant, observer):
    """The spec ``swatch spec --thickness/--voltage`` would write, in memory (checked as a spec.json is)."""
    from swatch.colorimetry.tolerance import parse_tolerance
    from swatch.commands.common import resolve_process
    from swatch.core.errors import SwatchError
    from swatch.physics.model import check_thickness_nm
    from swatch.production.spec import finish_spec

    proc = resolve_process(process)
    if voltage is not None:
        if proc.nm_per_V is None:
            raise SwatchError(f"process {proc.name} has no growth rate; give --thickness")
        d = float(proc.thickness_nm([voltage])[0])  # checked by the growth law
    else:
        d = float(check_thickness_nm([thickness])[0])
    return finish_spec({"kind": "thickness" if voltage is None else "voltage",
                        "value": thickness if voltage is None else voltage, "thickness_nm": d}, proc,
                       parse_tolerance(tolerance), illuminant=illuminant, observer=observer)


def _check_line(r: dict) -> str:
    """One part's line of the text report: verdict, worst ΔE, best-fit thickness, residual, what to do."""
    advice = r["voltage_advice"] if r["voltage_advice"] is not None else r["voltage_correction_reason"]
    worst = max(r["delta_E"], key=r["delta_E"].get)
    verdict = "PASS" if r["pass"] else ("NOT JUDGED" if r["action"] == "measure" else "FAIL")
    missing = "".join(f", {n} not measured" for n in r["unmeasured"])
    return (f"{r['id']}: {verdict}  max {r['metric']} {r['max_delta_E']:.2f} ({worst}{missing})  best-fit thickness "
            f"{r['thickness_nm']:.1f} nm ({r['thickness_offset_nm']:+.1f}), residual {r['metric']} "
            f"{r['max_residual_delta_E']:.2f}: {advice}")


@click.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(dir_okay=False, path_type=str))
@click.option("--spec", "spec_path", default=None, type=click.Path(dir_okay=False, path_type=str),
              help="the spec.json written by swatch spec")
@click.option("--thickness", type=float, default=None,
              help="instead of --spec: the nominal thickness in nm (a spec made on the fly with --process, "
                   "--tolerance, --illuminant, --observer)")
@click.option("--voltage", type=float, default=None, help="instead of --spec: the nominal voltage in V")
@click.option("--process", "process", default=None, metavar="NAME|FILE",
              help="with --thickness/--voltage: the process profile [default: titanium-fujii2019]")
@click.option("--tolerance", "tolerance", default="dE00:2", show_default=True, metavar="METRIC:MAX|SCHEME:GRADE",
              help="with --thickness/--voltage: the tolerance, judged in its own metric")
@click.option("--illuminant", default="D65", show_default=True, help="with --thickness/--voltage: CIE illuminant")
@click.option("--observer", default="10", show_default=True, help="with --thickness/--voltage: 10 or 2")
@common.unit_options("reflectance is in percent (0–100) [default: percent if any value > 1.5, else fraction]")
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of text")
@click.option("--report", "report_dir", default=None, type=click.Path(file_okay=False, path_type=str),
              help="write check.png (specified vs measured chips per angle) and check.json into this folder")
@click.option("--force", is_flag=True, help="overwrite existing report files")
def check(files, spec_path, thickness, voltage, process, tolerance, illuminant, observer, percent, as_json,
          report_dir, force):
    """Judge measured parts against a finish specification, per geometry, in the tolerance's metric.

    FILES: CxF3, CGATS or CSV measurement files (one or many parts each, CIELAB or spectra, one or
    many geometries of the spec). Prints per part the worst ΔE, pass/fail, the best-fit thickness,
    the residual (the part against the model at that thickness, in the tolerance's metric) and,
    only when that residual is within the tolerance, the voltage change that would bring the line
    back ("raise/lower the voltage by X V"); otherwise "not a thickness error: …" and no voltage.
    Exit status 0 when every part passes, 1 when any fails, 2 for bad input.
    """
    import json
    from pathlib import Path

    from swatch.core.errors import SwatchError
    from swatch.core.fileio import atomic_path, atomic_write_text, check_new, check_writable_dir
    from swatch.fit.resampling import resampling_notes
    from swatch.io.instrument_files import read_instrument_file
    from swatch.io.instruments import Request
    from swatch.production.advice import spec_notes
    from swatch.production.qc import check_file, load_spec_json
    from swatch.report.check_report import check_figure

    if sum(x is not None for x in (spec_path, thickness, voltage)) != 1:
        raise SwatchError("give exactly one of --spec spec.json, --thickness NM or --voltage V")
    if spec_path is not None:
        spec = load_spec_json(spec_path)
    else:
        spec = _spec_on_the_fly(thickness, voltage, process, tolerance, illuminant, observer)
        spec_path = f"--thickness {thickness:g}" if thickness is not None else f"--voltage {voltage:g}"
    written = spec.document  # what the report echoes, as the spec.json writes it
    col = written["colorimetry"]
    ref = written["reference"]
    request = Request(light_deg=ref["light_deg"], view_deg=ref["view_deg"], illuminant=col["illuminant"],
                      observer=col["observer"], percent=percent)
    if report_dir is not None:
        if not str(report_dir).strip():
            raise SwatchError("--report is an empty string; give a folder path")
        out = Path(report_dir)
        paths = [out / "check.png", out / "check.json"]
        check_new([p for p in paths if out.exists()], force)
    read = [read_instrument_file(p, request) for p in files]
    results = [r for f in read for r in check_file(f, spec)]
    ids = [r["id"] for r in results]
    if len(set(ids)) != len(ids):
        for r in results:
            r["id"] = f"{Path(r['source']).name}#{r['id']}"
    notes = spec_notes(spec)
    doc = {"spec": str(spec_path), "pass": all(r["pass"] for r in results),
           "tolerance": {"metric": spec.tolerance.metric, "max": spec.tolerance.max, "label": spec.tolerance.text,
                         "geometries": list(spec.judged)},
           "colorimetry": {"illuminant": col["illuminant"], "observer": col["observer"],
                           "srgb": "chips: sRGB by CIE 1931 2° colorimetry; a part's from its own measurement"},
           "advice": "action per part (docs/finisher.md): none inside the window; a voltage correction only for a "
                     "failing part or one near the window's edge, and only where the model at the best-fit thickness "
                     "explains the part within the tolerance (max_residual_delta_E); calibrate first where the spec's "
                     "uncalibrated model is the suspect; otherwise voltage_correction_reason says why not",
           "nominal": written["nominal"], "notes": [*notes, *(n for f in read for n in resampling_notes(f))],
           "n_parts": len(results), "n_failed": sum(not r["pass"] for r in results),
           "measurements": results}
    text = json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    if report_dir is not None:
        check_writable_dir(out)
        with atomic_path(paths[0]) as tmp:
            check_figure(results, written, notes).save(tmp, format="PNG")
        atomic_write_text(paths[1], text)
    if as_json:
        common.echo_json_text(text)
    else:
        judged = written["tolerance"].get("geometry", ref["geometry"])
        click.echo(f"# {spec.tolerance.text} at every measured geometry, required at {judged}; CIELAB under "
                   f"{col['illuminant']}, {col['observer']}° observer; nominal {written['nominal']['thickness_nm']} nm")
        for note in doc["notes"]:
            click.echo(f"note: {note}")
        for r in results:
            click.echo(_check_line(r))
        click.echo(f"{doc['n_parts'] - doc['n_failed']} of {doc['n_parts']} parts pass ({spec.tolerance.text})")
    return 0 if doc["pass"] else 1
