"""Delimited text tables as instruments and spreadsheets write them: the separator and the decimal
mark detected once, for every CSV reader of the package (measurements, coupons, instrument files).

European spreadsheets and instrument software export ``;``- or tab-separated files with decimal
commas (``45,2``). The separator is read from the header row: a tab if it has one, else ``;``,
else ``,``. With ``;`` or tab separators a number may use a decimal comma (``45,2`` → 45.2); a
thousands separator (``1.234,5``) is refused. With ``,`` separators decimal commas cannot be told
from separators: a data row with more fields than the header is refused with a hint to use
``;`` or tab. A header mixing ``;`` and ``,`` is ambiguous and refused in one line.
"""
from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_CSV_FIELD_CHARS

__all__ = ["Table", "split_table", "SEPARATORS"]

#: Separators a table may use, with the names the messages give them.
SEPARATORS = {"\t": "tab", ";": "';'", ",": "','"}
_DECIMAL_COMMA = re.compile(r"^[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?$")
_THOUSANDS = re.compile(r"^[+-]?\d{1,3}([.,]\d{3})+[.,]\d+$")


@dataclass(frozen=True)
class Table:
    """A delimited table: a header (as written, stripped) and numbered data rows.

    Attributes
    ----------
    source : str
        The file, for messages.
    separator : str
        One of :data:`SEPARATORS` (tab, ``;``, ``,``).
    header : list of str
        The column names.
    header_line : int
        The header's file line (1-based).
    rows : list of (int, list of str)
        (file line, fields) per data row; decimal commas already made points.
    """

    source: str
    separator: str
    header: list[str]
    header_line: int
    rows: list[tuple[int, list[str]]]

    @property
    def separator_name(self) -> str:
        """The separator as messages name it (``tab``, ``';'``, ``','``).

        Returns
        -------
        str
            The separator quoted, or ``tab``.
        """
        return SEPARATORS[self.separator]


def _pick_separator(line: str, source: str, line_no: int) -> str:
    if "\t" in line:
        return "\t"
    if ";" in line and "," in line:
        raise SwatchError(f"{source}: line {line_no}: the header mixes ';' and ',' separators; separate "
                          "columns by one of ',', ';' or tab (with ';' or tab a number may use a decimal comma)")
    if ";" in line:
        return ";"
    return ","


def _normalise(token: str, source: str, line_no: int) -> str:
    """A field with its decimal comma made a point (separators ';' or tab)."""
    if "," not in token:
        return token
    if _THOUSANDS.match(token) and "." in token:
        raise SwatchError(f"{source}: line {line_no}: {token!r} has a thousands separator; write numbers "
                          "without one (a decimal comma or point only)")
    if _DECIMAL_COMMA.match(token):
        return token.replace(",", ".")
    return token


def split_table(text: str, source: str, max_rows: int | None = None) -> Table:
    r"""Split delimited text into a header and data rows (``#`` comment lines and blank lines skipped).

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        Names the file in messages.
    max_rows : int, optional
        Caps the data rows (the message states the cap).

    Returns
    -------
    Table
        The separator, the header's cells and the data rows (line number, cells; decimal commas made points).

    Raises
    ------
    swatch.core.errors.SwatchError
        An empty text, a malformed row, an ambiguous separator, a thousands separator, or a
        comma-separated row that looks like it has decimal commas (one line, naming the file and line).

    Examples
    --------
    >>> t = split_table("voltage_V;L;a;b\n20;45,2;3,1;-20\n", "c.csv")
    >>> t.separator_name, t.header, t.rows
    ("';'", ['voltage_V', 'L', 'a', 'b'], [(2, ['20', '45.2', '3.1', '-20'])])
    """
    separator = None
    header: list[str] | None = None
    header_line = 0
    rows: list[tuple[int, list[str]]] = []
    for line_no, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if separator is None:
            separator = _pick_separator(line, source, line_no)
        try:
            fields = [f.strip() for f in next(csv.reader(io.StringIO(line), delimiter=separator))]
        except (csv.Error, StopIteration):
            raise SwatchError(f"{source}: line {line_no}: not a CSV row (a field longer than "
                              f"{MAX_CSV_FIELD_CHARS} characters, or a stray quote or NUL)") from None
        if header is None:
            header, header_line = fields, line_no
            continue
        if max_rows is not None and len(rows) >= max_rows:
            raise SwatchError(f"{source}: more than {max_rows} rows; a file has at most {max_rows}")
        if separator == ",":
            if len(fields) > len(header):
                raise SwatchError(
                    f"{source}: line {line_no}: {len(fields)} fields for a {len(header)}-column header; if the "
                    "numbers use decimal commas, separate the columns by ';' or tab")
        else:
            fields = [_normalise(f, source, line_no) for f in fields]
        rows.append((line_no, fields))
    if header is None or separator is None:
        raise SwatchError(f"{source}: the file is empty; give a CSV header row and data rows")
    return Table(source, separator, header, header_line, rows)
