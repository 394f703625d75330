"""CGATS.17 / ISO 28178 measurement text (i1Profiler, ArgyllCMS ``.ti3``, instrument exports).

Layout: an identifier line (``CGATS.17``, ``CTI3``, ``ISO28178`` …), ``KEYWORD value`` header
lines, ``BEGIN_DATA_FORMAT`` field names ``END_DATA_FORMAT``, then ``BEGIN_DATA`` rows ``END_DATA``
(whitespace separated, strings in double quotes; ``#`` starts a comment). Fields read:

* the sample: ``SAMPLE_NAME``, ``SAMPLE_ID`` / ``SampleID``, ``SAMPLE_LOC`` (the first present names it);
* CIELAB ``LAB_L LAB_A LAB_B``, or CIE XYZ ``XYZ_X XYZ_Y XYZ_Z`` (white Y = 100), or spectra:
  ``SPECTRAL_NNN`` / ``SPECTRAL_NM_NNN`` / ``SPECTRAL_NMNNN`` (CGATS.17), ``nmNNN`` (i1Profiler),
  ``SPEC_NNN`` (ArgyllCMS, whose bands are ``SPECTRAL_BANDS`` from ``SPECTRAL_START_NM`` to
  ``SPECTRAL_END_NM``: the names are the wavelengths rounded to whole nm, and must agree), the axis
  checked by :func:`swatch.io.measurements.check_spectral_axis`; CIE values beside spectra must be
  finite numbers (CIELAB within range) though the spectra decide;
* optional ``VOLTAGE_V`` (or ``VOLTAGE``) and ``THICKNESS_NM`` (coupons for ``swatch calibrate``).

Header conditions: ``MEASUREMENT_SOURCE "Illumination=D50 ObserverAngle=2 …"`` (i1Profiler),
``ILLUMINANT`` / ``ILLUMINATION_NAME``, ``OBSERVER`` / ``OBSERVER_ANGLE``, ``WEIGHTING_FUNCTION
"ILLUMINANT, D50"`` / ``"OBSERVER, 2 degree"`` and ``MEASUREMENT_GEOMETRY "45/0"``. A ``.ti3``
file's CIE values are D50 / 2° unless it says otherwise (ArgyllCMS's documented default) and its
reflectance is in percent. Statements that contradict each other are refused. Counts in the header
(``NUMBER_OF_SETS``, ``NUMBER_OF_FIELDS``, ``SPECTRAL_BANDS``) are whole numbers of at most
MAX_HEADER_COUNT_CHARS digits, within their caps.
"""
from __future__ import annotations

import re

import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.core.errors import SwatchError
from swatch.core.limits import (
    MAX_HEADER_COUNT_CHARS,
    MAX_INSTRUMENT_FIELDS,
    MAX_INSTRUMENT_SAMPLES,
    MAX_LAB_AB,
    MAX_WAVELENGTHS,
)
from swatch.io.instruments import (
    InstrumentFile,
    Request,
    Sample,
    check_agrees,
    check_lab,
    lab_sample,
    parse_geometry_text,
    parse_illuminant,
    parse_observer,
    same_geometries,
    spectral_sample,
)
from swatch.io.measurements import check_spectral_axis
from swatch.physics.materials import wavelength_grid

__all__ = ["is_cgats", "read_cgats"]

_TOKEN = re.compile(r'"[^"]*"|\S+')
_SPECTRAL = re.compile(r"^(?:SPECTRAL_NM_?|SPECTRAL_|SPEC_|NM_?|R)(\d{3,4}(?:\.\d+)?)$", re.IGNORECASE)
_ID_FIELDS = ("SAMPLE_NAME", "SAMPLE_ID", "SAMPLEID", "SAMPLE_LOC")
_DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?$")


def is_cgats(text: str) -> bool:
    r"""Whether ``text`` looks like CGATS (it has a ``BEGIN_DATA_FORMAT`` line).

    Parameters
    ----------
    text : str
        A measurement file's text.

    Returns
    -------
    bool
        True when a line is ``BEGIN_DATA_FORMAT`` (the text is then read as CGATS).

    Examples
    --------
    >>> is_cgats("CGATS.17\nBEGIN_DATA_FORMAT\nSAMPLE_ID LAB_L\nEND_DATA_FORMAT\n"), is_cgats("L,a,b\n")
    (True, False)
    """
    return re.search(r"^\s*BEGIN_DATA_FORMAT\s*$", text, re.MULTILINE) is not None


def _tokens(line: str) -> list[str]:
    line = line.split("#", 1)[0] if '"' not in line else line
    return [t[1:-1] if t.startswith('"') else t for t in _TOKEN.findall(line)]


def _parse(text: str, source: str):
    """(identifier, keywords {name: [values]}, fields, rows [(line, tokens)])."""
    lines = text.splitlines()
    ident = next((ln.strip() for ln in lines if ln.strip() and not ln.lstrip().startswith("#")), "")
    keywords: dict[str, list[str]] = {}
    fields: list[str] = []
    rows: list[tuple[int, list[str]]] = []
    state, tables = "header", 0
    for no, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        word = stripped.split()[0].upper()
        if word == "BEGIN_DATA_FORMAT":
            tables += 1
            if tables > 1:
                raise SwatchError(f"{source}: line {no}: a second table; a measurement file holds one table "
                                  "(split it, one table per file)")
            state = "format"
        elif word == "END_DATA_FORMAT":
            state = "header"
        elif word == "BEGIN_DATA":
            state = "data"
        elif word == "END_DATA":
            state = "header"
        elif state == "format":
            fields += _tokens(stripped)
            if len(fields) > MAX_INSTRUMENT_FIELDS:
                raise SwatchError(f"{source}: more than {MAX_INSTRUMENT_FIELDS} fields; a CGATS table has at most "
                                  f"{MAX_INSTRUMENT_FIELDS}")
        elif state == "data":
            if len(rows) >= MAX_INSTRUMENT_SAMPLES:
                raise SwatchError(f"{source}: more than {MAX_INSTRUMENT_SAMPLES} samples; a file holds at most "
                                  f"{MAX_INSTRUMENT_SAMPLES}")
            rows.append((no, _tokens(stripped)))
        elif no > 1 or stripped != ident:
            toks = _tokens(stripped)
            if toks and toks[0].upper() != "KEYWORD":
                keywords.setdefault(toks[0].upper(), []).append(" ".join(toks[1:]))
    if state == "data":
        raise SwatchError(f"{source}: BEGIN_DATA without END_DATA; the file is cut short")
    if not fields:
        raise SwatchError(f"{source}: no field names between BEGIN_DATA_FORMAT and END_DATA_FORMAT")
    if not rows:
        raise SwatchError(f"{source}: no data rows between BEGIN_DATA and END_DATA")
    for key, have, what, cap in (("NUMBER_OF_SETS", len(rows), "data rows", MAX_INSTRUMENT_SAMPLES),
                                 ("NUMBER_OF_FIELDS", len(fields), "fields", MAX_INSTRUMENT_FIELDS)):
        stated = _count(keywords, key, source, 1, cap)
        if stated is not None and stated != have:
            raise SwatchError(f"{source}: {key} says {stated} but the table has {have} {what}; the file is "
                              "cut short or edited by hand")
    _count(keywords, "SPECTRAL_BANDS", source, 2, MAX_WAVELENGTHS)  # a count wherever stated (used with spectra)
    return ident, keywords, fields, rows


def _shown(tok: str) -> str:
    """A header value for a message: quoted, cut to 40 characters."""
    return repr(tok) if len(tok) <= 40 else f"{tok[:24]!r}… ({len(tok)} characters)"


def _count(keywords: dict[str, list[str]], key: str, source: str, lo: int, hi: int) -> int | None:
    """A header count (``NUMBER_OF_SETS`` …) where stated: ASCII digits, at most MAX_HEADER_COUNT_CHARS of them
    (checked before :func:`int`, whose digit limit a 5 000-digit value would hit), within ``lo`` to ``hi``."""
    stated = keywords.get(key)
    if not stated:
        return None
    tok = stated[0].strip()
    if len(tok) > MAX_HEADER_COUNT_CHARS or re.fullmatch(r"[0-9]+", tok) is None:
        raise SwatchError(f"{source}: {key} {_shown(tok)} is not a whole number of at most {MAX_HEADER_COUNT_CHARS} "
                          f"digits; allowed {lo} to {hi}")
    n = int(tok)
    if not lo <= n <= hi:
        raise SwatchError(f"{source}: {key} {n} is out of range; allowed {lo} to {hi}")
    return n


def _header_nm(keywords: dict[str, list[str]], key: str, source: str) -> float:
    tok = keywords[key][0].strip()
    tok = tok.replace(",", ".") if _DECIMAL_COMMA.match(tok) else tok
    try:
        return float(tok)
    except ValueError:
        raise SwatchError(f"{source}: {key} {_shown(tok)} is not a number; give the wavelength in nm") from None


def _stated(ident: str, kw: dict[str, list[str]], source: str) -> dict:
    """The illuminant, observer and geometry the header states: {what: (value, where)}."""
    found: dict[str, list[tuple[str, str]]] = {"illuminant": [], "observer": [], "geometry": []}
    for text in kw.get("MEASUREMENT_SOURCE", []):
        for k, v in re.findall(r"(\w+)\s*=\s*([^\s\t]+)", text):
            if k.lower() in ("illumination", "illuminant"):
                found["illuminant"].append((v, "MEASUREMENT_SOURCE"))
            elif k.lower() in ("observerangle", "observer"):
                found["observer"].append((v, "MEASUREMENT_SOURCE"))
    for key in ("ILLUMINANT", "ILLUMINATION_NAME", "ILLUMINATION"):
        found["illuminant"] += [(v, key) for v in kw.get(key, [])]
    for key in ("OBSERVER", "OBSERVER_ANGLE"):
        found["observer"] += [(v, key) for v in kw.get(key, [])]
    for text in kw.get("WEIGHTING_FUNCTION", []):
        what, _, value = text.partition(",")
        if what.strip().upper() == "ILLUMINANT":
            found["illuminant"].append((value, "WEIGHTING_FUNCTION"))
        elif what.strip().upper() == "OBSERVER":
            found["observer"].append((value, "WEIGHTING_FUNCTION"))
    found["geometry"] += [(v, "MEASUREMENT_GEOMETRY") for v in kw.get("MEASUREMENT_GEOMETRY", [])]
    parse = {"illuminant": parse_illuminant, "observer": parse_observer, "geometry": parse_geometry_text}
    out = {}
    for what, items in found.items():
        values = [(parse[what](v, f"{source}: {where}"), where) for v, where in items]
        distinct = {str(v) for v, _ in values}
        if len(distinct) > 1:
            raise SwatchError(f"{source}: the header states two {what}s ({' and '.join(sorted(distinct))}); "
                              "a file is measured under one")
        if values:
            out[what] = values[0]
    if ident.upper().startswith("CTI3"):  # ArgyllCMS: CIE values are D50 (ICC PCS), 2° unless stated
        if "ILLUMINANT_WHITE_POINT_XYZ" in kw and "illuminant" not in out:
            raise SwatchError(f"{source}: ILLUMINANT_WHITE_POINT_XYZ gives a custom white; swatch reads CIE "
                              "illuminants only (give the spectra, or state ILLUMINANT)")
        out.setdefault("illuminant", ("D50", "ArgyllCMS .ti3 default"))
        out.setdefault("observer", ("2", "ArgyllCMS .ti3 default"))
    return out


def _number(tok: str, source: str, line: int, name: str) -> float:
    if _DECIMAL_COMMA.match(tok):
        tok = tok.replace(",", ".")
    try:
        return float(tok)
    except ValueError:
        raise SwatchError(f"{source}: line {line}: {name} {tok!r} is not a number") from None


def _column(rows, idx: int, source: str, name: str) -> np.ndarray:
    return np.array([_number(r[idx], source, no, name) for no, r in rows])


def _finite_column(rows, idx: int, source: str, name: str) -> np.ndarray:
    """A CIE value column (``LAB_L`` … ``XYZ_Z``), every value a finite number (checked beside spectra too,
    as CxF3's CIELAB is: a bad value is a bad file)."""
    values = _column(rows, idx, source, name)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        no, r = rows[int(bad[0])]
        raise SwatchError(f"{source}: line {no}: {name} {_shown(r[idx])} is not a finite number (NaN or infinite); "
                          "every value must be a number")
    return values


def _spectral_axis(kw: dict[str, list[str]], source: str, named: np.ndarray, labels: list[str]) -> np.ndarray:
    """The wavelengths of the spectral fields: ``SPECTRAL_BANDS`` from ``SPECTRAL_START_NM`` to ``SPECTRAL_END_NM``
    where the header states all three (ArgyllCMS; the field names, rounded to whole nm, must agree), else the
    field names'; checked by :func:`swatch.io.measurements.check_spectral_axis`."""
    keys = ("SPECTRAL_BANDS", "SPECTRAL_START_NM", "SPECTRAL_END_NM")
    if not all(k in kw for k in keys):
        return check_spectral_axis(named, source, labels)
    bands = _count(kw, "SPECTRAL_BANDS", source, 2, MAX_WAVELENGTHS)
    if bands != named.size:
        raise SwatchError(f"{source}: SPECTRAL_BANDS says {bands} bands but {named.size} spectral fields follow")
    ends = [_header_nm(kw, k, source) for k in keys[1:]]
    check_spectral_axis(ends, source, list(keys[1:]))  # finite, inside the range, start below end
    wl = np.linspace(ends[0], ends[1], bands)
    off = np.flatnonzero(np.abs(wl - named) > 0.5 + 1e-6)
    if off.size:
        i = int(off[0])
        raise SwatchError(f"{source}: {labels[i]} names {named[i]:g} nm but SPECTRAL_BANDS {bands} from "
                          f"SPECTRAL_START_NM {ends[0]:g} to SPECTRAL_END_NM {ends[1]:g} nm put it at {wl[i]:g} nm; "
                          "the field names are the bands' wavelengths rounded to whole nm")
    return check_spectral_axis(wl, source, labels)


def read_cgats(text: str, source: str, request: Request) -> InstrumentFile:
    """Read CGATS.17 / ISO 28178 text into samples (see the module docstring for the fields and header
    statements read).

    Parameters
    ----------
    text : str
        The file's text (already size-capped by the caller).
    source : str
        Names the file in messages.
    request : swatch.io.instruments.Request
        The command line's geometry, illuminant, observer and reflectance unit; a file statement that
        contradicts an explicit option is refused.

    Returns
    -------
    swatch.io.instruments.InstrumentFile
        Format ``"cgats"``; CIELAB (XYZ converted under the file's illuminant and observer) or spectra.

    Raises
    ------
    swatch.core.errors.SwatchError
        Malformed blocks, repeated or missing fields, too many samples or fields (the caps of
        :mod:`swatch.core.limits`), contradictory statements, or bad values (one line naming the line).
    """
    ident, kw, fields, rows = _parse(text, source)
    upper = [f.upper() for f in fields]
    col = {f: i for i, f in enumerate(upper)}
    if len(col) != len(upper):
        raise SwatchError(f"{source}: a field name is repeated in BEGIN_DATA_FORMAT")
    for no, r in rows:
        if len(r) != len(fields):
            raise SwatchError(f"{source}: line {no}: {len(r)} values for {len(fields)} fields")
    stated = _stated(ident, kw, source)
    geom = stated.get("geometry")
    check_agrees(source, "geometry", geom[0] if geom else None, geom[1] if geom else "", request, "geometry",
                 (request.light_deg, request.view_deg), "`light_deg`/`view_deg`")
    light, view = geom[0] if geom else (request.light_deg, request.view_deg)
    if request.view_azimuth_deg is not None or request.light_azimuth_deg:
        raise SwatchError(f"{source}: azimuths apply to CSV files with angle columns; a CGATS file is in plane")
    ids = next((i for i in (col.get(n) for n in _ID_FIELDS) if i is not None), None)
    names = [r[ids] if ids is not None else str(k + 1) for k, (_, r) in enumerate(rows)]
    volts = next((_column(rows, col[n], source, n) for n in ("VOLTAGE_V", "VOLTAGE") if n in col), None)
    thick = _column(rows, col["THICKNESS_NM"], source, "THICKNESS_NM") if "THICKNESS_NM" in col else None
    spectral = [(i, float(m.group(1))) for i, f in enumerate(fields) if (m := _SPECTRAL.match(f))]
    samples: list[Sample] = []

    def extra(k):
        return (None if volts is None else float(volts[k]), None if thick is None else float(thick[k]))

    lab = [col.get(n) for n in ("LAB_L", "LAB_A", "LAB_B")]
    xyz = [col.get(n) for n in ("XYZ_X", "XYZ_Y", "XYZ_Z")]
    cie = {i: _finite_column(rows, i, source, fields[i]) for i in (*lab, *xyz) if i is not None}
    if spectral:
        idx = [i for i, _ in spectral]
        wl = _spectral_axis(kw, source, np.array([w for _, w in spectral]), [fields[i] for i in idx])
        data = np.array([[_number(r[i], source, no, fields[i]) for i in idx] for no, r in rows])
        percent = request.percent if request.percent is not None else (True if ident.upper().startswith("CTI3")
                                                                      else None)
        if None not in lab:  # the file's own CIELAB beside its spectra: checked as CxF3's is (finite above)
            L = np.stack([cie[i] for i in lab], axis=1)  # type: ignore[index]
            out_of_range = (L[:, 0] < 0) | (L[:, 0] > 100) | np.any(np.abs(L[:, 1:]) > MAX_LAB_AB, axis=1)
            for k in np.flatnonzero(out_of_range)[:1]:
                check_lab(source, names[k], L[k])  # (raises, naming the sample)
        for k, name in enumerate(names):
            samples.append(spectral_sample(source, name, [(light, view)], wl, data[k], percent, *extra(k)))
    else:
        if None in lab and None in xyz:
            raise SwatchError(f"{source}: no LAB_L/LAB_A/LAB_B, XYZ_X/XYZ_Y/XYZ_Z or spectral (SPECTRAL_NNN, nmNNN, "
                              "SPEC_NNN) fields; nothing to read")
        illuminant, observer = _white(stated, request, source)
        if None not in lab:
            Lab = np.stack([cie[i] for i in lab], axis=1)  # type: ignore[index]
        else:
            XYZ = np.stack([cie[i] for i in xyz], axis=1)  # type: ignore[index]
            Lab = get_colorimeter(wavelength_grid(380.0, 780.0, 5.0), illuminant, observer).Lab(XYZ)
        for k, name in enumerate(names):
            samples.append(lab_sample(source, name, [(light, view)], Lab[k], *extra(k)))
    out = tuple(samples)
    same_geometries(out, source)
    ill, obs = _resolve(stated, request, source)
    return InstrumentFile(source, "cgats", out, ill, obs,
                          {k: (v[0] if k != "geometry" else f"{v[0][0]:g}/{v[0][1]:g}") for k, v in stated.items()})


def _resolve(stated: dict, request: Request, source: str) -> tuple[str, str]:
    for what, option in (("illuminant", "`illuminant`"), ("observer", "`observer`")):
        s = stated.get(what)
        cli = request.illuminant if what == "illuminant" else request.observer
        if s is not None and what in request.given:
            cli_norm = parse_illuminant(cli, "`illuminant`") if what == "illuminant" else parse_observer(cli, option)
            check_agrees(source, what, s[0], s[1], request, what, cli_norm, option)
    ill = stated["illuminant"][0] if "illuminant" in stated else request.illuminant
    obs = stated["observer"][0] if "observer" in stated else request.observer
    return ill, obs


def _white(stated: dict, request: Request, source: str) -> tuple[str, str]:
    """The white point CIE values from the file are relative to: stated, or given explicitly."""
    missing = [w for w in ("illuminant", "observer") if w not in stated and w not in request.given]
    if missing:
        raise SwatchError(f"{source}: CIE values without a white point: the file states no {' or '.join(missing)}; "
                          "give `illuminant` and `observer` as measured (e.g. D50 and 2)")
    return _resolve(stated, request, source)
