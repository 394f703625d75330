"""Colour tolerances, each judged in the metric it is defined in.

Named grades (``tables/tolerance_grades.csv``: CSAJ AAA…E, the NBS terms) are bounds on the
colour difference the table's ``metric`` column names (both shipped schemes bound CIE 1976
ΔE*ab). A tolerance may also be written as coating specifications write it, a metric and a
maximum (``dE00:2.0``, or ``{ metric = "dE00", max = 2.0 }`` in a catalog spec). Process
windows, ``swatch match`` and ``swatch fit`` compare a colour difference computed in the
tolerance's own metric with its bound; never one metric's number against another's bound.

References
----------
.. [1] :cite:`CSAJ1998`: the ``csaj`` grades.
.. [2] :cite:`Judd1975`: the ``nbs`` terms.
.. [3] :cite:`Sharma2005b`: ΔE00.
.. [4] :cite:`Carter2018`: ΔE*ab.
"""
from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_TOLERANCE
from swatch.core.registry import Registry
from swatch.physics.materials import tables_dir

__all__ = ["Grade", "Tolerance", "METRICS", "schemes", "check_scheme", "grades", "grade_for", "grade_bound", "grade_metric",
           "delta_E", "get_tolerance", "parse_tolerance"]

DEFAULT_SCHEME = "csaj"


def _colour_differences():
    """ΔE*ab and ΔE00 of swatch.colorimetry.colorimeter (colour-science: seconds to import), only when one is
    computed."""
    from swatch.colorimetry.colorimeter import delta_E_00, delta_E_ab

    return delta_E_ab, delta_E_00


def _delta_E_ab(Lab1, Lab2) -> np.ndarray:
    """CIE 1976 ΔE*ab (colour-science)."""
    return _colour_differences()[0](Lab1, Lab2)


def _delta_E_00(Lab1, Lab2) -> np.ndarray:
    """CIEDE2000 ΔE00 (colour-science)."""
    return _colour_differences()[1](Lab1, Lab2)


#: Colour-difference metrics a tolerance can bound: name -> (the ΔE function, its description); names in any case.
METRICS: Registry = Registry("colour-difference metric", "metric", {
    "dEab": (_delta_E_ab, "CIE 1976 ΔE*ab"), "dE00": (_delta_E_00, "CIEDE2000 ΔE00")})


@dataclass(frozen=True)
class Grade:
    """One row of ``tables/tolerance_grades.csv``.

    Parameters
    ----------
    scheme, name : str
        The grading scheme (``csaj``, ``nbs``) and the grade's name (``AAA`` … ``E``, ``trace`` …).
    metric : str
        The colour difference its bound is on (one of :data:`METRICS`).
    max : float
        The bound, in ``metric`` units.
    description : str
        The grade's wording.
    """

    scheme: str
    name: str
    metric: str
    max: float
    description: str


@dataclass(frozen=True)
class Tolerance:
    """A bound ``max`` on the colour difference ``metric``; ``scheme``/``grade`` when it is a named grade.

    A tolerance is judged in the metric it is defined in (the CSAJ grades bound ΔE*ab).

    Attributes
    ----------
    metric : str
        ``dEab`` (CIE 1976 ΔE*ab), ``dE00`` (CIEDE2000) or another of :data:`METRICS`.
    max : float
        The largest difference that passes, in ``metric`` units.
    scheme, grade : str or None
        The grading scheme (``csaj``, ``nbs``: lower case) and grade (``AAA`` … ``E``) when it is a named grade.
    description : str
        The grade's wording (e.g. what a viewer perceives at that difference).

    References
    ----------
    :cite:`Sharma2005b` (ΔE00), :cite:`Carter2018` (ΔE*ab).
    """

    metric: str
    max: float
    scheme: str | None = None
    grade: str | None = None
    description: str = ""

    @property
    def label(self) -> str:
        """A short label.

        Returns
        -------
        str
            ``C`` for a named grade, ``dE00 ≤ 2`` for a written tolerance.
        """
        return self.grade if self.grade is not None else f"{self.metric} ≤ {self.max:g}"

    @property
    def text(self) -> str:
        """One line for sheets and pages: what is bounded, by how much, from which grade.

        Returns
        -------
        str
            e.g. ``"csaj grade B: CIE 1976 ΔE*ab ≤ 3.2"`` or ``"CIEDE2000 ΔE00 ≤ 2"``.
        """
        grade = f"{self.scheme} grade {self.grade}: " if self.grade is not None else ""
        return f"{grade}{METRICS.description(self.metric)} ≤ {self.max:g}"

    def delta_E(self, Lab1, Lab2) -> np.ndarray:
        """The colour difference in this tolerance's own metric.

        Parameters
        ----------
        Lab1, Lab2 : array_like, shape (..., 3)
            CIELAB, broadcast together.

        Returns
        -------
        numpy.ndarray, shape (...)
            In ``metric`` units (compare with ``max``).
        """
        return delta_E(self.metric, Lab1, Lab2)

    def to_json(self) -> dict:
        """The tolerance as JSON (metric, max, scheme, grade, description).

        Returns
        -------
        dict
            ``{"metric", "max", "scheme", "grade", "description"}``; ``scheme``, ``grade`` are None for a written one.
        """
        return {"metric": self.metric, "max": self.max, "scheme": self.scheme, "grade": self.grade,
                "description": self.description}


@functools.lru_cache(maxsize=1)
def _table() -> Registry[tuple[Grade, ...]]:
    """The grading schemes of ``tables/tolerance_grades.csv``: name -> (its grades, tightest first; a description),
    in alphabetical order, names in any case."""
    path = tables_dir() / "tolerance_grades.csv"
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines() if ln and not ln.startswith("#")]
    out: dict[str, list[Grade]] = {}
    for row in csv.DictReader(lines):
        if row["metric"] not in METRICS.names():
            raise SwatchError(f"{path.name}: metric {row['metric']!r} is not one of {', '.join(METRICS)}")
        out.setdefault(row["scheme"], []).append(
            Grade(row["scheme"], row["grade"], row["metric"], float(row["max"]), row["description"])
        )
    table = {k: tuple(sorted(out[k], key=lambda g: g.max)) for k in sorted(out)}
    return Registry("tolerance scheme", "scheme", {
        k: (gs, f"grades {', '.join(g.name for g in gs)} (bounds on {gs[0].metric})") for k, gs in table.items()})


def schemes() -> list[str]:
    """The grading schemes of ``tables/tolerance_grades.csv``, sorted (``csaj``, ``nbs``).

    Returns
    -------
    list of str
        The scheme names, lower case, in alphabetical order.
    """
    return sorted(_table())


def check_scheme(scheme: str) -> str:
    """A grading scheme's name as the table spells it (case and surrounding blanks ignored).

    Parameters
    ----------
    scheme : str
        A scheme of :func:`schemes` in any case (``CSAJ``).

    Returns
    -------
    str
        Its name in ``tables/tolerance_grades.csv`` (``csaj``).

    Raises
    ------
    SwatchError
        For an unknown scheme, naming ```scheme``` and the schemes.
    """
    return _table().validate(scheme)


def grades(scheme: str = DEFAULT_SCHEME) -> tuple[Grade, ...]:
    """A scheme's grades, tightest first.

    Parameters
    ----------
    scheme : str
        A scheme of :func:`schemes` (default ``csaj``; in any case).

    Returns
    -------
    tuple of Grade
        Sorted by ``max``, ascending.

    Raises
    ------
    SwatchError
        For an unknown scheme.
    """
    return _table()[scheme]


def grade_metric(scheme: str = DEFAULT_SCHEME) -> str:
    """The metric a scheme's bounds are defined on.

    Parameters
    ----------
    scheme : str
        A scheme of :func:`schemes` (default ``csaj``).

    Returns
    -------
    str
        One of :data:`METRICS` (``dEab`` for both CSAJ and NBS).
    """
    return grades(scheme)[0].metric


def _grade(name: str, scheme: str) -> Grade:
    for g in grades(scheme):
        if g.name.lower() == str(name).lower():
            return g
    raise SwatchError(
        f"unknown grade {name!r} in scheme {_table().validate(scheme)}; use one of "
        f"{', '.join(g.name for g in grades(scheme))}"
    )


def grade_bound(name: str, scheme: str = DEFAULT_SCHEME) -> float:
    """Upper bound of a named grade, in the scheme's metric (:func:`grade_metric`).

    Parameters
    ----------
    name : str
        A grade of the scheme (case-insensitive).
    scheme : str
        A scheme of :func:`schemes` (default ``csaj``).

    Returns
    -------
    float
        The grade's ``max``: the largest colour difference that passes, in the scheme's metric units.

    Raises
    ------
    SwatchError
        For an unknown scheme or grade.

    Examples
    --------
    >>> grade_bound("B")
    3.2
    """
    return _grade(name, scheme).max


def grade_for(delta_E, scheme: str = DEFAULT_SCHEME):
    """The tightest grade whose bound is >= ``delta_E`` ("beyond" past the last); vectorised.

    Parameters
    ----------
    delta_E : float or array_like
        Colour differences in the scheme's metric (:func:`grade_metric`), finite and ≥ 0.
    scheme : str
        A scheme of :func:`schemes` (default ``csaj``).

    Returns
    -------
    str, or numpy.ndarray of str (dtype object) of the shape of ``delta_E``
        The grade name(s) (``"B"`` …), or ``"beyond"`` where ``delta_E`` exceeds the loosest grade's bound;
        a str for a scalar ``delta_E``.

    Raises
    ------
    SwatchError
        For a non-finite or negative difference, or an unknown scheme.
    """
    gs = grades(scheme)
    bounds = np.array([g.max for g in gs])
    dE = np.asarray(delta_E, dtype=np.float64)
    if np.any(~np.isfinite(dE)) or np.any(dE < 0):
        raise SwatchError("ΔE must be finite and >= 0")
    idx = np.searchsorted(bounds, dE, side="left")
    names = np.array([g.name for g in gs] + ["beyond"], dtype=object)
    res = names[idx]
    return str(res) if np.ndim(res) == 0 else res


def delta_E(metric: str, Lab1, Lab2) -> np.ndarray:
    """The colour difference ``metric`` (``dEab`` or ``dE00``) between CIELAB arrays (colour-science).

    Parameters
    ----------
    metric : str
        ``dEab`` (CIE 1976) or ``dE00`` (CIEDE2000).
    Lab1, Lab2 : array_like, shapes (..., 3) broadcasting together
        CIELAB colours (same illuminant and observer).

    Returns
    -------
    numpy.ndarray
        The broadcast shape without the last axis.

    Raises
    ------
    SwatchError
        For an unknown metric.

    References
    ----------
    :cite:`Sharma2005b` (CIEDE2000).
    """
    return METRICS[metric](Lab1, Lab2)


def _check_max(value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not 0 < value <= MAX_TOLERANCE:
        raise SwatchError(f"tolerance max must be a number more than 0 and at most {MAX_TOLERANCE:g}")
    return float(value)


def get_tolerance(scheme: str | None = None, grade: str | None = None, metric: str | None = None,
                  max: float | None = None) -> Tolerance:
    """A named grade (``scheme``, ``grade``) or a written tolerance (``metric``, ``max``), not both.

    Parameters
    ----------
    scheme, grade : str or None
        A grading scheme of ``tables/tolerance_grades.csv`` (``csaj``, ``nbs``: lower case) and one of its grades.
    metric : str or None
        A colour-difference metric (``dEab``, ``dE00`` …) for a written tolerance.
    max : float or None
        The written tolerance's bound, in ``metric`` units (0 < max ≤ ``MAX_TOLERANCE``).

    Returns
    -------
    Tolerance
        The named grade's metric and bound (default: the ``csaj`` scheme's grade C), or the written
        ``metric`` and ``max``.

    Raises
    ------
    SwatchError
        For an unknown scheme, grade or metric, a bound out of range, or both forms given.
    """
    if metric is not None or max is not None:
        if grade is not None:
            raise SwatchError("give a tolerance as a grade (scheme, grade) or as metric and max, not both")
        if metric is None or max is None:
            raise SwatchError("a written tolerance needs both metric (dEab or dE00) and max")
        return Tolerance(METRICS.validate(metric), _check_max(max))
    scheme = _table().validate(scheme or DEFAULT_SCHEME)
    g = _grade(grade if grade is not None else "C", scheme)
    return Tolerance(g.metric, g.max, scheme, g.name, g.description)


def parse_tolerance(text: str) -> Tolerance:
    """``METRIC:MAX`` (``dE00:2``, ``dEab:3.2``) or ``SCHEME:GRADE`` (``csaj:B``) from the command line.

    Parameters
    ----------
    text : str
        The option's value (surrounding blanks ignored).

    Returns
    -------
    Tolerance
        The written tolerance (``metric``, ``max``) or the named grade (``scheme``, ``grade``, its metric and bound).

    Raises
    ------
    SwatchError
        Without a colon, for a non-number bound, or a part before the colon that is neither a metric
        nor a scheme (and as :func:`get_tolerance` does).

    Examples
    --------
    >>> parse_tolerance("dE00:2").label
    'dE00 ≤ 2'
    """
    what, sep, value = str(text).strip().partition(":")
    if not sep:
        raise SwatchError(f"tolerance {text!r} must be METRIC:MAX (e.g. dE00:2.0) or SCHEME:GRADE (e.g. csaj:C)")
    if what in METRICS:  # names in any case: DE00:2, CSAJ:B
        try:
            number = float(value)
        except ValueError:
            raise SwatchError(f"tolerance {text!r}: {value!r} is not a number") from None
        return get_tolerance(metric=METRICS.validate(what), max=number)
    if what in _table():
        return get_tolerance(scheme=what, grade=value)
    raise SwatchError(f"tolerance {text!r}: {what!r} is neither a metric ({', '.join(METRICS)}) "
                      f"nor a scheme ({', '.join(schemes())})")
