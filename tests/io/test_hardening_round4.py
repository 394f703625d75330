"""Hardening round 4 (issue 49 item 1): the wavelength axis and the header counts of measurement files,
from the user's side. Every hostile case through `fit`, `check`, `match --measurement` and `calibrate` in
one capped subprocess: one line `error: …` naming the file and the field, exit 2, no numpy warning, nothing
written; and in the library with warnings as errors. A file on a wavelength grid the colorimetry cannot
integrate as measured (a 7 nm step; a ColorMunki's 106 bands of 3.3 nm) is read alike by every reader,
its spectra interpolated onto a 5 nm grid and said so; a grid off by float noise (729.99999999) is read as
the grid it is."""
from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import colour
import numpy as np
import pytest

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_HEADER_COUNT_CHARS, MAX_MEASURED_WAVELENGTH_NM, MIN_MEASURED_WAVELENGTH_NM
from swatch.io.instrument_files import read_instrument_file
from tests.cli_helpers import run_capped_batch

DATA = Path(__file__).resolve().parents[1] / "data" / "instruments"
TI3 = (DATA / "argyll_parts.ti3").read_text(encoding="utf-8")
I1 = (DATA / "i1profiler_coupons.txt").read_text(encoding="utf-8")
CXF = (DATA / "colour_cxf_sample_trimmed.cxf").read_text(encoding="utf-8")
CAP = 2 * 1024**3
DIGITS = "9" * 5000
RANGE = f"{MIN_MEASURED_WAVELENGTH_NM:g}–{MAX_MEASURED_WAVELENGTH_NM:g} nm"


def _sub(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _cgats(names: list[str], rows: list[list[float]], head: str = "CGATS.17\n") -> str:
    return (head + 'MEASUREMENT_SOURCE "Illumination=D50 ObserverAngle=2"\nBEGIN_DATA_FORMAT\nSAMPLE_ID '
            + " ".join(names) + "\nEND_DATA_FORMAT\nBEGIN_DATA\n"
            + "".join(f"S{k + 1} " + " ".join(f"{v:.6f}" for v in r) + "\n" for k, r in enumerate(rows))
            + "END_DATA\n")


#: name -> (file text, what the one line says besides the file's name)
CASES = {
    # ArgyllCMS .ti3 (SPECTRAL_BANDS / SPECTRAL_START_NM / SPECTRAL_END_NM, XYZ beside the spectra)
    "bands_nan.ti3": (_sub(TI3, 'SPECTRAL_BANDS "36"', 'SPECTRAL_BANDS "nan"'),
                      "SPECTRAL_BANDS 'nan' is not a whole number"),
    "bands_inf.ti3": (_sub(TI3, 'SPECTRAL_BANDS "36"', 'SPECTRAL_BANDS "inf"'),
                      "SPECTRAL_BANDS 'inf' is not a whole number"),
    "bands_5000_digits.ti3": (_sub(TI3, 'SPECTRAL_BANDS "36"', f"SPECTRAL_BANDS {DIGITS}"),
                              f"(5000 characters) is not a whole number of at most {MAX_HEADER_COUNT_CHARS} digits"),
    "sets_5000_digits.ti3": (_sub(TI3, "NUMBER_OF_SETS 3", f"NUMBER_OF_SETS {DIGITS}"),
                             f"NUMBER_OF_SETS '{'9' * 24}'… (5000 characters) is not a whole number"),
    "fields_5000_digits.ti3": (_sub(TI3, "NUMBER_OF_FIELDS 41", f"NUMBER_OF_FIELDS {DIGITS}"),
                               "NUMBER_OF_FIELDS '999"),
    "sets_minus_one.ti3": (_sub(TI3, "NUMBER_OF_SETS 3", "NUMBER_OF_SETS -1"), "NUMBER_OF_SETS '-1' is not a whole"),
    "start_minus_inf.ti3": (_sub(TI3, 'SPECTRAL_START_NM "380.000000"', "SPECTRAL_START_NM -inf"),
                            "SPECTRAL_START_NM: -inf is not a finite number"),
    "start_nan.ti3": (_sub(TI3, 'SPECTRAL_START_NM "380.000000"', "SPECTRAL_START_NM nan"),
                      "SPECTRAL_START_NM: nan is not a finite number"),
    "end_1e308.ti3": (_sub(TI3, 'SPECTRAL_END_NM "730.000000"', "SPECTRAL_END_NM 1e308"),
                      f"SPECTRAL_END_NM: 1e+308 nm is outside the measured range; a wavelength lies in {RANGE}"),
    "end_text.ti3": (_sub(TI3, 'SPECTRAL_END_NM "730.000000"', "SPECTRAL_END_NM far"),
                     "SPECTRAL_END_NM 'far' is not a number"),
    "start_above_end.ti3": (_sub(TI3, 'SPECTRAL_START_NM "380.000000"', 'SPECTRAL_START_NM "740"'),
                            "SPECTRAL_END_NM: 730 nm is not above SPECTRAL_START_NM's 740 nm"),
    "names_disagree.ti3": (_sub(TI3, 'SPECTRAL_END_NM "730.000000"', 'SPECTRAL_END_NM "780"'),
                           "SPEC_390 names 390 nm but SPECTRAL_BANDS 36 from SPECTRAL_START_NM 380 to "
                           "SPECTRAL_END_NM 780 nm put it at 391.429 nm"),
    "xyz_nan.ti3": (_sub(TI3, "52.61617", "nan"), "line 21: XYZ_X 'nan' is not a finite number"),
    "xyz_minus_inf.ti3": (_sub(TI3, "52.61617", "-inf"), "line 21: XYZ_X '-inf' is not a finite number"),
    # CGATS.17 (i1Profiler): CIELAB beside the spectra, field names as the axis
    "lab_nan.txt": (_sub(I1, "65.1065", "NaN"), "line 19: LAB_L 'NaN' is not a finite number"),
    "lab_minus_inf.txt": (_sub(I1, "-36.6283", "-inf"), "line 20: LAB_B '-inf' is not a finite number"),
    "lab_out_of_range.txt": (_sub(I1, "65.1065", "170"), "sample 'A1': L* 170 is outside [0, 100]"),
    "bands_nan_without_start_end.txt": (_sub(I1, 'MEASUREMENT_GEOMETRY "45/0"', 'MEASUREMENT_GEOMETRY "45/0"\n'
                                                                                'SPECTRAL_BANDS "nan"'),
                                        "SPECTRAL_BANDS 'nan' is not a whole number"),
    "names_out_of_order.txt": (_sub(I1, "nm380 nm390", "nm390 nm380"), "nm380: 380 nm is not above nm390's 390 nm"),
    "name_far_out.txt": (_sub(I1, "nm380 nm390", "nm180 nm390"), "nm180: 180 nm is outside the measured range"),
    # CxF3: StartWL + Increment
    "increment_0.cxf": (_sub(CXF, 'Increment="10"', 'Increment="0"'), "WavelengthRange Increment: 0 nm"),
    "increment_negative.cxf": (_sub(CXF, 'Increment="10"', 'Increment="-10"'), "the increment must be above 0 nm"),
    "increment_400_digits.cxf": (_sub(CXF, 'Increment="10"', f'Increment="{"9" * 400}"'),
                                 "WavelengthRange Increment: a 400-digit number"),
    "increment_far.cxf": (_sub(CXF, 'Increment="10"', 'Increment="1000000"'),
                          "its last wavelength (object '1': StartWL + 30 × object '1': WavelengthRange Increment): "
                          "3.00004e+07 nm is outside the measured range"),
    "start_0.cxf": (_sub(CXF, 'ReflectanceSpectrum StartWL="380"', 'ReflectanceSpectrum StartWL="0"'),
                    "object '1': StartWL: 0 nm is outside the measured range"),
    # CSV (a measurement; `calibrate` reads coupon CSVs: test_coupon_csv_wavelengths_are_held_to_the_same_range)
    "huge_wavelength.csv": ("wavelength_nm,reflectance\n400,0.2\n500,0.3\n1e300,0.4\n",
                            "line 4: wavelength_nm: 1e+300 nm is outside the measured range"),
}
COMMANDS = ("fit", "check", "match", "calibrate")


def _commands(name: str) -> tuple[str, ...]:
    return COMMANDS[:3] if name.endswith(".csv") else COMMANDS


@pytest.fixture(scope="module")
def answers(tmp_path_factory):
    """Each case through `fit`, `check --report`, `match --measurement` and `calibrate`, in one capped subprocess."""
    d = tmp_path_factory.mktemp("round4")
    argvs, keys = [], []
    for name, (text, _) in CASES.items():
        (d / name).write_text(text, encoding="utf-8")
        for argv in (["fit", d / name], ["check", d / name, "--thickness", "120", "--report", d / f"{name}.report"],
                     ["match", "--measurement", d / name], ["calibrate", d / name, "--out", d / f"{name}.toml"]):
            if argv[0] not in _commands(name):
                continue
            argvs.append(argv)
            keys.append((name, argv[0]))
    procs = run_capped_batch(argvs, CAP, timeout=600)
    return d, dict(zip(keys, procs, strict=True))


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_axis_or_count_gets_one_line_naming_file_and_field(answers, name):
    folder, procs = answers
    for command in _commands(name):
        proc = procs[(name, command)]
        assert proc.returncode == 2, (command, proc.stderr)
        assert proc.stderr.startswith(f"error: {folder / name}: ") and proc.stderr.count("\n") == 1, (command,
                                                                                                      proc.stderr)
        assert CASES[name][1] in proc.stderr, (command, proc.stderr)
        for word in ("Warning", "Traceback", "internal error"):
            assert word not in proc.stderr, (command, proc.stderr)
        assert proc.stdout == "", (command, proc.stdout)
    assert not list(folder.glob(f"{name}.toml*")) and not list(folder.glob(f"{name}.report*"))  # nothing written


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_axis_or_count_is_a_swatch_error_with_warnings_as_errors(tmp_path, name):
    """The library: the reader raises SwatchError, and no numpy RuntimeWarning is on the way to it."""
    path = tmp_path / name
    path.write_text(CASES[name][0], encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(SwatchError, match=re.escape(CASES[name][1])):
            read_instrument_file(path)


def test_coupon_csv_wavelengths_are_held_to_the_same_range(tmp_path):
    """`calibrate`'s own CSV form: a wavelength outside the measured range, or coupons off the ASTM E308 grid by
    float noise (read as the grid, as the instrument files are)."""
    from swatch.io.coupons import read_coupons

    far = tmp_path / "far.csv"
    far.write_text("voltage_V,wavelength_nm,reflectance\n20,400,0.2\n20,1e300,0.3\n", encoding="utf-8")
    with pytest.raises(SwatchError, match=re.escape(f"{far}:3: wavelength_nm = 1e300 is out of range; allowed "
                                                    f"{MIN_MEASURED_WAVELENGTH_NM:g} to {MAX_MEASURED_WAVELENGTH_NM:g}")):
        read_coupons(far)
    noisy = tmp_path / "noisy.csv"
    rows = "".join(f"{v},{w},{0.2 + 0.001 * w * (v / 10)}\n" for v in (10, 20) for w in (*range(380, 730, 10), 729.99999999))
    noisy.write_text("voltage_V,wavelength_nm,reflectance\n" + rows, encoding="utf-8")
    assert read_coupons(noisy).wavelength_nm.tolist() == list(np.arange(380.0, 731.0, 10.0))


def _axis_files(folder: Path, wl: np.ndarray, R: np.ndarray, stem: str) -> dict[str, Path]:
    """The spectra R (fraction, one row per sample) on the wavelengths wl as CSV, CGATS.17 (nmNNN fields) and an
    ArgyllCMS .ti3 (SPECTRAL_BANDS from SPECTRAL_START_NM to SPECTRAL_END_NM, names rounded, percent)."""
    out = {}
    out["csv"] = folder / f"{stem}.csv"
    out["csv"].write_text("wavelength_nm,reflectance\n" + "".join(f"{w!r},{r!r}\n" for w, r in zip(wl, R[0], strict=True)),
                          encoding="utf-8")
    out["cgats"] = folder / f"{stem}.txt"
    out["cgats"].write_text(_cgats([f"nm{w!r}" for w in wl], [R[0]]), encoding="utf-8")
    names = [f"SPEC_{int(np.floor(w + 0.5)):03d}" for w in wl]
    out["ti3"] = folder / f"{stem}.ti3"
    out["ti3"].write_text(f'CTI3\n\nSPECTRAL_BANDS "{wl.size}"\nSPECTRAL_START_NM "{wl[0]:f}"\nSPECTRAL_END_NM '
                          f'"{wl[-1]:f}"\nBEGIN_DATA_FORMAT\nSAMPLE_ID {" ".join(names)}\nEND_DATA_FORMAT\n'
                          f'BEGIN_DATA\n1 {" ".join(f"{100 * r!r}" for r in R[0])}\nEND_DATA\n', encoding="utf-8")
    return out


def _reference_Lab(wl: np.ndarray, R: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """colour-science's ASTM E308 CIELAB (D65, CIE 1964 10°) of R interpolated linearly onto ``grid`` by numpy."""
    cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS["D65"]
    sd = colour.SpectralDistribution(np.interp(grid, wl, R), grid)
    white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones(grid.size), grid), cmfs, ill, method="ASTM E308")
    XYZ = colour.sd_to_XYZ(sd, cmfs, ill, method="ASTM E308")
    return colour.XYZ_to_Lab(XYZ / 100, colour.XYZ_to_xy(white / 100))


def test_a_grid_off_astm_e308_is_read_alike_by_every_reader_and_the_resampling_said(tmp_path):
    """The first sample of the bundled CxF3 file on a 7 nm step (its Increment made 7) and the same numbers as
    CSV, CGATS.17 and .ti3: each command works, says the spectra were interpolated onto 380–590 nm at 5 nm, and
    `check` measures the CIELAB colour-science gives for them interpolated so (not swatch's colorimetry)."""
    values = re.search(r'<cc:ReflectanceSpectrum StartWL="380" ColorSpecification="CS1">([^<]*)<', CXF).group(1)
    R = np.array([[float(v) for v in values.split()]])
    wl = 380.0 + 7.0 * np.arange(R.shape[1])
    files = _axis_files(tmp_path, wl, R, "seven")
    files["cxf"] = tmp_path / "seven.cxf"
    files["cxf"].write_text(_sub(CXF, 'Increment="10"', 'Increment="7"'), encoding="utf-8")
    argvs = [[c, *a, p, *b, "--json"] for p in files.values() for c, a, b in
             (("check", [], ["--thickness", "120"]), ("fit", [], []), ("match", ["--measurement"], []))]
    procs = iter(run_capped_batch(argvs, CAP, timeout=600))
    said = ("not an even 1, 5, 10 or 20 nm grid inside 360–830 nm (ASTM E308); colour from the spectra interpolated "
            "linearly onto 380–590 nm at 5 nm")
    reference = _reference_Lab(wl, R[0], np.arange(380.0, 591.0, 5.0))
    for kind, path in files.items():
        check, fit, match = next(procs), next(procs), next(procs)
        for proc in (check, fit, match):
            assert proc.returncode in (0, 1) and proc.stderr == "", (kind, proc.stderr)
        doc = json.loads(check.stdout)
        assert f"{path}: 31 wavelengths 380–590 nm, {said}" in doc["notes"], (kind, doc["notes"])
        np.testing.assert_allclose(doc["measurements"][0]["Lab"]["45:0"], reference, atol=6e-4, err_msg=kind)
        fitted = json.loads(fit.stdout)
        one = fitted if "samples" not in fitted else fitted["samples"][0]
        assert one["colour_grid_interpolated"] and one["colour_wavelength_nm"] == [380.0, 590.0, 5.0], kind
        assert f"{path}: 31 wavelengths 380–590 nm, {said}" in json.loads(match.stdout)["notes"], kind


def test_a_colormunki_ti3_of_106_bands_reads_as_its_csv_and_says_it_was_resampled(tmp_path):
    """ArgyllCMS writes a ColorMunki's 106 bands of 3.33 nm (380–730 nm) with names rounded to whole nm: read from
    the header's start, end and bands, the same spectra as a CSV of those wavelengths, interpolated and said so."""
    wl = np.linspace(380.0, 730.0, 106)
    R = 0.2 + 0.15 * np.sin(wl / 40.0)[None, :]
    files = _axis_files(tmp_path, wl, R, "munki")
    procs = run_capped_batch([["check", files[k], "--thickness", "120", "--json"] for k in ("csv", "ti3")] +
                             [["fit", files["ti3"]]], CAP)
    docs = [json.loads(p.stdout) for p in procs[:2]]
    Lab = [d["measurements"][0]["Lab"]["45:0"] for d in docs]
    assert Lab[0] == Lab[1]
    np.testing.assert_allclose(Lab[0], _reference_Lab(wl, R[0], np.arange(380.0, 731.0, 5.0)), atol=6e-4)
    assert any("106 wavelengths 380–730 nm, not an even" in n for n in docs[1]["notes"])
    assert "# measured wavelengths: not an even 1, 5, 10 or 20 nm grid" in procs[2].stdout
    assert procs[2].stderr == ""


def test_a_wavelength_off_its_grid_by_float_noise_is_read_as_the_grid(tmp_path):
    """`SPECTRAL_NM_0729.99999999` (a 10 nm grid but for 1e-8 nm) stopped colour-science's ASTM E308 (exit 70):
    it is the 730 nm of the grid, read as measured (no interpolation), the same as the file that says 730."""
    wl = np.arange(380.0, 731.0, 10.0)
    R = [0.2 + 0.1 * np.cos(wl / 50.0)]
    exact = tmp_path / "exact.txt"
    exact.write_text(_cgats([f"SPECTRAL_NM_{w:03.0f}" for w in wl], R), encoding="utf-8")
    noisy = tmp_path / "noisy.txt"
    noisy.write_text(_sub(exact.read_text(encoding="utf-8"), "SPECTRAL_NM_730", "SPECTRAL_NM_0729.99999999"),
                     encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = read_instrument_file(noisy).samples[0].measurement
    assert m.wavelength_nm.tolist() == wl.tolist()
    argvs = [argv for p in (exact, noisy) for argv in
             (["check", p, "--thickness", "120", "--json"], ["fit", p, "--json"], ["match", "--measurement", p, "--json"])]
    procs = run_capped_batch(argvs, CAP)
    outs = []
    for proc in procs:
        assert proc.returncode in (0, 1) and proc.stderr == "", proc.stderr
        outs.append(json.loads(proc.stdout))
    for a, b in zip(outs[:3], outs[3:], strict=True):
        a.pop("spec", None), b.pop("spec", None)
        assert json.dumps(a).replace("exact.txt", "F") == json.dumps(b).replace("noisy.txt", "F")
    assert outs[1]["colour_grid_interpolated"] is False
