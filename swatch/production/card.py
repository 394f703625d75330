"""The one-page PDF spec card of ``swatch spec`` (reportlab), from the spec's spec.json document.

reportlab draws the page directly (no HTML engine or system fonts, a pure-Python wheel), and its
``invariant`` mode leaves out the creation date and document id, so a rerun writes the same bytes.
Every number of spec.json is printed on the card exactly as spec.json writes it (``str`` of the
rounded value), so the card and the file can be checked against each other (``pdftotext``), except a
profile's knee voltage, printed to the precision the growth law supports (0.1 V; spec.json keeps it whole).
Every sentence is whole: long ones wrap, none is cut.
"""
from __future__ import annotations

from pathlib import Path

from reportlab.lib.colors import HexColor
from reportlab.lib.pagesizes import A4
from reportlab.pdfgen import canvas

from swatch.colorimetry.geometry import Geometry
from swatch.physics.growth import voltage_text
from swatch.production.finish import FinishSpec
from swatch.production.spec import same_geometry

__all__ = ["write_spec_card", "how_to_measure", "PRINT_NOTE"]

PRINT_NOTE = ("Printed chips cannot show the metallic angle shift (the colour moves with the angles of light and "
              "view) and are not approval standards: approve on a physical sample, measured as below.")
_INK = HexColor("#1a1a1a")
_MUTED = HexColor("#666666")
_RED = HexColor("#c00000")
_AMBER = HexColor("#9a5b00")
_MM = 72.0 / 25.4


def _s(v) -> str:
    """A number as spec.json writes it (json.dumps of the rounded float)."""
    return "—" if v is None else str(v)


def _chip(c, x, y, w, h, hex_code, label):
    c.setFillColor(HexColor(hex_code))
    c.setStrokeColor(_MUTED)
    c.rect(x, y, w, h, fill=1, stroke=1)
    c.setFillColor(_INK)
    c.setFont("Helvetica", 6.5)
    c.drawCentredString(x + w / 2, y - 8, label)


def _wrapped(c, x, y, text: str, size: float, width: float) -> float:
    """Draw ``text`` from (x, y) wrapped to ``width`` points in the current font; returns the next y."""
    font = c._fontname
    words, line = text.split(), ""
    for w in words:
        trial = f"{line} {w}".strip()
        if c.stringWidth(trial, font, size) > width and line:
            c.drawString(x, y, line)
            y -= size + 2.5
            line = w
        else:
            line = trial
    if line:
        c.drawString(x, y, line)
        y -= size + 2.5
    return y


def _stamp(c, x, y, width, reach) -> float:
    """The plain stamp of a colour target out of reach within the tolerance (or accepted deliberately)."""
    accepted = reach["accepted_closest"]
    colour_ = _AMBER if accepted else _RED
    h = 46
    y -= h + 2
    c.setStrokeColor(colour_)
    c.setLineWidth(2.5)
    c.rect(x, y, width, h, fill=0, stroke=1)
    c.setLineWidth(1)
    c.setFillColor(colour_)
    c.setFont("Helvetica-Bold", 16)
    title = ("CLOSEST COLOUR ACCEPTED — TARGET NOT REACHABLE" if accepted
             else "TARGET NOT REACHABLE WITHIN THE TOLERANCE")
    c.drawString(x + 8, y + h - 20, title)
    c.setFont("Helvetica-Bold", 8.5)
    dist = f"{reach['metric']} {_s(reach['delta_E'])}"
    line = (f"The specifier accepted the closest reachable colour deliberately ({dist} from the target); this card "
            "specifies that colour, not the target." if accepted else
            f"This card specifies the closest reachable colour, {dist} from the target, not the target itself. Do not "
            "sign it as the target; change the target or the tolerance, or accept the closest colour deliberately.")
    _wrapped(c, x + 8, y + h - 31, line, 8.5, width - 16)
    c.setFillColor(_INK)
    c.setStrokeColor(_INK)
    return y - 6


def _table_rows(spec: dict) -> tuple[list[dict], list[str]]:
    """The card's geometries once each: the reference first, named with its multi-angle twin (45:0 = 45as45:
    the view along the normal), then the multi-angle set and the other judged angles."""
    def geometry_of(e: dict) -> Geometry:
        return Geometry(str(e["geometry"]), float(e["light_deg"]), float(e["view_deg"]), str(e["view_side"]))

    ref = spec["reference"]
    rows, names = [ref], [str(ref["geometry"])]
    for e in [*spec["multi_angle"], *spec.get("angles", [])]:
        if same_geometry(geometry_of(e), geometry_of(ref)):
            names[0] += f" = {e['geometry']}"
            continue
        rows.append(e)
        names.append(str(e["geometry"]))
    return rows, names


def how_to_measure(spec: dict) -> str:
    """The card's measuring instructions: the instrument, the geometries, what to send back (one paragraph).

    Parameters
    ----------
    spec : dict
        The spec.json dictionary.

    Returns
    -------
    str
        Whole sentences.
    """
    col, tol = spec["colorimetry"], spec["tolerance"]
    aspec = ", ".join(f"{e['aspecular_deg']:g}°" for e in spec["multi_angle"] if e.get("aspecular_deg") is not None)
    extra = [str(e["geometry"]) for e in spec.get("angles", [])]
    also = f" and at {', '.join(extra)}" if extra else ""
    return (f"Instrument: a multi-angle spectrophotometer with illumination at 45° and views at aspecular {aspec} "
            f"(ASTM E2194 / E2539), specular component excluded{also}; a 45/0 instrument gives the reference alone. "
            f"The tolerance is judged at {tol['geometry']}. Measure each part at three places away from edges "
            f"and average them. Send back, per part with its id: the reflectance spectra (380-730 nm or wider) "
            f"at every geometry measured, or CIELAB under {col['illuminant']} and the {col['observer']}° "
            "observer, as a CxF3, CGATS or CSV file. Each geometry is judged in the tolerance's metric against the "
            "table above; swatch check (swatch check FILE --spec spec.json) is one way to judge them.")


def write_spec_card(spec: FinishSpec, path: Path) -> None:
    """Draw the one-page PDF spec card (A4, reportlab, invariant: the same spec gives the same bytes).

    Parameters
    ----------
    spec : swatch.production.finish.FinishSpec
        The spec (:func:`swatch.production.spec.finish_spec`); every number is printed as its spec.json
        document writes it.
    path : pathlib.Path
        The PDF to write (the caller makes it atomic and checks it is new).

    Returns
    -------
    None
    """
    doc = spec.document
    c = canvas.Canvas(str(path), pagesize=A4, invariant=1, pageCompression=1)
    c.setTitle("Finish specification")
    c.setAuthor("swatch (anodic-swatch)")
    W, H = A4
    left, y = 16 * _MM, H - 18 * _MM
    col = doc["colorimetry"]
    nom, pw, tol, proc = doc["nominal"], doc["process_window"], doc["tolerance"], doc["process"]
    tgt = doc["target"]

    c.setFillColor(_INK)
    c.setFont("Helvetica-Bold", 15)
    c.drawString(left, y, "Finish specification — anodised colour")
    c.setFont("Helvetica", 8)
    c.drawRightString(W - left, y, f"spec format {doc['swatch_spec']} · swatch {doc['provenance']['swatch_version']}")
    y -= 16
    c.setFont("Helvetica", 9.5)
    obs = f"{col['illuminant']}, {col['observer']}° observer"
    c.drawString(left, y, f"Every CIELAB on this card: {obs}. Chips: sRGB from CIE 1931 2° colorimetry.")
    y -= 13
    if "Lab" in tgt:
        c.drawString(left, y, f"Target: {tgt['kind']} {tgt.get('value')} = Lab {' '.join(_s(v) for v in tgt['Lab'])} "
                              f"({obs}, {tgt['colorimetry']['geometry']})")
        y -= 11
        if tgt.get("conversion"):
            c.setFont("Helvetica", 7.5)
            y = _wrapped(c, left, y, f"({tgt['conversion']}; docs/processes.md)", 7.5, W - 2 * left) - 1
            c.setFont("Helvetica", 9.5)
    else:
        c.drawString(left, y, f"Target: {tgt['kind']} {tgt.get('value')}")
        y -= 11
    y -= 4
    c.setFont("Helvetica-Bold", 11)
    volts = f" at {_s(nom['voltage_V'])} V" if nom["voltage_V"] is not None else " (no growth rate: thickness only)"
    c.drawString(left, y, f"Nominal oxide thickness {_s(nom['thickness_nm'])} nm{volts}")
    y -= 13
    vb = nom.get("voltage")
    if vb is not None and not vb["calibrated"]:
        c.setFont("Helvetica-Bold", 9)
        c.drawString(left, y, "Voltage not calibrated:")
        c.setFont("Helvetica", 9)
        y = _wrapped(c, left + 104, y, vb["note"] + ".", 9, W - 2 * left - 104)
        y -= 2
    c.setFont("Helvetica", 9)
    reach = doc.get("reach")
    if reach is not None:
        ok = "within" if reach["within_tolerance"] else "NOT within"
        where = reach["colorimetry"]["geometry"]
        y = _wrapped(c, left, y, f"Closest reachable colour: {_s(reach['closest_thickness_nm'])} nm, Lab "
                                 f"{' '.join(_s(v) for v in reach['closest_Lab'])} ({obs}, "
                                 f"{reach.get('closest_Lab_geometry', where)}) — {reach['metric']} "
                                 f"{_s(reach['delta_E'])} from the target "
                                 f"({'worst over ' + where if reach.get('delta_E_per_geometry') else where}), {ok} the "
                                 "tolerance.", 9, W - 2 * left) - 1
        per = reach.get("delta_E_per_geometry")
        if per:
            c.drawString(left, y, f"Worst over the angles the target must hold at — {reach['metric']} "
                                  + ", ".join(f"{n}: {_s(v)}" for n, v in per.items()))
            y -= 12
        if not reach["within_tolerance"]:
            y = _stamp(c, left, y, W - 2 * left, reach)

    # chips: the target's own (a colour target), the nominal's reference (large), the multi-angle row
    y -= 64
    ref = doc["reference"]
    x = left
    if tgt.get("srgb_hex"):
        _chip(c, x, y, 60, 60, tgt["srgb_hex"], "target" + ("" if tgt.get("srgb_in_gamut", True) else " (outside sRGB)"))
        x += 66
    rows, names = _table_rows(doc)
    _chip(c, x, y, 60, 60, ref["srgb_hex"], f"nominal {names[0]}")
    x += 80
    for e, name in zip(rows[1:], names[1:], strict=True):
        _chip(c, x, y + 14, 46, 46, e["srgb_hex"], name)
        x += 52
    y -= 26

    # the multi-angle table
    c.setFont("Helvetica-Bold", 8.5)
    heads = ["geometry", "light °", "view °", "side", "aspec. °", "L*", "a*", "b*", "C*", "h°", "sRGB"]
    xs = [left] + [left + (22.0 + k * 15.5) * _MM for k in range(len(heads) - 1)]  # the first holds two names
    for hx, t in zip(xs, heads, strict=True):
        c.drawString(hx, y, t)
    c.setFont("Helvetica", 8.5)
    for e, name in zip(rows, names, strict=True):
        y -= 11
        cells = [name, _s(e["light_deg"]), _s(e["view_deg"]), e["view_side"], _s(e.get("aspecular_deg")),
                 *(_s(v) for v in e["Lab"]), _s(e["LCh"][1]), _s(e["LCh"][2]), e["srgb_hex"]]
        for hx, t in zip(xs, cells, strict=True):
            c.drawString(hx, y, t)
    y -= 11
    c.setFont("Helvetica", 7.5)
    c.setFillColor(_MUTED)
    c.drawString(left, y, f"L*C*h {' '.join(_s(v) for v in ref['LCh'])} at the reference; CIELAB under {col['illuminant']}, "
                          f"{col['observer']}° observer; {col['model']}; ASTM E2194 / E2539 angles.")
    c.setFillColor(_INK)
    y -= 16
    fl = doc["flop"]
    c.setFont("Helvetica", 9)
    c.drawString(left, y, f"Flop (angle-to-angle ΔE00, light {_s(fl['light_deg'])}°, view {_s(fl['view_a_deg'])}° vs "
                          f"{_s(fl['view_b_deg'])}°): {_s(fl['delta_E_00'])}")
    y -= 13
    every = " (each)" if len(tol.get("geometries", [])) > 1 else ""
    y = _wrapped(c, left, y, f"Tolerance: {tol['label']} (max {_s(tol['max'])}, metric {tol['metric']}) at "
                             f"{tol['geometry']}{every}; a part is judged at every geometry it is measured at.", 9,
                 W - 2 * left) - 2
    vw = (f"; voltage -{_s(pw['voltage_minus_V'])} / +{_s(pw['voltage_plus_V'])} V"
          if pw["voltage_minus_V"] is not None else "")
    per = pw.get("per_geometry", {})
    holds = (" (the colour holds at all of them; each alone: " + ", ".join(
        f"{n} -{_s(w['thickness_minus_nm'])} / +{_s(w['thickness_plus_nm'])} nm" for n, w in per.items()) + ")"
        if every else "")
    y = _wrapped(c, left, y, f"Process window ({pw['metric']} ≤ {_s(pw['max'])} at {pw['geometry']}{holds}): "
                             f"thickness -{_s(pw['thickness_minus_nm'])} / +{_s(pw['thickness_plus_nm'])} nm, i.e. "
                             f"{_s(pw['thickness_min_nm'])} to {_s(pw['thickness_max_nm'])} nm{vw}.", 9, W - 2 * left)
    y -= 5

    c.setFont("Helvetica-Bold", 9.5)
    c.drawString(left, y, "Process profile and provenance")
    c.setFont("Helvetica", 8.5)
    skip = {"process", "process_origin", "film", "substrate"}
    # a voltage as a person reads it (the growth law's precision, swatch.physics.growth.voltage_text)
    more = ", ".join(f"{k} {voltage_text(v) if k == 'knee_V' and v is not None else _s(v)}"
                     for k, v in proc.items() if k not in skip)
    y -= 11
    for line in (f"{proc['process']} ({proc['process_origin']}): {proc['film']} on {proc['substrate']}",
                 more,
                 f"Finish roughness {_s(doc['finish']['roughness'])} (GGX): {doc['finish']['note']}."):
        y = _wrapped(c, left, y, line, 8.5, W - 2 * left)  # a calibrated line's parameters take two lines
    c.setFont("Helvetica", 7)
    c.setFillColor(_MUTED)
    for key, text in doc.get("process_sources", {}).items():  # every source whole, wrapped
        y = _wrapped(c, left, y, f"{key}: {text}", 7, W - 2 * left)
    c.setFillColor(_INK)
    y -= 9
    c.setFont("Helvetica-Bold", 9.5)
    c.drawString(left, y, "How to measure")
    c.setFont("Helvetica", 8.5)
    y -= 11
    y = _wrapped(c, left, y, how_to_measure(doc), 8.5, W - 2 * left) + 11
    y -= 16
    c.setFont("Helvetica-Oblique", 8.5)
    cut = PRINT_NOTE.rfind(" ", 0, 112)
    c.drawString(left, y, PRINT_NOTE[:cut])
    y -= 11
    c.drawString(left, y, PRINT_NOTE[cut + 1:])
    # sign-off box
    y -= 18
    box_h = 26 * _MM
    c.setStrokeColor(_INK)
    c.rect(left, y - box_h, W - 2 * left, box_h)
    c.setFont("Helvetica-Bold", 9)
    c.drawString(left + 6, y - 12, "Sign-off")
    c.setFont("Helvetica", 8.5)
    half = (W - 2 * left) / 2
    for k, who in enumerate(("Specifier (architect / designer)", "Fabricator (finisher)")):
        bx = left + 6 + k * half
        c.drawString(bx, y - 26, who)
        for j, what in enumerate(("Name", "Signature", "Date")):
            c.drawString(bx, y - 42 - 14 * j, f"{what}:")
            c.line(bx + 40, y - 43 - 14 * j, bx + half - 20, y - 43 - 14 * j)
    c.showPage()
    c.save()
