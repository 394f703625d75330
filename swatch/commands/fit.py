"""``swatch fit`` (thickness from measurements, ΔE report) and ``swatch match`` (thickness from a colour)."""
from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import click
import numpy as np

from swatch.commands.common import (
    colour_options, echo_json, geometry_options, grid_option, material_options, process_options, resolve_process,
)
from swatch.errors import SwatchError
from swatch.model import DEFAULT_NM_PER_V

SCALE_CHOICES = ("energy", "lsq", "global", "none")
#: Viridis anchors (perceptually ordered dark -> light) for the ΔE colour scale.
_VIRIDIS = np.array([
    (68, 1, 84), (71, 44, 122), (59, 81, 139), (44, 113, 142), (33, 144, 141),
    (39, 173, 129), (92, 200, 99), (170, 220, 50), (253, 231, 37),
], dtype=np.float64)


def _parse_pair(text: str, what: str) -> tuple[float, float]:
    parts = str(text).split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        a, b = (float(p) for p in parts)
    except ValueError:
        raise SwatchError(f"{what} {text!r} must be A:B in nm, e.g. 0:400") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise SwatchError(f"{what} must be finite numbers")
    return a, b


def _parse_lab(text: str) -> np.ndarray:
    parts = [p for p in str(text).replace(" ", "").split(",")]
    try:
        if len(parts) != 3:
            raise ValueError
        vals = np.array([float(p) for p in parts])
    except ValueError:
        raise SwatchError(f"--lab {text!r} must be three numbers L,a,b, e.g. 45,-5,-30") from None
    if not np.all(np.isfinite(vals)) or not 0 <= vals[0] <= 100:
        raise SwatchError("--lab needs finite values with L between 0 and 100")
    return vals


# -- fit --------------------------------------------------------------------------------------------
@click.command()
@click.argument("measurements", nargs=-1, required=True, type=click.Path(dir_okay=False, path_type=str))
@click.option("--percent/--fraction", "percent", default=None,
              help="reflectance unit [default: percent if any value > 1.5, else fraction]")
@click.option("--scale", type=click.Choice(SCALE_CHOICES), default="energy", show_default=True,
              help="intensity correction: energy = the paper's (match each geometry's mean energy), "
                   "lsq = least-squares scale per geometry, global = one scale, none = absolute")
@click.option("--exclude-mirror", "exclude_mirror", type=float, default=10.0, show_default=True,
              help="leave out geometries whose view is within this many degrees of the mirror direction (0: keep all)")
@click.option("--range", "thickness_range", default="0:400", show_default=True, help="thickness search range A:B in nm")
@click.option("--step", type=float, default=1.0, show_default=True, help="global search step in nm")
@geometry_options
@material_options
@colour_options
@grid_option
@click.option("--scheme", default="csaj", show_default=True, help="tolerance scheme for the grade")
@process_options
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of text")
@click.option("--report", "report_dir", type=click.Path(file_okay=False, path_type=str), default=None,
              help="write delta_e_map.png/.exr, summary.csv/.md and geometries.csv into this folder")
@click.option("--force", is_flag=True, help="overwrite existing report files")
def fit(measurements, percent, scale, exclude_mirror, thickness_range, step, light, view, light_azimuth,
        view_azimuth, film, substrate, illuminant, observer, wavelengths, scheme, process, nm_per_volt, as_json,
        report_dir, force):
    """Estimate oxide thickness from measured spectra (or CIELAB) and report ΔE per geometry.

    MEASUREMENTS: CSV files, each one of: wavelength_nm,reflectance (one spectrum at --light/--view);
    light_deg,view_deg[,light_azimuth_deg,view_azimuth_deg],wavelength_nm,reflectance (sBRDF set, long
    form; negative view_deg = on the light's side); light_deg,view_deg,L,a,b (CIELAB: fitted by ΔE2000).
    The fit minimises the mean squared spectral error over all geometries outside the mirror region
    (global search over the range, then local refinement) and reports the best thickness, an
    uncertainty, the next-best minimum, ΔE*ab and ΔE2000 per geometry, their means and the grade.
    """
    from swatch.commands.common import resolve_grid
    from swatch.fitting import fit_lab, fit_spectra
    from swatch.measurements import LabMeasurement, read_measurement

    proc = resolve_process(process, film, substrate, nm_per_volt)
    film, substrate = proc.film, proc.substrate
    rng = _parse_pair(thickness_range, "--range")
    geom = dict(light_deg=light, view_deg=view, light_azimuth_deg=light_azimuth, view_azimuth_deg=view_azimuth)
    paths = _report_paths(report_dir, measurements) if report_dir is not None else None
    if paths:
        from swatch.fileio import check_new

        if not str(report_dir).strip():
            raise SwatchError("--report is an empty string; give a folder path")
        check_new([p for pair in paths["maps"] for p in pair]
                  + [paths[k] for k in ("summary_csv", "summary_md", "geometries_csv")], force)
    results = []
    for path in measurements:
        m = read_measurement(path, percent, **geom)
        common = dict(scale=scale, exclude_mirror_deg=exclude_mirror, thickness_range=rng, step_nm=step,
                      illuminant=illuminant, observer=observer, scheme=scheme)
        if isinstance(m, LabMeasurement):
            res = fit_lab(m, film, substrate, wavelength_nm=resolve_grid(wavelengths), **common)
        else:
            res = fit_spectra(m, film, substrate, **common)
        results.append(res)
    dicts = [_with_process(r.to_dict(proc.nm_per_V or DEFAULT_NM_PER_V), proc) for r in results]
    if paths:
        from swatch.fileio import check_writable_dir

        check_writable_dir(report_dir)  # created only once every measurement has been read and fitted
        _write_report(results, dicts, paths)
    if as_json:
        echo_json(dicts[0] if len(dicts) == 1 else _multi_summary(dicts, scheme))
        return
    for r, d in zip(results, dicts):
        _print_fit(r, d)
    if len(dicts) > 1:
        s = _multi_summary(dicts, scheme)
        click.echo(f"\nall {len(dicts)} samples: mean ΔE*ab {s['mean_delta_E_ab']:.2f}, "
                   f"mean ΔE2000 {s['mean_delta_E_00']:.2f}, grade {s['grade']} ({scheme})")
    if paths:
        click.echo(f"report written to {report_dir}")


def _with_process(d: dict, proc) -> dict:
    """A fit's dict with the voltage from the process's growth law and the profile named."""
    v = proc.voltage_V(d["thickness_nm"])
    d["voltage_V"] = None if v is None else float(v)
    d["nm_per_V"] = proc.nm_per_V
    d["process"] = proc.metadata()
    d["grade"] = _grade(d, d["scheme"])
    return d


def _grade(d: dict, scheme: str) -> str:
    """The scheme's grade of a mean colour difference, taken in the metric the scheme bounds."""
    from swatch.tolerance import grade_for, grade_metric

    return grade_for(d["mean_delta_E_ab" if grade_metric(scheme) == "dEab" else "mean_delta_E_00"], scheme)


def _multi_summary(dicts: list[dict], scheme: str) -> dict:
    out = {
        "samples": dicts,
        "mean_delta_E_ab": float(np.mean([d["mean_delta_E_ab"] for d in dicts])),
        "mean_delta_E_00": float(np.mean([d["mean_delta_E_00"] for d in dicts])),
        "scheme": scheme,
    }
    out["grade"] = _grade(out, scheme)
    return out


def _fmt(x, spec=".2f", none="—"):
    return none if x is None else format(x, spec)


def _print_fit(r, d: dict) -> None:
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
    click.echo(head)
    click.echo(f"# {d['film']} on {d['substrate']}; intensity: {d['scale_mode']}; {d['illuminant']}, "
               f"{d['observer']}° observer")
    unc = f" ± {d['uncertainty_nm']:.2f}" if d["uncertainty_nm"] is not None else ""
    volts = ("no growth rate" if d["voltage_V"] is None
             else f"≈ {d['voltage_V']:.1f} V at {d['nm_per_V']:.3g} nm/V + {d['process']['offset_nm']:g} nm")
    click.echo(f"thickness      {d['thickness_nm']:.2f}{unc} nm   ({volts}; process {d['process']['process']})")
    unit = "mean squared error" if d["kind"] == "spectral" else "mean squared ΔE2000"
    click.echo(f"residual       {d['residual']:.4g} ({unit})")
    if d["second_best_thickness_nm"] is not None:
        click.echo(f"second best    {d['second_best_thickness_nm']:.2f} nm (residual {d['second_best_residual']:.4g})")
    else:
        click.echo("second best    none (one minimum in the range)")
    click.echo(f"mean ΔE*ab     {d['mean_delta_E_ab']:.2f}   mean ΔE2000 {d['mean_delta_E_00']:.2f}   "
               f"max ΔE*ab {d['max_delta_E_ab']:.2f}   grade {d['grade']} ({d['scheme']})")
    click.echo(f"{'light':>6} {'view':>6} {'az_l':>6} {'az_v':>6}  {'L*':>6} {'a*':>6} {'b*':>6}  "
               f"{'L*sim':>6} {'a*sim':>6} {'b*sim':>6}  {'dE_ab':>6} {'dE_00':>6}")
    for g in d["geometries"]:
        Lm, Ls = g["Lab_measured"], g["Lab_simulated"]
        mark = "  (mirror region, left out)" if g["excluded"] else ""
        click.echo(f"{g['light_deg']:6.1f} {g['view_deg']:6.1f} {g['light_azimuth_deg']:6.1f} {g['view_azimuth_deg']:6.1f}  "
                   f"{Lm[0]:6.2f} {Lm[1]:6.2f} {Lm[2]:6.2f}  {Ls[0]:6.2f} {Ls[1]:6.2f} {Ls[2]:6.2f}  "
                   f"{g['delta_E_ab']:6.2f} {g['delta_E_00']:6.2f}{mark}")


# -- report -----------------------------------------------------------------------------------------
def _report_paths(report_dir, measurements) -> dict:
    out = Path(report_dir)
    if len(measurements) == 1:
        maps = [(out / "delta_e_map.png", out / "delta_e_map.exr")]
    else:
        used, maps = set(), []
        for p in measurements:
            stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in Path(p).stem)
            name, k = stem, 1
            while name.lower() in used:  # unique even against a file already named x_2
                k += 1
                name = f"{stem}_{k}"
            used.add(name.lower())
            maps.append((out / f"delta_e_map_{name}.png", out / f"delta_e_map_{name}.exr"))
    return {
        "maps": maps,
        "summary_csv": out / "summary.csv",
        "summary_md": out / "summary.md",
        "geometries_csv": out / "geometries.csv",
    }


def _colormap(t: np.ndarray) -> np.ndarray:
    """Viridis-like colours (..., 3) uint8 for t in [0, 1]."""
    t = np.clip(np.asarray(t, dtype=np.float64), 0.0, 1.0) * (len(_VIRIDIS) - 1)
    i = np.minimum(np.floor(t).astype(int), len(_VIRIDIS) - 2)
    f = (t - i)[..., None]
    return np.round(_VIRIDIS[i] * (1 - f) + _VIRIDIS[i + 1] * f).astype(np.uint8)


def _nice_max(x: float) -> float:
    x = max(float(x), 1.0)
    k = 10.0 ** math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * k >= x - 1e-12:
            return m * k
    return 10.0 * k


def render_delta_e_map(result, title: str) -> tuple[np.ndarray, dict]:
    """The light × view ΔE*ab map (uint8 RGB image) with labels and a colour scale; and its data.

    Labels are ASCII ("dE*ab", "deg"): the font shipped with OpenImageIO has no Greek letters.
    """""
    import OpenImageIO as oiio

    from swatch.fitting import delta_e_grid
    from swatch.imageio import drawable_text, font_path

    lv, vv, grid, excluded, signed = delta_e_grid(result, "delta_E_ab")
    nL, nV = grid.shape
    cell = int(np.clip(640 // max(nL, nV), 12, 56))
    ml, mt, mb = 84, 88, 64
    bar_gap, bar_w, bar_lab = 28, 22, 64
    W = ml + nV * cell + bar_gap + bar_w + bar_lab
    H = max(mt + nL * cell + mb, 360)
    img = np.full((H, W, 3), 255, dtype=np.uint8)
    finite = grid[np.isfinite(grid)]
    used_vals = result.delta_E_ab[result.used]
    vmax = _nice_max(used_vals.max() if used_vals.size else (finite.max() if finite.size else 1.0))
    colours = _colormap(np.where(np.isfinite(grid), grid, 0.0) / vmax)
    texts = []  # (x, y, text, size, colour, align, valign)
    for i in range(nL):
        y0 = mt + i * cell
        for j in range(nV):
            x0 = ml + j * cell
            if not np.isfinite(grid[i, j]):
                img[y0:y0 + cell, x0:x0 + cell] = 228
                continue
            img[y0:y0 + cell, x0:x0 + cell] = colours[i, j]
            if excluded[i, j]:  # mirror region: black outline
                t = max(2, cell // 14)
                img[y0:y0 + t, x0:x0 + cell] = 0
                img[y0 + cell - t:y0 + cell, x0:x0 + cell] = 0
                img[y0:y0 + cell, x0:x0 + t] = 0
                img[y0:y0 + cell, x0 + cell - t:x0 + cell] = 0
            if cell >= 34:
                lum = colours[i, j] @ np.array([0.2126, 0.7152, 0.0722])
                col = (1, 1, 1) if lum < 140 else (0, 0, 0)
                texts.append((x0 + cell // 2, y0 + cell // 2, f"{grid[i, j]:.1f}", max(10, cell // 4), col, "center", "center"))
    # grid lines between cells
    for j in range(nV + 1):
        x = ml + j * cell
        img[mt:mt + nL * cell, min(x, W - 1)] = 255
    for i in range(nL + 1):
        y = mt + i * cell
        img[min(y, H - 1), ml:ml + nV * cell] = 255
    every_v = max(1, int(math.ceil(28 / cell)))
    every_l = max(1, int(math.ceil(16 / cell)))
    for j in range(0, nV, every_v):
        texts.append((ml + j * cell + cell // 2, mt + nL * cell + 6, f"{vv[j]:g}", 12, (0, 0, 0), "center", "top"))
    for i in range(0, nL, every_l):
        texts.append((ml - 8, mt + i * cell + cell // 2, f"{lv[i]:g}", 12, (0, 0, 0), "right", "center"))
    view_title = "view angle (deg; negative: light's side)" if signed and vv.min() < 0 else "view angle (deg)"
    texts.append((ml + nV * cell // 2, mt + nL * cell + 30, view_title, 14, (0, 0, 0), "center", "top"))
    texts.append((8, mt - 10, "light (deg)", 14, (0, 0, 0), "left", "bottom"))
    texts.append((8, 8, title, 16, (0, 0, 0), "left", "top"))
    texts.append((8, 32, f"mean dE*ab {result.mean_delta_E_ab:.2f} (grade {result.grade} of {result.scheme}); "
                  f"outlined: mirror region (within {result.exclude_mirror_deg:g} deg), left out of the mean",
                  12, (0, 0, 0), "left", "top"))
    # colour bar
    bx = ml + nV * cell + bar_gap
    bh = max(nL * cell, 200)
    ys = np.arange(bh)
    img[mt:mt + bh, bx:bx + bar_w] = _colormap(1.0 - ys / max(bh - 1, 1))[:, None, :]
    for k in range(6):
        v = vmax * k / 5
        y = mt + int(round((1 - k / 5) * (bh - 1)))
        img[y, bx + bar_w:bx + bar_w + 5] = 0
        texts.append((bx + bar_w + 8, y, f"{v:g}", 12, (0, 0, 0), "left", "center"))
    texts.append((bx, mt - 10, "dE*ab", 12, (0, 0, 0), "left", "bottom"))

    buf = oiio.ImageBuf(oiio.ImageSpec(W, H, 3, "float"))
    buf.set_pixels(oiio.ROI(0, W, 0, H), img.astype(np.float32) / 255.0)
    font = font_path("DroidSans")
    for x, y, text, size, col, align, valign in texts:
        if not oiio.ImageBufAlgo.render_text(buf, int(x), int(y), drawable_text(text), int(size), font, col, align,
                                             valign):
            raise SwatchError(f"cannot draw text on the ΔE map: {buf.geterror()}")
    out = np.clip(np.round(buf.get_pixels(oiio.FLOAT).reshape(H, W, 3) * 255.0), 0, 255).astype(np.uint8)
    data = {"light_deg": lv, "view_deg": vv, "grid": grid, "excluded": excluded, "signed": signed, "vmax": vmax}
    return out, data


def _write_report(results, dicts, paths) -> None:
    from swatch.fileio import atomic_write_text
    from swatch.imageio import write_exr, write_png

    for r, d, (png, exr) in zip(results, dicts, paths["maps"]):
        stem = Path(r.source).name
        title = f"dE*ab (CIE 1976)  {stem}   d = {r.thickness_nm:.1f} nm"
        image, data = render_delta_e_map(r, title)
        meta = {
            "source": stem, "thickness_nm": float(r.thickness_nm), "mean_delta_E_ab": float(r.mean_delta_E_ab),
            "grade": r.grade, "light_deg": data["light_deg"].tolist(), "view_deg": data["view_deg"].tolist(),
            "view_signed": bool(data["signed"]), "exclude_mirror_deg": float(r.exclude_mirror_deg),
        }
        write_png(png, image, metadata=meta)
        # EXR: the data themselves, one pixel per (light, view) cell; rows = light, columns = view.
        from swatch.fitting import delta_e_grid

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
        s = _multi_summary(dicts, dicts[0]["scheme"])
        w.writerow(["mean", "", "", "", "", "", "", cell(s["mean_delta_E_ab"]), cell(s["mean_delta_E_00"]), "",
                    s["grade"], "", ""])
    atomic_write_text(paths["summary_csv"], buf.getvalue())

    md = ["# Thickness fit and colour difference (cf. Fujii et al., Tables 2 and 3)", "",
          f"Intensity correction: {dicts[0]['scale_mode']}; mirror region (view within "
          f"{dicts[0]['exclude_mirror_deg']:g}° of the mirror direction) left out of the means; "
          f"{dicts[0]['illuminant']}, {dicts[0]['observer']}° observer; grades: {dicts[0]['scheme']}.", "",
          "| sample | thickness (nm) | ± (nm) | voltage (V) | 2nd minimum (nm) | mean ΔE*ab | mean ΔE2000 | max ΔE*ab | grade | geometries used |",
          "|---|---:|---:|---:|---:|---:|---:|---:|:---:|---:|"]
    for d in dicts:
        md.append(f"| {Path(d['source']).name} | {d['thickness_nm']:.1f} | {_fmt(d['uncertainty_nm'], '.2f')} | "
                  f"{_fmt(d['voltage_V'], '.1f')} | {_fmt(d['second_best_thickness_nm'], '.1f')} | {d['mean_delta_E_ab']:.2f} | "
                  f"{d['mean_delta_E_00']:.2f} | {d['max_delta_E_ab']:.2f} | {d['grade']} | {d['n_used']}/{d['n_geometries']} |")
    if len(dicts) > 1:
        s = _multi_summary(dicts, dicts[0]["scheme"])
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


# -- match ------------------------------------------------------------------------------------------
@click.command()
@click.option("--lab", "lab", default=None, help="target CIELAB L,a,b (under --illuminant/--observer)")
@click.option("--hex", "hex_code", default=None, help="target sRGB colour RRGGBB")
@geometry_options
@material_options
@colour_options
@grid_option
@click.option("--range", "thickness_range", default="0:400", show_default=True, help="thickness range A:B in nm")
@click.option("--step", type=float, default=0.1, show_default=True, help="search step in nm")
@click.option("--top", type=int, default=5, show_default=True, help="number of candidates")
@click.option("--grade", default="C", show_default=True,
              help="tolerance grade a candidate must meet, judged in the scheme's metric (CSAJ: ΔE*ab)")
@click.option("--scheme", default="csaj", show_default=True, help="tolerance scheme")
@click.option("--tolerance", "tolerance", default=None, metavar="METRIC:MAX",
              help="a tolerance as coating specifications write it, e.g. dE00:2.0 or dEab:3.2 (instead of --grade)")
@process_options
@click.option("--match-lightness", is_flag=True,
              help="scale the simulated colour to the target's lightness (compare hue and chroma only)")
@click.option("--json", "as_json", is_flag=True, help="print JSON instead of a table")
def match(lab, hex_code, light, view, light_azimuth, view_azimuth, film, substrate, illuminant, observer,
          wavelengths, thickness_range, step, top, grade, scheme, tolerance, process, nm_per_volt, match_lightness,
          as_json):
    """Thicknesses (and voltages) whose colour matches a target, across interference orders.

    The geometry defaults to the catalog's reference 45°:0° (light at 45°, view along the normal).
    Candidates are ranked by ΔE2000; each says whether it is within the tolerance (--grade of
    --scheme, or --tolerance), judged in the tolerance's own metric.
    """
    from swatch.colorimetry import get_colorimeter, hex_to_Lab
    from swatch.commands.common import resolve_grid
    from swatch.fitting import match_colour
    from swatch.tolerance import get_tolerance, parse_tolerance

    tol = parse_tolerance(tolerance) if tolerance is not None else get_tolerance(scheme, grade)

    if (lab is None) == (hex_code is None):
        raise SwatchError("give exactly one of --lab L,a,b or --hex RRGGBB")
    proc = resolve_process(process, film, substrate, nm_per_volt)
    coating = proc.coating(resolve_grid(wavelengths))
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    if hex_code is not None:  # sRGB is defined on CIE 1931 2° colorimetry: match in it
        cm = cm.display_colorimeter
    target = _parse_lab(lab) if lab is not None else hex_to_Lab(hex_code, cm)
    res = match_colour(target, coating, cm, light, view, light_azimuth, view_azimuth,
                       thickness_range=_parse_pair(thickness_range, "--range"), step_nm=step, top=top,
                       nm_per_V=proc.nm_per_V or DEFAULT_NM_PER_V, grade=grade, scheme=scheme,
                       match_lightness=match_lightness)
    for c in res.candidates:  # voltages by the process's growth law (offset included; None without a rate)
        v = proc.voltage_V(c["thickness_nm"])
        c["voltage_V"] = None if v is None else float(v)
        c["within_grade"] = bool(c["delta_E_ab" if tol.metric == "dEab" else "delta_E_00"] <= tol.max)
    out = res.to_dict()
    out["process"] = proc.metadata()
    out["tolerance"] = tol.to_json()
    if hex_code is not None:
        out["target_hex"] = "#" + hex_code.strip().lstrip("#").lower()
    if as_json:
        echo_json(out)
        return
    L, a, b = res.target_Lab
    src = f" (from {out['target_hex']})" if hex_code is not None else ""
    click.echo(f"# target L*a*b* {L:.2f}, {a:.2f}, {b:.2f}{src}; light {light:g}°, view {view:g}° "
               f"(theta_d {res.theta_d_deg:.2f}°); {cm.illuminant}, {cm.observer}° observer; {coating.film} on {coating.substrate}, "
               f"process {proc.name}")
    click.echo(f"{'rank':>4} {'d_nm':>8} {'volt_V':>7} {'L*':>7} {'a*':>7} {'b*':>7} {'dE00':>6} {'dE_ab':>6}  {tol.label}")
    for k, c in enumerate(res.candidates, start=1):
        Lc, ac, bc = c["Lab"]
        ok = "yes" if c["within_grade"] else "no"
        volts = "" if c["voltage_V"] is None else f"{c['voltage_V']:7.1f}"
        click.echo(f"{k:4d} {c['thickness_nm']:8.2f} {volts:>7} {Lc:7.2f} {ac:7.2f} {bc:7.2f} "
                   f"{c['delta_E_00']:6.2f} {c['delta_E_ab']:6.2f}  {ok}{'  (end of the range)' if c['at_range_bound'] else ''}")
    if not res.any_within_grade:
        click.echo(f"no thickness in {thickness_range} nm comes within {tol.text} at this geometry")
