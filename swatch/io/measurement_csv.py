"""Measurement CSV files: spectral reflectance (one spectrum or a multi-geometry sBRDF set) and CIELAB.

Formats (CSV, comma separated, one header row; ``#`` comment lines and blank lines are skipped;
column names are case-insensitive; extra columns are ignored):

* one spectrum: ``wavelength_nm,reflectance`` — its geometry is given by the caller
  (the CLI's ``--light/--view``, default 45°:0°);
* an sBRDF set in long form: ``light_deg,view_deg[,light_azimuth_deg,view_azimuth_deg],wavelength_nm,reflectance``,
  one row per geometry and wavelength, in any order; every geometry must have the same wavelengths;
* CIELAB: ``light_deg,view_deg[,light_azimuth_deg,view_azimuth_deg],L,a,b`` (one row per geometry),
  or ``L,a,b`` alone (one row; geometry from the caller).

Geometry: polar angles from the normal. Without azimuth columns light and view are in one plane of
incidence; a positive ``view_deg`` is on the far side of the normal (``light == view`` is the mirror
direction), a negative one on the light's side (stored as ``view_azimuth = light_azimuth``). With
azimuth columns both polar angles are in [0, 90) and the azimuths are used as given.

The wavelengths are checked by :func:`swatch.io.measurements.check_spectral_axis` (at most MAX_WAVELENGTHS,
inside the measured range of :mod:`swatch.core.limits`).

Reflectance is a fraction (1 = 100 %) or in percent: percent when any value exceeds 1.5
(:data:`PERCENT_THRESHOLD`) unless the caller says which. Values are stored as fractions.

Every error names the file, the line and what is wrong (:class:`~swatch.core.errors.SwatchError`).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_FIT_GEOMETRIES,
    MAX_LAB_AB,
    MAX_MEASUREMENT_BYTES,
    MAX_REFLECTANCE,
    MIN_PEAK_REFLECTANCE,
    MIN_REFLECTANCE,
    read_capped,
)
from swatch.io.measurements import PERCENT_THRESHOLD, LabMeasurement, SpectralMeasurement, check_spectral_axis
from swatch.io.tabular import Table, split_table
from swatch.physics import geometry

__all__ = ["read_measurement", "read_spectral_csv", "read_lab_csv", "parse_measurement_text", "parse_measurement_table"]

_KEY_DIGITS = 9


class _Rows:
    """Header and numbered data rows of a CSV text (comments and blank lines skipped; the separator
    and decimal mark detected by :func:`swatch.io.tabular.split_table`)."""

    def __init__(self, text: str, source: str, table: Table | None = None):
        self.source = source
        table = table if table is not None else split_table(text, source)
        self.rows: list[tuple[int, list[str]]] = table.rows
        self.header: list[str] = [f.lower() for f in table.header]
        self.header_line = table.header_line

    def error(self, line_no: int, message: str) -> SwatchError:
        return SwatchError(f"{self.source}: line {line_no}: {message}")

    def has(self, *names: str) -> bool:
        return all(n in self.header for n in names)

    def columns(self, names: list[str]) -> dict[str, np.ndarray]:
        """Parse the named columns as finite floats (one array per name)."""
        if not self.rows:
            raise self.error(self.header_line, "no data rows after the header")
        idx = {n: self.header.index(n) for n in names}
        width = len(self.header)
        out = {n: np.empty(len(self.rows)) for n in names}
        for r, (line_no, fields) in enumerate(self.rows):
            if len(fields) != width:
                raise self.error(line_no, f"expected {width} fields like the header, got {len(fields)}")
            for n, i in idx.items():
                tok = fields[i]
                try:
                    val = float(tok)
                except ValueError:
                    raise self.error(line_no, f"{n} {tok!r} is not a number") from None
                if not math.isfinite(val):
                    raise self.error(line_no, f"{n} {tok!r} is not a finite number")
                out[n][r] = val
        return out

    @property
    def lines(self) -> np.ndarray:
        return np.array([ln for ln, _ in self.rows], dtype=np.int64)


def _geometry_columns(rows: _Rows, light_deg: float, view_deg: float, light_azimuth_deg: float,
                      view_azimuth_deg: float | None):
    """Per-row (light, view, light_az, view_az) from the file or the caller's geometry."""
    has_l, has_v = rows.has("light_deg"), rows.has("view_deg")
    has_la, has_va = rows.has("light_azimuth_deg"), rows.has("view_azimuth_deg")
    if has_l != has_v:
        missing = "view_deg" if has_l else "light_deg"
        raise rows.error(rows.header_line, f"missing column {missing}; give both light_deg and view_deg or neither")
    if has_la != has_va:
        missing = "view_azimuth_deg" if has_la else "light_azimuth_deg"
        raise rows.error(rows.header_line, f"missing column {missing}; give both azimuth columns or neither")
    if has_la and not has_l:
        raise rows.error(rows.header_line, "azimuth columns need light_deg and view_deg columns too")
    n = len(rows.rows)
    lines = rows.lines
    if not has_l:
        l = np.full(n, float(light_deg))
        v = np.full(n, float(view_deg))
        la = np.full(n, float(light_azimuth_deg))
        va = np.array(np.broadcast_to(geometry.resolve_view_azimuth_deg(la, view_azimuth_deg), (n,)))
        for what, a in (("light", float(light_deg)), ("view", float(view_deg))):
            if not (math.isfinite(a) and 0 <= a < 90):
                raise SwatchError(f"{what} angle must be in [0, 90) degrees from the normal (file without angle columns)")
        return l, v, la, va
    cols = rows.columns(["light_deg", "view_deg"] + (["light_azimuth_deg", "view_azimuth_deg"] if has_la else []))
    l, v = cols["light_deg"], cols["view_deg"]
    bad = np.flatnonzero((l < 0) | (l >= 90))
    if bad.size:
        raise rows.error(lines[bad[0]], f"light_deg {l[bad[0]]:g} is outside [0, 90) degrees from the normal")
    if has_la:
        bad = np.flatnonzero((v < 0) | (v >= 90))
        if bad.size:
            raise rows.error(lines[bad[0]], f"view_deg {v[bad[0]]:g} is outside [0, 90) degrees "
                             "(with azimuth columns, angles are polar angles from the normal)")
        return l, v, cols["light_azimuth_deg"], cols["view_azimuth_deg"]
    bad = np.flatnonzero(np.abs(v) >= 90)
    if bad.size:
        raise rows.error(lines[bad[0]], f"view_deg {v[bad[0]]:g} is outside (-90, 90) degrees "
                         "(negative: on the light's side)")
    la = np.zeros_like(l)
    va = np.where(v < 0, 0.0, 180.0)
    return l, np.abs(v), la, va


def _geometry_keys(l, v, la, va) -> np.ndarray:
    key = np.stack([l, v, np.mod(la, 360.0), np.mod(va, 360.0)], axis=1)
    return np.round(key, _KEY_DIGITS)


def _fmt_geometry(l, v, la, va) -> str:
    return f"light {l:g}° view {v:g}° (azimuths {la:g}°, {va:g}°)"


def parse_measurement_text(text: str, source: str = "<text>", percent: bool | None = None,
                           light_deg: float = 45.0, view_deg: float = 0.0, light_azimuth_deg: float = 0.0,
                           view_azimuth_deg: float | None = None):
    r"""Parse measurement CSV text (see the module docstring for the forms).

    Parameters
    ----------
    text : str
        The CSV text (spectral or CIELAB columns).
    source : str
        Names the text in messages.
    percent : bool or None
        Reflectance unit: percent (True), fraction (False), or detected (None: percent if a value
        exceeds :data:`swatch.io.measurements.PERCENT_THRESHOLD`).
    light_deg, view_deg, light_azimuth_deg, view_azimuth_deg : float
        The geometry, degrees, for files without angle columns (``view_azimuth_deg`` None: opposite side).

    Returns
    -------
    swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        Spectra (reflectance as a fraction) or CIELAB, per geometry row.

    Raises
    ------
    swatch.core.errors.SwatchError
        One line naming the file, the line and what is wrong.

    Examples
    --------
    >>> m = parse_measurement_text("wavelength_nm,reflectance\n500,20\n600,35\n")
    >>> m.reflectance.tolist(), m.percent, (float(m.light_deg[0]), float(m.view_deg[0]))
    ([[0.2, 0.35]], True, (45.0, 0.0))
    """
    return parse_measurement_table(split_table(text, source), percent, light_deg, view_deg, light_azimuth_deg,
                                   view_azimuth_deg)


def parse_measurement_table(table: Table, percent: bool | None = None, light_deg: float = 45.0,
                            view_deg: float = 0.0, light_azimuth_deg: float = 0.0,
                            view_azimuth_deg: float | None = None):
    """:func:`parse_measurement_text` of a table already split (:func:`swatch.io.tabular.split_table`);
    extra columns (e.g. a sample id) are ignored.

    Parameters
    ----------
    table : swatch.io.tabular.Table
        The header and data rows of the text.
    percent, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg
        As :func:`parse_measurement_text`.

    Returns
    -------
    swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        Spectra (reflectance as a fraction) or CIELAB, per geometry row.

    Raises
    ------
    swatch.core.errors.SwatchError
        No data rows, or neither the spectral nor the CIELAB columns.
    """
    rows = _Rows("", table.source, table)
    if not rows.rows:
        raise rows.error(rows.header_line, "no data rows after the header")
    if rows.has("l", "a", "b"):
        return _parse_lab(rows, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    if rows.has("wavelength_nm", "reflectance"):
        return _parse_spectral(rows, percent, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    missing = [c for c in ("wavelength_nm", "reflectance") if c not in rows.header]
    raise rows.error(
        rows.header_line,
        f"missing column{'s' if len(missing) > 1 else ''} {', '.join(missing)}; the header must be "
        "wavelength_nm,reflectance (one spectrum), light_deg,view_deg[,light_azimuth_deg,view_azimuth_deg],"
        "wavelength_nm,reflectance (sBRDF set) or light_deg,view_deg,L,a,b (CIELAB)",
    )


def _parse_spectral(rows: _Rows, percent, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg):
    l, v, la, va = _geometry_columns(rows, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    cols = rows.columns(["wavelength_nm", "reflectance"])
    lines = rows.lines
    wl, refl = cols["wavelength_nm"], cols["reflectance"]
    bad = np.flatnonzero(wl <= 0)
    if bad.size:
        raise rows.error(lines[bad[0]], f"wavelength_nm {wl[bad[0]]:g} must be > 0 nm")

    keys = _geometry_keys(l, v, la, va)
    _ukeys, g_first, g_inv = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    g_inv = g_inv.reshape(-1)
    # Keep geometries in file order.
    order = np.argsort(g_first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    g_idx = rank[g_inv]
    G = order.size
    if G > MAX_FIT_GEOMETRIES:
        raise rows.error(lines[int(np.sort(g_first)[MAX_FIT_GEOMETRIES])], f"more than {MAX_FIT_GEOMETRIES} "
                         f"geometries; a measurement holds at most {MAX_FIT_GEOMETRIES} (an 86 × 86 sBRDF set: 7396)")

    wl_key = wl.copy()  # rounded where that cannot overflow (2e300 did: "appears twice", and numpy's warning lines)
    small = np.abs(wl) < 1e12
    wl_key[small] = np.round(wl[small], _KEY_DIGITS)
    uwl, w_first, w_inv = np.unique(wl_key, return_index=True, return_inverse=True)
    w_inv = w_inv.reshape(-1)
    W = uwl.size

    # Duplicates: the same (geometry, wavelength) twice.
    cell = g_idx * W + w_inv
    _, _cell_first, cell_count = np.unique(cell, return_index=True, return_counts=True)
    if np.any(cell_count > 1):
        seen = np.zeros(G * W, dtype=bool)
        for r, c in enumerate(cell):  # find the first repeated row (error path only)
            if seen[c]:
                raise rows.error(lines[r], f"wavelength {wl[r]:g} nm appears twice for "
                                 + _fmt_geometry(l[r], v[r], la[r], va[r]))
            seen[c] = True
    if W < 2:
        raise rows.error(lines[0], f"only one wavelength ({uwl[0]:g} nm); a spectrum needs at least 2 wavelengths")
    axis = check_spectral_axis(wl[w_first], rows.source, lambda i: f"line {lines[w_first[i]]}: wavelength_nm")
    # Completeness: every geometry has every wavelength.
    counts = np.bincount(g_idx, minlength=G)
    if np.any(counts != W):
        g_bad = int(np.flatnonzero(counts != W)[0])
        first_row = int(g_first[order[g_bad]])
        have = np.zeros(W, dtype=bool)
        have[w_inv[g_idx == g_bad]] = True
        missing = uwl[~have]
        raise rows.error(
            lines[first_row],
            f"{_fmt_geometry(l[first_row], v[first_row], la[first_row], va[first_row])} has "
            f"{counts[g_bad]} of the {W} wavelengths (missing {', '.join(f'{m:g}' for m in missing[:3])} nm"
            f"{' ...' if missing.size > 3 else ''}); every geometry needs the same wavelengths",
        )
    R = np.empty((G, W))
    R[g_idx, w_inv] = refl

    if percent is None:
        is_percent = bool(np.max(refl) > PERCENT_THRESHOLD)
        detected = True
    else:
        is_percent = bool(percent)
        detected = False
    if is_percent:
        R = R / 100.0
    low = np.flatnonzero((refl / (100.0 if is_percent else 1.0)) < MIN_REFLECTANCE)
    if low.size:
        unit = "%" if is_percent else ""
        raise rows.error(lines[low[0]], f"reflectance {refl[low[0]]:g}{unit} is negative; reflectance must be >= 0 "
                         f"(noise down to {MIN_REFLECTANCE * (100 if is_percent else 1):g}{unit} is accepted)")
    high = np.flatnonzero((refl / (100.0 if is_percent else 1.0)) > MAX_REFLECTANCE)
    if high.size:
        raise rows.error(lines[high[0]], f"reflectance {refl[high[0]]:g} is implausibly large; a reflectance "
                         f"factor must be at most {MAX_REFLECTANCE:g} (as a fraction)")
    if not np.any(R > 0):
        raise rows.error(lines[0], "every reflectance value is zero: there is nothing to fit")
    if not np.max(R) >= MIN_PEAK_REFLECTANCE:
        raise rows.error(lines[int(np.argmax(refl))], f"the largest reflectance is {np.max(R):.3g} (as a fraction): "
                         f"implausibly dark for a measurement; the peak must be at least {MIN_PEAK_REFLECTANCE:g}")

    first_rows = g_first[order]
    return SpectralMeasurement(
        source=rows.source,
        light_deg=l[first_rows], view_deg=v[first_rows],
        light_azimuth_deg=la[first_rows], view_azimuth_deg=va[first_rows],
        wavelength_nm=axis,
        reflectance=R, percent=is_percent, unit_detected=detected,
        geometry_line=lines[first_rows], wavelength_line=lines[w_first],
    )


def _parse_lab(rows: _Rows, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg):
    if not rows.has("light_deg") and len(rows.rows) > 1:
        raise rows.error(rows.rows[1][0], "several L,a,b rows need light_deg and view_deg columns "
                         "(one row per geometry)")
    if len(rows.rows) > MAX_FIT_GEOMETRIES:
        raise rows.error(rows.lines[MAX_FIT_GEOMETRIES], f"more than {MAX_FIT_GEOMETRIES} geometries; a measurement "
                         f"holds at most {MAX_FIT_GEOMETRIES} (one L,a,b row each)")
    l, v, la, va = _geometry_columns(rows, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    cols = rows.columns(["l", "a", "b"])
    lines = rows.lines
    Lab = np.stack([cols["l"], cols["a"], cols["b"]], axis=1)
    bad = np.flatnonzero((Lab[:, 0] < 0) | (Lab[:, 0] > 100))
    if bad.size:
        raise rows.error(lines[bad[0]], f"L {Lab[bad[0], 0]:g} is outside [0, 100]")
    bad = np.flatnonzero(np.abs(Lab[:, 1:]).max(axis=1) > MAX_LAB_AB)
    if bad.size:
        raise rows.error(lines[bad[0]], f"a {Lab[bad[0], 1]:g}, b {Lab[bad[0], 2]:g}: a and b must lie within "
                         f"±{MAX_LAB_AB:g}")
    keys = _geometry_keys(l, v, la, va)
    _, _first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        seen = set()
        for r, k in enumerate(map(tuple, keys)):
            if k in seen:
                raise rows.error(lines[r], _fmt_geometry(l[r], v[r], la[r], va[r]) + " appears twice")
            seen.add(k)
    return LabMeasurement(rows.source, l, v, la, va, Lab, geometry_line=lines)


def read_measurement(path, percent: bool | None = None, light_deg: float = 45.0, view_deg: float = 0.0,
                     light_azimuth_deg: float = 0.0, view_azimuth_deg: float | None = None):
    """Read a measurement CSV file (spectral or CIELAB; see the module docstring).

    Parameters
    ----------
    path : str or path-like
        The CSV (untrusted: size-capped before reading; non-regular files refused).
    percent : bool or None
        Reflectance given in percent (True) or as a fraction (False); None: detected from the values.
    light_deg, view_deg : float
        The geometry, degrees from the normal, for files without per-row angle columns.
    light_azimuth_deg, view_azimuth_deg : float
        Azimuths, degrees; ``view_azimuth_deg`` None puts the view opposite the light.

    Returns
    -------
    SpectralMeasurement or LabMeasurement
        Per-geometry spectra (reflectance factor, fraction) on the file's wavelengths, or CIELAB values.

    Raises
    ------
    SwatchError
        One line naming the file, the row or column, what is wrong and what is allowed.
    """
    p = Path(path)
    if not p.exists():
        raise SwatchError(f"{p}: no such file")
    if p.is_dir():
        raise SwatchError(f"{p} is a folder; give a CSV file")
    try:
        text = read_capped(p, MAX_MEASUREMENT_BYTES, "measurement file").decode("utf-8-sig")
    except UnicodeDecodeError:
        raise SwatchError(f"{p}: not a UTF-8 text file; give a CSV file") from None
    except OSError as exc:
        raise SwatchError(f"{p}: cannot read it ({exc.strerror})") from None
    return parse_measurement_text(text, str(p), percent, light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)


def read_spectral_csv(path, percent: bool | None = None, **geometry) -> SpectralMeasurement:
    """:func:`read_measurement` of a file that must hold spectra.

    Parameters
    ----------
    path : str or path-like
        The measurement CSV file.
    percent : bool or None
        As :func:`read_measurement`.
    **geometry
        ``light_deg``, ``view_deg``, ``light_azimuth_deg``, ``view_azimuth_deg`` (degrees).

    Returns
    -------
    swatch.io.measurements.SpectralMeasurement
        The spectra (reflectance as a fraction) per geometry.

    Raises
    ------
    swatch.core.errors.SwatchError
        The file holds CIELAB, or cannot be read.
    """
    m = read_measurement(path, percent, **geometry)
    if not isinstance(m, SpectralMeasurement):
        raise SwatchError(f"{path}: expected spectral columns wavelength_nm,reflectance, found CIELAB columns")
    return m


def read_lab_csv(path, **geometry) -> LabMeasurement:
    """:func:`read_measurement` of a file that must hold CIELAB.

    Parameters
    ----------
    path : str or path-like
        The measurement CSV file.
    **geometry
        ``light_deg``, ``view_deg``, ``light_azimuth_deg``, ``view_azimuth_deg`` (degrees).

    Returns
    -------
    swatch.io.measurements.LabMeasurement
        The CIELAB per geometry.

    Raises
    ------
    swatch.core.errors.SwatchError
        The file holds spectra, or cannot be read.
    """
    m = read_measurement(path, None, **geometry)
    if not isinstance(m, LabMeasurement):
        raise SwatchError(f"{path}: expected CIELAB columns L,a,b, found spectral columns")
    return m
