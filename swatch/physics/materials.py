"""Optical constants of film and substrate materials, read from plain CSV tables.

The tables live in ``tables/optical/<Material>-<Author>.csv`` and are generated from
the refractiveindex.info database (public domain, CC0 1.0) by
``scripts/convert_refractiveindex.py``.  Each file has ``#`` header lines
(``# key: value``: name, role, formula, reference, doi, source_file, license, ...),
a ``wavelength_nm,n,k`` header row and the data rows.

Sign convention: the complex refractive index is ``N = n + i k`` with ``k >= 0``
meaning absorption.

Interpolation: ``Material.nk`` interpolates ``n`` and ``k`` separately and
*linearly in wavelength* between table points (``numpy.interp``).  Linear
interpolation reproduces every table point exactly, never overshoots (so ``k`` stays
``>= 0``) and is adequate because all tables are sampled much more finely than the
spectral structure that matters for interference colours.  It never extrapolates:
a wavelength outside the table raises :class:`~swatch.core.errors.SwatchError`.

References
----------
.. [1] :cite:`Polyanskiy2024`: every table; the other tables' own references are in tables/README.md and each file's
   header.
.. [2] :cite:`Johnson1974`: ``Ti-Johnson``, the default substrate.
.. [3] :cite:`Siefke2016`: ``TiO2-Siefke``, the default film.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_WAVELENGTHS

__all__ = [
    "same_formula",
    "table_pairs",
    "metal_name",
    "DEFAULT_FILM",
    "DEFAULT_SUBSTRATE",
    "DEFAULT_WAVELENGTHS_NM",
    "ROLES",
    "Material",
    "list_materials",
    "load_material",
    "tables_dir",
    "wavelength_grid",
]

#: Amorphous ALD TiO2 (Siefke et al. 2016), n ~ 2.4 at 550 nm.
DEFAULT_FILM = "TiO2-Siefke"
#: Titanium metal (Johnson & Christy 1974).
DEFAULT_SUBSTRATE = "Ti-Johnson"
#: Allowed values of :attr:`Material.role`.
ROLES = ("film", "substrate")
#: The metals of the shipped substrate tables, by element (a table is named ``<element>-<author>``).
METAL_NAMES = {"Ti": "titanium", "Nb": "niobium", "Ta": "tantalum"}

_OPTICAL_SUBDIR = "optical"
_COLUMNS = ("wavelength_nm", "n", "k")


def _count(span: float) -> str:
    return f"{span + 1:.3g}" if math.isfinite(span) else "too many"


def wavelength_grid(start_nm: float = 380.0, stop_nm: float = 780.0,
                    step_nm: float = 5.0) -> np.ndarray:
    """Evenly spaced vacuum wavelengths ``start_nm, start_nm + step_nm, ...`` up to ``stop_nm``.

    Parameters
    ----------
    start_nm, stop_nm, step_nm : float
        First wavelength, last wavelength (included when it lies on the grid, to within 1e-9 of a
        step; otherwise the grid ends at the last point below it) and step, nm.

    Returns
    -------
    numpy.ndarray, float64, shape (N,)
        ``start_nm + i * step_nm`` (no accumulated rounding), at most ``MAX_WAVELENGTHS`` points.

    Raises
    ------
    SwatchError
        If a value is not finite, ``start_nm <= 0``, ``start_nm >= stop_nm`` or ``step_nm <= 0``.

    Examples
    --------
    >>> wavelength_grid(380, 780, 5).size
    81
    """
    try:
        start, stop, step = float(start_nm), float(stop_nm), float(step_nm)
    except (TypeError, ValueError) as exc:
        raise SwatchError(f"wavelength grid values must be numbers: {exc}") from None
    if not all(math.isfinite(v) for v in (start, stop, step)):
        raise SwatchError(
            f"wavelength grid values must be finite (got start {start_nm}, stop {stop_nm}, "
            f"step {step_nm} nm)")
    if start <= 0:
        raise SwatchError(f"wavelength grid start must be > 0 nm (got {start:g} nm)")
    if start >= stop:
        raise SwatchError(
            f"wavelength grid start must be below stop (got {start:g}–{stop:g} nm)")
    if step <= 0:
        raise SwatchError(f"wavelength grid step must be > 0 nm (got {step:g} nm)")
    span = (stop - start) / step  # inf for a subnormal step: compared, never converted first
    if not span + 1 <= MAX_WAVELENGTHS:
        raise SwatchError(f"wavelength grid {start:g}:{stop:g}:{step:g} nm has {_count(span)} points; at most "
                          f"{MAX_WAVELENGTHS} (e.g. a step of at least {(stop - start) / (MAX_WAVELENGTHS - 1):.3g} nm "
                          "over this range)")
    count = math.floor(span + 1e-9) + 1
    grid = start + step * np.arange(count, dtype=np.float64)
    if abs(grid[-1] - stop) <= 1e-9 * step:
        grid[-1] = stop
    return grid


#: 380–780 nm every 5 nm (81 points): the default spectral grid.
DEFAULT_WAVELENGTHS_NM = wavelength_grid()


def _fmt_nm(value: float) -> str:
    return f"{value:.6g}"


@dataclass(frozen=True, eq=False)
class Material:
    """Tabulated optical constants of one material (one CSV table of ``tables/optical/``).

    Instances are immutable (arrays are read-only) and compare by identity, so they
    can be cached and shared.

    Attributes
    ----------
    name : str
        Table name, e.g. ``"TiO2-Siefke"`` (``<Material>-<Author>``).
    role : str
        ``"film"`` (a clear oxide) or ``"substrate"`` (a metal).
    formula, reference, doi, source_file, license : str
        Chemical formula, the measurement's reference and DOI, the file of the refractiveindex.info
        database it was converted from, and the data's licence (CC0).
    wavelength_nm : numpy.ndarray, float64, shape (M,)
        Tabulated vacuum wavelengths, nm, strictly increasing.
    n, k : numpy.ndarray, float64, shape (M,)
        Real part of the refractive index and extinction coefficient (``N = n + i k``, k ≥ 0 absorbs).

    References
    ----------
    :cite:`Polyanskiy2024`.
    """

    name: str  #: table name, e.g. ``"TiO2-Siefke"``
    role: str  #: ``"film"`` or ``"substrate"``
    formula: str  #: chemical formula, e.g. ``"TiO2"``
    reference: str  #: measurement reference (authors, title, journal, year)
    doi: str  #: DOI of the reference ("none ..." when none exists)
    source_file: str  #: path of the original file in the refractiveindex.info database
    license: str  #: licence of the data
    wavelength_nm: np.ndarray = field(repr=False)  #: strictly increasing, nm
    n: np.ndarray = field(repr=False)  #: real part of the refractive index
    k: np.ndarray = field(repr=False)  #: extinction coefficient, k >= 0 absorbs

    @property
    def wavelength_range_nm(self) -> tuple[float, float]:
        """The tabulated range.

        Returns
        -------
        tuple of float
            (shortest, longest) tabulated wavelength, nm.
        """
        return float(self.wavelength_nm[0]), float(self.wavelength_nm[-1])

    def nk(self, wavelength_nm) -> np.ndarray:
        """Complex index ``n + i k`` at wavelengths, interpolated linearly in the table.

        Parameters
        ----------
        wavelength_nm : array_like
            Vacuum wavelengths, nm (a scalar or any shape), inside the table's range.

        Returns
        -------
        numpy.ndarray
            complex128, the shape of ``wavelength_nm``.

        Raises
        ------
        SwatchError
            If any wavelength is not finite or lies outside the table (no extrapolation).

        Examples
        --------
        >>> n = load_material("TiO2-Siefke").nk(550.0)
        >>> n.dtype.name, bool(2.0 < n.real < 3.0)
        ('complex128', True)
        """
        wl = np.asarray(wavelength_nm, dtype=np.float64)
        if wl.size == 0:
            raise SwatchError("wavelength grid is empty")
        if not np.all(np.isfinite(wl)):
            raise SwatchError("wavelength grid contains non-finite values")
        lo, hi = self.wavelength_range_nm
        wl_min, wl_max = float(wl.min()), float(wl.max())
        if wl_min < lo or wl_max > hi:
            raise SwatchError(
                f"wavelength grid {_fmt_nm(wl_min)}–{_fmt_nm(wl_max)} nm is outside the "
                f"range of {self.name} ({_fmt_nm(lo)}–{_fmt_nm(hi)} nm); "
                "choose a grid inside it")
        n = np.interp(wl, self.wavelength_nm, self.n)
        k = np.interp(wl, self.wavelength_nm, self.k)
        return np.asarray(n + 1j * k, dtype=np.complex128)


def tables_dir() -> Path:
    """The ``tables/`` folder holding ``optical/*.csv``.

    Looked up first inside the package (``swatch/tables``, for installed copies that
    ship the tables as package data), then next to it in the source tree
    (``<repo>/tables``).

    Returns
    -------
    pathlib.Path
        The absolute path of the ``tables/`` folder found (it has an ``optical/`` subfolder).

    Raises
    ------
    SwatchError
        If neither has an ``optical`` folder.
    """
    package_dir = Path(__file__).resolve().parent.parent  # swatch/ (this module is swatch/physics/materials.py)
    candidates = (package_dir / "tables", package_dir.parent / "tables")
    for candidate in candidates:
        if (candidate / _OPTICAL_SUBDIR).is_dir():
            return candidate
    raise SwatchError(
        "optical-constant tables not found; looked in "
        + " and ".join(str(c / _OPTICAL_SUBDIR) for c in candidates))


def _optical_files() -> dict[str, Path]:
    """Table name -> CSV path, for every table in ``tables/optical``."""
    folder = tables_dir() / _OPTICAL_SUBDIR
    return {path.stem: path for path in sorted(folder.glob("*.csv"))}


def _read_table(path: Path) -> Material:
    """Parse one CSV table (``# key: value`` header lines, column row, data rows)."""
    meta: dict[str, str] = {}
    rows: list[tuple[float, float, float]] = []
    columns_seen = False
    with path.open(encoding="utf-8") as handle:
        for line_no, line in enumerate(handle, start=1):
            line = line.strip()
            if not line:
                continue
            if line.startswith("#"):
                key, sep, value = line[1:].partition(":")
                if sep:
                    meta.setdefault(key.strip(), value.strip())
                continue
            if not columns_seen:
                if tuple(c.strip() for c in line.split(",")) != _COLUMNS:
                    raise SwatchError(
                        f"{path}: line {line_no}: expected header row "
                        f"{','.join(_COLUMNS)!r}, got {line!r}")
                columns_seen = True
                continue
            try:
                values = tuple(float(x) for x in line.split(","))
            except ValueError:
                values = ()
            if len(values) != 3:
                raise SwatchError(f"{path}: line {line_no}: expected 3 numbers, got {line!r}")
            rows.append(values)

    if len(rows) < 2:
        raise SwatchError(f"{path}: needs at least two data rows")
    data = np.array(rows, dtype=np.float64)
    wavelength_nm, n, k = (np.ascontiguousarray(data[:, i]) for i in range(3))
    if not np.all(np.isfinite(data)):
        raise SwatchError(f"{path}: non-finite values in the table")
    if not np.all(np.diff(wavelength_nm) > 0):
        raise SwatchError(f"{path}: wavelengths must be strictly increasing")
    if np.any(n <= 0) or np.any(k < 0):
        raise SwatchError(f"{path}: needs n > 0 and k >= 0 everywhere")
    role = meta.get("role", "")
    if role not in ROLES:
        raise SwatchError(f"{path}: role must be one of {', '.join(ROLES)} (got {role!r})")
    for array in (wavelength_nm, n, k):
        array.setflags(write=False)
    return Material(
        name=meta.get("name", path.stem),
        role=role,
        formula=meta.get("formula", path.stem.split("-", 1)[0]),
        reference=meta.get("reference", ""),
        doi=meta.get("doi", ""),
        source_file=meta.get("source_file", ""),
        license=meta.get("license", ""),
        wavelength_nm=wavelength_nm,
        n=n,
        k=k,
    )


@functools.cache
def _load_cached(name: str) -> Material:
    return _read_table(_optical_files()[name])


def load_material(name: str) -> Material:
    """The material table called ``name`` (e.g. ``"Ti-Johnson"``); case-insensitive.

    Parameters
    ----------
    name : str
        A table name as ``swatch materials list`` shows it.

    Returns
    -------
    Material
        Read once and cached (the same object on every call).

    Raises
    ------
    SwatchError
        Listing the available names, if there is no such table.

    Examples
    --------
    >>> m = load_material("Ti-Johnson")
    >>> m.role
    'substrate'
    """
    files = _optical_files()
    if name not in files:
        matches = [stem for stem in files if stem.lower() == str(name).strip().lower()]
        if len(matches) != 1:
            raise SwatchError(
                f"unknown material {name!r}; available: {', '.join(sorted(files)) or 'none'}")
        name = matches[0]
    return _load_cached(name)


def list_materials(role: str | None = None) -> list[Material]:
    """All material tables, sorted by name; only those of ``role`` if given.

    Parameters
    ----------
    role : {"film", "substrate"} or None
        Keep only films (clear oxides) or substrates (metals); None: every table.

    Returns
    -------
    list of Material
        Sorted by table name.

    Raises
    ------
    SwatchError
        For a role other than those of :data:`ROLES`.
    """
    if role is not None and role not in ROLES:
        raise SwatchError(f"role must be one of {', '.join(ROLES)} (got {role!r})")
    materials = [_load_cached(name) for name in sorted(_optical_files())]
    return [m for m in materials if role is None or m.role == role]


def same_formula(role: str, name: str) -> list[str]:
    """The names of the tables of ``role`` whose material has the formula of table ``name``.

    Parameters
    ----------
    role : str
        ``"film"`` or ``"substrate"``.
    name : str
        A table name.

    Returns
    -------
    list of str
        Sorted names, ``name`` among them when it has that role.
    """
    formula = load_material(name).formula
    return [m.name for m in list_materials(role) if m.formula == formula]


def table_pairs(film: str, substrate: str) -> list[tuple[str, str]]:
    """The shipped optical models of a film on a metal: every film table of the film's formula on every
    substrate table of the metal's (``swatch materials list``), the given pair among them.

    Parameters
    ----------
    film, substrate : str
        Table names.

    Returns
    -------
    list of (str, str)
        (film, substrate) pairs, films outer.
    """
    return [(f, s) for f in same_formula("film", film) for s in same_formula("substrate", substrate)]


def metal_name(substrate: str) -> str:
    """The metal a substrate table is of, in words, for what a person reads (``titanium`` for ``Ti-Johnson``).

    Parameters
    ----------
    substrate : str
        A substrate table's name (``<element>-<author>``).

    Returns
    -------
    str
        The metal's English name, lower case; the element symbol for a metal not in :data:`METAL_NAMES`.

    Examples
    --------
    >>> metal_name("Nb-Weaver"), metal_name("Ti-Rakic-LD")
    ('niobium', 'titanium')
    """
    symbol = str(substrate).split("-")[0]
    return METAL_NAMES.get(symbol, symbol)
