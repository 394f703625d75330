"""A finish specification (``swatch spec``): from a target colour or thickness to what a fabricator
must make and how closely — the numbers of ``spec.json`` and of the PDF spec card.

For a target (sRGB hex, CIELAB, thickness or voltage) on a process profile: the nominal
thickness (for a colour target, the best match at the reference geometry over every interference
order, :func:`swatch.fit.matching.match_colour`) and voltage; CIELAB at the reference geometry (45:0)
and at the multi-angle geometries of ASTM E2194 / E2539 (light 45°, aspecular −15°, 15°, 25°,
45°, 75°, 110°); the "flop", ΔE2000 between the view along the normal and the view 60° from it
(light 45°); the tolerance in its own metric and the process window it allows in nm and V
(:func:`swatch.colorimetry.window.process_window`, the catalog's one definition) at every geometry
the tolerance is judged at (``--angles``; by default 45:0), the narrowest side over them; and, when the
target cannot be reached within the tolerance, the closest reachable colour and how far it is.

Colour model: the half-vector model's reflectance factor at each geometry (Fujii et al., no
intensity term), so the numbers do not depend on the finish's roughness; the roughness is
recorded with the spec (it sets the look of renders, not these colours). Every number states its
illuminant, observer and geometry (``colorimetry`` and each entry's ``geometry``). Numbers are
rounded to the precision printed on the card (Lab 0.01, nm 0.1, V 0.1, ΔE 0.01).
"""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import Lab_to_LCh, delta_E_00, get_colorimeter, srgb_hex
from swatch.colorimetry.geometry import DEFAULT_ASPECULAR_DEG, Geometry
from swatch.colorimetry.observers import HEX_CONVENTION, document_Lab_display
from swatch.colorimetry.tolerance import Tolerance
from swatch.colorimetry.window import process_window, window_voltage_V
from swatch.core.errors import SwatchError
from swatch.core.version import __version__
from swatch.fit.matching import match_colour
from swatch.fit.multi_match import match_angles
from swatch.production.finish import FinishSpec

__all__ = ["SPEC_VERSION", "FLOP_VIEWS_DEG", "REFERENCE", "multi_angle_geometries", "judged_geometries", "same_geometry",
           "finish_spec", "voltage_basis", "ROUGHNESS_NOTE"]

#: Version of the spec.json layout (bumped when a key changes meaning).
SPEC_VERSION = 1
#: The flop: light 45°, view along the normal against view 60° from it (across the normal).
FLOP_LIGHT_DEG = 45.0
FLOP_VIEWS_DEG = (0.0, 60.0)
#: The reference geometry (CIE 45/0) and the window's search span.
REFERENCE = Geometry("45:0", 45.0, 0.0, "opposite")
WINDOW_SEARCH_NM = 50.0
#: What the finish's roughness means for the spec's colours, in a fabricator's words.
ROUGHNESS_NOTE = ("the colours are those of the film on the tiny facets of the surface that mirror the light into "
                  "the instrument, so they are the same for a polished, satin or brushed part; the roughness only "
                  "spreads the reflection (a softer, less glossy look)")


def multi_angle_geometries(light_deg: float = 45.0, aspecular_deg=DEFAULT_ASPECULAR_DEG) -> tuple[Geometry, ...]:
    """The multi-angle set of ASTM E2194 / E2539: in plane, view = light − aspecular.

    Parameters
    ----------
    light_deg : float
        Illumination polar angle from the normal, degrees.
    aspecular_deg : sequence of float
        Aspecular angles, degrees (default −15°, 15°, 25°, 45°, 75°, 110°); a view that comes out
        negative lies on the light's side.

    Returns
    -------
    tuple of swatch.colorimetry.geometry.Geometry
        One per aspecular angle, named ``<light>as<aspecular>``.

    Examples
    --------
    >>> [(g.name, g.view_deg, g.view_side) for g in multi_angle_geometries(45.0, (15.0, 110.0))]
    [('45as15', 30.0, 'opposite'), ('45as110', 65.0, 'light')]
    """
    out = []
    for a in aspecular_deg:
        v = light_deg - a
        out.append(Geometry(f"{light_deg:g}as{a:g}", light_deg, abs(v), "opposite" if v >= 0 else "light", a))
    return tuple(out)


def same_geometry(a: Geometry, b: Geometry) -> bool:
    """Whether two in-plane geometries are one: the same light and view angles, on the same side (a view
    along the normal has no side: 45:0 is 45as45).

    Parameters
    ----------
    a, b : swatch.colorimetry.geometry.Geometry
        The geometries.

    Returns
    -------
    bool
        True when light and view agree within 1e-6° and the sides agree (or the view is 0°).

    Examples
    --------
    >>> same_geometry(REFERENCE, multi_angle_geometries(45.0, (45.0,))[0])
    True
    """
    close = abs(a.light_deg - b.light_deg) < 1e-6 and abs(a.view_deg - b.view_deg) < 1e-6
    return close and (a.view_side == b.view_side or abs(a.view_deg) < 1e-6)


def judged_geometries(angles, given: tuple[Geometry, ...]) -> tuple[list[Geometry], list[Geometry], list[str]]:
    """The geometries a spec's tolerance is judged at, and those of them the spec does not list already.

    Parameters
    ----------
    angles : list of (str, float, float) or None
        ``--angles`` as :func:`swatch.fit.multi_match.parse_angles` gives them (name, light_deg, signed
        view_deg; a negative view on the light's side); None: the reference geometry alone.
    given : tuple of swatch.colorimetry.geometry.Geometry
        The geometries the spec lists anyway (the reference and the multi-angle set).

    Returns
    -------
    judged : list of swatch.colorimetry.geometry.Geometry
        One per listed geometry, in order; a listed geometry that is one of ``given`` takes its name
        (``45as45`` is ``45:0``).
    extra : list of swatch.colorimetry.geometry.Geometry
        The judged geometries not among ``given`` (the spec lists them under ``angles``).
    labels : list of str
        Per judged geometry, the name as given and the spec's where they differ (``45:60 = 45as-15``).

    Examples
    --------
    >>> given = (REFERENCE, *multi_angle_geometries())
    >>> [g.name for g in judged_geometries([("45:0", 45.0, 0.0), ("45:60", 45.0, 60.0)], given)[0]]
    ['45:0', '45as-15']
    >>> judged_geometries([("45:0", 45.0, 0.0), ("45:60", 45.0, 60.0)], given)[2]
    ['45:0', '45:60 = 45as-15']
    """
    if not angles:
        return [given[0]], [], [given[0].name]
    judged: list[Geometry] = []
    extra: list[Geometry] = []
    labels: list[str] = []
    for name, light, view in angles:
        g = Geometry(str(name), float(light), abs(float(view)), "light" if view < 0 else "opposite")
        known = next((k for k in (*given, *extra) if same_geometry(k, g)), None)
        if known is None:
            extra.append(g)
            known = g
        if all(j.name != known.name for j in judged):
            judged.append(known)
            labels.append(known.name if known.name == g.name else f"{g.name} = {known.name}")
    return judged, extra, labels


def _r(x, nd: int):
    return None if x is None or not np.isfinite(x) else round(float(x), nd)


def _Lab_at(coating, cm, d: float, geometries) -> tuple[np.ndarray, np.ndarray]:
    R = np.stack([coating.half_vector(np.array([d]), g.light_deg, g.view_deg, 0.0, g.view_azimuth_deg)[0].R[0]
                  for g in geometries])
    return cm.Lab(cm.XYZ(R)), R


def voltage_basis(proc) -> dict:
    """Where the nominal voltage comes from, in words a specifier reads on the card.

    Parameters
    ----------
    proc : swatch.physics.process.Process
        The anodising line's profile (its growth rate, origin and calibration).

    Returns
    -------
    dict
        ``basis``: ``"calibrated"`` (a profile written by ``swatch calibrate`` from the line's coupons),
        ``"given"`` (a growth rate given for this spec), ``"preset"`` (a profile's published rate, not
        the line's), ``"profile"`` (a profile file without a calibration) or None (no growth rate);
        ``calibrated`` (bool) and ``note`` (one sentence for the card and the command's output).
    """
    how = ("calibrate the line from its test coupons (swatch calibrate) and make the spec with the profile it "
           "writes")
    if proc.nm_per_V is None:
        return {"basis": None, "calibrated": False,
                "note": f"process {proc.name} has no growth rate: thickness only, no voltage; {how}"}
    rate = f"{proc.nm_per_V:g} nm/V"
    if "overridden" in proc.origin and "nm_per_V" in proc.origin:
        return {"basis": "given", "calibrated": False,
                "note": f"the nominal voltage uses the growth rate given for this spec ({rate}), not a calibrated "
                        f"line; {how}"}
    if proc.calibration:
        src = dict(proc.calibration).get("source")
        return {"basis": "calibrated", "calibrated": True,
                "note": f"the nominal voltage comes from the line's calibration ({proc.name}"
                        f"{'' if src is None else ', from ' + str(src)}; {rate})"}
    if proc.origin == "preset":
        return {"basis": "preset", "calibrated": False,
                "note": f"the nominal voltage comes from the default preset {proc.name} ({rate}, published for "
                        f"another line), not from your line: {how}"}
    return {"basis": "profile", "calibrated": False,
            "note": f"the nominal voltage comes from the profile {proc.name} ({rate}), which was not calibrated "
                    f"from coupons: {how}"}


def finish_spec(target: dict, proc, tolerance: Tolerance, *, illuminant: str = "D65", observer: str = "10",
                wavelength_nm=None, roughness: float | None = None, thickness_range=(0.0, 400.0),
                angles=None, accept_closest: bool = False) -> FinishSpec:
    """The finish specification for ``target`` on the process profile ``proc``.

    Parameters
    ----------
    target : dict
        ``{"kind": "hex"|"lab", "Lab": [L, a, b], "value": ...}`` (a colour, Lab under
        ``illuminant``/``observer``, the document's; a hex code brought there by
        :func:`swatch.colorimetry.observers.hex_to_document_Lab`) or
        ``{"kind": "thickness"|"voltage", "thickness_nm": d, "value": ...}``.
    proc : swatch.physics.process.Process
        The process profile (growth law, materials, film index scale).
    tolerance : swatch.colorimetry.tolerance.Tolerance
        Judged in its own metric (ΔE*ab or ΔE2000) at every geometry of ``angles`` (default the
        reference geometry): the process window is where the colour holds at all of them.
    roughness : float, optional
        The finish's GGX roughness (recorded; the colours are roughness-independent).
    angles : list of (name, light_deg, signed view_deg), optional
        For a colour target: choose the nominal thickness whose worst difference (in the tolerance's
        metric) over these geometries is smallest (:func:`swatch.fit.multi_match.match_angles`), e.g. a
        colour that must still read the same at a 60° view; default the reference geometry alone. The
        tolerance and the process window are judged at every one of them.
    accept_closest : bool
        For a colour target out of reach within the tolerance: the specifier accepts the closest
        reachable colour deliberately (recorded as ``reach.accepted_closest``, said on the card).

    Returns
    -------
    swatch.production.finish.FinishSpec
        The spec; its ``document`` is spec.json's (stable keys, docs/file-formats.md).
    """
    coating = proc.coating(wavelength_nm)
    cm = get_colorimeter(coating.wavelength_nm, illuminant, observer)
    reach: dict | None = None
    if target["kind"] in ("hex", "lab"):
        target_cm = cm  # one document, one observer: a hex target arrives already in it
        goal = np.asarray(target["Lab"], dtype=np.float64)
        if angles:
            res_a = match_angles(goal, angles, coating, target_cm, tolerance, rank="worst",
                                 thickness_range=thickness_range, top=3)
            best_a = min(res_a["candidates"], key=lambda c: max(g["delta_E"] for g in c["geometries"].values()))
            d = float(best_a["thickness_nm"])
            per = {n: g["delta_E"] for n, g in best_a["geometries"].items()}
            dE = max(per.values())
            reached = np.asarray(best_a["geometries"][angles[0][0]]["Lab"])
            where = ", ".join(n for n, _, _ in angles)
        else:  # among the best ΔE2000 minima of each order, the closest in the tolerance's own metric
            res = match_colour(goal, coating, target_cm, REFERENCE.light_deg, REFERENCE.view_deg,
                               thickness_range=thickness_range, top=3)
            best = min(res.candidates, key=lambda c: float(tolerance.delta_E(np.asarray(c["Lab"]), goal)))
            d = float(best["thickness_nm"])
            reached = np.asarray(best["Lab"])
            dE = float(tolerance.delta_E(reached, goal))
            per, where = None, REFERENCE.name
        within = bool(dE <= tolerance.max)
        reach = {"delta_E": _r(dE, 2), "metric": tolerance.metric, "within_tolerance": within,
                 "accepted_closest": bool(accept_closest and not within),
                 "closest_thickness_nm": _r(d, 1), "closest_Lab": [_r(v, 2) for v in reached],
                 "closest_Lab_geometry": angles[0][0] if angles else REFERENCE.name,
                 "colorimetry": {"illuminant": target_cm.illuminant, "observer": target_cm.observer,
                                 "geometry": where}}
        if per is not None:
            reach["delta_E_per_geometry"] = {n: _r(v, 2) for n, v in per.items()}
    else:
        d = float(target["thickness_nm"])
    if not 0 <= d <= 1000:
        raise SwatchError(f"nominal thickness {d:g} nm is outside 0–1000 nm")
    volts = proc.voltage_V(np.array([d]))
    v_nom = None if volts is None else float(volts[0])
    multi = multi_angle_geometries()
    judged, extra, labels = judged_geometries(angles, (REFERENCE, *multi))
    geoms = (REFERENCE, *multi, *extra)
    Lab, R = _Lab_at(coating, cm, d, geoms)
    LCh = Lab_to_LCh(Lab)
    disp = cm.display_colorimeter
    hexes = [str(h) for h in np.atleast_1d(srgb_hex(cm.reflectance_display(R, "srgb")[0]))]
    flop_g = [Geometry(f"45:{v:g}", FLOP_LIGHT_DEG, v, "opposite") for v in FLOP_VIEWS_DEG]
    Lab_f, _ = _Lab_at(coating, cm, d, flop_g)
    flop = float(delta_E_00(Lab_f[0], Lab_f[1]))
    # the process window holds the colour at every judged geometry: the narrowest side over them
    per_window = {g.name: process_window(coating, cm, np.array([d]), g, tolerance.max, WINDOW_SEARCH_NM,
                                         tolerance.metric) for g in judged}
    lows = [w[0][0] for w in per_window.values()]
    highs = [w[1][0] for w in per_window.values()]
    i_lo, i_hi = int(np.argmin(lows)), int(np.argmin(highs))
    walls = list(per_window.values())
    minus, plus = np.array([lows[i_lo]]), np.array([highs[i_hi]])
    mcap, pcap = walls[i_lo][2], walls[i_hi][3]
    window_V = window_voltage_V(proc.voltage_V, np.array([d]), minus, plus)
    names = [g.name for g in judged]
    where_judged = ", ".join(labels)

    def entry(i, g):
        e = {"geometry": g.name, "light_deg": g.light_deg, "view_deg": g.view_deg, "view_side": g.view_side,
             "Lab": [_r(v, 2) for v in Lab[i]], "LCh": [_r(v, 2) for v in LCh[i]], "srgb_hex": hexes[i]}
        if g.aspecular_deg is not None:
            e["aspecular_deg"] = g.aspecular_deg
        return e

    target_out = {k: v for k, v in target.items() if k != "Lab"}
    if "Lab" in target:
        target_out["Lab"] = [_r(v, 2) for v in target["Lab"]]
        target_out["colorimetry"] = {"illuminant": cm.illuminant, "observer": cm.observer, "geometry": REFERENCE.name}
        if target["kind"] == "hex":  # the chip is the hex itself; its Lab came through the observer bridge
            target_out.update(srgb_hex=str(target["value"]), srgb_in_gamut=True, conversion=HEX_CONVENTION)
        else:
            enc, ok = document_Lab_display(np.asarray(target["Lab"], dtype=np.float64), cm)
            target_out.update(srgb_hex=str(srgb_hex(enc)), srgb_in_gamut=bool(ok))
    n_given = 1 + len(multi)
    document = {
        "swatch_spec": SPEC_VERSION,
        "target": target_out,
        "nominal": {"thickness_nm": _r(d, 1), "voltage_V": _r(v_nom, 1), "voltage": voltage_basis(proc)},
        "reach": reach,
        "colorimetry": {"illuminant": cm.illuminant, "observer": cm.observer,
                        "srgb_observer": disp.observer, "model": "half-vector reflectance factor (Fujii et al. 2019)"},
        "reference": entry(0, REFERENCE),
        "multi_angle": [entry(i + 1, g) for i, g in enumerate(multi)],
        # the --angles geometries that are neither the reference nor a multi-angle one (45:60, say)
        "angles": [entry(n_given + i, g) for i, g in enumerate(extra)],
        "flop": {"geometry": f"{FLOP_LIGHT_DEG:g}:{FLOP_VIEWS_DEG[0]:g} vs {FLOP_LIGHT_DEG:g}:{FLOP_VIEWS_DEG[1]:g}",
                 "light_deg": FLOP_LIGHT_DEG, "view_a_deg": FLOP_VIEWS_DEG[0], "view_b_deg": FLOP_VIEWS_DEG[1],
                 "delta_E_00": _r(flop, 2)},
        "tolerance": {**tolerance.to_json(), "label": tolerance.text, "geometry": where_judged, "geometries": names},
        "process_window": {
            "metric": tolerance.metric, "max": tolerance.max, "geometry": where_judged, "geometries": names,
            "thickness_minus_nm": _r(minus[0], 1), "thickness_plus_nm": _r(plus[0], 1),
            # from the rounded numbers the card prints, so that nominal − minus = min on paper too
            "thickness_min_nm": _r(_r(d, 1) - _r(minus[0], 1), 1), "thickness_max_nm": _r(_r(d, 1) + _r(plus[0], 1), 1),
            # through the growth law (one or two slopes): the voltage steps to the window's edges
            "voltage_minus_V": None if window_V is None else _r(float(window_V[0][0]), 1),
            "voltage_plus_V": None if window_V is None else _r(float(window_V[1][0]), 1),
            "minus_capped": bool(mcap[0]), "plus_capped": bool(pcap[0]),
            # each judged geometry's own window; the window above is the narrowest side over them
            "per_geometry": {n: {"thickness_minus_nm": _r(w[0][0], 1), "thickness_plus_nm": _r(w[1][0], 1)}
                             for n, w in per_window.items()},
        },
        "process": proc.metadata(),
        # whether the optical model (tables, index scale, spread) was calibrated from the line's coupons
        "calibrated_model": bool(proc.calibration),
        "process_sources": {str(k): str(v) for k, v in proc.sources},
        "finish": {"roughness": None if roughness is None else float(roughness), "note": ROUGHNESS_NOTE},
        "provenance": {"swatch_version": __version__},
    }
    return FinishSpec.from_json(document, "the spec")
