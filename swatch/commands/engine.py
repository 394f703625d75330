"""Engine commands: spectrum, color, materials, roughness."""
from __future__ import annotations

import click

from swatch.commands.common import (
    colour_options, echo_json, geometry_options, grid_option, material_options, overcoat_option, resolve_coating,
    resolve_grid, resolve_process, resolve_thickness, thickness_options,
)
from swatch.model import overcoat_json, overcoat_text
from swatch.report import colour_table_text, material_text, materials_text, spectrum_text


@click.command()
@thickness_options(multiple=False)
@geometry_options
@material_options
@overcoat_option
@grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def spectrum(thickness, voltage, process, nm_per_volt, light, view, light_azimuth, view_azimuth, film, substrate,
             overcoats, wavelengths, as_json):
    """Spectral reflectance of one thickness on the half-vector facet (R, R_s, R_p)."""
    proc = resolve_process(process, film, substrate, nm_per_volt)
    d, _ = resolve_thickness(thickness, voltage, proc, multiple=False)
    coating = resolve_coating(proc, wavelengths=wavelengths, overcoats=overcoats)
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
        echo_json(out)
        return
    click.echo("\n".join(spectrum_text(out, overcoat_text(coating), proc.name)))


@click.command()
@thickness_options(multiple=True)
@geometry_options
@material_options
@overcoat_option
@colour_options
@grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def color(thickness, voltage, process, nm_per_volt, light, view, light_azimuth, view_azimuth, film, substrate,
          overcoats, illuminant, observer, wavelengths, as_json):
    """Colour of each thickness at one geometry: XYZ, CIELAB, LCh, sRGB and ΔE*ab to the previous row."""
    from swatch.appearance import thickness_colours
    from swatch.colorimetry import get_colorimeter

    proc = resolve_process(process, film, substrate, nm_per_volt)
    d, v = resolve_thickness(thickness, voltage, proc, multiple=True)
    coating = resolve_coating(proc, wavelengths=wavelengths, overcoats=overcoats)
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    table = thickness_colours(d, light, view, coating, cm, light_azimuth, view_azimuth)
    rows = table.rows()
    if v is not None:
        for row, volts in zip(rows, v):
            row["voltage_V"] = float(volts)
    if as_json:
        echo_json({
            "illuminant": cm.illuminant, "observer": cm.observer, "film": coating.film,
            "substrate": coating.substrate, "light_deg": light, "view_deg": view,
            "theta_d_deg": table.theta_d_deg, **overcoat_json(coating), "process": proc.metadata(), "rows": rows,
        })
        return
    click.echo("\n".join(colour_table_text(rows, coating, cm, light, view, table.theta_d_deg, proc.name)))


@click.group()
def materials():
    """Optical-constant tables (film and substrate) shipped in tables/optical."""


@materials.command("list")
@click.option("--role", type=click.Choice(["film", "substrate"]), default=None, help="only films or substrates")
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def materials_list(role, as_json):
    """List the tables with their role, range and reference."""
    from swatch.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, list_materials

    mats = list_materials(role)
    if as_json:
        echo_json([{
            "name": m.name, "role": m.role, "formula": m.formula, "reference": m.reference, "doi": m.doi,
            "wavelength_range_nm": list(m.wavelength_range_nm),
            "default": m.name in (DEFAULT_FILM, DEFAULT_SUBSTRATE),
        } for m in mats])
        return
    click.echo("\n".join(materials_text(mats, (DEFAULT_FILM, DEFAULT_SUBSTRATE))))


@materials.command("show")
@click.argument("name")
@grid_option
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def materials_show(name, wavelengths, as_json):
    """n and k of one table on the wavelength grid, with its source."""
    from swatch.materials import load_material

    m = load_material(name)
    wl = resolve_grid(wavelengths)
    nk = m.nk(wl)
    out = {
        "name": m.name, "role": m.role, "formula": m.formula,
        "source": {"reference": m.reference, "doi": m.doi, "file": m.source_file, "license": m.license},
        "wavelength_nm": wl.tolist(), "n": nk.real.tolist(), "k": nk.imag.tolist(),
    }
    if as_json:
        echo_json(out)
        return
    click.echo("\n".join(material_text(m, wl, nk)))


@click.command()
@click.option("--ra", "ra_nm", type=float, required=True, help="arithmetic mean roughness Ra in nm")
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def roughness(ra_nm, as_json):
    """Rayleigh criterion h = λ / (8 cos θ) over 380–780 nm and 0–60°: is the surface optically rough?

    The paper's blue sample (Ra 268 nm) is rough: h spans 47.5–195 nm.
    """
    from swatch.rayleigh import ANGLES_DEG, WAVELENGTHS_NM, rayleigh_criterion, rayleigh_text

    r = rayleigh_criterion(ra_nm)
    if as_json:
        echo_json({"ra_nm": ra_nm, "h_min_nm": r["h_min_nm"], "h_max_nm": r["h_max_nm"], "verdict": r["verdict"],
                   "angle_deg": ANGLES_DEG.tolist(), "wavelength_nm": WAVELENGTHS_NM.tolist(), "h_nm": r["h_nm"].tolist()})
        return
    click.echo("\n".join(rayleigh_text(r, ra_nm)))
