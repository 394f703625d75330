"""``swatch calibrate``: a line's process profile from its test coupons."""
from __future__ import annotations

from pathlib import Path

import click

from swatch.commands.common import colour_options, echo_json, resolve_process
from swatch.errors import SwatchError


@click.command()
@click.argument("coupons", type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out_path", required=True, type=click.Path(dir_okay=False, path_type=str),
              help="the profile to write (.toml; use it with --process or process = \"...\" in a spec)")
@click.option("--process", "process", default=None, metavar="NAME|FILE",
              help="the profile to start from: film, substrate, film index scale [default: titanium-fujii2019]")
@click.option("--film", default=None, help="film table, overriding the starting profile's")
@click.option("--substrate", default=None, help="substrate table, overriding the starting profile's")
@click.option("--name", default=None, help="the new profile's name [default: <starting profile>-calibrated]")
@click.option("--light", type=float, default=45.0, show_default=True, help="measuring geometry: light polar angle (deg)")
@click.option("--view", type=float, default=0.0, show_default=True, help="measuring geometry: view polar angle (deg)")
@colour_options
@click.option("--fit-scale/--fixed-scale", "fit_scale", default=None,
              help="fit the film index scale, or keep the starting profile's [default: fit it when the coupons "
                   "determine it]")
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of text")
@click.option("--report", "report_dir", default=None, type=click.Path(file_okay=False, path_type=str),
              help="write calibration.png (measured vs predicted chips, fitted voltage -> colour strip) here")
@click.option("--force", is_flag=True, help="overwrite existing output files")
def calibrate(coupons, out_path, process, film, substrate, name, light, view, illuminant, observer, fit_scale,
              as_json, report_dir, force):
    """Fit growth rate, offset and film index scale of a line from its coupons (CSV).

    COUPONS: a header row, then voltage_V,L,a,b (CIELAB measured at --light/--view, --illuminant,
    --observer) or voltage_V,wavelength_nm,reflectance (spectra, long form); optional columns
    thickness_nm (measured) and coupon (a label). The interference order is searched globally, a
    robust loss keeps a mislabelled coupon from pulling the line (it is flagged as an outlier), and
    the parameters come with standard errors. Data that cannot determine them are refused.
    """
    from swatch.calibration import calibrate as fit
    from swatch.coupons import read_coupons
    from swatch.fileio import atomic_write_text, check_new, check_writable_dir
    from swatch.process import process_toml

    out = Path(out_path)
    if not str(out_path).strip() or out.suffix.lower() != ".toml":
        raise SwatchError(f"--out {out_path!r} must name a .toml file")
    png = Path(report_dir) / "calibration.png" if report_dir is not None else None
    if report_dir is not None and not str(report_dir).strip():
        raise SwatchError("--report is an empty string; give a folder path")
    check_new([out] + ([png] if png else []), force)
    base = resolve_process(process, film, substrate)
    data = read_coupons(coupons)
    cal = fit(data, base, light, view, illuminant, observer, fit_scale, name)
    header = (f"process profile calibrated by swatch calibrate from {Path(coupons).name} "
              f"({len(data)} coupons); format: docs/processes.md")
    atomic_write_text(out, process_toml(cal.process, header=header))
    if png is not None:
        from swatch.imageio import write_png

        check_writable_dir(report_dir)
        write_png(png, cal.figure(), {"calibration": cal.to_dict()})
    d = cal.to_dict()
    if as_json:
        echo_json(d)
        return
    u = d["uncertainty"]

    def pm(key, nd):
        return f"{d[key]:.{nd}f}" + ("" if u[key] is None else f" ± {u[key]:.{nd}f}")

    click.echo(f"# {d['process']['process']}: {base.film} on {base.substrate}; light {light:g}°, view {view:g}°, "
               f"{d['illuminant']}, CIE {d['observer']}° observer")
    click.echo(f"nm_per_V          {pm('nm_per_V', 4)}")
    click.echo(f"offset_nm         {pm('offset_nm', 2)}")
    scale = pm("film_index_scale", 4) + ("" if u["film_index_scale"] is not None else " (kept: not determined)")
    click.echo(f"film_index_scale  {scale}")
    click.echo(f"mean ΔE2000 {d['mean_delta_E_00']:.2f}, max {d['max_delta_E_00']:.2f} over "
               f"{len(d['samples']) - d['outliers']} coupons; {d['outliers']} outlier(s)")
    if d["runner_up"]:
        r = d["runner_up"]
        click.echo(f"next-best order: {r['nm_per_V']:g} nm/V + {r['offset_nm']:g} nm "
                   f"(median ΔE2000 {r['mean_delta_E_00']:.2f})")
    click.echo(f"{'coupon':>16} {'voltage_V':>9} {'thickness_nm':>12} {'ΔE2000':>7}")
    for s in d["samples"]:
        flag = "  outlier" if s["outlier"] else ""
        click.echo(f"{s['coupon'][:16]:>16} {s['voltage_V']:9g} {s['thickness_nm']:12.2f} {s['delta_E_00']:7.2f}{flag}")
    click.echo(f"profile written to {out}" + (f"; report {png}" if png else ""))
