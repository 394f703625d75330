"""Quality control of measured parts against a finish specification (``swatch check``).

Each sample of a measurement file (CIELAB or spectra, at one or several geometries) is judged at
every geometry it was measured at against the spec's colour there (the reference 45:0 or a
multi-angle geometry; a geometry the spec does not give is refused), in the tolerance's own
metric and under the spec's illuminant and observer (spectra are integrated under them; CIELAB
must have been computed under them). A part passes when every geometry is within the tolerance.

The part's thickness is fitted to its measurement near the nominal (±:data:`FIT_SPAN_NM`, so the
fit stays on the spec's interference order) with no intensity scaling: the spec's colours are the
half-vector model's absolute reflectance factor. The voltage correction is the voltage change that
would grow the nominal thickness instead: ``(nominal − fitted) / nm_per_V`` (positive: raise it).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from swatch.errors import SwatchError
from swatch.fitting import colour_grid, interp_rows
from swatch.instruments import InstrumentFile
from swatch.lab_fit import fit_lab
from swatch.limits import MAX_SPEC_BYTES, read_text_capped
from swatch.measurements import LabMeasurement
from swatch.spectral_fit import fit_spectra
from swatch.spread import ThicknessSpread
from swatch.tolerance import get_tolerance

__all__ = ["load_spec_json", "check_file", "FIT_SPAN_NM", "GEOMETRY_MATCH_DEG"]

#: The thickness fit searches the nominal ± this (nm).
FIT_SPAN_NM = 40.0
#: A measured geometry is the spec's when light and view agree within this (degrees).
GEOMETRY_MATCH_DEG = 0.5


def load_spec_json(path) -> dict:
    """Read and check a spec.json written by ``swatch spec`` (untrusted: capped, keys checked)."""
    text = read_text_capped(Path(path), MAX_SPEC_BYTES, "spec", "JSON", str(path))
    try:
        spec = json.loads(text)
    except (json.JSONDecodeError, RecursionError):
        raise SwatchError(f"{path}: not valid JSON; give the spec.json that swatch spec wrote") from None
    need = ("swatch_spec", "nominal", "colorimetry", "reference", "multi_angle", "tolerance", "process")
    if not isinstance(spec, dict) or any(k not in spec for k in need):
        raise SwatchError(f"{path}: not a swatch spec.json (keys {', '.join(need)} expected)")
    if spec["swatch_spec"] != 1:
        raise SwatchError(f"{path}: spec layout {spec['swatch_spec']!r}; this swatch reads layout 1")
    try:
        tol = spec["tolerance"]
        spec["_tolerance"] = get_tolerance(metric=tol["metric"], max=tol["max"])
        float(spec["nominal"]["thickness_nm"])
        for e in [spec["reference"], *spec["multi_angle"]]:
            float(e["light_deg"]), float(e["view_deg"]), [float(v) for v in e["Lab"]]
            if e["view_side"] not in ("opposite", "light"):
                raise ValueError
    except (KeyError, TypeError, ValueError):
        raise SwatchError(f"{path}: a value of the spec is missing or not a number") from None
    return spec


def _spec_geometries(spec: dict):
    return [spec["reference"], *spec["multi_angle"]]


def _match_geometry(spec, light, view, same_side, source, sample_id) -> dict:
    for e in _spec_geometries(spec):
        side_ok = (e["view_side"] == "light") == bool(same_side) or (float(e["view_deg"]) == 0.0 and view == 0.0)
        if abs(e["light_deg"] - light) <= GEOMETRY_MATCH_DEG and abs(e["view_deg"] - view) <= GEOMETRY_MATCH_DEG \
                and side_ok:
            return e
    names = ", ".join(e["geometry"] for e in _spec_geometries(spec))
    raise SwatchError(f"{source}: sample {sample_id!r} is measured at light {light:g}° view {view:g}°"
                      f"{' (light side)' if same_side else ''}, a geometry the spec does not give ({names})")


def check_file(f: InstrumentFile, spec: dict) -> list[dict]:
    """Judge every sample of ``f`` against ``spec`` (see the module docstring)."""
    from swatch.colorimetry import get_colorimeter

    col, proc, tol = spec["colorimetry"], spec["process"], spec["_tolerance"]
    ill, obs = col["illuminant"], col["observer"]
    d0 = float(spec["nominal"]["thickness_nm"])
    rate = proc.get("nm_per_V")
    lo, hi = max(0.0, d0 - FIT_SPAN_NM), d0 + FIT_SPAN_NM
    spread = ThicknessSpread(float(proc.get("spread_nm", 0.0)), float(proc.get("spread_fraction", 0.0)))
    if f.kind == "colour" and (f.illuminant.upper(), str(f.observer)) != (str(ill).upper(), str(obs)):
        raise SwatchError(f"{f.source}: its CIELAB is under {f.illuminant}/{f.observer}°, the spec's under "
                          f"{ill}/{obs}°; export spectra or CIELAB under the spec's illuminant and observer")
    out = []
    for s in f.samples:
        m = s.measurement
        same = (m.view_azimuth_deg == m.light_azimuth_deg) & (m.view_deg > 0)
        targets = [_match_geometry(spec, float(a), float(b), bool(c), f.source, s.id)
                   for a, b, c in zip(m.light_deg, m.view_deg, same, strict=True)]
        if isinstance(m, LabMeasurement):
            Lab = m.Lab
            fit = fit_lab(m, proc["film"], proc["substrate"], scale="none", exclude_mirror_deg=0.0,
                          thickness_range=(lo, hi), step_nm=0.5, illuminant=ill, observer=obs,
                          film_index_scale=float(proc["film_index_scale"]), spread=spread)
        else:
            wl, interp = colour_grid(m.wavelength_nm)
            R = interp_rows(wl, m.wavelength_nm, m.reflectance) if interp else m.reflectance
            cm = get_colorimeter(wl, ill, obs)
            Lab = cm.Lab(cm.XYZ(R))
            fit = fit_spectra(m, proc["film"], proc["substrate"], scale="none", exclude_mirror_deg=0.0,
                              thickness_range=(lo, hi), step_nm=0.5, illuminant=ill, observer=obs,
                              film_index_scale=float(proc["film_index_scale"]), spread=spread)
        ref = np.array([t["Lab"] for t in targets], dtype=np.float64)
        dE = np.atleast_1d(tol.delta_E(Lab, ref))
        d = float(fit.thickness_nm)
        out.append({
            "id": s.id, "source": f.source,
            "pass": bool(np.all(dE <= tol.max)),
            "delta_E": {t["geometry"]: round(float(e), 3) for t, e in zip(targets, dE, strict=True)},
            "max_delta_E": round(float(dE.max()), 3), "metric": tol.metric,
            "Lab": {t["geometry"]: [round(float(v), 3) for v in lab] for t, lab in zip(targets, Lab, strict=True)},
            "thickness_nm": round(d, 2), "thickness_offset_nm": round(d - d0, 2),
            "voltage_correction_V": None if not rate else round((d0 - d) / float(rate), 2),
        })
    return out
