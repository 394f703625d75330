"""Reports: the ΔE grid and the files of ``swatch fit --report`` (ΔE maps, summary CSV/Markdown,
per-geometry CSV), the summary of several fits, and the Lab tables of an angular map."""
from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swatch.colorimetry.tolerance import grade_for, grade_metric
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text, check_creatable_dir, check_new
from swatch.fit.fitting import delta_e_grid
from swatch.io.imageio import write_exr, write_png
from swatch.physics.model import overcoat_text
from swatch.report.figures import delta_e_figure

if TYPE_CHECKING:
    from swatch.fit.matching import MatchResult
    from swatch.render.angular import AngularMap

__all__ = ["multi_summary", "report_paths", "write_report", "angular_lab_csv", "angular_lab_json",
           "fit_text", "multi_text", "match_text", "with_process", "grade_in_metric", "spectrum_text", "colour_table_text",
           "materials_text", "material_text", "materials_json", "material_json"]


def grade_in_metric(d: dict, scheme: str) -> str:
    """The scheme's grade of a mean colour difference (``d``'s ``mean_delta_E_ab`` or
    ``mean_delta_E_00``), taken in the metric the scheme bounds."""

    return grade_for(d["mean_delta_E_ab" if grade_metric(scheme) == "dEab" else "mean_delta_E_00"], scheme)


def with_process(d: dict, proc) -> dict:
    """A fit's dict with the voltage from the process's growth law, the profile, and the grade
    in the scheme's metric."""
    v = proc.voltage_V(d["thickness_nm"])
    d["voltage_V"] = None if v is None else float(v)
    d["nm_per_V"] = proc.nm_per_V
    d["process"] = proc.metadata()
    d["grade"] = grade_in_metric(d, d["scheme"])
    return d


def multi_summary(dicts: list[dict], scheme: str) -> dict:
    """Several fits together: the mean ΔE*ab and ΔE2000 over the samples and the scheme's grade
    of the mean, in the metric the scheme bounds."""
    out = {
        "samples": dicts,
        "mean_delta_E_ab": float(np.mean([d["mean_delta_E_ab"] for d in dicts])),
        "mean_delta_E_00": float(np.mean([d["mean_delta_E_00"] for d in dicts])),
        "scheme": scheme,
    }
    out["grade"] = grade_in_metric(out, scheme)
    return out


def multi_text(s: dict) -> str:
    """The closing line of ``swatch fit`` over several samples (``s`` = :func:`multi_summary`)."""
    return (f"all {len(s['samples'])} samples: mean ΔE*ab {s['mean_delta_E_ab']:.2f}, "
            f"mean ΔE2000 {s['mean_delta_E_00']:.2f}, grade {s['grade']} ({s['scheme']})")


def _fmt(x, spec=".2f", none="—"):
    return none if x is None else format(x, spec)


def report_paths(report_dir, measurements, force: bool = False) -> dict:
    """The files of ``swatch fit --report`` (one ΔE map per measurement), checked: the folder name is
    not empty and no file exists unless ``force``."""

    if not str(report_dir).strip():
        raise SwatchError("`report_dir` is an empty string; give a folder path")
    out = check_creatable_dir(report_dir)  # (before the fit: a file in the way is refused at once)
    if len(measurements) == 1:
        maps = [(out / "delta_e_map.png", out / "delta_e_map.exr")]
    else:
        used: set[str] = set()
        maps = []
        for p in measurements:
            stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in Path(p).stem)
            name, k = stem, 1
            while name.lower() in used:  # unique even against a file already named x_2
                k += 1
                name = f"{stem}_{k}"
            used.add(name.lower())
            maps.append((out / f"delta_e_map_{name}.png", out / f"delta_e_map_{name}.exr"))
    paths: dict[str, Any] = {
        "maps": maps,
        "summary_csv": out / "summary.csv",
        "summary_md": out / "summary.md",
        "geometries_csv": out / "geometries.csv",
    }
    check_new([p for pair in paths["maps"] for p in pair]
              + [paths[k] for k in ("summary_csv", "summary_md", "geometries_csv")], force)
    return paths


def write_report(results, dicts, paths) -> None:
    for r, (png, exr) in zip(results, paths["maps"], strict=True):
        stem = Path(r.source).name
        title = f"dE*ab (CIE 1976)  {stem}   d = {r.thickness_nm:.1f} nm"
        image, data = delta_e_figure(r, title)
        meta = {
            "source": stem, "thickness_nm": float(r.thickness_nm), "mean_delta_E_ab": float(r.mean_delta_E_ab),
            "grade": r.grade, "light_deg": data["light_deg"].tolist(), "view_deg": data["view_deg"].tolist(),
            "view_signed": bool(data["signed"]), "exclude_mirror_deg": float(r.exclude_mirror_deg),
        }
        write_png(png, image, metadata=meta)
        # EXR: the data themselves, one pixel per (light, view) cell; rows = light, columns = view.
        _, _, g00, _, _ = delta_e_grid(r, "delta_E_00")
        measured = np.isfinite(data["grid"])
        pix = np.stack([np.where(measured, data["grid"], 0.0), np.where(measured, g00, 0.0),
                        measured.astype(float), data["excluded"].astype(float)], axis=-1)
        write_exr(exr, pix, metadata=meta, channel_names=("delta_E_ab", "delta_E_00", "measured", "excluded"),
                  space=None, half=False)

    cols = ["sample", "kind", "thickness_nm", "uncertainty_nm", "voltage_V", "second_best_thickness_nm",
            "residual", "mean_delta_E_ab", "mean_delta_E_00", "max_delta_E_ab", "grade", "n_used", "n_geometries"]

    def cell(v):
        if v is None:
            return ""
        if isinstance(v, float):
            return f"{v:.6g}"
        return str(v)

    rows = []
    for d in dicts:
        row = dict(d, sample=Path(d["source"]).name)
        rows.append([cell(row[c]) for c in cols])
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    w.writerows(rows)
    if len(dicts) > 1:
        s = multi_summary(dicts, dicts[0]["scheme"])
        w.writerow(["mean", "", "", "", "", "", "", cell(s["mean_delta_E_ab"]), cell(s["mean_delta_E_00"]), "",
                    s["grade"], "", ""])
    atomic_write_text(paths["summary_csv"], buf.getvalue())

    md = ["# Thickness fit and colour difference (cf. Fujii et al., Tables 2 and 3)", "",
          f"Intensity correction: {dicts[0]['scale_mode']}; mirror region (view within "
          f"{dicts[0]['exclude_mirror_deg']:g}° of the mirror direction) left out of the means; "
          f"{dicts[0]['illuminant']}, {dicts[0]['observer']}° observer; grades: {dicts[0]['scheme']}"
          + (f"; process {dicts[0]['process']['process']}" if "process" in dicts[0] else "") + ".", "",
          "| sample | thickness (nm) | ± (nm) | voltage (V) | 2nd minimum (nm) | mean ΔE*ab | mean ΔE2000 | max ΔE*ab | grade | geometries used |",
          "|---|---:|---:|---:|---:|---:|---:|---:|:---:|---:|"]
    for d in dicts:
        md.append(f"| {Path(d['source']).name} | {d['thickness_nm']:.1f} | {_fmt(d['uncertainty_nm'], '.2f')} | "
                  f"{_fmt(d['voltage_V'], '.1f')} | {_fmt(d['second_best_thickness_nm'], '.1f')} | {d['mean_delta_E_ab']:.2f} | "
                  f"{d['mean_delta_E_00']:.2f} | {d['max_delta_E_ab']:.2f} | {d['grade']} | {d['n_used']}/{d['n_geometries']} |")
    if len(dicts) > 1:
        s = multi_summary(dicts, dicts[0]["scheme"])
        md.append(f"| **mean** | | | | | **{s['mean_delta_E_ab']:.2f}** | **{s['mean_delta_E_00']:.2f}** | | "
                  f"**{s['grade']}** | |")
    md.append("")
    atomic_write_text(paths["summary_md"], "\n".join(md))

    gcols = ["sample", "light_deg", "view_deg", "light_azimuth_deg", "view_azimuth_deg", "theta_d_deg",
             "mirror_angle_deg", "excluded", "L_measured", "a_measured", "b_measured", "L_simulated",
             "a_simulated", "b_simulated", "delta_E_ab", "delta_E_00"]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(gcols)
    for d in dicts:
        name = Path(d["source"]).name
        for g in d["geometries"]:
            w.writerow([name] + [cell(g[k]) for k in ("light_deg", "view_deg", "light_azimuth_deg",
                                                      "view_azimuth_deg", "theta_d_deg", "mirror_angle_deg")]
                       + [str(g["excluded"]).lower()] + [f"{v:.4f}" for v in g["Lab_measured"]]
                       + [f"{v:.4f}" for v in g["Lab_simulated"]] + [f"{g['delta_E_ab']:.4f}", f"{g['delta_E_00']:.4f}"])
    atomic_write_text(paths["geometries_csv"], buf.getvalue())


def angular_lab_csv(amap: AngularMap) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["light_deg", "view_deg", "theta_d_deg", "X", "Y", "Z", "L", "a", "b"])
    L, V = np.meshgrid(amap.light_deg, amap.view_deg, indexing="ij")
    rows = np.column_stack([L.ravel(), V.ravel(), amap.theta_d_deg.ravel(), amap.XYZ.reshape(-1, 3),
                            amap.Lab.reshape(-1, 3)])
    for r in rows:
        w.writerow([f"{r[0]:g}", f"{r[1]:g}", f"{r[2]:.4f}"] + [f"{x:.4f}" for x in r[3:]])
    return buf.getvalue()


def angular_lab_json(amap: AngularMap) -> str:
    out = {
        "metadata": amap.metadata,
        "light_deg": amap.light_deg.tolist(),
        "view_deg": amap.view_deg.tolist(),
        "Lab": np.round(amap.Lab, 4).tolist(),
    }
    return json.dumps(out, indent=1, ensure_ascii=False, allow_nan=False, sort_keys=True) + "\n"


def fit_text(d: dict) -> list[str]:
    """The lines ``swatch fit`` prints for one fit (``d`` = :meth:`FitResult.to_dict`)."""
    lines = []
    n_ex = d["n_geometries"] - d["n_used"]
    head = f"# {d['source']}: {d['n_geometries']} geometr{'y' if d['n_geometries'] == 1 else 'ies'}"
    if n_ex:
        head += f" ({n_ex} within {d['exclude_mirror_deg']:g}° of the mirror direction left out)"
    if d["kind"] == "spectral":
        lo, hi, nw = d["wavelength_nm"]
        how = "detected: a value above 1.5" if d["reflectance_unit_detected"] and d["reflectance_unit"] == "percent" \
            else ("detected: all values <= 1.5" if d["reflectance_unit_detected"] else "as stated")
        head += f"; {lo:g}–{hi:g} nm ({nw} wavelengths); reflectance in {d['reflectance_unit']} ({how})"
    else:
        head += "; CIELAB (fitted by ΔE2000)"
    lines.append(head)
    lines.append(f"# {d['film']} on {d['substrate']}; intensity: {d['scale_mode']}; {d['illuminant']}, "
                 f"{d['observer']}° observer")
    unc = f" ± {d['uncertainty_nm']:.2f}" if d["uncertainty_nm"] is not None else ""
    volts = ("no growth rate" if d["voltage_V"] is None
             else f"≈ {d['voltage_V']:.1f} V at {d['nm_per_V']:.3g} nm/V + {d['process']['offset_nm']:g} nm")
    lines.append(f"thickness      {d['thickness_nm']:.2f}{unc} nm   ({volts}; process {d['process']['process']})")
    unit = "mean squared error" if d["kind"] == "spectral" else "mean squared ΔE2000"
    lines.append(f"residual       {d['residual']:.4g} ({unit})")
    if d["second_best_thickness_nm"] is not None:
        lines.append(f"second best    {d['second_best_thickness_nm']:.2f} nm (residual {d['second_best_residual']:.4g})")
    else:
        lines.append("second best    none (one minimum in the range)")
    lines.append(f"mean ΔE*ab     {d['mean_delta_E_ab']:.2f}   mean ΔE2000 {d['mean_delta_E_00']:.2f}   "
                 f"max ΔE*ab {d['max_delta_E_ab']:.2f}   grade {d['grade']} ({d['scheme']})")
    lines.append(f"{'light':>6} {'view':>6} {'az_l':>6} {'az_v':>6}  {'L*':>6} {'a*':>6} {'b*':>6}  "
                 f"{'L*sim':>6} {'a*sim':>6} {'b*sim':>6}  {'dE_ab':>6} {'dE_00':>6}")
    for g in d["geometries"]:
        Lm, Ls = g["Lab_measured"], g["Lab_simulated"]
        mark = "  (mirror region, left out)" if g["excluded"] else ""
        lines.append(f"{g['light_deg']:6.1f} {g['view_deg']:6.1f} {g['light_azimuth_deg']:6.1f} {g['view_azimuth_deg']:6.1f}  "
                   f"{Lm[0]:6.2f} {Lm[1]:6.2f} {Lm[2]:6.2f}  {Ls[0]:6.2f} {Ls[1]:6.2f} {Ls[2]:6.2f}  "
                   f"{g['delta_E_ab']:6.2f} {g['delta_E_00']:6.2f}{mark}")
    return lines


def match_text(res: MatchResult, target_hex: str | None, thickness_range: str, cm, coating, process: str,
               tol) -> list[str]:
    """The table ``swatch match`` prints (target, geometry, candidates, and a note when none is within grade)."""
    lines = []
    L, a, b = res.target_Lab
    src = f" (from {target_hex})" if target_hex is not None else ""
    lines.append(f"# target L*a*b* {L:.2f}, {a:.2f}, {b:.2f}{src}; light {res.light_deg:g}°, view {res.view_deg:g}° "
                 f"(theta_d {res.theta_d_deg:.2f}°); {cm.illuminant}, {cm.observer}° observer; {coating.film} on "
                 f"{coating.substrate}, process {process}")
    lines.append(f"{'rank':>4} {'d_nm':>8} {'volt_V':>7} {'L*':>7} {'a*':>7} {'b*':>7} {'dE00':>6} {'dE_ab':>6}  {tol.label}")
    for k, c in enumerate(res.candidates, start=1):
        Lc, ac, bc = c["Lab"]
        ok = "yes" if c["within_grade"] else "no"
        volts = "" if c["voltage_V"] is None else f"{c['voltage_V']:7.1f}"
        lines.append(f"{k:4d} {c['thickness_nm']:8.2f} {volts:>7} {Lc:7.2f} {ac:7.2f} {bc:7.2f} "
                   f"{c['delta_E_00']:6.2f} {c['delta_E_ab']:6.2f}  {ok}{'  (end of the range)' if c['at_range_bound'] else ''}")
    if not res.any_within_grade:
        lines.append(f"no thickness in {thickness_range} nm comes within {tol.text} at this geometry")
    return lines


# -- the engine commands' tables -------------------------------------------------------------------
def spectrum_text(out: dict, under: str = "", process: str = "") -> list[str]:
    """``swatch spectrum``'s table from its JSON dictionary (``under``: the overcoat description)."""
    lines = [f"# {out['film']} on {out['substrate']}{under}, d = {out['thickness_nm']:g} nm, "
             f"theta_d = {out['theta_d_deg']:.3f} deg; process {process}", f"{'wavelength_nm':>13} {'R':>10} {'R_s':>10} {'R_p':>10}"]
    for row in zip(out["wavelength_nm"], out["reflectance"], out["reflectance_s"], out["reflectance_p"], strict=True):
        lines.append(f"{row[0]:13.1f} {row[1]:10.6f} {row[2]:10.6f} {row[3]:10.6f}")
    return lines


def colour_table_text(rows: list[dict], coating, cm, light: float, view: float, theta_d_deg: float,
                      process: str = "") -> list[str]:
    """``swatch color``'s table from :meth:`swatch.colorimetry.appearance.ThicknessColours.rows`."""

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
        lines.append(f"{r['thickness_nm']:7.1f}" + (f" {r['voltage_V']:7.2f}" if volts else "")
                     + f" {L:7.2f} {a:7.2f} {b:7.2f} {C:7.2f} {h:6.1f}  "
                     f"{r['srgb_hex']:7} {'yes' if r['in_srgb_gamut'] else 'no':5} {dE:>6}")
    return lines


def materials_text(mats, defaults: tuple[str, ...]) -> list[str]:
    """``swatch materials list``: one line per table, defaults starred."""
    lines = []
    for m in mats:
        lo, hi = m.wavelength_range_nm
        star = "*" if m.name in defaults else " "
        lines.append(f"{star}{m.name:24} {m.role:9} {lo:8.1f}–{hi:<9.1f} nm  doi:{m.doi}")
    return [*lines, "(* default)"]


def material_text(m, wl: np.ndarray, nk: np.ndarray) -> list[str]:
    """``swatch materials show``: the source, then n and k per wavelength."""
    lines = [f"# {m.name} ({m.role}): {' '.join(m.reference.split())}", f"# doi:{m.doi}; {m.license}",
             f"{'wavelength_nm':>13} {'n':>9} {'k':>9}"]
    return lines + [f"{w:13.1f} {n:9.4f} {k:9.4f}" for w, n, k in zip(wl, nk.real, nk.imag, strict=True)]


def materials_json(mats, defaults: tuple[str, ...]) -> list[dict]:
    """``swatch materials list --json``."""
    return [{"name": m.name, "role": m.role, "formula": m.formula, "reference": m.reference, "doi": m.doi,
             "wavelength_range_nm": list(m.wavelength_range_nm), "default": m.name in defaults} for m in mats]


def material_json(m, wl: np.ndarray, nk: np.ndarray) -> dict:
    """``swatch materials show --json``: the table's source and n, k on the grid."""
    return {"name": m.name, "role": m.role, "formula": m.formula,
            "source": {"reference": m.reference, "doi": m.doi, "file": m.source_file, "license": m.license},
            "wavelength_nm": wl.tolist(), "n": nk.real.tolist(), "k": nk.imag.tolist()}
