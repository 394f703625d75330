"""catalog.csv: its columns (colorimetry and units in the names) and its rows, from the swatch records."""
from __future__ import annotations

import csv
import io

from swatch.catalog.presets import FORMAT_FIGURES
from swatch.catalog.spec import CatalogSpec
from swatch.presets import PRESET_FORMATS

__all__ = ["csv_columns", "csv_bytes", "preset_figures"]


def preset_figures(spec: CatalogSpec) -> list[str]:
    """The presets' error keys, in catalog.json's order (max over mirror 0–60°, 0–45°, at 45:0), then those of the
    page's ``<model-viewer>`` (``[presets] ar``) and of the USD fallback (``[presets] usd``) where the spec asks.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    list of str
        The keys of each preset's ΔE2000 figures, as catalog.json names them.
    """
    keys = [f"{prefix}{tail}" for fmt in PRESET_FORMATS for prefix in FORMAT_FIGURES[fmt]
            for tail in ("_max_delta_E_00", "_max_delta_E_00_45", "_delta_E_00_45_0")]
    for on, prefix in ((spec.presets and spec.ar, "modelviewer"), (spec.presets and spec.presets_usd, "usd_preview")):
        if on:
            keys += [f"{prefix}_max_delta_E_00", f"{prefix}_max_delta_E_00_45"]
    return keys


def csv_columns(spec: CatalogSpec, illuminant: str, observer: str) -> list[str]:
    """catalog.csv's header: colorimetry and units in the names (``L_D65_10``, ``h_D65_10_deg``).

    Lab/LCh and XYZ (white Y = 100) at the reference geometry under the catalog's illuminant and
    observer, then Lab under D50 / CIE 1931 2° (``L_D50_2`` …, what ICC and Adobe tools assume), the
    sRGB hex (CIE 1931 2° colorimetry), the hue family and colour name, and Lab/LCh and the sRGB hex
    per multi-angle geometry (``L_D65_10_45as-15`` …); the 3-D presets' errors (ΔE2000, D65, 2°) and
    every file of the swatch.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    illuminant, observer : str
        The Lab columns' illuminant and observer (named in their headers).

    Returns
    -------
    list of str
        The CSV's column names, in order.
    """
    cs = f"{illuminant}_{observer}"
    lab = [f"L_{cs}", f"a_{cs}", f"b_{cs}", f"C_{cs}", f"h_{cs}_deg"]
    head = ["id", "thickness_nm", "voltage_V", *lab, f"X_{cs}", f"Y_{cs}", f"Z_{cs}", "L_D50_2", "a_D50_2", "b_D50_2",
            "srgb_hex", "in_srgb_gamut", "hue_family", "colour_name", "dE00_previous", "dE00_next", "dEab_previous",
            "dEab_next", "window_grade", "window_metric", "window_max", "thickness_minus_nm", "thickness_plus_nm",
            "voltage_minus_V", "voltage_plus_V", "minus_capped", "plus_capped"]
    for g in spec.multi_angle:
        head += [f"L_{cs}_{g.name}", f"a_{cs}_{g.name}", f"b_{cs}_{g.name}", f"C_{cs}_{g.name}",
                 f"h_{cs}_deg_{g.name}", f"srgb_hex_{g.name}"]
    files = ["sheet_png", "sheet_exr", "tile_row", "tile_col", "chip_png", "chip_tiff", "preset_gltf",
             "preset_blender", "preset_materialx", "preset_mitsuba", "preset_mitsuba_json"]
    return [*head, *preset_figures(spec), *files]


def csv_bytes(spec: CatalogSpec, records: list[dict], illuminant: str, observer: str) -> bytes:
    r"""catalog.csv: one row per swatch in the columns of :func:`csv_columns` (UTF-8, ``\n``).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (JSON view), in order.
    illuminant, observer : str
        The Lab columns' illuminant and observer.

    Returns
    -------
    bytes
        catalog.csv, UTF-8.
    """
    buf = io.StringIO(newline="")
    w = csv.writer(buf, lineterminator="\n")
    geo = [g.name for g in spec.multi_angle]
    w.writerow(csv_columns(spec, illuminant, observer))
    figures = preset_figures(spec)

    def f(x):
        return "" if x is None else repr(x) if isinstance(x, float) else str(x)

    for r in records:
        pw = r["process_window"]
        row = [r["id"], r["thickness_nm"], r["voltage_V"], *r["Lab"], r["LCh"][1], r["LCh"][2], *r["XYZ"],
               *r["Lab_D50_2"], r["srgb_hex"], r["in_srgb_gamut"], r["hue_family"], r.get("colour_name"),
               r["delta_E_00_to_neighbours"]["previous"], r["delta_E_00_to_neighbours"]["next"],
               r["delta_E_ab_to_neighbours"]["previous"], r["delta_E_ab_to_neighbours"]["next"],
               f"{pw['scheme']} {pw['grade']}" if pw["scheme"] else pw["grade"], pw["metric"], pw["max"],
               pw["thickness_minus_nm"], pw["thickness_plus_nm"],
               pw["voltage_minus_V"], pw["voltage_plus_V"], pw["minus_capped"], pw["plus_capped"]]
        for g in geo:
            row += [*r["multi_angle"][g], *r["multi_angle_LCh"][g][1:], r["multi_angle_srgb_hex"][g]]
        presets = r.get("presets") or {}
        chip = r.get("print_chip") or {}
        row += [presets.get(k) for k in figures]
        row += [r["sheet_png"], r["sheet_exr"], *r["tile"], chip.get("png"), chip.get("tiff"), presets.get("gltf"),
                presets.get("blender"), presets.get("materialx"), presets.get("mitsuba"), presets.get("mitsuba_json")]
        w.writerow([f(x) for x in row])
    return buf.getvalue().encode("utf-8")
