"""The calibration figure: measured against predicted chips per coupon, and the fitted voltage → colour strip.

Chips are display sRGB (from CIE 1931 2° colorimetry of the spectra when the coupons were
measured as spectra; from the measured CIELAB otherwise, for display only: a Lab value carries
no spectrum). ΔE2000 under each pair is the fit's residual in the measuring geometry,
illuminant and observer; outliers are framed in red.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text, check_creatable_dir, check_new, output_batch
from swatch.core.limits import MAX_THICKNESS_NM, MAX_VOLTAGE_V
from swatch.fit.calibration import Calibration
from swatch.io.drawing import draw_line, draw_rect, draw_text
from swatch.io.imageio import write_png
from swatch.physics.growth import VOLTAGE_DECIMALS, voltage_text
from swatch.physics.process import process_toml

__all__ = ["calibration_figure", "report_figure", "calibration_text", "calibration_paths", "write_calibration"]

PAGE = (246, 246, 244)
INK = (20, 20, 20)
MUTED = (110, 110, 110)
RED = (200, 30, 30)
CHIP = 56
COLS = 8
TILE_W = 2 * CHIP + 14
TILE_H = CHIP + 58
MARGIN = 24
STRIP_H = 60


def _fmt(value, unc, nd: int) -> str:
    return f"{value:.{nd}f}" + ("" if unc is None else f" ± {unc:.{nd}f}")


def _chips(cal: Calibration, model_R, measured_R, cm):
    """Display sRGB (N, 3) uint8 of measured and predicted colours."""
    if measured_R is not None:
        meas, _ = cm.reflectance_display(measured_R)
        pred, _ = cm.reflectance_display(model_R)
    else:
        meas, _ = cm.display(cm.Lab_to_XYZ(cal.Lab_measured))
        pred, _ = cm.display(cm.Lab_to_XYZ(cal.Lab_predicted))
    return (np.round(meas * 255).astype(np.uint8), np.round(pred * 255).astype(np.uint8))


def calibration_figure(cal: Calibration, model_R, measured_R, strip_V, strip_R, cm) -> np.ndarray:
    """The calibration figure: measured against predicted chips per coupon and the voltage → colour strip.

    Parameters
    ----------
    cal : swatch.fit.calibration.Calibration
        The calibration (its coupons' voltages and CIELAB).
    model_R : numpy.ndarray, shape (N, W)
        Predicted reflectance factors of the N coupons.
    measured_R : numpy.ndarray, shape (N, W), or None
        Measured spectra; None for colour (CIELAB) coupons.
    strip_V : numpy.ndarray, shape (K,)
        Voltages of the strip, V.
    strip_R : numpy.ndarray, shape (K, W)
        Their predicted spectra.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        Colorimetry of the chips (display sRGB from CIE 1931 2°).

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, 3)
        The figure as display sRGB, 8 bits per channel; H and W are its height and width in pixels (the
        height grows with the coupon count; not the wavelength count W above).
    """

    n = cal.voltage_V.size
    rows = -(-n // COLS)
    width = 2 * MARGIN + COLS * TILE_W
    top = 116
    strip_top = top + rows * TILE_H + 34
    height = strip_top + STRIP_H + 64
    img = np.empty((height, width, 3), np.uint8)
    img[:] = PAGE
    p, u = cal.process, cal.uncertainty
    inl = ~cal.outlier
    img = draw_text(img, f"Calibration: {p.name}  ({p.film} on {p.substrate})", MARGIN, 32, 22, INK,
                    font="DroidSans-Bold", inplace=True)
    line = (f"thickness = {_fmt(p.offset_nm, u['offset_nm'], 2)} nm + {_fmt(p.nm_per_V, u['nm_per_V'], 4)} nm/V × V"
            + (f" (to {p.knee_V:.1f} V, then {p.nm_per_V_above_knee:.3f} nm/V)" if p.knee_V is not None else "")
            + (f"   ·   spread {100 * p.spread.spread_fraction:.1f} %" if not p.spread.is_zero else "")
            + f"   ·   film index × {_fmt(p.film_index_scale, u['film_index_scale'], 4)}"
            + ("" if u["film_index_scale"] is not None else " (kept)"))
    img = draw_text(img, line, MARGIN, 58, 16, INK, inplace=True)
    line = (f"{n} coupons, {int(cal.outlier.sum())} outlier(s) set aside   ·   mean dE00 "
            f"{cal.delta_E_00[inl].mean():.2f}, max {cal.delta_E_00[inl].max():.2f} (without outliers)   ·   "
            f"light {cal.geometry['light_deg']:g}°, view {cal.geometry['view_deg']:g}°, {cal.illuminant}, "
            f"CIE {cal.observer}° observer")
    img = draw_text(img, line, MARGIN, 80, 14, MUTED, inplace=True)

    meas, pred = _chips(cal, model_R, measured_R, cm)
    order = np.argsort(cal.voltage_V, kind="stable")
    for k, i in enumerate(order):
        x = MARGIN + (k % COLS) * TILE_W
        y = top + (k // COLS) * TILE_H
        img = draw_rect(img, x, y, x + CHIP, y + CHIP, tuple(int(c) for c in meas[i]), inplace=True)
        img = draw_rect(img, x + CHIP, y, x + 2 * CHIP, y + CHIP, tuple(int(c) for c in pred[i]), inplace=True)
        frame = RED if cal.outlier[i] else MUTED
        img = draw_rect(img, x - 1, y - 1, x + 2 * CHIP + 1, y + CHIP + 1, frame, fill=False,
                        width=3 if cal.outlier[i] else 1, inplace=True)
        img = draw_text(img, f"{voltage_text(cal.voltage_V[i])} V · {cal.thickness_nm[i]:.1f} nm", x, y + CHIP + 16, 13, INK, inplace=True)
        tag = "  OUTLIER" if cal.outlier[i] else ""
        img = draw_text(img, f"dE00 {cal.delta_E_00[i]:.2f}{tag}", x, y + CHIP + 32, 13,
                        RED if cal.outlier[i] else INK, inplace=True)
        img = draw_text(img, cal.labels[i][:16], x, y + CHIP + 47, 11, MUTED, inplace=True)
    note = ("each pair: measured (left) | predicted by the fitted profile (right); "
            + ("display sRGB of the spectra (CIE 1931 2°)" if measured_R is not None
               else "display sRGB from the measured CIELAB (display only: a Lab carries no spectrum)"))
    img = draw_text(img, note, MARGIN, top - 10, 12, MUTED, inplace=True)

    # the fitted voltage -> colour strip, with the coupons' measured colours at their voltages
    x0, x1 = MARGIN, width - MARGIN
    img = draw_text(img, "fitted voltage -> colour (half-vector model at the measuring geometry); "
                    "ticks: coupons, measured colour below", x0, strip_top - 10, 13, INK, inplace=True)
    cols, _ = cm.reflectance_display(strip_R)
    cols = np.round(cols * 255).astype(np.uint8)
    xs = np.linspace(x0, x1, strip_V.size + 1).astype(int)
    band = np.repeat(np.arange(strip_V.size), np.diff(xs))
    img[strip_top:strip_top + STRIP_H - 16, x0:x0 + band.size] = cols[band][None, :, :]
    v_lo, v_hi = float(strip_V[0]), float(strip_V[-1])

    def xv(v):
        return round(x0 + (v - v_lo) / (v_hi - v_lo) * (x1 - x0 - 1))

    for i in range(n):
        x = xv(cal.voltage_V[i])
        img = draw_rect(img, x - 4, strip_top + STRIP_H - 14, x + 5, strip_top + STRIP_H - 5,
                        tuple(int(c) for c in meas[i]), inplace=True)
        img = draw_line(img, x, strip_top - 4, x, strip_top, RED if cal.outlier[i] else INK, inplace=True)
    step = 10.0 if v_hi - v_lo <= 150 else 20.0
    for v in np.arange(np.ceil(v_lo / step) * step, v_hi + 1e-9, step):
        x = xv(v)
        img = draw_line(img, x, strip_top + STRIP_H - 2, x, strip_top + STRIP_H + 4, INK, inplace=True)
        img = draw_text(img, f"{v:g} V", x, strip_top + STRIP_H + 20, 12, INK, align="center", inplace=True)
    return img


def report_figure(cal: Calibration) -> np.ndarray:
    """The report figure of a calibration (:func:`calibration_figure` over 0 to 1.1 × the highest voltage, at most
    :data:`swatch.core.limits.MAX_VOLTAGE_V`).

    Parameters
    ----------
    cal : swatch.fit.calibration.Calibration
        A calibration from :func:`swatch.fit.calibration.calibrate` (it carries its colorimeter).

    Returns
    -------
    numpy.ndarray of uint8, shape (H, W, 3)
        The figure as display sRGB, 8 bits per channel (see :func:`calibration_figure`).
    """
    p = cal.process
    assert cal.cm is not None, "calibrate() gives a colorimeter"
    coating = p.coating(cal.cm.wavelength_nm)
    strip_V = np.linspace(0.0, min(1.1 * float(cal.voltage_V.max()), MAX_VOLTAGE_V), 400)  # (coupons at 300 V:
    strip_d = np.clip(p.thickness_nm(strip_V), 0.0, MAX_THICKNESS_NM)  # the strip stops at the voltage cap)
    return calibration_figure(cal, coating.reflectance_cos(cal.thickness_nm, cal.cos_d).R, cal.measured_R,
                              strip_V, coating.reflectance_cos(strip_d, cal.cos_d).R, cal.cm)


def calibration_text(d: dict, base, light: float, view: float) -> list[str]:
    """The lines ``swatch calibrate`` prints.

    The tables, the fitted parameters ± one standard error, what each added parameter bought
    (held-out ΔE2000), what was fixed and why, the ranking of the table pairs, the residual ΔE2000,
    the runner-up order and one line per coupon.

    Parameters
    ----------
    d : dict
        :meth:`swatch.fit.calibration.Calibration.to_dict`.
    base : swatch.physics.process.Process
        The profile the calibration started from (its values are shown beside the fitted ones).
    light, view : float
        The measuring geometry's polar angles, degrees.

    Returns
    -------
    list of str
        The report's lines, without line ends.
    """
    lines = []
    u = d["uncertainty"]

    def pm(key, nd):
        return f"{d[key]:.{nd}f}" + ("" if u.get(key) is None else f" ± {u[key]:.{nd}f}")

    lines.append(f"# {d['process']['process']}: {d['film']} on {d['substrate']} (from {base.name}: {base.film} on "
                 f"{base.substrate}); light {light:g}°, view {view:g}°, {d['illuminant']}, CIE {d['observer']}° observer")
    lines.append(f"nm_per_V          {pm('nm_per_V', 4)}" + ("  (up to the knee)" if "knee_V" in d else ""))
    lines.append(f"offset_nm         {pm('offset_nm', 2)}")
    if "knee_V" in d:
        lines.append(f"knee_V            {pm('knee_V', VOLTAGE_DECIMALS)}")
        lines.append(f"nm_per_V above    {pm('nm_per_V_above_knee', 4)}")
    scale = pm("film_index_scale", 4) + ("" if u["film_index_scale"] is not None else " (kept: not fitted)")
    lines.append(f"film_index_scale  {scale}")
    if "spread_fraction" in d:
        lines.append(f"spread_fraction   {pm('spread_fraction', 4)}  (1σ of the local thickness / thickness)")
    lines.append(f"mean ΔE2000 {d['mean_delta_E_00']:.2f}, max {d['max_delta_E_00']:.2f} over "
                 f"{len(d['samples']) - d['outliers']} coupons; {d['outliers']} outlier(s)"
                 + (f"; held out (leave-one-out) mean {d['held_out_mean_delta_E_00']:.2f}, max "
                    f"{d['held_out_max_delta_E_00']:.2f}" if "held_out_mean_delta_E_00" in d else ""))
    if d.get("steps"):
        lines.append("what each parameter bought (held-out ΔE2000 mean / max, coupons left out one at a time):")
        for st in d["steps"]:
            fig = (f"{st['held_out_mean_delta_E_00']:.2f} / {st['held_out_max_delta_E_00']:.2f}"
                   if "held_out_mean_delta_E_00" in st else "not fitted")
            lines.append(f"  {st['model']:<28} {fig:>14}  " + ("kept" if st["kept"] else f"not kept: {st.get('why', '')}"))
    for key, why in d.get("fixed", {}).items():
        lines.append(f"fixed: {key}: {why}")
    if len(d.get("ranking", [])) > 1:
        lines.append("table pairs, best first (held-out ΔE2000 mean / max; screened out: in-sample mean at a fixed scale):")
        for k, r in enumerate(d["ranking"][:8], start=1):
            fig = (f"{r['held_out_mean_delta_E_00']:.2f} / {r['held_out_max_delta_E_00']:.2f}  {r['model']}"
                   if "held_out_mean_delta_E_00" in r else f"screened out ({r['in_sample_mean_delta_E_00']:.2f})")
            lines.append(f"  {k}. {r['film']} on {r['substrate']}: {fig}")
        if len(d["ranking"]) > 8:
            lines.append(f"  ... {len(d['ranking']) - 8} more (--json lists them)")
    if d["runner_up"]:
        r = d["runner_up"]
        lines.append(f"next-best order: {r['nm_per_V']:g} nm/V + {r['offset_nm']:g} nm "
                     f"(median ΔE2000 {r['mean_delta_E_00']:.2f})")
    lines.append(f"{'coupon':>16} {'voltage_V':>9} {'thickness_nm':>12} {'ΔE2000':>7} {'held out':>8}")
    for s in d["samples"]:
        flag = ""
        if s["outlier"]:
            m = s.get("matches_voltage_V")
            flag = ("  outlier" if m is None else f"  outlier: its colour matches {voltage_text(m)} V on the fitted law "
                    f"(ΔE2000 {s['matches_delta_E_00']:.2f}; mislabelled?)")
        h = s.get("held_out_delta_E_00")
        lines.append(f"{s['coupon'][:16]:>16} {voltage_text(s['voltage_V']):>9} {s['thickness_nm']:12.2f} {s['delta_E_00']:7.2f} "
                     f"{'' if h is None else f'{h:8.2f}':>8}{flag}")
    return lines


def calibration_paths(out_path: str, report_dir: str | None, force: bool):
    """The profile to write and the report figure, checked before the fit.

    Parameters
    ----------
    out_path : str
        The calibrated profile, a ``.toml`` file.
    report_dir : str or None
        The folder of ``calibration.png``, or None for no figure.
    force : bool
        Allow replacing existing files.

    Returns
    -------
    (pathlib.Path, pathlib.Path or None)
        The profile's path and the figure's (or None).

    Raises
    ------
    swatch.core.errors.SwatchError
        A name is empty or not a ``.toml``, a file exists without ``force``, or a folder cannot be created.
    """

    out = Path(out_path)
    if not str(out_path).strip() or out.suffix.lower() != ".toml":
        raise SwatchError(f"`out_path` {out_path!r} must name a .toml file")
    png = Path(report_dir) / "calibration.png" if report_dir is not None else None
    if report_dir is not None and not str(report_dir).strip():
        raise SwatchError("`report_dir` is an empty string; give a folder path")
    check_new([out] + ([png] if png else []), force)
    check_creatable_dir(out.parent)  # (before the fit: created, with its parents, when the profile is written)
    if png is not None:
        check_creatable_dir(png.parent)
    return out, png


def write_calibration(cal: Calibration, out, png, source: str) -> None:
    """Write the calibrated profile (TOML) and, when ``png`` is given, the figure: both or neither.

    Parameters
    ----------
    cal : swatch.fit.calibration.Calibration
        The calibration.
    out : pathlib.Path
        The profile (``.toml``; format docs/processes.md).
    png : pathlib.Path or None
        The figure (its metadata carries the calibration's dict).
    source : str
        The measurement file, named in the profile's header.

    Returns
    -------
    None
    """

    header = f"process profile calibrated by swatch calibrate from {source}; format: docs/processes.md"
    with output_batch(out.parent):  # the profile and its figure, or neither (a full disk, Ctrl-C)
        atomic_write_text(out, process_toml(cal.process, header=header))
        if png is not None:
            with output_batch(png.parent):
                write_png(png, report_figure(cal), {"calibration": cal.to_dict()})
