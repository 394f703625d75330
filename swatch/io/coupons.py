"""Test coupons of an anodising line, read from CSV (the input of ``swatch calibrate``).

A header row, then one of two forms (``#`` comment lines and blank lines are skipped):

* colour: ``voltage_V,L,a,b`` — one coupon per row, CIELAB measured at the calibration's
  geometry, illuminant and observer;
* spectrum: ``voltage_V,wavelength_nm,reflectance`` — long form, one row per wavelength; rows of
  one coupon share its voltage (or its ``coupon`` label); every coupon on the same evenly spaced
  wavelength grid (checked by :func:`swatch.io.measurements.check_spectral_axis`); reflectance as a
  fraction or in percent (detected: percent when any value exceeds 1.5).

Optional columns: ``thickness_nm`` (measured by ellipsometry or XRR; one value per coupon) and
``coupon`` (a label). A coupon file is untrusted: its size, rows and coupons are capped before
memory is spent, and every error is one line naming the file, the line and what is allowed.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_COUPON_BYTES,
    MAX_COUPON_ROWS,
    MAX_COUPONS,
    MAX_MEASURED_WAVELENGTH_NM,
    MAX_VOLTAGE_V,
    MIN_MEASURED_WAVELENGTH_NM,
    MIN_PEAK_REFLECTANCE,
    read_text_capped,
)
from swatch.io.measurements import check_spectral_axis
from swatch.io.tabular import split_table

__all__ = ["Coupons", "read_coupons", "coupons_from_samples", "MAX_COUPON_BYTES", "MAX_COUPONS"]

_LAB = ("voltage_V", "L", "a", "b")
_SPECTRAL = ("voltage_V", "wavelength_nm", "reflectance")
_OPTIONAL = ("thickness_nm", "coupon")


@dataclass(frozen=True)
class Coupons:
    """N test coupons of an anodising line (the input of ``swatch calibrate``).

    Attributes
    ----------
    source : str
        The file.
    voltage_V : numpy.ndarray, shape (N,)
        Anodising voltages, V.
    thickness_nm : numpy.ndarray, shape (N,)
        Measured oxide thicknesses, nm (NaN where not measured).
    labels : tuple of str
        The coupons' labels.
    Lab : numpy.ndarray, shape (N, 3), or None
        CIELAB at the calibration's geometry, illuminant and observer (colour coupons).
    wavelength_nm : numpy.ndarray, shape (W,), or None
        The spectra's grid, nm (spectral coupons).
    reflectance : numpy.ndarray, shape (N, W), or None
        Reflectance factors, fraction.
    lines : tuple of int
        The first CSV line of each coupon (for messages).
    """

    source: str
    voltage_V: np.ndarray
    thickness_nm: np.ndarray  # NaN where not measured
    labels: tuple[str, ...]
    Lab: np.ndarray | None = None
    wavelength_nm: np.ndarray | None = None
    reflectance: np.ndarray | None = None  # fraction, (N, W)
    lines: tuple[int, ...] = ()  # the first CSV line of each coupon (for messages)

    @property
    def kind(self) -> str:
        """``"colour"`` (CIELAB coupons) or ``"spectrum"``.

        Returns
        -------
        str
            Which of ``Lab`` and ``reflectance`` the coupons hold.
        """
        return "colour" if self.Lab is not None else "spectrum"

    def __len__(self) -> int:
        return int(self.voltage_V.size)


def _number(text: str, where: str, what: str, lo: float, hi: float) -> float:
    try:
        v = float(text)
    except ValueError:
        raise SwatchError(f"{where}: {what} {text.strip()!r} is not a number") from None
    if not math.isfinite(v) or not lo <= v <= hi:
        raise SwatchError(f"{where}: {what} = {text.strip()} is out of range; allowed {lo:g} to {hi:g}")
    return v


def _rows(path: Path, source: str):
    text = read_text_capped(path, MAX_COUPON_BYTES, "coupon file", "CSV", source, encoding="utf-8-sig")
    table = split_table(text, source, max_rows=MAX_COUPON_ROWS)
    return [(table.header_line, table.header), *table.rows]


def read_coupons(path) -> Coupons:
    """Read and validate a coupon file (CSV; see the module docstring).

    Parameters
    ----------
    path : str or path-like
        ``voltage_V,L,a,b`` per coupon, or spectra in long form ``voltage_V,wavelength_nm,reflectance``;
        an optional ``thickness_nm`` column (untrusted: size, rows and coupons capped).

    Returns
    -------
    Coupons
        Voltages (V), the measured CIELAB or spectra, and thicknesses where given (nm).

    Raises
    ------
    SwatchError
        One line naming the file and what is wrong in it.
    """
    p = Path(path)
    source = str(path)
    rows = _rows(p, source)
    if not rows:
        raise SwatchError(f"{source}: empty; give a header row (voltage_V,L,a,b or "
                          "voltage_V,wavelength_nm,reflectance) and one row per coupon")
    head_line, header = rows[0]
    where = f"{source}:{head_line}"
    if len(set(header)) != len(header):
        raise SwatchError(f"{where}: a column is repeated in the header")
    spectral = "wavelength_nm" in header or "reflectance" in header
    required = _SPECTRAL if spectral else _LAB
    for col in header:
        if col not in required + _OPTIONAL:
            raise SwatchError(f"{where}: unknown column {col!r}; the header is voltage_V,L,a,b or "
                              "voltage_V,wavelength_nm,reflectance, plus optional thickness_nm, coupon")
    missing = [c for c in required if c not in header]
    if missing:
        raise SwatchError(f"{where}: missing column {missing[0]!r} (header {','.join(required)})")
    col = {name: i for i, name in enumerate(header)}
    if len(rows) < 2:
        raise SwatchError(f"{source}: no coupons after the header")

    groups: dict[str, dict] = {}
    for number, cells in rows[1:]:
        here = f"{source}:{number}"
        if len(cells) != len(header):
            raise SwatchError(f"{here}: {len(cells)} cells; the header has {len(header)}")
        volts = _number(cells[col["voltage_V"]], here, "voltage_V", 0.0, MAX_VOLTAGE_V)
        label = cells[col["coupon"]] if "coupon" in col else (f"{volts:g} V" if spectral else f"line {number}")
        if len(label) > 80:
            raise SwatchError(f"{here}: coupon label longer than 80 characters")
        thick = (_number(cells[col["thickness_nm"]], here, "thickness_nm", 0.0, 1000.0)
                 if "thickness_nm" in col and cells[col["thickness_nm"]] != "" else math.nan)
        g = groups.get(label)
        if g is None:
            if len(groups) >= MAX_COUPONS:
                raise SwatchError(f"{here}: more than {MAX_COUPONS} coupons; a calibration takes at most {MAX_COUPONS} (its search's time "
                                  "grows with the count; a line is calibrated from tens)")
            g = groups[label] = {"line": number, "V": volts, "d": thick, "values": []}
        elif not spectral:
            raise SwatchError(f"{here}: coupon {label!r} appears twice; give each coupon one row")
        elif g["V"] != volts or not (g["d"] == thick or (math.isnan(g["d"]) and math.isnan(thick))):
            raise SwatchError(f"{here}: coupon {label!r} changes its voltage_V or thickness_nm between rows")
        if spectral:
            wl = _number(cells[col["wavelength_nm"]], here, "wavelength_nm", MIN_MEASURED_WAVELENGTH_NM,
                         MAX_MEASURED_WAVELENGTH_NM)
            refl = _number(cells[col["reflectance"]], here, "reflectance", 0.0, 100.0)
            g["values"].append((wl, refl, number))
        else:
            g["values"] = [_number(cells[col["L"]], here, "L", 0.0, 100.0),
                           _number(cells[col["a"]], here, "a", -200.0, 200.0),
                           _number(cells[col["b"]], here, "b", -200.0, 200.0)]

    labels = tuple(groups)
    volts_V = np.array([g["V"] for g in groups.values()])
    thick_nm = np.array([g["d"] for g in groups.values()])
    lines = tuple(g["line"] for g in groups.values())
    if not spectral:
        return Coupons(source, volts_V, thick_nm, labels, Lab=np.array([g["values"] for g in groups.values()]),
                       lines=lines)
    return _spectra(source, groups, volts_V, thick_nm, labels, lines)


def _spectra(source, groups, volts_V, thick_nm, labels, lines) -> Coupons:
    grid = None
    spectra = []
    for label, g in groups.items():
        vals = sorted(g["values"])
        wl = np.array([v[0] for v in vals])
        if np.any(np.diff(wl) <= 0):
            dup = next(v[2] for a, v in itertools.pairwise(vals) if v[0] == a[0])
            raise SwatchError(f"{source}:{dup}: coupon {label!r} repeats wavelength {vals[0][0]:g} nm")
        wl = check_spectral_axis(wl, f"{source}:{g['line']}", what=f"coupon {label!r}: wavelength_nm")
        if grid is None:
            grid = wl
            steps = np.diff(wl)
            if wl.size < 3 or not np.allclose(steps, steps[0]) or steps[0] not in (1.0, 5.0, 10.0, 20.0):
                raise SwatchError(f"{source}:{g['line']}: coupon {label!r}: wavelengths must be evenly spaced "
                                  "by 1, 5, 10 or 20 nm (ASTM E308 intervals), at least three of them")
        elif wl.shape != grid.shape or not np.allclose(wl, grid):
            raise SwatchError(f"{source}:{g['line']}: coupon {label!r} is on other wavelengths than the first "
                              "coupon; give every coupon the same wavelengths")
        spectra.append([v[1] for v in vals])
    refl = np.array(spectra)
    if refl.max() > 1.5:  # percent
        refl = refl / 100.0
    dark = np.flatnonzero(~(refl.max(axis=1) >= MIN_PEAK_REFLECTANCE))  # (all-black spectra calibrated to nonsense)
    if dark.size:
        i = int(dark[0])
        raise SwatchError(f"{source}: coupon {labels[i]!r}: its spectrum peaks at {refl[i].max():g} (fraction), "
                          f"implausibly dark for a measurement; the peak must be at least {MIN_PEAK_REFLECTANCE:g}")
    return Coupons(source, volts_V, thick_nm, labels, wavelength_nm=grid, reflectance=refl, lines=lines)


def coupons_from_samples(source: str, samples) -> Coupons:
    """Coupons from an instrument file's samples (CGATS with a ``VOLTAGE_V`` field, CxF3 objects tagged ``voltage_V``).

    Parameters
    ----------
    source : str
        Names the file.
    samples : sequence of swatch.io.instruments.Sample
        One geometry each, every one with a voltage.

    Returns
    -------
    Coupons
        One coupon per sample, in the file's order: voltages (V), CIELAB or spectra (fraction), labels.

    Raises
    ------
    swatch.core.errors.SwatchError
        More than :data:`MAX_COUPONS`, a sample without a voltage, with several geometries or viewed on
        the light's side, a voltage outside 0 to :data:`swatch.core.limits.MAX_VOLTAGE_V`, or spectra not
        evenly spaced by 1, 5, 10 or 20 nm (ASTM E308).
    """
    if len(samples) > MAX_COUPONS:
        raise SwatchError(f"{source}: more than {MAX_COUPONS} coupons; a calibration takes at most {MAX_COUPONS} (its search's "
                          "time grows with the count; a line is calibrated from tens)")
    missing = [s.id for s in samples if s.voltage_V is None]
    if missing:
        raise SwatchError(f"{source}: sample {missing[0]!r} has no voltage; coupons need a VOLTAGE_V field (CGATS) "
                          "or a voltage_V tag (CxF3)")
    for s in samples:
        if s.measurement.n_geometries != 1:
            raise SwatchError(f"{source}: coupon {s.id!r} has {s.measurement.n_geometries} geometries; calibrate "
                              "reads one geometry per coupon")
        if float(s.measurement.view_azimuth_deg[0]) == float(s.measurement.light_azimuth_deg[0]) \
                and float(s.measurement.view_deg[0]) > 0:
            raise SwatchError(f"{source}: coupon {s.id!r} is viewed on the light's side; calibrate reads an in-plane "
                              "geometry with the view across the normal (e.g. 45/0)")
        if not (math.isfinite(s.voltage_V) and 0 <= s.voltage_V <= MAX_VOLTAGE_V):
            raise SwatchError(f"{source}: coupon {s.id!r}: voltage_V {s.voltage_V:g} is out of range; allowed 0 to "
                              f"{MAX_VOLTAGE_V:g}")
    volts = np.array([s.voltage_V for s in samples], dtype=np.float64)
    thick = np.array([math.nan if s.thickness_nm is None else s.thickness_nm for s in samples], dtype=np.float64)
    labels = tuple(s.id for s in samples)
    first = samples[0].measurement
    if hasattr(first, "Lab"):
        return Coupons(source, volts, thick, labels, Lab=np.stack([s.measurement.Lab[0] for s in samples]))
    wl = first.wavelength_nm
    steps = np.diff(wl)
    if wl.size < 3 or not np.allclose(steps, steps[0]) or round(float(steps[0]), 6) not in (1.0, 5.0, 10.0, 20.0):
        raise SwatchError(f"{source}: coupon spectra must be evenly spaced by 1, 5, 10 or 20 nm (ASTM E308 "
                          "intervals), at least three wavelengths")
    return Coupons(source, volts, thick, labels, wavelength_nm=wl,
                   reflectance=np.stack([s.measurement.reflectance[0] for s in samples]))
