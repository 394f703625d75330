"""The tables the optics commands print (``swatch spectrum``, ``swatch color``, ``swatch materials``)
and their JSON forms: plain functions from computed values to lines or JSON-ready dicts."""
from __future__ import annotations

import numpy as np

from swatch.physics.growth import voltage_text
from swatch.physics.overcoat import overcoat_text

__all__ = ["spectrum_text", "colour_table_text", "materials_text", "material_text", "materials_json", "material_json"]


def spectrum_text(out: dict, under: str = "", process: str = "") -> list[str]:
    """``swatch spectrum``'s table from its JSON dictionary.

    Parameters
    ----------
    out : dict
        ``film``, ``substrate``, ``thickness_nm`` (nm), ``theta_d_deg`` (degrees) and the columns
        ``wavelength_nm``, ``reflectance``, ``reflectance_s``, ``reflectance_p`` (reflectance factors, 0–1).
    under : str
        The overcoat description (:func:`swatch.physics.overcoat.overcoat_text`), or empty.
    process : str
        The process profile's label.

    Returns
    -------
    list of str
        A header line, the column names and one line per wavelength.
    """
    lines = [f"# {out['film']} on {out['substrate']}{under}, d = {out['thickness_nm']:g} nm, "
             f"theta_d = {out['theta_d_deg']:.3f} deg; process {process}", f"{'wavelength_nm':>13} {'R':>10} {'R_s':>10} {'R_p':>10}"]
    for row in zip(out["wavelength_nm"], out["reflectance"], out["reflectance_s"], out["reflectance_p"], strict=True):
        lines.append(f"{row[0]:13.1f} {row[1]:10.6f} {row[2]:10.6f} {row[3]:10.6f}")
    return lines


def colour_table_text(rows: list[dict], coating, cm, light: float, view: float, theta_d_deg: float,
                      process: str = "") -> list[str]:
    """``swatch color``'s table (one line per thickness).

    Parameters
    ----------
    rows : list of dict
        :meth:`swatch.colorimetry.appearance.ThicknessColours.rows` (thickness nm, optional voltage V,
        CIELAB, LCh, sRGB hex and gamut flag, ΔE*ab to the previous row).
    coating : swatch.physics.model.Coating
        Film, substrate and overcoats (named in the header).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the CIELAB values.
    light, view, theta_d_deg : float
        Light and view polar angles and the facet's incidence angle, degrees.
    process : str
        The process profile's label.

    Returns
    -------
    list of str
        A ``#`` header line (materials, geometry, illuminant and observer), a column header, then one line per
        row; no line ends.
    """

    lines = [f"# {coating.film} on {coating.substrate}{overcoat_text(coating)}; light {light:g}°, view {view:g}° "
             f"(theta_d {theta_d_deg:.2f}°); {cm.illuminant}, {cm.observer}° observer; process {process}",
             ]
    volts = bool(rows) and "voltage_V" in rows[0]  # given as voltages: a voltage column beside the thickness
    lines.append(f"{'d_nm':>7}" + (f" {'volt_V':>7}" if volts else "")
                 + f" {'L*':>7} {'a*':>7} {'b*':>7} {'C*':>7} {'h':>6}  {'sRGB':7} {'gamut':5} {'dE_ab':>6}")
    for r in rows:
        L, a, b = r["Lab"]
        _, C, h = r["LCh"]
        dE = "" if r["delta_E_ab_to_previous"] is None else f"{r['delta_E_ab_to_previous']:6.2f}"
        lines.append(f"{r['thickness_nm']:7.1f}" + (f" {voltage_text(r['voltage_V']):>7}" if volts else "")
                     + f" {L:7.2f} {a:7.2f} {b:7.2f} {C:7.2f} {h:6.1f}  "
                     f"{r['srgb_hex']:7} {'yes' if r['in_srgb_gamut'] else 'no':5} {dE:>6}")
    return lines


def materials_text(mats, defaults: tuple[str, ...]) -> list[str]:
    """``swatch materials list``: one line per optical-constant table, the defaults starred.

    Parameters
    ----------
    mats : iterable of swatch.physics.materials.Material
        The tables.
    defaults : tuple of str
        The default film and substrate names.

    Returns
    -------
    list of str
        Name, role, wavelength range (nm) and DOI per table, then ``(* default)``.
    """
    lines = []
    for m in mats:
        lo, hi = m.wavelength_range_nm
        star = "*" if m.name in defaults else " "
        lines.append(f"{star}{m.name:24} {m.role:9} {lo:8.1f}–{hi:<9.1f} nm  doi:{m.doi}")
    return [*lines, "(* default)"]


def material_text(m, wl: np.ndarray, nk: np.ndarray) -> list[str]:
    """``swatch materials show``: the table's source, then n and k per wavelength.

    Parameters
    ----------
    m : swatch.physics.materials.Material
        The table.
    wl : numpy.ndarray, shape (W,)
        Wavelengths, nm.
    nk : numpy.ndarray of complex, shape (W,)
        The complex index n + ik at ``wl``.

    Returns
    -------
    list of str
        Two ``#`` lines (reference, DOI and licence), a column header, then ``wavelength_nm n k`` per wavelength.
    """
    lines = [f"# {m.name} ({m.role}): {' '.join(m.reference.split())}", f"# doi:{m.doi}; {m.license}",
             f"{'wavelength_nm':>13} {'n':>9} {'k':>9}"]
    return lines + [f"{w:13.1f} {n:9.4f} {k:9.4f}" for w, n, k in zip(wl, nk.real, nk.imag, strict=True)]


def materials_json(mats, defaults: tuple[str, ...]) -> list[dict]:
    """``swatch materials list --json``: name, role, formula, reference, DOI, range (nm) and default flag.

    Parameters
    ----------
    mats : iterable of swatch.physics.materials.Material
        The tables.
    defaults : tuple of str
        The default film and substrate names.

    Returns
    -------
    list of dict
        One dict per table: ``name``, ``role``, ``formula``, ``reference``, ``doi``, ``wavelength_range_nm`` ([lo, hi],
        nm) and ``default`` (bool).
    """
    return [{"name": m.name, "role": m.role, "formula": m.formula, "reference": m.reference, "doi": m.doi,
             "wavelength_range_nm": list(m.wavelength_range_nm), "default": m.name in defaults} for m in mats]


def material_json(m, wl: np.ndarray, nk: np.ndarray) -> dict:
    """``swatch materials show --json``: the table's source and n, k on the grid.

    Parameters
    ----------
    m : swatch.physics.materials.Material
        The table.
    wl : numpy.ndarray, shape (W,)
        Wavelengths, nm.
    nk : numpy.ndarray of complex, shape (W,)
        The complex index at ``wl``.

    Returns
    -------
    dict
        ``name``, ``role``, ``formula``, ``source`` (reference, DOI, file, licence), ``wavelength_nm``, ``n``, ``k``.
    """
    return {"name": m.name, "role": m.role, "formula": m.formula,
            "source": {"reference": m.reference, "doi": m.doi, "file": m.source_file, "license": m.license},
            "wavelength_nm": wl.tolist(), "n": nk.real.tolist(), "k": nk.imag.tolist()}
