#!/usr/bin/env python3
"""Convert refractiveindex.info YAML files into the plain CSV tables used by ``swatch``.

Source: the refractiveindex.info database (M. N. Polyanskiy, "Refractiveindex.info
database of optical constants", Scientific Data 11, 94 (2024)), public domain
(CC0 1.0), copied unchanged into ``../shared/data/refractiveindex/<material>/`` (beside the repository).

Output: ``tables/optical/<Material>-<Author>.csv`` with ``#`` comment header lines
(material, reference, DOI, original database path, database citation, licence,
role, wavelength range) followed by a ``wavelength_nm,n,k`` header row and the
data rows.  Convention: complex index ``n + i k`` with ``k >= 0`` meaning absorption.

* Wavelengths are converted µm -> nm exactly (decimal arithmetic), so no rounding
  is introduced beyond the ``repr`` of the resulting float.
* ``n`` and ``k`` are written as ``repr(float(value))`` of the source text.
* ``tabulated nk`` rows are kept in full (the whole measured range).
* ``tabulated n`` (k = 0), ``tabulated k`` and ``formula 1``
  (Sellmeier) / ``formula 4`` (RefractiveIndex.INFO formula) blocks are supported;
  formula blocks are tabulated every 1 nm over their valid range clipped to
  200-2000 nm.  Several DATA blocks of one file are merged (see ``merge_blocks``).
  ``tabulated n2`` blocks hold the nonlinear (Kerr) index, not n, and are ignored.
* Files whose data do not cover 380-780 nm are skipped (reported on stdout).

The YAML subset used by the database is parsed by a tiny reader here, so the script
needs only the Python standard library and numpy (no PyYAML).

Usage::

    python scripts/convert_refractiveindex.py [--source DIR] [--output DIR]
"""

from __future__ import annotations

import argparse
import html
import re
import sys
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path

import numpy as np

REPO_DIR = Path(__file__).resolve().parent.parent
DEFAULT_SOURCE_DIR = REPO_DIR.parent / "shared" / "data" / "refractiveindex"
DEFAULT_OUTPUT_DIR = REPO_DIR / "tables" / "optical"

DATABASE_CITATION = (
    'M. N. Polyanskiy, "Refractiveindex.info database of optical constants", '
    "Scientific Data 11, 94 (2024), doi:10.1038/s41597-023-02898-2"
)
LICENSE = "CC0 1.0 (public domain dedication; copyright and related rights waived)"

#: Visible range every converted table must cover (nm).
REQUIRED_RANGE_NM = (380.0, 780.0)
#: Range and step used to tabulate formula-based data (nm).
FORMULA_RANGE_NM = (200.0, 2000.0)
FORMULA_STEP_NM = 1

#: Chemical formula -> plain name, for the ``# material:`` header line.
MATERIAL_NAMES = {
    "Ti": "titanium",
    "Nb": "niobium",
    "Ta": "tantalum",
    "TiO2": "titanium dioxide",
    "Nb2O5": "niobium pentoxide",
    "Ta2O5": "tantalum pentoxide",
}

#: (folder, file stem, role) of every file to convert, in output order.
SELECTION: tuple[tuple[str, str, str], ...] = (
    ("Ti", "Johnson", "substrate"),  # default substrate
    ("Ti", "Palm", "substrate"),
    ("Ti", "Rakic-LD", "substrate"),
    ("Ti", "Rakic-BB", "substrate"),
    ("Ti", "Werner", "substrate"),
    ("Nb", "Weaver", "substrate"),
    ("Nb", "Golovashkin-293K", "substrate"),
    ("Ta", "Werner", "substrate"),
    ("Ta", "Ordal", "substrate"),
    ("TiO2", "Siefke", "film"),  # default film
    ("TiO2", "Jolivet-amorphous", "film"),
    ("TiO2", "Franta", "film"),
    ("TiO2", "Sarkar", "film"),
    ("TiO2", "Zhukovsky", "film"),
    ("TiO2", "Kischkat", "film"),
    ("Nb2O5", "Franta", "film"),
    ("Nb2O5", "Lemarchand", "film"),
    ("Ta2O5", "Bright-amorphous", "film"),
    ("Ta2O5", "Franta-2015", "film"),
    ("Ta2O5", "Gao", "film"),
)


# --------------------------------------------------------------------------- YAML


@dataclass
class DataBlock:
    """One entry of a file's ``DATA`` list."""

    type: str
    data: str = ""  # tabulated rows (text)
    wavelength_range: str = ""  # formula validity range, µm
    coefficients: str = ""  # formula coefficients


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip(" "))


def parse_database_yaml(text: str) -> tuple[dict[str, str], list[DataBlock]]:
    """Parse the YAML subset used by refractiveindex.info ``nk`` files.

    Returns the top-level scalar / literal-block fields (``REFERENCES``,
    ``COMMENTS``, ...) as text, and the ``DATA`` list.  Nested mappings other than
    ``DATA`` (e.g. ``CONDITIONS``) are returned as their raw indented text.
    """
    lines = text.splitlines()
    fields: dict[str, str] = {}
    blocks: list[DataBlock] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if not line.strip() or line.lstrip().startswith("#") or _indent(line) > 0:
            i += 1
            continue
        match = re.match(r"^([A-Za-z_]+):\s*(.*)$", line)
        if match is None:
            raise ValueError(f"unexpected top-level line {i + 1}: {line!r}")
        key, value = match.group(1), match.group(2).strip()
        i += 1
        body: list[str] = []
        while i < len(lines) and (not lines[i].strip() or _indent(lines[i]) > 0):
            body.append(lines[i])
            i += 1
        if key == "DATA":
            blocks = _parse_data_list(body)
        elif value in ("|", ">", ""):
            fields[key] = "\n".join(b.strip() for b in body).strip()
        else:
            fields[key] = value
    return fields, blocks


def _parse_data_list(body: list[str]) -> list[DataBlock]:
    blocks: list[DataBlock] = []
    current: DataBlock | None = None
    i = 0
    while i < len(body):
        line = body[i]
        stripped = line.strip()
        if not stripped:
            i += 1
            continue
        item_indent = _indent(line)
        if stripped.startswith("- "):
            current = DataBlock(type="")
            blocks.append(current)
            stripped = stripped[2:].strip()
            item_indent += 2
        if current is None:
            raise ValueError(f"DATA entry outside a list item: {line!r}")
        key, _, value = stripped.partition(":")
        key, value = key.strip(), value.strip()
        i += 1
        if value == "|":
            rows: list[str] = []
            while i < len(body) and (not body[i].strip() or _indent(body[i]) > item_indent):
                if body[i].strip():
                    rows.append(body[i].strip())
                i += 1
            value = "\n".join(rows)
        if key in ("type", "data", "wavelength_range", "coefficients"):
            setattr(current, key, value)
    return blocks


# ------------------------------------------------------------------ DATA -> n, k


def um_text_to_nm(text: str) -> float:
    """Exact decimal µm -> nm conversion of a source number (no binary rounding drift)."""
    return float(Decimal(text) * 1000)


def parse_rows(text: str, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """Return (wavelength_nm, values[rows, columns-1]) from tabulated data text."""
    wavelength_nm: list[float] = []
    values: list[list[float]] = []
    for row in text.splitlines():
        parts = row.split()
        if len(parts) != columns:
            raise ValueError(f"expected {columns} columns, got {row!r}")
        wavelength_nm.append(um_text_to_nm(parts[0]))
        values.append([float(p) for p in parts[1:]])
    return np.array(wavelength_nm), np.array(values).reshape(len(values), columns - 1)


def formula_n(kind: int, coefficients: np.ndarray, wavelength_um: np.ndarray) -> np.ndarray:
    """Evaluate refractiveindex.info dispersion formula 1 or 4 (wavelength in µm)."""
    c = np.concatenate([coefficients, np.zeros(max(0, 17 - coefficients.size))])
    lam = wavelength_um
    if kind == 1:  # Sellmeier: n^2 - 1 = C1 + sum_i C(2i) lam^2 / (lam^2 - C(2i+1)^2)
        n2 = 1.0 + c[0]
        for j in range(1, coefficients.size - 1, 2):
            n2 = n2 + c[j] * lam**2 / (lam**2 - c[j + 1] ** 2)
        return np.sqrt(n2)
    if kind == 4:  # n^2 = C1 + C2 lam^C3/(lam^2 - C4^C5) + C6 lam^C7/(lam^2 - C8^C9) + sum C lam^C
        n2 = c[0] + c[1] * lam ** c[2] / (lam**2 - c[3] ** c[4])
        n2 = n2 + c[5] * lam ** c[6] / (lam**2 - c[7] ** c[8])
        for j in range(9, coefficients.size - 1, 2):
            n2 = n2 + c[j] * lam ** c[j + 1]
        return np.sqrt(n2)
    raise NotImplementedError(f"formula {kind} is not implemented")


@dataclass
class Series:
    """One quantity (n or k) tabulated on its own wavelength grid."""

    wavelength_nm: np.ndarray
    values: np.ndarray


def block_series(block: DataBlock) -> tuple[Series | None, Series | None]:
    """Return the (n, k) series a DATA block provides (None where it provides none)."""
    kind = block.type.strip()
    if kind == "tabulated nk":
        wl, v = parse_rows(block.data, 3)
        return Series(wl, v[:, 0]), Series(wl, v[:, 1])
    if kind == "tabulated n":
        wl, v = parse_rows(block.data, 2)
        return Series(wl, v[:, 0]), None
    if kind == "tabulated k":
        wl, v = parse_rows(block.data, 2)
        return None, Series(wl, v[:, 0])
    if kind == "tabulated n2":
        # Nonlinear (Kerr) index n2 in m^2/W: no linear optical constants, ignored.
        parse_rows(block.data, 2)  # still validate the block
        return None, None
    match = re.fullmatch(r"formula (\d+)", kind)
    if match:
        lo_um, hi_um = (Decimal(x) for x in block.wavelength_range.split())
        lo_nm = max(float(lo_um * 1000), FORMULA_RANGE_NM[0])
        hi_nm = min(float(hi_um * 1000), FORMULA_RANGE_NM[1])
        first, last = int(np.ceil(lo_nm)), int(np.floor(hi_nm))
        wl = np.arange(first, last + 1, FORMULA_STEP_NM, dtype=float)
        coeffs = np.array([float(x) for x in block.coefficients.split()])
        return Series(wl, formula_n(int(match.group(1)), coeffs, wl / 1000.0)), None
    raise NotImplementedError(f"DATA type {kind!r} is not supported")


def _join(series: list[Series]) -> Series | None:
    """Concatenate series of one quantity, sorted by wavelength; identical duplicates dropped."""
    if not series:
        return None
    wl = np.concatenate([s.wavelength_nm for s in series])
    v = np.concatenate([s.values for s in series])
    order = np.argsort(wl, kind="stable")
    wl, v = wl[order], v[order]
    keep = np.ones(wl.size, dtype=bool)
    dup = wl[1:] == wl[:-1]
    if np.any(dup & (v[1:] != v[:-1])):
        raise ValueError("conflicting values at a repeated wavelength")
    keep[1:] = ~dup
    return Series(wl[keep], v[keep])


def merge_blocks(blocks: list[DataBlock]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge a file's DATA blocks into one (wavelength_nm, n, k) table.

    The output grid is the n grid.  If k comes from a separate block on a different
    grid, the n grid is clipped to the k range and k is interpolated linearly onto it
    (never extrapolated).  Without any k data, k = 0 (transparent).
    """
    ns, ks = [], []
    for block in blocks:
        n_series, k_series = block_series(block)
        if n_series is not None:
            ns.append(n_series)
        if k_series is not None:
            ks.append(k_series)
    n_all, k_all = _join(ns), _join(ks)
    if n_all is None:
        raise ValueError("file has no refractive-index (n) data")
    wl, n = n_all.wavelength_nm, n_all.values
    if k_all is None:
        return wl, n, np.zeros_like(n)
    if np.array_equal(wl, k_all.wavelength_nm):
        return wl, n, k_all.values
    inside = (wl >= k_all.wavelength_nm[0]) & (wl <= k_all.wavelength_nm[-1])
    wl, n = wl[inside], n[inside]
    return wl, n, np.interp(wl, k_all.wavelength_nm, k_all.values)


# --------------------------------------------------------------------- metadata


def clean_reference(text: str) -> str:
    """REFERENCES field -> one line of plain text (HTML tags and script links removed)."""
    text = re.sub(r"\[<a [^>]*>Calculation script[^\]]*\]", "", text)
    text = re.sub(r"<br\s*/?>", " ", text)
    text = re.sub(r"<[^>]+>", "", text)
    text = html.unescape(text)
    return re.sub(r"\s+", " ", text).strip()


def clean_comment(text: str) -> str:
    text = re.sub(r"<br\s*/?>", "; ", text)
    text = re.sub(r"<[^>]+>", "", text)
    text = html.unescape(text).strip().strip('"').strip()
    return re.sub(r"\s+", " ", text)


def find_doi(text: str) -> str:
    match = re.search(r"doi\.org/(10\.[^\"'<>\s]+)", text)
    return match.group(1) if match else ""


def find_url(text: str) -> str:
    match = re.search(r'href="([^"]+)"', text)
    return match.group(1) if match else ""


def format_number(value: float) -> str:
    """Shortest repr of a float, without a trailing '.0' for whole numbers."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


# ---------------------------------------------------------------------- convert


def convert_file(source_dir: Path, folder: str, stem: str, role: str) -> tuple[str, str]:
    """Return (table name, CSV text) for one database file."""
    path = source_dir / folder / f"{stem}.yml"
    fields, blocks = parse_database_yaml(path.read_text(encoding="utf-8"))
    wavelength_nm, n, k = merge_blocks(blocks)
    if not np.all(np.diff(wavelength_nm) > 0):
        raise ValueError(f"{path}: wavelengths are not strictly increasing")
    if np.any(n <= 0) or np.any(k < 0):
        raise ValueError(f"{path}: n <= 0 or k < 0 in the data")

    name = f"{folder}-{stem}"
    references = fields.get("REFERENCES", "")
    doi = find_doi(references)
    header = [
        f"name: {name}",
        f"material: {MATERIAL_NAMES.get(folder, folder)}",
        f"formula: {folder}",
        f"role: {role}",
        f"reference: {clean_reference(references)}",
        f"doi: {doi if doi else 'none (no DOI exists for this reference)'}",
    ]
    if not doi and find_url(references):
        header.append(f"url: {find_url(references)}")
    comments = clean_comment(fields.get("COMMENTS", ""))
    if comments:
        header.append(f"comments: {comments}")
    header += [
        f"source_file: database/data/main/{folder}/nk/{stem}.yml",
        f"data_types: {', '.join(b.type for b in blocks)}",
        f"database: {DATABASE_CITATION}",
        f"license: {LICENSE}",
        f"wavelength_range_nm: {format_number(wavelength_nm[0])}-{format_number(wavelength_nm[-1])}",
        "columns: wavelength_nm = vacuum wavelength in nm; complex index n + i k (k >= 0 absorbs)",
        "generated_by: scripts/convert_refractiveindex.py (do not edit by hand)",
    ]
    out = [f"# {line}" for line in header]
    out.append("wavelength_nm,n,k")
    out += [
        f"{format_number(w)},{format_number(a)},{format_number(b)}"
        for w, a, b in zip(wavelength_nm, n, k, strict=True)
    ]
    return name, "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, default=DEFAULT_SOURCE_DIR,
                        help="refractiveindex.info YAML folder (default: %(default)s)")
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT_DIR,
                        help="CSV output folder (default: %(default)s)")
    args = parser.parse_args(argv)
    if not args.source.is_dir():
        print(f"error: source folder {args.source} not found", file=sys.stderr)
        return 2
    args.output.mkdir(parents=True, exist_ok=True)

    lo_req, hi_req = REQUIRED_RANGE_NM
    for folder, stem, role in SELECTION:
        name, csv_text = convert_file(args.source, folder, stem, role)
        wl_line = next(line for line in csv_text.splitlines() if "wavelength_range_nm" in line)
        lo, hi = (float(x) for x in wl_line.split(": ")[1].split("-"))
        target = args.output / f"{name}.csv"
        if lo > lo_req or hi < hi_req:
            print(f"skipped {name}: covers {lo:g}-{hi:g} nm, not {lo_req:g}-{hi_req:g} nm")
            if target.exists():
                target.unlink()
            continue
        target.write_text(csv_text, encoding="utf-8", newline="\n")
        print(f"wrote {target.relative_to(REPO_DIR) if target.is_relative_to(REPO_DIR) else target}"
              f" ({lo:g}-{hi:g} nm)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
