"""What ``swatch check`` tells a finisher to do about a part: the rules, and the words.

A finisher acts on what ``check`` says, so it advises only what the measurement and the model support
(one rule per case, in this order; docs/finisher.md states them):

1. **The spec's model is not calibrated for the line, and explains the part no better than another
   shipped optical model does** (action ``calibrate``). A spec made on a preset predicts the colours
   away from 45:0 with optical tables that were never checked against the line; a part the spec's
   model leaves more than the tolerance from any thickness, but that another shipped film × substrate
   pair of the same metal explains within the tolerance (:func:`swatch.production.qc.other_models`), is
   evidence against
   the spec's model, not against the shop: calibrate the line and re-issue the spec.
2. **No thickness explains the part** (action ``investigate``): the residual (the part against the
   model at its best-fit thickness, in the tolerance's metric) is over the tolerance under the spec's
   model (and, for an uncalibrated spec, under every shipped model too), or the fit lies on the edge of
   its search. No voltage fixes it: the alloy, the surface preparation, contamination, sealing or heat
   tint, the measurement.
3. **The part is not measured at every geometry the tolerance is judged at** (action ``measure``): it is
   not passed, and nothing is advised until it is measured there.
4. **The part fails and the thickness explains it** (action ``correct``): the voltage correction.
5. **The part passes near the window's edge** (action ``centre``): its worst ΔE is more than
   :data:`EDGE_FRACTION` of the tolerance, or its best-fit thickness is in the outer
   (1 − :data:`EDGE_FRACTION`) of the process window on its side. The correction that centres it.
6. **The part passes inside the window** (action ``none``): no action, no voltage.
"""
from __future__ import annotations

from dataclasses import dataclass

from swatch.physics.growth import voltage_text
from swatch.production.finish import FinishSpec

__all__ = ["EDGE_FRACTION", "ACTIONS", "OtherModel", "near_edge", "voltage_advice",
           "not_a_thickness_error", "calibrate_first", "spec_notes"]

#: A passing part is near the edge of the window past this fraction of the tolerance (its worst ΔE) or of
#: the process window on its side (its best-fit thickness): two thirds leaves the last third as the margin
#: a finisher centres the line in before parts fail.
EDGE_FRACTION = 2.0 / 3.0
#: The actions a part's check ends in (``action`` in check.json), in the order the rules are tried.
ACTIONS = ("calibrate", "investigate", "measure", "correct", "centre", "none")


@dataclass(frozen=True)
class OtherModel:
    """The best of the other shipped optical models at explaining one part.

    Attributes
    ----------
    film, substrate : str
        The optical tables (``swatch materials list``).
    thickness_nm : float
        The part's best-fit thickness under them, nm.
    residual : float
        The worst ΔE (the tolerance's metric) over the measured geometries between the part and that
        model at that thickness.
    """

    film: str
    substrate: str
    thickness_nm: float
    residual: float

    @property
    def name(self) -> str:
        """The model in words: ``TiO2-Franta on Ti-Palm``.

        Returns
        -------
        str
            Film on substrate.
        """
        return f"{self.film} on {self.substrate}"


def near_edge(worst_delta_E: float, bound: float, offset_nm: float, minus_nm, plus_nm) -> bool:
    """Whether a passing part sits near the edge of the spec's window (rule 5 of the module docstring).

    Parameters
    ----------
    worst_delta_E : float
        The part's worst ΔE over its measured geometries, in the tolerance's metric.
    bound : float
        The tolerance's maximum.
    offset_nm : float
        Best-fit thickness − nominal, nm.
    minus_nm, plus_nm : float or None
        The process window's depth below and above the nominal, nm (None: not known).

    Returns
    -------
    bool
        True past :data:`EDGE_FRACTION` of the tolerance or of the window on the offset's side.

    Examples
    --------
    >>> near_edge(0.4, 2.0, -0.2, 1.1, 1.2), near_edge(1.44, 2.0, -0.8, 1.1, 1.2), near_edge(0.5, 2.0, 1.0, 1.1, 1.2)
    (False, True, True)
    """
    side = minus_nm if offset_nm < 0 else plus_nm
    by_thickness = side is not None and float(side) > 0 and abs(offset_nm) > EDGE_FRACTION * float(side)
    return bool(worst_delta_E > EDGE_FRACTION * bound or by_thickness)


def voltage_advice(correction_V: float) -> str:
    """The voltage correction in a finisher's words, to the precision the growth law supports.

    Parameters
    ----------
    correction_V : float
        ``V(nominal) − V(fitted)``, volts (positive: the line grows too thin a film).

    Returns
    -------
    str
        ``"raise the voltage by X V"``, ``"lower the voltage by X V"``, or ``"keep the voltage"`` when
        the change rounds to zero (:func:`swatch.physics.growth.voltage_text`).

    Examples
    --------
    >>> voltage_advice(1.2649), voltage_advice(-0.04)
    ('raise the voltage by 1.3 V', 'keep the voltage (the fitted thickness is the nominal)')
    """
    text = voltage_text(abs(correction_V))
    if float(text) == 0.0:
        return "keep the voltage (the fitted thickness is the nominal)"
    return f"{'raise' if correction_V > 0 else 'lower'} the voltage by {text} V"


def not_a_thickness_error(residual: float, metric: str, bound: float, d_fit: float,
                          others: OtherModel | None = None) -> str:
    """Why no voltage correction is given to a part no thickness explains (one sentence).

    Parameters
    ----------
    residual : float
        The worst ΔE (``metric``) over the measured geometries between the part and the model at
        its best-fit thickness.
    metric : str
        The tolerance's metric.
    bound : float
        The bound it is above (the tolerance's maximum).
    d_fit : float
        The best-fit thickness, nm.
    others : OtherModel, optional
        For a spec whose model is not calibrated: the best of the other shipped models, which does not
        explain the part either.

    Returns
    -------
    str
        One sentence: the residual, why no voltage explains it, and what to check instead.
    """
    also = ("" if others is None else
            f"; no other shipped optical model explains it either (the closest, {others.name}, leaves "
            f"{metric} {others.residual:.2f})")
    return (f"not a thickness error: the best-fit thickness {d_fit:.1f} nm still leaves {metric} {residual:.2f} "
            f"between the part and the model (more than the tolerance, {bound:g}){also}, so no voltage explains "
            f"it; check the alloy, the surface preparation, contamination, sealing or heat tint, and the measurement")


def calibrate_first(residual: float, metric: str, bound: float, other: OtherModel) -> str:
    """Why a part the uncalibrated spec's model does not explain is not blamed on the shop (one sentence).

    Parameters
    ----------
    residual : float
        The worst ΔE under the spec's own model at the best-fit thickness.
    metric : str
        The tolerance's metric.
    bound : float
        The tolerance's maximum.
    other : OtherModel
        The other shipped model that explains the part within the tolerance.

    Returns
    -------
    str
        One sentence: the spec's model is the suspect, the numbers, and what to do.
    """
    return (f"the spec's model, not the part: the spec is not calibrated for this line, and its model leaves "
            f"{metric} {residual:.2f} at any thickness while another shipped optical model ({other.name}) explains "
            f"the part at {other.thickness_nm:.1f} nm within {metric} {other.residual:.2f} (tolerance {bound:g}); "
            "that is no evidence of a shop fault: calibrate the line (swatch calibrate) and re-issue the spec "
            "before acting on this part")


def spec_notes(spec: FinishSpec) -> list[str]:
    """What a finisher must know about the spec before acting on a check (one sentence each, first first).

    Parameters
    ----------
    spec : swatch.production.finish.FinishSpec
        The spec.

    Returns
    -------
    list of str
        A spec whose model is not calibrated for the line (its colours away from 45:0 are predictions);
        a colour target that was out of reach (accepted or not); a nominal voltage that is not a
        calibrated line's (the corrections' direction holds, their size is that rate's).
    """
    notes = []
    if not spec.calibrated_model:
        notes.append(f"the spec was made on the profile {spec.model.process}, which is not calibrated "
                     "for this line: its colours away from 45:0 are predictions of an uncalibrated model, so a part "
                     "can differ from them without any fault of the shop; calibrate the line from its test coupons "
                     "(swatch calibrate coupons.csv --out line.toml) and re-issue the spec on it (swatch spec with "
                     "--process line.toml)")
    reach = spec.reach
    if reach is not None and reach.within_tolerance is False:
        far = f"{spec.tolerance.metric} {reach.delta_E:g}" if reach.delta_E is not None else "too far"
        notes.append(f"the spec's target was out of reach ({far} from the closest colour) and the closest colour "
                     + ("was accepted deliberately" if reach.accepted_closest else "was NOT accepted")
                     + ": parts are judged against that closest colour, not the target")
    rate = spec.model.nm_per_V
    if rate and spec.voltage_calibrated is False:
        kind = spec.voltage_basis if spec.voltage_basis in ("preset", "given", "profile") else "not calibrated"
        notes.append(f"voltages use the spec's growth rate ({rate:g} nm/V, {kind}), not a calibrated "
                     "line: a correction's direction holds, its size is only as good as that rate")
    return notes
