"""The figure of ``swatch check --report`` (check.png): the spec's chip beside each part's own chip.

Rows are parts, columns the geometries that were measured (only those). Each cell is the spec's
colour (left) and the part's (right), both sRGB by CIE 1931 2° colorimetry: the spec's from the
model's spectra, the part's from its measured spectra, or from its CIELAB through the observer
bridge (:func:`swatch.colorimetry.observers.document_Lab_display`); a part colour outside sRGB is
marked with a black corner (the chip shows only the nearest colour sRGB can show). A cell over the
tolerance is framed red. Each row says pass/fail, the worst ΔE and either the voltage advice or
"not a thickness error"; the header states the tolerance, illuminant and observer.
"""
from __future__ import annotations

from PIL import Image, ImageDraw, ImageFont

from swatch.core.limits import MAX_FIGURE_ROWS
from swatch.io.drawing import drawable_text, font_path

__all__ = ["check_figure"]
_INK, _RED, _GREY = (30, 30, 30), (200, 0, 0), (120, 120, 120)


def check_figure(results: list[dict], spec: dict, notes=()) -> Image.Image:
    """Specified vs measured chips per measured geometry (rows: parts), as a PIL image.

    Parameters
    ----------
    results : list of dict
        :func:`swatch.production.qc.check_file`'s entries.
    spec : dict
        The checked spec.
    notes : sequence of str
        Sentences printed under the header (:func:`swatch.production.qc.spec_notes`).

    Returns
    -------
    PIL.Image.Image
        RGB; deterministic for the same inputs.
    """
    entries = [spec["reference"], *spec["multi_angle"]]
    measured = {g for r in results for g in r["Lab"]}
    geoms = [e["geometry"] for e in entries if e["geometry"] in measured]
    spec_hex = {e["geometry"]: e["srgb_hex"] for e in entries}
    rows = results[:MAX_FIGURE_ROWS]
    font = ImageFont.truetype(font_path("DroidSans"), 13)
    bold = ImageFont.truetype(font_path("DroidSans-Bold"), 13)
    small = ImageFont.truetype(font_path("DroidSans"), 11)
    cell, pad, label, advice_w = 48, 8, 170, 470
    width = max(label + len(geoms) * (2 * cell + pad) + advice_w, 900)
    col, tol = spec["colorimetry"], spec["tolerance"]
    nom = spec["nominal"]
    volts = "" if nom.get("voltage_V") is None else f" at {nom['voltage_V']} V"
    lines = [f"swatch check: {len(results)} parts against nominal {nom['thickness_nm']} nm{volts}, "
             f"tolerance {tol['metric']} <= {tol['max']:g} at each measured geometry, required at "
             f"{tol.get('geometry', spec['reference']['geometry'])}",
             f"CIELAB under {col['illuminant']}, {col['observer']}° observer; chips sRGB from CIE 1931 2° "
             "(left: spec, right: the part's own measurement; black corner: outside sRGB)",
             "Advice only where the model at the best-fit thickness explains the part within the tolerance; "
             "none for a part inside the window."]
    for n in notes:  # whole sentences, wrapped to the figure's width
        lines += _wrap(f"Note: {n}.", small, width - 16)
    head = 33 + 17 * len(lines)
    height = head + len(rows) * (cell + pad) + pad + (18 if len(results) > len(rows) else 0)
    img = Image.new("RGB", (width, height), "white")
    dr = ImageDraw.Draw(img)
    for k, t in enumerate(lines):
        dr.text((8, 6 + 17 * k), drawable_text(t), fill=_INK, font=bold if k == 0 else small)
    for j, g in enumerate(geoms):
        dr.text((label + j * (2 * cell + pad), head - 18), g, fill=_INK, font=font)
    x_adv = label + len(geoms) * (2 * cell + pad) + pad
    for i, r in enumerate(rows):
        y = head + i * (cell + pad)
        ok = r["pass"]
        dr.text((6, y + 6), drawable_text(r["id"][:22]), fill=_INK, font=font)
        verdict = "PASS" if ok else ("NOT JUDGED" if r.get("action") == "measure" else "FAIL")
        dr.text((6, y + 24), f"{verdict}  max {r['metric']} {r['max_delta_E']:.2f}", fill=_INK if ok else _RED,
                font=bold)
        for j, g in enumerate(geoms):
            if g not in r["Lab"]:
                continue
            x = label + j * (2 * cell + pad)
            dr.rectangle([x, y, x + cell, y + cell], fill=spec_hex[g])
            dr.rectangle([x + cell, y, x + 2 * cell, y + cell], fill=r["srgb_hex"][g])
            if not r.get("srgb_in_gamut", {}).get(g, True):
                dr.polygon([(x + 2 * cell, y), (x + 2 * cell - 12, y), (x + 2 * cell, y + 12)], fill=(0, 0, 0))
            bad = r["delta_E"][g] > tol["max"]
            dr.rectangle([x, y, x + 2 * cell, y + cell], outline=_RED if bad else _GREY, width=3 if bad else 1)
        fit = (f"best-fit {r['thickness_nm']:.1f} nm ({r['thickness_offset_nm']:+.1f}), residual {r['metric']} "
               f"{r['max_residual_delta_E']:.2f}")
        dr.text((x_adv, y + 6), drawable_text(fit), fill=_INK, font=small)
        what, colour_ = _action_text(r)
        dr.text((x_adv, y + 24), drawable_text(what), fill=colour_, font=bold)
    if len(results) > len(rows):
        dr.text((8, height - 18), f"… {len(results) - len(rows)} more parts in check.json", fill=_INK, font=small)
    return img


def _action_text(r: dict) -> tuple[str, tuple[int, int, int]]:
    """A part's action in a few words for the figure (check.json has the whole sentence), and its colour."""
    action = r.get("action")
    if r["voltage_advice"] is not None:
        return r["voltage_advice"], _INK
    if action == "none":
        return "no action: inside the window", _INK
    if action == "calibrate":
        return "the spec's model, not the part: calibrate the line first", _RED
    if action == "measure":
        return f"not measured at {', '.join(r['unmeasured'])}: measure it there", _RED
    why = r["voltage_correction_reason"] or ""
    short = why.split(":")[0] if why.startswith("not a thickness error") else why[:60]
    return short + " — no voltage advice", _RED


def _wrap(text: str, font, width: float) -> list[str]:
    """``text`` in lines of at most ``width`` pixels in ``font`` (whole words)."""
    lines, line = [], ""
    for word in text.split():
        trial = f"{line} {word}".strip()
        if line and font.getlength(trial) > width:
            lines.append(line)
            line = word
        else:
            line = trial
    return [*lines, line] if line else lines
