"""``swatch calibrate``: a line's process profile from its test coupons."""
from __future__ import annotations

from pathlib import Path

import click

from swatch.commands.common import colour_options, echo_json, instrument_request, resolve_process


def _read(path: str, light: float, view: float, illuminant: str, observer: str):
    """Coupons from a coupon CSV, or from a CGATS / CxF3 file (with its geometry and colorimetry)."""
    from swatch.core.limits import MAX_COUPON_BYTES, read_capped
    from swatch.io.coupons import coupons_from_samples, read_coupons
    from swatch.io.instrument_files import read_instrument_file

    try:
        head = read_capped(path, MAX_COUPON_BYTES, "coupon file")
    except OSError:
        return read_coupons(path), light, view, illuminant, observer  # its own one-line errors
    if not (head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<") or b"BEGIN_DATA_FORMAT" in head):
        return read_coupons(path), light, view, illuminant, observer
    f = read_instrument_file(path, instrument_request())
    m = f.samples[0].measurement
    return coupons_from_samples(path, f.samples), float(m.light_deg[0]), float(m.view_deg[0]), f.illuminant, f.observer


@click.command()
@click.argument("coupons", type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out_path", required=True, type=click.Path(dir_okay=False, path_type=str),
              help="the profile to write (.toml; use it with --process or process = \"...\" in a spec)")
@click.option("--process", "process", default=None, metavar="NAME|FILE",
              help="the profile to start from: film, substrate, film index scale [default: titanium-fujii2019]")
@click.option("--film", default=None, help="film table: fixes it (not searched)")
@click.option("--substrate", default=None, help="substrate table: fixes it (not searched)")
@click.option("--fixed-tables", "fixed_tables", is_flag=True,
              help="keep the starting profile's film and substrate tables (do not rank the shipped ones)")
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
def calibrate(coupons, out_path, process, film, substrate, fixed_tables, name, light, view, illuminant, observer,
              fit_scale, as_json, report_dir, force):
    """Fit a line's profile from its coupons (CSV): growth law, tables, film index scale, spread.

    COUPONS: a CGATS file with a VOLTAGE_V field or a CxF3 file with voltage_V tags (geometry,
    illuminant and observer from the file), or a CSV file (',', ';' or tab separated; decimal commas
    with ';' or tab): a header row, then voltage_V,L,a,b (CIELAB measured at --light/--view, --illuminant,
    --observer) or voltage_V,wavelength_nm,reflectance (spectra, long form); optional columns
    thickness_nm (measured) and coupon (a label). The interference order is searched globally, a
    robust loss keeps a mislabelled coupon from pulling the line (it is flagged as an outlier), and
    the parameters come with standard errors. The shipped film and substrate tables of the
    profile's materials are ranked by leave-one-out ΔE2000 (the first is written); a film index
    scale, a thickness spread and a knee in the growth law join only when they lower the held-out
    error (the report says what each bought). Data that cannot determine them are refused.
    """
    from swatch.fit.calibration import calibrate as fit
    from swatch.physics.process import check_profile_name
    from swatch.report.calibration import calibration_paths, calibration_text, write_calibration

    if name is not None:
        check_profile_name(name)  # (a newline or ESC wrote a profile that --process then refused)
    out, png = calibration_paths(out_path, report_dir, force)
    resolve_process(process, film, substrate)  # checks --film/--substrate
    base = resolve_process(process)
    data, light, view, illuminant, observer = _read(coupons, light, view, illuminant, observer)
    cal = fit(data, base.with_overrides(film, substrate) if fixed_tables else base, light, view, illuminant,
              observer, fit_scale, name, search_tables=not fixed_tables, film=film, substrate=substrate)
    write_calibration(cal, out, png, f"{Path(coupons).name} ({len(data)} coupons)")
    d = cal.to_dict()
    if as_json:
        echo_json(d)
        return
    click.echo("\n".join(calibration_text(d, base, light, view)))
    click.echo(f"profile written to {out}" + (f"; report {png}" if png else ""))
