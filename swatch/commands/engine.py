"""Engine commands: spectrum, color, materials, roughness."""
from __future__ import annotations

import click
import numpy as np

from swatch.commands.common import (
    colour_options, echo_json, geometry_options, grid_option, material_options, overcoat_option, resolve_coating,
    resolve_grid, resolve_process, resolve_thickness, thickness_options,
)
from swatch.errors import SwatchError


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
    out.update(_overcoat_json(coating))
    if as_json:
        echo_json(out)
        return
    click.echo(f"# {coating.film} on {coating.substrate}{_overcoat_text(coating)}, d = {d[0]:g} nm, "
               f"theta_d = {theta_d:.3f} deg; process {proc.name}")
    click.echo(f"{'wavelength_nm':>13} {'R':>10} {'R_s':>10} {'R_p':>10}")
    for row in zip(out["wavelength_nm"], out["reflectance"], out["reflectance_s"], out["reflectance_p"]):
        click.echo(f"{row[0]:13.1f} {row[1]:10.6f} {row[2]:10.6f} {row[3]:10.6f}")


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
    from swatch.appearance import color_table
    from swatch.colorimetry import get_colorimeter

    proc = resolve_process(process, film, substrate, nm_per_volt)
    d, v = resolve_thickness(thickness, voltage, proc, multiple=True)
    coating = resolve_coating(proc, wavelengths=wavelengths, overcoats=overcoats)
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    table = color_table(d, light, view, coating, cm, light_azimuth, view_azimuth)
    rows = table.rows()
    if v is not None:
        for row, volts in zip(rows, v):
            row["voltage_V"] = float(volts)
    if as_json:
        echo_json({
            "illuminant": cm.illuminant, "observer": cm.observer, "film": coating.film,
            "substrate": coating.substrate, "light_deg": light, "view_deg": view,
            "theta_d_deg": table.theta_d_deg, **_overcoat_json(coating), "process": proc.metadata(), "rows": rows,
        })
        return
    click.echo(f"# {coating.film} on {coating.substrate}{_overcoat_text(coating)}; light {light:g}°, view {view:g}° "
               f"(theta_d {table.theta_d_deg:.2f}°); {cm.illuminant}, {cm.observer}° observer; process {proc.name}")
    click.echo(f"{'d_nm':>7} {'L*':>7} {'a*':>7} {'b*':>7} {'C*':>7} {'h':>6}  {'sRGB':7} {'gamut':5} {'dE_ab':>6}")
    for r in rows:
        L, a, b = r["Lab"]
        _, C, h = r["LCh"]
        dE = "" if r["delta_E_ab_to_previous"] is None else f"{r['delta_E_ab_to_previous']:6.2f}"
        click.echo(f"{r['thickness_nm']:7.1f} {L:7.2f} {a:7.2f} {b:7.2f} {C:7.2f} {h:6.1f}  "
                   f"{r['srgb_hex']:7} {'yes' if r['in_srgb_gamut'] else 'no':5} {dE:>6}")


def _overcoat_json(coating) -> dict:
    overcoats = getattr(coating, "overcoats", ())
    if not overcoats:
        return {}
    return {"overcoat": [{"layer": o.label, "thickness_nm": o.thickness_nm} for o in overcoats]}


def _overcoat_text(coating) -> str:
    layers = [f"{o.label} {o.thickness_nm:g} nm" for o in getattr(coating, "overcoats", ())]
    return f" under {' / '.join(layers)}" if layers else ""


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
    for m in mats:
        lo, hi = m.wavelength_range_nm
        star = "*" if m.name in (DEFAULT_FILM, DEFAULT_SUBSTRATE) else " "
        click.echo(f"{star}{m.name:24} {m.role:9} {lo:8.1f}–{hi:<9.1f} nm  doi:{m.doi}")
    click.echo("(* default)")


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
    click.echo(f"# {m.name} ({m.role}): {' '.join(m.reference.split())}")
    click.echo(f"# doi:{m.doi}; {m.license}")
    click.echo(f"{'wavelength_nm':>13} {'n':>9} {'k':>9}")
    for w, n, k in zip(wl, nk.real, nk.imag):
        click.echo(f"{w:13.1f} {n:9.4f} {k:9.4f}")


@click.command()
@click.option("--ra", "ra_nm", type=float, required=True, help="arithmetic mean roughness Ra in nm")
@click.option("--json", "as_json", is_flag=True, help="print JSON")
def roughness(ra_nm, as_json):
    """Rayleigh criterion h = λ / (8 cos θ) over 380–780 nm and 0–60°: is the surface optically rough?

    The paper's blue sample (Ra 268 nm) is rough: h spans 47.5–195 nm.
    """
    if not np.isfinite(ra_nm) or ra_nm < 0 or ra_nm > 1e6:
        raise SwatchError("--ra must be a roughness from 0 to 1e6 nm")
    angles = np.arange(0.0, 61.0, 10.0)
    wl = np.array([380.0, 480.0, 580.0, 680.0, 780.0])
    h = wl[None, :] / (8.0 * np.cos(np.radians(angles))[:, None])
    h_min, h_max = float(h.min()), float(h.max())
    if ra_nm > h_max:
        verdict = "rough"
        text = "optically rough over the whole visible range and 0–60°: facets scatter off-mirror (half-vector model applies)"
    elif ra_nm < h_min:
        verdict = "smooth"
        text = "optically smooth over the whole visible range and 0–60°: a mirror; colour only near the specular direction"
    else:
        verdict = "partly rough"
        text = "rough for short wavelengths or steep angles, smooth otherwise"
    if as_json:
        echo_json({"ra_nm": ra_nm, "h_min_nm": h_min, "h_max_nm": h_max, "verdict": verdict,
                   "angle_deg": angles.tolist(), "wavelength_nm": wl.tolist(), "h_nm": h.tolist()})
        return
    click.echo(f"Rayleigh criterion h = λ/(8 cos θ): {h_min:.1f}–{h_max:.1f} nm over 380–780 nm, 0–60°")
    click.echo(f"{'θ_deg':>6} " + " ".join(f"{w:>7.0f}nm" for w in wl))
    for a, row in zip(angles, h):
        click.echo(f"{a:6.0f} " + " ".join(f"{v:9.1f}" for v in row))
    click.echo(f"Ra = {ra_nm:g} nm: {text}")
