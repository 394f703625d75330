"""Quality control of measured parts against a finish specification (``swatch check``).

Each sample of a measurement file (CIELAB or spectra, at one or several geometries) is judged at
every geometry it was measured at against the spec's colour there (the reference 45:0 or a
multi-angle geometry; a geometry the spec does not give is refused), in the tolerance's own
metric and under the spec's illuminant and observer (spectra are integrated under them; CIELAB
must have been computed under them). A part passes when every geometry is within the tolerance.

The part's thickness is fitted to its CIELAB at the measured geometries (spectra integrated first)
by least squares in ΔE2000 near the nominal (±:data:`FIT_SPAN_NM`, so the fit stays on the spec's
interference order), with no intensity scaling: the spec's colours are the half-vector model's
absolute reflectance factor. The fit is vectorised over the parts of a file (one thickness
table). The voltage correction is the voltage change that would grow the nominal thickness
instead: ``V(nominal) − V(fitted)`` by the spec's growth law (one or two slopes; positive: raise it).

A part passes when it is within the tolerance at every geometry it was measured at and was measured
at every geometry the spec's tolerance is judged at (``tolerance.geometries``: 45:0, or every
``--angles`` geometry). What the finisher is told to do (``action``: no action inside the window, a
correction only for a failing part or one near the window's edge, none where no thickness explains the
part, "calibrate first" where an uncalibrated spec's model is the suspect) follows the rules of
:mod:`swatch.production.advice`; ``voltage_correction_V`` is None with ``voltage_correction_reason``
wherever no correction is advised.

The part's chip is its own colour: its spectra by CIE 1931 2° colorimetry, or its CIELAB through the
observer bridge (:func:`swatch.colorimetry.observers.document_Lab_display`), out-of-gamut marked.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter, srgb_hex
from swatch.colorimetry.observers import LAB_CHIP_CONVENTION, document_Lab_display
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_SPEC_BYTES, read_text_capped
from swatch.fit.fitting import sweep_reflectance, unique_geometry
from swatch.fit.result import colour_grid, interp_rows
from swatch.io.instruments import InstrumentFile
from swatch.io.measurements import LabMeasurement, SpectralMeasurement
from swatch.physics import geometry
from swatch.physics.growth import thickness_to_voltage_V
from swatch.physics.materials import table_pairs, wavelength_grid
from swatch.physics.model import get_coating
from swatch.physics.spread import ThicknessSpread
from swatch.production.advice import OtherModel, calibrate_first, near_edge, not_a_thickness_error, voltage_advice
from swatch.production.finish import FinishSpec, SpecGeometry

__all__ = ["load_spec_json", "check_file", "fit_thickness_Lab", "other_models",
           "FIT_SPAN_NM", "SCREEN_STEP_NM", "GEOMETRY_MATCH_DEG"]

#: The thickness fit searches the nominal ± this (nm).
FIT_SPAN_NM = 40.0
#: The thickness fit's grids (nm): the table's step and the step of the first search over it.
FINE_STEP_NM = 0.01
COARSE_STEP_NM = 0.25
#: ΔE2000 evaluations per chunk of the thickness fit (parts × table rows × geometries): colour-science's
#: CIEDE2000 makes a few dozen temporaries of that size; ~100k keeps them in the CPU cache and out of fresh
#: pages (10,000 parts at one geometry: 4.7 CPU-s in one piece, 1.3 in chunks, the same result bit for bit).
_CHUNK_ELEMENTS = 1 << 17
#: The thickness grid of the screen over the other shipped optical models, nm (its first search's step is
#: five of these): a tenth of a nanometre moves a blue's colour by ΔE2000 ≈ 0.1, below any tolerance.
SCREEN_STEP_NM = 0.1
#: A measured geometry is the spec's when light and view agree within this (degrees).
GEOMETRY_MATCH_DEG = 0.5


def load_spec_json(path) -> FinishSpec:
    """Read and check a spec.json written by ``swatch spec`` (untrusted: size-capped, keys checked).

    Parameters
    ----------
    path : str or path-like
        The spec.json file (at most :data:`swatch.core.limits.MAX_SPEC_BYTES`).

    Returns
    -------
    swatch.production.finish.FinishSpec
        The spec, checked by :meth:`swatch.production.finish.FinishSpec.from_json`.

    Raises
    ------
    swatch.core.errors.SwatchError
        The file is too big, not UTF-8, not JSON, or not a spec of layout 1 (one line: what and where).
    """
    text = read_text_capped(Path(path), MAX_SPEC_BYTES, "spec", "JSON", str(path))
    try:
        document = json.loads(text)
    except (json.JSONDecodeError, RecursionError):
        raise SwatchError(f"{path}: not valid JSON; give the spec.json that swatch spec wrote") from None
    return FinishSpec.from_json(document, str(path))


def _match_geometry(spec: FinishSpec, light, view, same_side, source, sample_id) -> SpecGeometry:
    for g in spec.geometries:
        side_ok = (g.view_side == "light") == bool(same_side) or (g.view_deg == 0.0 and view == 0.0)
        if abs(g.light_deg - light) <= GEOMETRY_MATCH_DEG and abs(g.view_deg - view) <= GEOMETRY_MATCH_DEG \
                and side_ok:
            return g
    names = ", ".join(g.name for g in spec.geometries)
    raise SwatchError(f"{source}: sample {sample_id!r} is measured at light {light:g}° view {view:g}°"
                      f"{' (light side)' if same_side else ''}, a geometry the spec does not give ({names})")


def fit_thickness_Lab(Lab_meas: np.ndarray, light_deg, view_deg, same_side, coating, cm, lo: float,
                      hi: float, step_nm: float = FINE_STEP_NM) -> tuple[np.ndarray, np.ndarray]:
    """Fit the oxide thickness of P parts to their CIELAB at G geometries (least squares in ΔE2000).

    One thickness → CIELAB table every ``step_nm`` on [``lo``, ``hi``] (one sweep for all parts),
    searched every :data:`COARSE_STEP_NM` (or five steps, if coarser), then finely within one coarse step
    of each part's minimum. Vectorised over parts; no intensity scaling (the half-vector model's absolute reflectance factor).

    Parameters
    ----------
    Lab_meas : numpy.ndarray, shape (P, G, 3)
        Measured CIELAB under the colorimeter's illuminant and observer.
    light_deg, view_deg : array_like, shape (G,)
        Polar angles of light and view from the normal, degrees.
    same_side : array_like of bool, shape (G,)
        The view is on the light's side (azimuth 0°) rather than across the normal (180°).
    coating : swatch.physics.model.Coating
        Film, substrate and wavelength grid.
    cm : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of ``Lab_meas`` on the coating's grid.
    lo, hi : float
        The thickness interval searched, nm.
    step_nm : float
        The table's step, nm (default :data:`FINE_STEP_NM`).

    Returns
    -------
    thickness_nm : numpy.ndarray, shape (P,)
        Fitted thickness of each part, nm (to ``step_nm``).
    model_Lab : numpy.ndarray, shape (P, G, 3)
        The model's CIELAB at each part's fitted thickness and measured geometries (under ``cm``).
    """
    cos_d = np.atleast_1d(geometry.cos_theta_d(light_deg, view_deg, 0.0, np.where(same_side, 0.0, 180.0)))
    cu, inv = unique_geometry(cos_d)
    count = int(np.floor((hi - lo) / step_nm + 1e-9)) + 1
    table = cm.Lab(cm.XYZ(sweep_reflectance(coating, lo, step_nm, count, cu)))[:, inv]  # (K, G, 3)
    every = max(5, round(COARSE_STEP_NM / step_nm))
    coarse = table[::every]  # (Kc, G, 3)
    P = Lab_meas.shape[0]
    k0 = _argmin_delta_E_by_chunks(Lab_meas, lambda a, b: np.broadcast_to(coarse, (b - a, *coarse.shape)),
                                   coarse.shape[0]) * every  # index into the fine table
    idx = np.clip(k0[:, None] + np.arange(-every, every + 1)[None, :], 0, count - 1)  # (P, F)
    best = _argmin_delta_E_by_chunks(Lab_meas, lambda a, b: table[idx[a:b]], idx.shape[1])
    k = idx[np.arange(P), best]
    return lo + step_nm * k, table[k]


def other_models(Lab_meas: np.ndarray, light_deg, view_deg, same_side, coating, cm, lo: float, hi: float,
                 tolerance) -> list[OtherModel | None]:
    """For each part, the other shipped optical model (film × substrate of the same metal) that explains it best.

    Each pair's best-fit thickness on [``lo``, ``hi``] (:func:`fit_thickness_Lab` every
    :data:`SCREEN_STEP_NM`), keeping the spec's film index scale and thickness spread; the residual in the
    tolerance's metric, worst over the measured geometries.

    Parameters
    ----------
    Lab_meas : numpy.ndarray, shape (P, G, 3)
        The parts' CIELAB under ``cm``.
    light_deg, view_deg, same_side : array_like, shape (G,)
        The measured geometries (as :func:`fit_thickness_Lab`).
    coating : swatch.physics.model.Coating
        The spec's model (its tables are left out of the screen; its scale and spread are kept).
    cm : swatch.colorimetry.colorimeter.Colorimeter
        The spec's illuminant and observer on the coating's grid.
    lo, hi : float
        The thickness interval searched, nm.
    tolerance : swatch.colorimetry.tolerance.Tolerance
        Its metric measures the residual.

    Returns
    -------
    list of OtherModel or None
        One per part; None for every part when the metal has no other tables.
    """
    pairs = [p for p in table_pairs(coating.film, coating.substrate) if p != (coating.film, coating.substrate)]
    if not pairs:
        return [None] * Lab_meas.shape[0]
    fits = []
    for film, substrate in pairs:  # one vectorised sweep per pair, over all parts
        other = get_coating(film, substrate, coating.wavelength_nm, coating.film_index_scale, coating.spread)
        d, model = fit_thickness_Lab(Lab_meas, light_deg, view_deg, same_side, other, cm, lo, hi, SCREEN_STEP_NM)
        fits.append((d, np.atleast_2d(tolerance.delta_E(Lab_meas, model)).max(axis=1)))
    d_all = np.stack([f[0] for f in fits])  # (pairs, P)
    res_all = np.stack([f[1] for f in fits])
    best = np.argmin(res_all, axis=0)
    cols = np.arange(Lab_meas.shape[0])
    return [OtherModel(pairs[k][0], pairs[k][1], float(d), float(r))
            for k, d, r in zip(best.tolist(), d_all[best, cols], res_all[best, cols], strict=True)]


def _argmin_delta_E_by_chunks(Lab_meas: np.ndarray, candidates, per_part: int) -> np.ndarray:
    """Each part's candidate of least summed squared ΔE2000 over the geometries, over chunks of parts of
    about :data:`_CHUNK_ELEMENTS` evaluations: ``candidates(a, b)`` gives parts a..b's (b - a, per_part, G, 3)
    CIELAB candidates. Returns the (P,) indices along ``per_part``."""
    P, G = Lab_meas.shape[:2]
    out = np.empty(P, dtype=np.intp)
    step = max(1, _CHUNK_ELEMENTS // (per_part * G))
    for a in range(0, P, step):
        b = min(P, a + step)
        cand = candidates(a, b)
        cost = np.sum(delta_E_00(cand, np.broadcast_to(Lab_meas[a:b, None], cand.shape)) ** 2, axis=-1)
        out[a:b] = np.argmin(cost, axis=1)
    return out


def check_file(f: InstrumentFile, spec: FinishSpec) -> list[dict]:
    """Judge every sample of a measurement file against a spec (see the module docstring).

    Parameters
    ----------
    f : swatch.io.instruments.InstrumentFile
        CIELAB or spectra of P samples, at the same geometries in every sample.
    spec : swatch.production.finish.FinishSpec
        The spec.

    Returns
    -------
    list of dict
        Per sample: ``pass`` (within the tolerance at every measured geometry, and measured at every
        judged one), ``unmeasured`` (the judged geometries the file does not measure), ``delta_E`` and
        ``Lab`` per geometry (in the tolerance's metric, under the spec's illuminant and observer),
        ``delta_Lab`` (measured − specified), the best-fit ``thickness_nm`` and its offset, nm, the
        ``residual_delta_E`` per geometry (the tolerance's metric, part vs the model at that thickness),
        ``thickness_explains`` (the worst residual is within the tolerance and the fit is inside the
        search), ``other_model`` (for a spec whose model is not calibrated and does not explain the part:
        the best other shipped optical model, its thickness and residual), ``action`` (one of
        :data:`swatch.production.advice.ACTIONS`), ``near_edge``, the ``voltage_correction_V`` (V, with
        ``voltage_advice`` in words; None with ``voltage_correction_reason`` wherever no correction is
        advised) and the part's own sRGB chips (CIE 1931 2°, from its spectra, or from its CIELAB by
        :func:`swatch.colorimetry.observers.document_Lab_display`), with ``srgb_in_gamut``.

    Raises
    ------
    swatch.core.errors.SwatchError
        The file's CIELAB is under another illuminant or observer than the spec's, or a sample is
        measured at a geometry the spec does not give.
    """
    model, tol = spec.model, spec.tolerance
    ill, obs = spec.illuminant, spec.observer
    d0 = spec.thickness_nm
    rate = model.nm_per_V
    lo, hi = max(0.0, d0 - FIT_SPAN_NM), d0 + FIT_SPAN_NM
    spread = ThicknessSpread(model.spread_nm, model.spread_fraction)
    coating = get_coating(model.film, model.substrate, wavelength_grid(380.0, 780.0, 5.0), model.film_index_scale,
                          spread)
    cm = get_colorimeter(coating.wavelength_nm, ill, obs)
    if f.kind == "colour" and (f.illuminant.upper(), str(f.observer)) != (str(ill).upper(), str(obs)):
        raise SwatchError(f"{f.source}: its CIELAB is under {f.illuminant}/{f.observer}°, the spec's under "
                          f"{ill}/{obs}°; export spectra or CIELAB under the spec's illuminant and observer")
    m0 = f.samples[0].measurement
    same = (m0.view_azimuth_deg == m0.light_azimuth_deg) & (m0.view_deg > 0)
    targets = [_match_geometry(spec, float(a), float(b), bool(c), f.source, f.samples[0].id)
               for a, b, c in zip(m0.light_deg, m0.view_deg, same, strict=True)]
    measured: list[np.ndarray] = []
    enc_all = np.empty((len(f.samples), len(targets), 3))
    gamut_all = np.empty((len(f.samples), len(targets)), dtype=bool)
    for i, s in enumerate(f.samples):  # same geometries in every sample of a file (instruments.same_geometries)
        m = s.measurement
        if isinstance(m, LabMeasurement):
            measured.append(m.Lab)
        else:
            wl, interp = colour_grid(m.wavelength_nm)
            R = interp_rows(wl, m.wavelength_nm, m.reflectance) if interp else m.reflectance
            mcm = get_colorimeter(wl, ill, obs)
            measured.append(mcm.Lab(mcm.XYZ(R)))
            enc_all[i], gamut_all[i] = mcm.reflectance_display(R, "srgb")
    Lab_all = np.stack(measured)  # (P, G, 3)
    lab_only = np.array([isinstance(s.measurement, LabMeasurement) for s in f.samples])
    if lab_only.any():  # the parts' own CIELAB, all at once
        enc_all[lab_only], gamut_all[lab_only] = document_Lab_display(Lab_all[lab_only], cm)
    hex_all = np.asarray(srgb_hex(enc_all.reshape(-1, 3))).reshape(enc_all.shape[:2])
    d_fit, Lab_model = fit_thickness_Lab(Lab_all, m0.light_deg, m0.view_deg, same, coating, cm, lo, hi)
    residual_all = np.atleast_2d(tol.delta_E(Lab_all, Lab_model))  # (P, G), the tolerance's metric
    ref = np.array([t.Lab for t in targets], dtype=np.float64)
    dE_all = np.atleast_2d(tol.delta_E(Lab_all, np.broadcast_to(ref, Lab_all.shape)))

    def volts(x: float) -> float:  # the spec's growth law (one or two slopes); asked only with a growth rate
        assert rate is not None
        return float(thickness_to_voltage_V(x, rate, model.offset_nm, model.knee_V, model.nm_per_V_above_knee))

    def per_geometry(values, nd: int) -> dict:
        return {t.name: round(float(v), nd) for t, v in zip(targets, values, strict=True)}

    measured_names = {t.name for t in targets}
    unmeasured = [n for n in spec.judged if n not in measured_names]
    calibrated = spec.calibrated_model
    worst_res_all = residual_all.max(axis=1)
    # an uncalibrated spec's model that leaves a part unexplained is screened against the other shipped models
    suspects = np.flatnonzero(worst_res_all > tol.max) if not calibrated else np.array([], dtype=np.intp)
    screened = other_models(Lab_all[suspects], m0.light_deg, m0.view_deg, same, coating, cm, lo, hi, tol) \
        if suspects.size else []
    others = dict(zip(suspects.tolist(), screened, strict=True))

    out = []
    for i, (s, Lab, dE, d, hexes, in_gamut, res) in enumerate(zip(f.samples, Lab_all, dE_all, d_fit, hex_all,
                                                                  gamut_all, residual_all, strict=True)):
        d = float(d)
        worst_res = float(res.max())
        on_edge = (d - lo < 2 * FINE_STEP_NM and lo > 0.0) or hi - d < 2 * FINE_STEP_NM
        explains = worst_res <= tol.max and not on_edge
        within = bool(np.all(dE <= tol.max))
        other = others.get(i)
        edge = within and near_edge(float(dE.max()), tol.max, d - d0, spec.window_minus_nm, spec.window_plus_nm)
        reason: str | None
        if worst_res > tol.max and other is not None and other.residual <= tol.max:
            action, reason = "calibrate", calibrate_first(worst_res, tol.metric, tol.max, other)
        elif worst_res > tol.max:
            action, reason = "investigate", not_a_thickness_error(worst_res, tol.metric, tol.max, d, other)
        elif on_edge:
            action, reason = "investigate", (
                f"not a thickness error near the nominal: the best fit lies on the edge of the search "
                f"(nominal ± {FIT_SPAN_NM:g} nm), another interference order or no thickness at all")
        elif unmeasured:
            action, reason = "measure", (f"not judged at {', '.join(unmeasured)}, where the spec's tolerance "
                                         "holds too: measure the part there before acting on it")
        elif within and not edge:
            action, reason = "none", (f"no action: inside the window (worst {tol.metric} {float(dE.max()):.2f} of "
                                      f"{tol.max:g}, best-fit thickness {d - d0:+.1f} nm from the nominal)")
        else:
            action, reason = ("centre" if within else "correct"), None
        if reason is None and not rate:
            reason = "the process profile has no growth rate: no voltage to correct"
        corr = None if reason is not None else round(float(volts(d0) - volts(d)), 2)
        advice = None if corr is None else voltage_advice(corr)
        if advice is not None and action == "centre":
            advice = f"near the edge of the window: {advice} to centre it"
        out.append({
            "srgb_hex": {t.name: str(h) for t, h in zip(targets, hexes, strict=True)},
            "srgb_in_gamut": {t.name: bool(g) for t, g in zip(targets, in_gamut, strict=True)},
            "srgb_from": "measured spectra (CIE 1931 2°)" if isinstance(s.measurement, SpectralMeasurement)
            else f"measured CIELAB ({ill}, {obs}°): {LAB_CHIP_CONVENTION}",
            "id": s.id, "source": f.source,
            "pass": within and not unmeasured, "unmeasured": unmeasured,
            "delta_E": per_geometry(dE, 3),
            "max_delta_E": round(float(dE.max()), 3), "metric": tol.metric,
            "Lab": {t.name: [round(float(v), 3) for v in lab] for t, lab in zip(targets, Lab, strict=True)},
            # measured − specified: which way the part is off (darker, redder, yellower …) at each geometry
            "delta_Lab": {t.name: [round(float(v), 3) for v in lab - np.asarray(t.Lab)]
                          for t, lab in zip(targets, Lab, strict=True)},
            "thickness_nm": round(d, 2), "thickness_offset_nm": round(d - d0, 2),
            # the part against the model at its best-fit thickness: what no thickness explains
            "residual_delta_E": per_geometry(res, 3), "max_residual_delta_E": round(worst_res, 3),
            "thickness_explains": bool(explains),
            "other_model": None if other is None else {
                "film": other.film, "substrate": other.substrate, "thickness_nm": round(other.thickness_nm, 2),
                "max_residual_delta_E": round(other.residual, 3)},
            "action": action, "near_edge": bool(edge),
            "voltage_correction_V": corr,
            "voltage_advice": advice,
            "voltage_correction_reason": reason,
        })
    return out
