"""A finish specification as production/ works with it: :class:`FinishSpec`.

The spec.json document is the file's form (``swatch spec`` writes it, ``swatch check`` reads it back);
between the two edges production/ carries one checked, typed object: the tolerance with its grade
(:class:`swatch.colorimetry.tolerance.Tolerance`), the geometries and their colours, the nominal
thickness, the process's optical model and growth law, and what the spec says of its calibration and
reach. :meth:`FinishSpec.from_json` checks a document (untrusted when read from a file) and makes the
object; ``document`` keeps the document itself, whose rounded numbers the card and the reports print.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from swatch.colorimetry.tolerance import Tolerance, get_tolerance
from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_INSTRUMENT_GEOMETRIES,
    MAX_SPREAD_FRACTION,
    MAX_SPREAD_NM,
    MAX_THICKNESS_NM,
    MAX_VOLTAGE_V,
)
from swatch.physics.process import OFFSET_RANGE, RATE_RANGE, SCALE_RANGE

__all__ = ["SPEC_LAYOUT", "SpecGeometry", "SpecModel", "SpecReach", "FinishSpec"]

#: The spec.json layout this swatch writes and reads (``swatch_spec``).
SPEC_LAYOUT = 1
_NEED = ("swatch_spec", "nominal", "colorimetry", "reference", "multi_angle", "tolerance", "process")


@dataclass(frozen=True)
class SpecGeometry:
    """One geometry of a spec and the colour specified there.

    Attributes
    ----------
    name : str
        The entry's name (``45:0``, ``45as15``, ``45:60``).
    light_deg, view_deg : float
        Polar angles of light and view from the normal, degrees (in plane).
    view_side : {"opposite", "light"}
        The view across the normal from the light, or on the light's side.
    Lab : tuple of float
        The specified CIELAB (L*, a*, b*) under the spec's illuminant and observer.
    """

    name: str
    light_deg: float
    view_deg: float
    view_side: str
    Lab: tuple[float, float, float]


@dataclass(frozen=True)
class SpecModel:
    """The process profile as a spec records it: the optical model and the growth law.

    Attributes
    ----------
    process : str or None
        The profile's name.
    film, substrate : str
        The optical tables' names.
    film_index_scale : float
        The film's refractive index scale.
    spread_nm, spread_fraction : float
        The thickness spread: 1σ = spread_nm + spread_fraction × d (nm).
    nm_per_V : float or None
        The growth rate, nm per volt (None: no growth law, thickness only).
    offset_nm : float
        The growth law's offset, nm.
    knee_V, nm_per_V_above_knee : float or None
        A two-slope law's knee (V) and the rate above it (nm/V); None for one slope.
    """

    process: str | None
    film: str
    substrate: str
    film_index_scale: float
    spread_nm: float = 0.0
    spread_fraction: float = 0.0
    nm_per_V: float | None = None
    offset_nm: float = 0.0
    knee_V: float | None = None
    nm_per_V_above_knee: float | None = None


@dataclass(frozen=True)
class SpecReach:
    """How close a colour target came (a thickness or voltage target has none).

    Attributes
    ----------
    within_tolerance : bool or None
        Whether the closest reachable colour is within the tolerance (None where the document does not say).
    delta_E : float or None
        Its difference from the target in the tolerance's metric (None where the document gives no finite number).
    accepted_closest : bool
        The specifier accepted the closest colour deliberately.
    """

    within_tolerance: bool | None
    delta_E: float | None
    accepted_closest: bool


@dataclass(frozen=True)
class FinishSpec:
    """A checked finish specification (made by :func:`swatch.production.spec.finish_spec` or read from spec.json).

    Attributes
    ----------
    tolerance : swatch.colorimetry.tolerance.Tolerance
        Judged in its own metric; its scheme and grade when it is a named grade.
    illuminant, observer : str
        The CIELAB's illuminant and observer (``"D65"``, ``"10"``).
    thickness_nm : float
        The nominal oxide thickness, nm.
    geometries : tuple of SpecGeometry
        The reference, the multi-angle set and the other judged angles, in the document's order.
    judged : tuple of str
        The names of the geometries the tolerance is judged at.
    model : SpecModel
        The process's optical model and growth law.
    calibrated_model : bool
        Whether the optical model was calibrated from the line's coupons.
    voltage_basis : str or None
        Where the nominal voltage comes from (``calibrated``, ``given``, ``preset``, ``profile``; None: not said).
    voltage_calibrated : bool or None
        Whether that voltage is a calibrated line's (None where the document does not say).
    reach : SpecReach or None
        For a colour target, how close it came.
    window_minus_nm, window_plus_nm : float or None
        The process window's sides, nm below and above the nominal.
    document : dict
        The spec.json document itself (its rounded numbers are what the card and the reports print).
    """

    tolerance: Tolerance
    illuminant: str
    observer: str
    thickness_nm: float
    geometries: tuple[SpecGeometry, ...]
    judged: tuple[str, ...]
    model: SpecModel
    calibrated_model: bool
    voltage_basis: str | None
    voltage_calibrated: bool | None
    reach: SpecReach | None
    window_minus_nm: float | None
    window_plus_nm: float | None
    document: dict = field(repr=False, compare=False)

    @classmethod
    def from_json(cls, document, source: str = "spec") -> FinishSpec:
        """Check a spec.json document and make the spec of it.

        Parameters
        ----------
        document : object
            The decoded JSON (untrusted when read from a file).
        source : str
            Names the spec in messages.

        Returns
        -------
        FinishSpec
            The spec; ``document`` is ``document`` itself.

        Raises
        ------
        swatch.core.errors.SwatchError
            A key is missing, the layout is not :data:`SPEC_LAYOUT`, or a value is of the wrong kind, not
            finite or out of range (thickness 0 to :data:`swatch.core.limits.MAX_THICKNESS_NM` nm, rate > 0).
        """
        if not isinstance(document, dict) or any(k not in document for k in _NEED):
            raise SwatchError(f"{source}: not a swatch spec.json (keys {', '.join(_NEED)} expected)")
        if document["swatch_spec"] != SPEC_LAYOUT:
            raise SwatchError(f"{source}: spec layout {document['swatch_spec']!r}; this swatch reads layout 1")
        try:
            return cls._of(document)
        except (KeyError, TypeError, ValueError, AttributeError):
            raise SwatchError(f"{source}: a value of the spec is missing, not a finite number or out of range; "
                              "give the spec.json that swatch spec wrote") from None

    @classmethod
    def _of(cls, doc: dict) -> FinishSpec:
        tol = doc["tolerance"]
        checked = get_tolerance(metric=tol["metric"], max=tol["max"])  # the metric known, the bound in range
        scheme, grade = tol.get("scheme"), tol.get("grade")
        if not all(v is None or isinstance(v, str) for v in (scheme, grade, tol.get("description"))):
            raise ValueError
        tolerance = Tolerance(checked.metric, checked.max, scheme, grade, str(tol.get("description") or ""))
        d = float(doc["nominal"]["thickness_nm"])
        proc = doc["process"]
        rate = proc.get("nm_per_V")
        if not isinstance(doc.get("angles", []), list) or len(doc.get("angles", [])) > MAX_INSTRUMENT_GEOMETRIES:
            raise ValueError
        geometries = tuple(_geometry(e) for e in [doc["reference"], *doc["multi_angle"], *doc.get("angles", [])])
        judged = _judged(tol, doc["reference"])
        names = {g.name for g in geometries}
        if not all(isinstance(n, str) and n in names for n in judged):
            raise ValueError
        if not np.isfinite(d) or not 0 <= d <= MAX_THICKNESS_NM \
                or (rate is not None and not (np.isfinite(float(rate)) and float(rate) > 0)):
            raise ValueError
        basis = doc["nominal"].get("voltage")
        basis = basis if isinstance(basis, dict) else {}
        voltage_calibrated = basis.get("calibrated") if isinstance(basis.get("calibrated"), bool) else None
        calibrated = doc.get("calibrated_model")
        col = doc["colorimetry"]
        window = doc.get("process_window") or {}
        if not isinstance(window, dict):
            raise ValueError(window)
        return cls(
            tolerance=tolerance, illuminant=col["illuminant"], observer=col["observer"], thickness_nm=d,
            geometries=geometries, judged=tuple(judged), model=_model(proc),
            calibrated_model=calibrated if isinstance(calibrated, bool) else voltage_calibrated is True,
            voltage_basis=basis.get("basis") if isinstance(basis.get("basis"), str) else None,
            voltage_calibrated=voltage_calibrated, reach=_reach(doc.get("reach")),
            window_minus_nm=_window_side(window.get("thickness_minus_nm")),
            window_plus_nm=_window_side(window.get("thickness_plus_nm")),
            document=doc)


def _geometry(e: dict) -> SpecGeometry:
    L, a, b = (float(v) for v in e["Lab"])  # three numbers, else ValueError
    g = SpecGeometry(str(e["geometry"]), float(e["light_deg"]), float(e["view_deg"]), e["view_side"], (L, a, b))
    if g.view_side not in ("opposite", "light") or g.name == "" \
            or not np.all(np.isfinite([g.light_deg, g.view_deg, L, a, b])):
        raise ValueError
    return g


def _judged(tol: dict, reference: dict) -> list[str]:
    """``tolerance.geometries``; a spec written before that key: the reference geometry's name."""
    names = tol.get("geometries")
    if names is None:
        return [str(reference["geometry"])]
    if not isinstance(names, list) or not 1 <= len(names) <= MAX_INSTRUMENT_GEOMETRIES:
        raise ValueError
    return names


def _model(proc: dict) -> SpecModel:
    """The spec's process, each number in the range a process profile allows (swatch.physics.process), else
    ValueError: a spec.json is read back from a file."""
    def num(key, lo, hi, default=None):
        value = proc.get(key, default)
        if value is None:
            return None
        value = float(value)
        if not (np.isfinite(value) and lo <= value <= hi):
            raise ValueError(key)
        return value

    return SpecModel(proc.get("process"), str(proc["film"]), str(proc["substrate"]),
                     num("film_index_scale", *SCALE_RANGE), num("spread_nm", 0.0, MAX_SPREAD_NM, 0.0),
                     num("spread_fraction", 0.0, MAX_SPREAD_FRACTION, 0.0), num("nm_per_V", *RATE_RANGE),
                     num("offset_nm", *OFFSET_RANGE, 0.0), num("knee_V", 0.0, MAX_VOLTAGE_V),
                     num("nm_per_V_above_knee", *RATE_RANGE))


def _window_side(value) -> float | None:
    """A process window's side read back (nm): None (capped, or not stated) or a finite number 0 … MAX_THICKNESS_NM."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 <= value <= MAX_THICKNESS_NM:
        raise ValueError(value)
    return float(value)


def _reach(reach) -> SpecReach | None:
    if not isinstance(reach, dict):
        return None
    dE = reach.get("delta_E")  # read back from a file: kept only when it is a finite number
    within = reach.get("within_tolerance")
    return SpecReach(within if isinstance(within, bool) else None,
                     float(dE) if isinstance(dE, (int, float)) and np.isfinite(dE) else None,
                     bool(reach.get("accepted_closest")))
