"""Engine commands: spectrum, color, materials, roughness."""
from __future__ import annotations

import click

from swatch.commands import common
from swatch.physics.overcoat import overcoat_json, overcoat_text


@click.command()
@common.thickness_options(multiple=False)
@common.geometry_options
@common.material_options
@common.overcoat_option
@common.grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def spectrum(thickness, voltage, process, nm_per_volt, light, view, light_azimuth, view_azimuth, film, substrate,
             overcoats, wavelengths, as_json):
    """Spectral reflectance of one thickness on the half-vector facet (R, R_s, R_p)."""
    from swatch.report import tables as report
    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    d, _ = common.resolve_thickness(thickness, voltage, proc, multiple=False)
    coating = common.resolve_coating(proc, wavelengths, overcoats)
    refl, theta_d = coating.half_vector(d[0], light, view, light_azimuth, view_azimuth)
    out = {
        "thickness_nm": float(d[0]),
        "theta_d_deg": float(theta_d),
        "film": coating.film,
        "substrate": coating.substrate,
        "wavelength_nm": coating.wavelength_nm.tolist(),
        "reflectance": refl.R.tolist(),
        "reflectance_s": refl.R_s.tolist(),
        "reflectance_p": refl.R_p.tolist(),
        "process": proc.metadata(),
    }
    out.update(overcoat_json(coating))
    if as_json:
        common.echo_json(out)
        return
    click.echo("\n".join(report.spectrum_text(out, overcoat_text(coating), proc.label)))


@click.command()
@common.thickness_options(multiple=True)
@common.geometry_options
@common.material_options
@common.overcoat_option
@common.colour_options
@common.grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def color(thickness, voltage, process, nm_per_volt, light, view, light_azimuth, view_azimuth, film, substrate,
          overcoats, illuminant, observer, wavelengths, as_json):
    """Colour of each thickness at one geometry: XYZ, CIELAB, LCh, sRGB and ΔE*ab to the previous row."""
    from swatch.colorimetry.appearance import thickness_colours
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.report import tables as report

    proc = common.resolve_process(process, film, substrate, nm_per_volt)
    d, v = common.resolve_thickness(thickness, voltage, proc, multiple=True)
    coating = common.resolve_coating(proc, wavelengths, overcoats)
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    table = thickness_colours(d, light, view, coating, cm, light_azimuth, view_azimuth)
    rows = table.rows()
    if v is not None:
        for row, volts in zip(rows, v, strict=True):
            row["voltage_V"] = float(volts)
    if as_json:
        common.echo_json({
            "illuminant": cm.illuminant, "observer": cm.observer, "film": coating.film,
            "substrate": coating.substrate, "light_deg": light, "view_deg": view,
            "theta_d_deg": table.theta_d_deg, **overcoat_json(coating), "process": proc.metadata(), "rows": rows,
        })
        return
    click.echo("\n".join(report.colour_table_text(rows, coating, cm, light, view, table.theta_d_deg, proc.label)))


@click.group()
def materials():
    """Optical-constant tables (film and substrate) shipped in tables/optical."""


@materials.command("list")
@click.option("--role", type=click.Choice(["film", "substrate"]), default=None, help="only films or substrates")
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def materials_list(role, as_json):
    """List the tables with their role, range and reference."""
    from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, list_materials
    from swatch.report import tables as report

    mats = list_materials(role)
    if as_json:
        common.echo_json(report.materials_json(mats, (DEFAULT_FILM, DEFAULT_SUBSTRATE)))
        return
    click.echo("\n".join(report.materials_text(mats, (DEFAULT_FILM, DEFAULT_SUBSTRATE))))


@materials.command("show")
@click.argument("name")
@common.grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def materials_show(name, wavelengths, as_json):
    """n and k of one table on the wavelength grid, with its source."""
    from swatch.physics.materials import load_material
    from swatch.report import tables as report

    m = load_material(name)
    wl = common.resolve_grid(wavelengths)
    nk = m.nk(wl)
    if as_json:
        common.echo_json(report.material_json(m, wl, nk))
        return
    click.echo("\n".join(report.material_text(m, wl, nk)))


@click.command()
@click.option("--ra", "ra_nm", type=float, required=True, help="arithmetic mean roughness Ra in nm")
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def roughness(ra_nm, as_json):
    """Rayleigh criterion h = λ / (8 cos θ) over 380–780 nm and 0–60°: is the surface optically rough?

    The paper's blue sample (Ra 268 nm) is rough: h spans 47.5–195 nm.
    """
    from swatch.physics import rayleigh

    r = rayleigh.rayleigh_criterion(ra_nm)
    if as_json:
        common.echo_json(rayleigh.rayleigh_json(r, ra_nm))
        return
    click.echo("\n".join(rayleigh.rayleigh_text(r, ra_nm)))
