"""Measurement CSV parsing (swatch.io.measurements) and its errors, in the library and through the CLI."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swatch.cli import main
from swatch.core.errors import SwatchError
from swatch.io.measurement_csv import parse_measurement_text, read_measurement
from swatch.io.measurements import LabMeasurement, SpectralMeasurement, check_in_tables


def long_text(light, view, wl, R, az=None, percent=False):
    head = "light_deg,view_deg," + ("light_azimuth_deg,view_azimuth_deg," if az else "") + "wavelength_nm,reflectance"
    rows = [head]
    for g in range(len(light)):
        for w in range(len(wl)):
            a = f"{az[0][g]},{az[1][g]}," if az else ""
            rows.append(f"{light[g]},{view[g]},{a}{wl[w]},{float(R[g][w]) * (100 if percent else 1)!r}")
    return "\n".join(rows) + "\n"


def test_single_spectrum_uses_caller_geometry():
    m = parse_measurement_text("# a comment\nwavelength_nm,reflectance\n\n500,0.2\n400,0.1\n600,0.3\n",
                               "x.csv", light_deg=30, view_deg=10)
    assert isinstance(m, SpectralMeasurement)
    np.testing.assert_array_equal(m.wavelength_nm, [400, 500, 600])  # sorted
    np.testing.assert_array_equal(m.reflectance, [[0.1, 0.2, 0.3]])
    assert (m.light_deg[0], m.view_deg[0], m.light_azimuth_deg[0], m.view_azimuth_deg[0]) == (30, 10, 0, 180)
    assert not m.percent and m.unit_detected
    np.testing.assert_array_equal(m.wavelength_line, [5, 4, 6])


def test_long_form_any_row_order_and_signed_view():
    rng = np.random.default_rng(3)
    light, view = [45, 45, 20], [0, -30, 60]
    wl = [400, 450, 500, 550]
    R = rng.uniform(0.05, 0.6, (3, 4))
    lines = long_text(light, view, wl, R).splitlines()
    body = lines[1:]
    order = rng.permutation(len(body))
    m = parse_measurement_text("\n".join([lines[0]] + [body[i] for i in order]), "x.csv")
    # geometries in order of first appearance; check by matching keys
    got = {(m.light_deg[g], m.view_deg[g], m.view_azimuth_deg[g]): m.reflectance[g] for g in range(3)}
    np.testing.assert_allclose(got[(45, 0, 180)], R[0])
    np.testing.assert_allclose(got[(45, 30, 0)], R[1])  # light's side: view azimuth = light azimuth
    np.testing.assert_allclose(got[(20, 60, 180)], R[2])


def test_azimuth_columns_used_as_given():
    txt = long_text([30, 30], [20, 20], [400, 500], [[0.1, 0.2], [0.3, 0.4]], az=([0, 0], [90, 270]))
    m = parse_measurement_text(txt, "x.csv")
    np.testing.assert_array_equal(m.view_azimuth_deg, [90, 270])


def test_percent_detection_and_override():
    txt = long_text([30], [0], [400, 500, 600], [[0.1, 0.25, 0.4]], percent=True)
    m = parse_measurement_text(txt, "x.csv")
    assert m.percent and m.unit_detected
    np.testing.assert_allclose(m.reflectance, [[0.1, 0.25, 0.4]])
    m2 = parse_measurement_text(txt, "x.csv", percent=False)
    assert not m2.percent and not m2.unit_detected
    np.testing.assert_allclose(m2.reflectance, [[10, 25, 40]])
    frac = long_text([30], [0], [400, 500], [[0.9, 1.2]])
    assert not parse_measurement_text(frac, "x.csv").percent
    assert parse_measurement_text(frac, "x.csv", percent=True).percent


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 5), st.integers(2, 12), st.booleans(), st.integers(0, 2**32 - 1))
def test_round_trip_random_sets(G, W, percent, seed):
    rng = np.random.default_rng(seed)
    light = rng.choice(np.arange(0, 89), G, replace=False).astype(float)
    view = rng.uniform(-80, 80, G).round(3)
    wl = np.sort(rng.choice(np.arange(380, 781), W, replace=False)).astype(float)
    R = rng.uniform(0.02, 0.9, (G, W))
    m = parse_measurement_text(long_text(light, view, wl, R, percent=percent), "x.csv")
    assert m.percent == percent
    np.testing.assert_allclose(m.light_deg, light)
    np.testing.assert_allclose(m.view_deg, np.abs(view))
    np.testing.assert_allclose(m.wavelength_nm, wl)
    np.testing.assert_allclose(m.reflectance, R, rtol=1e-12)


def test_lab_file():
    m = parse_measurement_text("light_deg,view_deg,L,a,b\n45,0,50,-3,-30\n45,20,40,-2,-20\n", "lab.csv")
    assert isinstance(m, LabMeasurement)
    np.testing.assert_array_equal(m.Lab, [[50, -3, -30], [40, -2, -20]])
    one = parse_measurement_text("L,a,b\n50,1,2\n", "lab.csv", light_deg=45, view_deg=0)
    assert one.n_geometries == 1


BAD = [
    ("light_deg,view_deg,wavelength_nm\n45,0,500\n", 1, "missing column reflectance"),
    ("light_deg,wavelength_nm,reflectance\n45,500,0.1\n45,510,0.1\n", 1, "missing column view_deg"),
    ("wavelength_nm,reflectance\n400,0.1\n500,abc\n", 3, "'abc' is not a number"),
    ("wavelength_nm,reflectance\n400,0.1\n# c\n500,nan\n", 4, "not a finite number"),
    ("wavelength_nm,reflectance\n400,0.1\n-500,0.2\n", 3, "must be > 0"),
    ("wavelength_nm,reflectance\n500,0.1\n", 2, "only one wavelength"),
    ("wavelength_nm,reflectance\n400,0.1\n400,0.2\n", 3, "appears twice"),
    ("wavelength_nm,reflectance\n400,0.1\n500\n", 3, "expected 2 fields"),
    ("wavelength_nm,reflectance\n400,0.1\n500,-0.4\n", 3, "negative"),
    ("light_deg,view_deg,wavelength_nm,reflectance\n45,0,400,0.1\n45,0,500,0.1\n30,10,400,0.1\n", 4,
     "missing 500"),
    ("light_deg,view_deg,wavelength_nm,reflectance\n95,0,400,0.1\n95,0,500,0.1\n", 2, "light_deg 95"),
    ("light_deg,view_deg,L,a,b\n45,0,50,1,2\n45,0,51,1,2\n", 3, "appears twice"),
    ("light_deg,view_deg,L,a,b\n45,0,150,1,2\n", 2, "outside [0, 100]"),
    ("wavelength_nm,reflectance\n", 1, "no data rows"),
    ("wavelength_nm,reflectance\n400,0.1\n500,1e308\n", 3, "implausibly large"),
    ("wavelength_nm,reflectance\n400,0\n500,0\n", 2, "every reflectance value is zero"),
]


@pytest.mark.parametrize("text,line,phrase", BAD)
def test_malformed_rejected_with_line(text, line, phrase):
    with pytest.raises(SwatchError) as exc:
        parse_measurement_text(text, "bad.csv")
    msg = str(exc.value)
    assert f"bad.csv: line {line}:" in msg, msg
    assert phrase in msg, msg


def test_range_outside_tables_names_the_line():
    """1950 nm is inside the measured range (swatch.core.limits) and past Ti-Johnson's table (188–1937 nm)."""
    m = parse_measurement_text("wavelength_nm,reflectance\n400,0.1\n500,0.1\n1950,0.1\n", "far.csv")
    with pytest.raises(SwatchError, match=r"far.csv: line 4: wavelength 1950 nm is outside the table of Ti-Johnson"):
        check_in_tables(m, "TiO2-Siefke", "Ti-Johnson")
    with pytest.raises(SwatchError, match=r"far.csv: line 4: wavelength_nm: 5e\+06 nm is outside the measured range"):
        parse_measurement_text("wavelength_nm,reflectance\n400,0.1\n500,0.1\n5000000,0.1\n", "far.csv")


@pytest.mark.parametrize("text,line,phrase", BAD[:6])
def test_cli_malformed_exit_2_one_line(tmp_path, capsys, text, line, phrase):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    rc = main(["fit", str(p)])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith("error: ")
    assert f"line {line}:" in err and phrase in err


def test_cli_outside_tables_and_missing_file(tmp_path, capsys):
    p = tmp_path / "far.csv"
    p.write_text("wavelength_nm,reflectance\n400,0.1\n1950,0.1\n")
    assert main(["fit", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 3:" in err and "outside the table of Ti-Johnson" in err
    assert main(["fit", str(tmp_path / "nope.csv")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_cli_too_few_wavelengths_for_colorimetry(tmp_path, capsys):
    """Two wavelengths parse, but colorimetry needs a wider range: a clear error, not a crash."""
    path = tmp_path / "two.csv"
    path.write_text("wavelength_nm,reflectance\n380,0.1\n390,0.2\n")
    from swatch.cli import main

    assert main(["fit", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and "too narrow for colorimetry" in err[0]


def test_read_measurement_utf8_bom(tmp_path):
    p = tmp_path / "bom.csv"
    p.write_bytes("\ufeffWavelength_nm,Reflectance\n400,0.1\n500,0.2\n".encode("utf-8"))
    m = read_measurement(p)
    assert m.reflectance.shape == (1, 2)
