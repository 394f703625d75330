"""One reader for every measurement file a command takes: CxF3, CGATS text or CSV, detected from
the content (not the extension), capped, and refused in one line when hostile or contradictory.

CSV (``,``, ``;`` or tab separated, decimal commas detected; see :mod:`swatch.io.tabular`) is the
format of :mod:`swatch.io.measurements`, plus an optional ``id`` (or ``sample_id``) column that
splits one file into several samples (parts); without it the file is one sample named after it.
"""
from __future__ import annotations

from pathlib import Path

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_INSTRUMENT_SAMPLES, MAX_MEASUREMENT_BYTES, read_capped
from swatch.io.cgats import is_cgats, read_cgats
from swatch.io.cxf_in import is_cxf, read_cxf3
from swatch.io.instruments import InstrumentFile, Request, Sample
from swatch.io.measurement_csv import parse_measurement_table
from swatch.io.tabular import Table, split_table

__all__ = ["read_instrument_file", "ID_COLUMNS"]

#: CSV columns that name the sample of each row (several parts in one file).
ID_COLUMNS = ("id", "sample_id", "sample")


def _read_bytes(path: Path) -> bytes:
    try:
        return read_capped(path, MAX_MEASUREMENT_BYTES, "measurement file")
    except FileNotFoundError:
        raise SwatchError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise SwatchError(f"{path} is a folder; give a measurement file (CxF3, CGATS or CSV)") from None
    except OSError as exc:
        raise SwatchError(f"{path}: cannot read it ({exc.strerror})") from None


def _csv(table: Table, request: Request) -> tuple[Sample, ...]:
    geom = (request.light_deg, request.view_deg, request.light_azimuth_deg, request.view_azimuth_deg)
    lower = [h.lower() for h in table.header]
    id_col = next((lower.index(c) for c in ID_COLUMNS if c in lower), None)
    if id_col is None:
        m = parse_measurement_table(table, request.percent, *geom)
        return (Sample(Path(table.source).stem, m),)
    groups: dict[str, list] = {}
    for line_no, fields in table.rows:
        key = fields[id_col] if id_col < len(fields) else ""
        if not key:
            raise SwatchError(f"{table.source}: line {line_no}: the {table.header[id_col]} column is empty")
        if key not in groups and len(groups) >= MAX_INSTRUMENT_SAMPLES:
            raise SwatchError(f"{table.source}: more than {MAX_INSTRUMENT_SAMPLES} samples; a file holds at most "
                              f"{MAX_INSTRUMENT_SAMPLES}")
        groups.setdefault(key, []).append((line_no, fields))
    out = []
    for key, rows in groups.items():
        sub = Table(table.source, table.separator, table.header, table.header_line, rows)
        m = parse_measurement_table(sub, request.percent, *geom)
        out.append(Sample(key, m))
    return tuple(out)


def read_instrument_file(path, request: Request | None = None) -> InstrumentFile:
    """Read a measurement file (CxF3, CGATS or CSV) into its samples.

    Parameters
    ----------
    path : path-like
        The file (at most :data:`swatch.core.limits.MAX_MEASUREMENT_BYTES`).
    request : Request
        The command line's geometry, illuminant, observer and reflectance unit, and which of them
        were given explicitly (those must agree with what the file states).

    Returns
    -------
    InstrumentFile
        The samples and the illuminant and observer to read them under.
    """
    request = request or Request()
    p = Path(path)
    source = str(path)
    data = _read_bytes(p)
    if is_cxf(data):
        return read_cxf3(data, source, request)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        if b"BEGIN_DATA_FORMAT" not in data:
            raise SwatchError(f"{source}: not UTF-8 text; give a CxF3, CGATS or CSV file") from None
        text = data.decode("cp1252", errors="replace")  # CGATS from Windows software (e.g. "2°" in cp1252)
    if is_cgats(text):
        return read_cgats(text, source, request)
    samples = _csv(split_table(text, source), request)
    return InstrumentFile(source, "csv", samples, request.illuminant, request.observer, {})
