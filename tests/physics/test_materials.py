"""Tests of the optical-constant tables (tables/optical/*.csv) and swatch.physics.materials."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.core.errors import SwatchError
from swatch.physics import materials
from swatch.physics.materials import (
    DEFAULT_FILM,
    DEFAULT_SUBSTRATE,
    DEFAULT_WAVELENGTHS_NM,
    Material,
    list_materials,
    load_material,
    tables_dir,
    wavelength_grid,
)

OPTICAL_DIR = tables_dir() / "optical"
CSV_PATHS = sorted(OPTICAL_DIR.glob("*.csv"))
CSV_NAMES = [p.stem for p in CSV_PATHS]
SHARED_DATA_DIR = Path(__file__).resolve().parents[3] / "shared" / "data" / "refractiveindex"


def header_lines(path: Path) -> dict[str, str]:
    meta = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        key, _, value = line[1:].partition(":")
        meta[key.strip()] = value.strip()
    return meta


# ---------------------------------------------------------------- the tables


def test_required_tables_present():
    required = {
        "Ti-Johnson", "Ti-Palm", "Ti-Rakic-LD", "Ti-Werner", "Nb-Weaver", "Ta-Werner",
        "TiO2-Siefke", "TiO2-Jolivet-amorphous", "TiO2-Franta", "TiO2-Sarkar",
        "TiO2-Zhukovsky", "Nb2O5-Franta", "Nb2O5-Lemarchand", "Ta2O5-Franta-2015",
        "Ta2O5-Gao",
    }
    assert required <= set(CSV_NAMES)


@pytest.mark.parametrize("path", CSV_PATHS, ids=CSV_NAMES)
def test_csv_header(path):
    meta = header_lines(path)
    assert meta["name"] == path.stem
    assert meta["role"] in ("film", "substrate")
    assert path.stem.startswith(meta["formula"] + "-")
    assert re.fullmatch(r"10\.\d{4,9}/\S+", meta["doi"]), meta["doi"]
    assert "CC0 1.0" in meta["license"]
    assert "Polyanskiy" in meta["database"] and "Scientific Data 11, 94 (2024)" in meta["database"]
    assert re.fullmatch(r"database/data/main/\w+/nk/[\w.-]+\.yml", meta["source_file"])
    assert meta["reference"]
    first_data_line = next(
        line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith("#"))
    assert first_data_line == "wavelength_nm,n,k"


@pytest.mark.parametrize("name", CSV_NAMES)
def test_every_table_loads_and_is_physical(name):
    m = load_material(name)
    assert isinstance(m, Material)
    assert m.name == name
    assert m.wavelength_nm.dtype == np.float64
    assert m.wavelength_nm.shape == m.n.shape == m.k.shape
    assert np.all(np.diff(m.wavelength_nm) > 0)
    assert np.all(m.n > 0)
    assert np.all(m.k >= 0)
    lo, hi = m.wavelength_range_nm
    assert lo <= 380.0 and hi >= 780.0  # all tables cover the visible
    header_range = header_lines(OPTICAL_DIR / f"{name}.csv")["wavelength_range_nm"]
    assert [float(x) for x in header_range.split("-")] == [lo, hi]
    nk = m.nk(DEFAULT_WAVELENGTHS_NM)
    assert nk.dtype == np.complex128 and nk.shape == DEFAULT_WAVELENGTHS_NM.shape
    assert np.all(np.isfinite(nk))


def test_defaults():
    film, substrate = load_material(DEFAULT_FILM), load_material(DEFAULT_SUBSTRATE)
    assert film.role == "film" and film.formula == "TiO2"
    assert substrate.role == "substrate" and substrate.formula == "Ti"
    assert film.doi == "10.1002/adom.201600250"
    assert substrate.doi == "10.1103/PhysRevB.9.5056"


def test_siefke_index_at_550nm():
    nk = load_material("TiO2-Siefke").nk(550.0)
    assert 2.3 <= nk.real <= 2.5
    assert 0 <= nk.imag < 1e-3


def test_johnson_titanium_at_550nm():
    # Johnson & Christy: a strongly absorbing metal, n ~ 2.5, k ~ 3.4 in the green.
    nk = load_material("Ti-Johnson").nk(550.0)
    assert 2.3 < nk.real < 2.8 and 3.0 < nk.imag < 3.8


def test_arrays_are_read_only_and_cached():
    m = load_material("Ti-Johnson")
    assert load_material("Ti-Johnson") is m
    assert load_material("ti-johnson") is m
    with pytest.raises(ValueError):
        m.n[0] = 1.0


def test_list_materials():
    everything = list_materials()
    assert [m.name for m in everything] == sorted(CSV_NAMES)
    films, substrates = list_materials("film"), list_materials("substrate")
    assert all(m.role == "film" for m in films) and all(m.role == "substrate" for m in substrates)
    assert len(films) + len(substrates) == len(everything)
    assert DEFAULT_FILM in [m.name for m in films]
    assert DEFAULT_SUBSTRATE in [m.name for m in substrates]
    with pytest.raises(SwatchError):
        list_materials("oxide")


def test_unknown_material_lists_available_names():
    with pytest.raises(SwatchError) as info:
        load_material("Unobtainium-Nobody")
    message = str(info.value)
    assert "Unobtainium-Nobody" in message
    assert DEFAULT_FILM in message and DEFAULT_SUBSTRATE in message


def test_tables_dir_has_optical():
    assert (tables_dir() / "optical").is_dir()


# ------------------------------------------------------------- interpolation


@pytest.mark.parametrize("name", CSV_NAMES)
def test_interpolation_reproduces_table_points(name):
    m = load_material(name)
    nk = m.nk(m.wavelength_nm)
    assert np.array_equal(nk.real, m.n)
    assert np.array_equal(nk.imag, m.k)


@settings(max_examples=200, deadline=None)
@given(name=st.sampled_from(CSV_NAMES), data=st.data())
def test_interpolation_is_linear_between_points(name, data):
    m = load_material(name)
    i = data.draw(st.integers(0, m.wavelength_nm.size - 2))
    t = data.draw(st.floats(0.0, 1.0))
    w0, w1 = m.wavelength_nm[i], m.wavelength_nm[i + 1]
    w = min(max(w0 + t * (w1 - w0), w0), w1)
    frac = (w - w0) / (w1 - w0)
    got = m.nk(w)
    expected_n = m.n[i] + frac * (m.n[i + 1] - m.n[i])
    expected_k = m.k[i] + frac * (m.k[i + 1] - m.k[i])
    assert got.real == pytest.approx(expected_n, rel=1e-12, abs=1e-12)
    assert got.imag == pytest.approx(expected_k, rel=1e-12, abs=1e-15)
    assert got.imag >= 0


def test_nk_shape_follows_input():
    m = load_material(DEFAULT_FILM)
    assert m.nk(500.0).shape == ()
    assert m.nk([[400.0, 500.0], [600.0, 700.0]]).shape == (2, 2)


def test_out_of_range_grid_names_both_ranges():
    m = load_material("Ti-Johnson")  # 188-1937 nm
    with pytest.raises(SwatchError) as info:
        m.nk(wavelength_grid(150.0, 780.0, 5.0))
    message = str(info.value)
    assert "150–780 nm" in message
    assert "Ti-Johnson (188–1937 nm)" in message
    assert "choose a grid inside it" in message
    with pytest.raises(SwatchError, match="2500"):
        m.nk([500.0, 2500.0])


@settings(max_examples=50, deadline=None)
@given(name=st.sampled_from(CSV_NAMES), excess_nm=st.floats(1e-6, 1e4))
def test_never_extrapolates(name, excess_nm):
    m = load_material(name)
    lo, hi = m.wavelength_range_nm
    with pytest.raises(SwatchError):
        m.nk([500.0, hi + excess_nm])
    if lo - excess_nm > 0:
        with pytest.raises(SwatchError):
            m.nk([lo - excess_nm, 500.0])


def test_nonfinite_wavelengths_rejected():
    with pytest.raises(SwatchError):
        load_material(DEFAULT_FILM).nk([500.0, float("nan")])


# ------------------------------------------------------------ wavelength grid


def test_default_grid():
    assert DEFAULT_WAVELENGTHS_NM.dtype == np.float64
    assert DEFAULT_WAVELENGTHS_NM.size == 81
    assert DEFAULT_WAVELENGTHS_NM[0] == 380.0 and DEFAULT_WAVELENGTHS_NM[-1] == 780.0
    assert np.array_equal(np.diff(DEFAULT_WAVELENGTHS_NM), np.full(80, 5.0))


@settings(max_examples=200, deadline=None)
@given(start=st.floats(1.0, 1000.0), span=st.floats(0.1, 2000.0), steps=st.integers(1, 500))
def test_grid_is_inclusive_of_stop_when_on_grid(start, span, steps):
    step = span / steps
    stop = start + step * steps
    grid = wavelength_grid(start, stop, step)
    assert grid[0] == start
    assert grid[-1] == pytest.approx(stop, rel=1e-12)
    assert grid.size in (steps + 1,)
    assert np.all(np.diff(grid) > 0)


def test_grid_truncates_when_stop_off_grid():
    grid = wavelength_grid(380.0, 782.0, 5.0)
    assert grid[-1] == 780.0 and grid.size == 81


@pytest.mark.parametrize("args", [
    (380.0, 780.0, 0.0), (380.0, 780.0, -5.0), (780.0, 380.0, 5.0), (500.0, 500.0, 1.0),
    (0.0, 780.0, 5.0), (-10.0, 780.0, 5.0), (float("nan"), 780.0, 5.0),
    (380.0, float("inf"), 5.0), (380.0, 780.0, float("nan")),
])
def test_bad_grid_raises(args):
    with pytest.raises(SwatchError):
        wavelength_grid(*args)


# ------------------------------------------------ round-trip against the YAML


def _yaml_tabulated_nk_rows(path: Path) -> list[tuple[float, float, float]]:
    """The rows of the single ``tabulated nk`` DATA block (tiny parser, no PyYAML)."""
    rows, in_data = [], False
    for line in path.read_text(encoding="utf-8").splitlines():
        stripped = line.strip()
        if stripped == "data: |":
            in_data = True
            continue
        if in_data:
            parts = stripped.split()
            if len(parts) == 3 and line.startswith("        "):
                rows.append(tuple(float(p) for p in parts))
            else:
                in_data = False
    return rows


@pytest.mark.skipif(not SHARED_DATA_DIR.is_dir(), reason="shared refractiveindex data absent")
def test_johnson_csv_matches_original_yaml():
    yaml_path = SHARED_DATA_DIR / "Ti" / "Johnson.yml"
    assert "type: tabulated nk" in yaml_path.read_text(encoding="utf-8")
    rows = np.array(_yaml_tabulated_nk_rows(yaml_path))
    assert rows.shape == (49, 3)
    m = load_material("Ti-Johnson")
    np.testing.assert_allclose(m.wavelength_nm, rows[:, 0] * 1000.0, rtol=1e-15, atol=0)
    assert np.array_equal(m.n, rows[:, 1])
    assert np.array_equal(m.k, rows[:, 2])
    assert header_lines(OPTICAL_DIR / "Ti-Johnson.csv")["source_file"] == (
        "database/data/main/Ti/nk/Johnson.yml")


def test_module_has_no_yaml_dependency():
    source = Path(materials.__file__).read_text(encoding="utf-8")
    assert "import yaml" not in source and "pandas" not in source
