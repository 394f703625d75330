"""Colour-tolerance grades: a ΔE*ab maps to a named grade of a scheme (tables/tolerance_grades.csv)."""
from __future__ import annotations

import csv
import functools
from dataclasses import dataclass

import numpy as np

from swatch.errors import SwatchError
from swatch.materials import tables_dir

__all__ = ["Grade", "schemes", "grades", "grade_for", "grade_bound"]

DEFAULT_SCHEME = "csaj"


@dataclass(frozen=True)
class Grade:
    scheme: str
    name: str
    max_delta_E_ab: float
    description: str


@functools.lru_cache(maxsize=1)
def _table() -> dict[str, tuple[Grade, ...]]:
    path = tables_dir() / "tolerance_grades.csv"
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines() if ln and not ln.startswith("#")]
    out: dict[str, list[Grade]] = {}
    for row in csv.DictReader(lines):
        out.setdefault(row["scheme"], []).append(
            Grade(row["scheme"], row["grade"], float(row["max_delta_E_ab"]), row["description"])
        )
    return {k: tuple(sorted(v, key=lambda g: g.max_delta_E_ab)) for k, v in out.items()}


def schemes() -> list[str]:
    return sorted(_table())


def grades(scheme: str = DEFAULT_SCHEME) -> tuple[Grade, ...]:
    table = _table()
    if scheme not in table:
        raise SwatchError(f"unknown tolerance scheme {scheme!r}; use one of {', '.join(schemes())}")
    return table[scheme]


def grade_bound(name: str, scheme: str = DEFAULT_SCHEME) -> float:
    """Upper ΔE*ab bound of a named grade."""
    for g in grades(scheme):
        if g.name.lower() == str(name).lower():
            return g.max_delta_E_ab
    raise SwatchError(
        f"unknown grade {name!r} in scheme {scheme}; use one of {', '.join(g.name for g in grades(scheme))}"
    )


def grade_for(delta_E_ab, scheme: str = DEFAULT_SCHEME):
    """The tightest grade whose bound is >= ΔE*ab ("beyond" past the last); vectorised."""
    gs = grades(scheme)
    bounds = np.array([g.max_delta_E_ab for g in gs])
    dE = np.asarray(delta_E_ab, dtype=np.float64)
    if np.any(~np.isfinite(dE)) or np.any(dE < 0):
        raise SwatchError("ΔE must be finite and >= 0")
    idx = np.searchsorted(bounds, dE, side="left")
    names = np.array([g.name for g in gs] + ["beyond"], dtype=object)
    res = names[idx]
    return str(res) if np.ndim(res) == 0 else res
