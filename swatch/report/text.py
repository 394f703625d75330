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
from swatch.fit.result import delta_e_grid, resampled_words
from swatch.io.imageio import write_exr, write_png
from swatch.report.figures import delta_e_figure

if TYPE_CHECKING:
    from swatch.fit.matching import MatchResult
    from swatch.render.angular import AngularMap

__all__ = ["multi_summary", "report_paths", "write_report", "angular_lab_csv", "angular_lab_json",
           "fit_text", "multi_text", "match_text", "with_process", "grade_in_metric"]


def grade_in_metric(d: dict, scheme: str) -> str:
    """The scheme's grade of a fit's mean colour difference, taken in the metric the scheme bounds.

    Parameters
    ----------
    d : dict
        A fit's dict with ``mean_delta_E_ab`` and ``mean_delta_E_00`` (ΔE*ab and ΔE2000, unitless).
    scheme : str
        A tolerance scheme of :func:`swatch.colorimetry.tolerance.schemes` (CSAJ grades bound ΔE*ab).

    Returns
    -------
    str
        The grade's name (e.g. ``"A"``), or the scheme's "beyond every grade" label.
    """

    return grade_for(d["mean_delta_E_ab" if grade_metric(scheme) == "dEab" else "mean_delta_E_00"], scheme)


def with_process(d: dict, proc) -> dict:
    """Put a process's growth law on a fit's dict: the voltage, the rate, the profile and the grade.

    Parameters
    ----------
    d : dict
        :meth:`swatch.fit.result.FitResult.to_dict` (``thickness_nm`` in nm, ``scheme``); changed in place.
    proc : swatch.physics.process.Process
        The process profile (its ``voltage_V`` growth law, one slope or two with a knee).

    Returns
    -------
    dict
        ``d``, with ``voltage_V`` (V; None without a rate), ``nm_per_V``, ``process`` and ``grade``.
    """
    v = proc.voltage_V(d["thickness_nm"])
    d["voltage_V"] = None if v is None else float(v)
    d["nm_per_V"] = proc.nm_per_V
    d["process"] = proc.metadata()
    d["grade"] = grade_in_metric(d, d["scheme"])
    return d


def multi_summary(dicts: list[dict], scheme: str) -> dict:
    """Several fits together: the mean ΔE*ab and ΔE2000 over the samples and the scheme's grade of the mean.

    Parameters
    ----------
    dicts : list of dict
        The fits (:func:`with_process`), each with ``mean_delta_E_ab`` and ``mean_delta_E_00``.
    scheme : str
        The tolerance scheme the grade is taken in (its own metric).

    Returns
    -------
    dict
        ``samples`` (``dicts``), ``mean_delta_E_ab``, ``mean_delta_E_00``, ``scheme`` and ``grade``.
    """
    out = {
        "samples": dicts,
        "mean_delta_E_ab": float(np.mean([d["mean_delta_E_ab"] for d in dicts])),
        "mean_delta_E_00": float(np.mean([d["mean_delta_E_00"] for d in dicts])),
        "scheme": scheme,
    }
    out["grade"] = grade_in_metric(out, scheme)
    return out


def multi_text(s: dict) -> str:
    """The closing line of ``swatch fit`` over several samples.

    Parameters
    ----------
    s : dict
        :func:`multi_summary`.

    Returns
    -------
    str
        One line: the number of samples, the mean ΔE*ab and ΔE2000 and the grade.
    """
    return (f"all {len(s['samples'])} samples: mean ΔE*ab {s['mean_delta_E_ab']:.2f}, "
            f"mean ΔE2000 {s['mean_delta_E_00']:.2f}, grade {s['grade']} ({s['scheme']})")


def _fmt(x, spec=".2f", none="—"):
    return none if x is None else format(x, spec)


def report_paths(report_dir, measurements, force: bool = False) -> dict:
    """The files of ``swatch fit --report``, checked before the fit: one ΔE map (PNG and EXR) per
    measurement and the summary CSV/Markdown and per-geometry CSV.

    Parameters
    ----------
    report_dir : str or path-like
        The report folder (created later if missing; a file in the way is refused now).
    measurements : sequence of str or path-like
        The measurement files (their stems name the maps when there are several, made unique).
    force : bool
        Allow replacing existing files.

    Returns
    -------
    dict
        ``maps`` (list of (PNG, EXR) paths), ``summary_csv``, ``summary_md``, ``geometries_csv``.

    Raises
    ------
    swatch.core.errors.SwatchError
        ``report_dir`` is empty or not a creatable folder, or a file exists and ``force`` is not set.
    """

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
    """Write the files of ``swatch fit --report`` (atomically, each file whole or not at all).

    The ΔE*ab maps (PNG figure; EXR with the data, one pixel per (light, view) cell: ΔE*ab, ΔE2000,
    measured, excluded), ``summary.csv`` and ``summary.md`` (thickness, uncertainty nm, voltage V,
    mean/max ΔE, grade; cf. Fujii et al. Tables 2 and 3) and ``geometries.csv`` (measured and
    simulated CIELAB per geometry).

    Parameters
    ----------
    results : sequence of swatch.fit.result.FitResult
        The fits, in the order of ``paths["maps"]``.
    dicts : list of dict
        Their dicts (:func:`with_process`).
    paths : dict
        :func:`report_paths`.

    Returns
    -------
    None
    """
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
    """An angular map's colours as CSV: one row per (light, view) cell.

    Parameters
    ----------
    amap : swatch.render.angular.AngularMap
        The map (light × view polar angles, degrees).

    Returns
    -------
    str
        Columns ``light_deg, view_deg, theta_d_deg, X, Y, Z, L, a, b`` (XYZ with Y = 100 for the
        perfect diffuser, CIELAB under the map's illuminant and observer; 4 decimals).
    """
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
    """An angular map's CIELAB as JSON (sorted keys, 4 decimals, no NaN).

    Parameters
    ----------
    amap : swatch.render.angular.AngularMap
        The map.

    Returns
    -------
    str
        ``{"metadata", "light_deg", "view_deg", "Lab"}``: ``Lab`` nested as (light, view, 3).
    """
    out = {
        "metadata": amap.metadata,
        "light_deg": amap.light_deg.tolist(),
        "view_deg": amap.view_deg.tolist(),
        "Lab": np.round(amap.Lab, 4).tolist(),
    }
    return json.dumps(out, indent=1, ensure_ascii=False, allow_nan=False, sort_keys=True) + "\n"


def fit_text(d: dict) -> list[str]:
    """The lines ``swatch fit`` prints for one fit.

    Parameters
    ----------
    d : dict
        :meth:`swatch.fit.result.FitResult.to_dict` with the process (:func:`with_process`).

    Returns
    -------
    list of str
        Header (geometries, data, materials, colorimetry), thickness ± uncertainty (nm) and voltage (V),
        residual, second minimum, the mean/max ΔE and grade, and one line per geometry.
    """
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
    if d.get("colour_grid_interpolated"):
        lines.append(f"# measured wavelengths: {resampled_words(d['colour_wavelength_nm'])}")
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
    """The table ``swatch match`` prints: target, geometry, candidates, and a note when none is within grade.

    Parameters
    ----------
    res : swatch.fit.matching.MatchResult
        The candidates (thickness nm, voltage V, CIELAB, ΔE2000 and ΔE*ab).
    target_hex : str or None
        The target's sRGB hex code when it was given as one.
    thickness_range : str
        The searched range as given (``A:B``, nm), for the note.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the CIELAB values.
    coating : swatch.physics.model.Coating
        Film and substrate (named in the header).
    process : str
        The process profile's label.
    tol : swatch.colorimetry.tolerance.Tolerance
        The tolerance the ``within_grade`` column judges.

    Returns
    -------
    list of str
        The lines to print, without line ends.
    """
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
