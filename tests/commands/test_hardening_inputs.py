"""Issue #12: bad input is answered in one line (exit 2) before memory is spent, never with exit 70,
a hang or an out-of-memory; the big-grid cases run under a memory cap so a regression fails fast."""
from __future__ import annotations

import contextlib
import io
import subprocess

import pytest

from swatch.cli import main
from swatch.core.limits import MAX_RUN_BYTES
from tests.cli_helpers import assert_one_line_error, run_capped_batch

MEMORY_CAP_BYTES = 1024 ** 3  # well under MAX_RUN_BYTES: a refusal must come before any big allocation


def run_here(*args) -> subprocess.CompletedProcess:
    """The CLI in this process (faster) for the cases that spend no memory."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main([str(a) for a in args])
    return subprocess.CompletedProcess(args, rc, out.getvalue(), err.getvalue())


def test_issue12_memory_cap_is_below_the_run_budget():
    assert MEMORY_CAP_BYTES < MAX_RUN_BYTES


HUGE_INPUTS = [
    (["materials", "show", "TiO2-Siefke", "--wavelengths", "380:780:1e-7"], "at most 10001"),
    (["materials", "show", "TiO2-Siefke", "--wavelengths", "380:780:0.00001"], "at most 10001"),
    (["spectrum", "--thickness", "50", "--wavelengths", "380:780:5e-324"], "at most 10001"),
    (["color", "--thickness", "20:300:5e-324"], "at most 100000"),
    (["color", "--thickness", "0:1000:1e-6"], "at most 100000"),
    (["fit", "/dev/zero"], "at most 16 MB"),
    (["catalog", "validate", "/dev/urandom"], "at most 1 MB"),
    (["catalog", "validate", "/dev/zero"], "at most 1 MB"),
    (["angular", "--thickness", "50", "--out", "{tmp}/a", "--light-range", "0:85:0.0852", "--view-range",
      "0:85:0.0852"], "at most 40,000,000 samples"),
    (["render", "--thickness", "50", "--out", "{tmp}/r", "--size", "8192"], "from 1 to 4096"),
]


#: The cases below that read a file or write a result: (name, argv with {tmp} for their folder).
FILE_CASES = [
    ("angular-blocks", ["angular", "--thickness", "50", "--out", "{tmp}", "--light-range", "0:85:0.35",
                        "--view-range", "0:85:0.35"]),
    ("giant-csv-field", ["fit", "{tmp}/big.csv"]),
    ("deep-toml-validate", ["catalog", "validate", "{tmp}/deep.toml"]),
    ("deep-toml-build", ["catalog", "build", "{tmp}/deep.toml", "--out", "{tmp}/o"]),
]


@pytest.fixture(scope="module")
def capped_runs(tmp_path_factory):
    """Every HUGE_INPUTS case and every FILE_CASES case run under MEMORY_CAP_BYTES, all in one capped
    subprocess (issue 17 item 7: one interpreter start-up, ~1.4 CPU-s, instead of fourteen), each case
    writing under its own empty folder: (HUGE_INPUTS' (folder, result)s, FILE_CASES' name → (folder, result))."""
    root = tmp_path_factory.mktemp("huge")
    folders = [root / str(i) for i in range(len(HUGE_INPUTS) + len(FILE_CASES))]
    for f in folders:
        f.mkdir()
    files = dict(zip((name for name, _ in FILE_CASES), folders[len(HUGE_INPUTS):], strict=True))
    (files["giant-csv-field"] / "big.csv").write_text("wavelength_nm,reflectance\n380," + "1" * 200_000 + "\n",
                                                      encoding="utf-8")
    for name in ("deep-toml-validate", "deep-toml-build"):
        (files[name] / "deep.toml").write_text('name = "x"\na = ' + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    argvs = [[a.replace("{tmp}", str(f)) for a in args]
             for args, f in zip([a for a, _ in HUGE_INPUTS] + [a for _, a in FILE_CASES], folders, strict=True)]
    results = run_capped_batch(argvs, MEMORY_CAP_BYTES, timeout=300)
    runs = list(zip(folders, results, strict=True))
    return runs[:len(HUGE_INPUTS)], dict(zip(files, runs[len(HUGE_INPUTS):], strict=True))


@pytest.fixture(scope="module")
def huge_input_runs(capped_runs):
    return capped_runs[0]


@pytest.mark.parametrize("case", range(len(HUGE_INPUTS)), ids=[f"{a[0]}-{i}" for i, (a, _) in enumerate(HUGE_INPUTS)])
def test_issue12_huge_inputs_are_refused_under_a_memory_cap(huge_input_runs, case):
    folder, proc = huge_input_runs[case]
    assert_one_line_error(proc, HUGE_INPUTS[case][1])
    assert proc.returncode == 2
    assert list(folder.iterdir()) == []  # nothing written


def test_issue12_angular_map_is_computed_in_blocks(capped_runs):
    """243 × 243 cells needed ~1.4 GB before the optics ran in blocks of light rows; now ~0.4 GB."""
    tmp_path, proc = capped_runs[1]["angular-blocks"]
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "angular_050.0nm_spectral.exr").is_file()


def test_issue12_giant_csv_field(capped_runs):
    _, proc = capped_runs[1]["giant-csv-field"]
    assert_one_line_error(proc, "line 2", "131072 characters")
    assert proc.returncode == 2


def test_issue12_deeply_nested_toml(capped_runs):
    for cmd in ("validate", "build"):
        tmp_path, proc = capped_runs[1][f"deep-toml-{cmd}"]
        assert_one_line_error(proc, "nested too deeply")
        assert proc.returncode == 2
    assert not (tmp_path / "o").exists()


SPEC_TAIL = "\n[thickness]\nlist_nm = [50]\n"


@pytest.mark.parametrize("toml, fragment", [
    ('name = "x"\n[colour]\nilluminant = "D99"' + SPEC_TAIL, "key colour.illuminant"),
    ('name = "a\\u0007b"' + SPEC_TAIL, "control characters"),
    ('name = "a\\u0000b"' + SPEC_TAIL, "control characters"),
    ('name = "x"\ndescription = "line\\u001bESC"' + SPEC_TAIL, "control characters"),
    ('name = "x"\n[thickness]\nstart_nm = 20\nstop_nm = 30\nstep_nm = 5e-324\n', "at most 400"),
])
def test_issue12_validate_refuses_what_build_refuses(tmp_path, toml, fragment):
    spec = tmp_path / "s.toml"
    spec.write_text(toml, encoding="utf-8")
    for cmd in ("validate", "build"):
        extra = ["--out", tmp_path / "o"] if cmd == "build" else []
        proc = run_here("catalog", cmd, spec, *extra)
        assert_one_line_error(proc, fragment)
        assert proc.returncode == 2
    assert not (tmp_path / "o").exists()


def test_issue12_multiline_description_is_still_allowed(tmp_path):
    from swatch.catalog.spec import load_spec

    spec = tmp_path / "s.toml"
    spec.write_text('name = "x"\ndescription = """two\n\tlines"""' + SPEC_TAIL, encoding="utf-8")
    assert load_spec(spec)[0].description == "two\n\tlines"


@pytest.mark.parametrize("text, fragment", [
    ("wavelength_nm,reflectance\n" + "".join(f"{w},1e-310\n" for w in range(380, 781, 5)), "implausibly dark"),
    ("L,a,b\n50,1e200,0\n", "within ±200"),
    ("light_deg,view_deg,L,a,b\n45,0,50,3,-1e300\n", "within ±200"),
])
def test_issue12_implausible_measurements(tmp_path, text, fragment):
    p = tmp_path / "m.csv"
    p.write_text(text, encoding="utf-8")
    proc = run_here("fit", p)
    assert_one_line_error(proc, fragment)
    assert proc.returncode == 2
    assert "Warning" not in proc.stderr


def test_issue12_absurd_lab_target_is_refused():
    proc = run_here("match", "--lab", "50,1e300,0")
    assert_one_line_error(proc, "within ±200")
    assert proc.returncode == 2 and "Warning" not in proc.stderr


def test_issue12_wavelengths_on_a_spectral_fit_are_refused(tmp_path):
    p = tmp_path / "s.csv"
    p.write_text("wavelength_nm,reflectance\n" + "".join(f"{w},0.3\n" for w in range(380, 781, 5)))
    proc = run_here("fit", p, "--wavelengths", "380:780:10")
    assert_one_line_error(proc, "--wavelengths applies to CIELAB files")
    assert proc.returncode == 2


@pytest.mark.parametrize("args", [["match", "--hex", "257ab8", "--step", "5e-324"],
                                  ["fit", "{csv}", "--step", "5e-324"]])
def test_issue12_subnormal_search_step_is_refused(tmp_path, args):
    p = tmp_path / "s.csv"
    p.write_text("wavelength_nm,reflectance\n" + "".join(f"{w},0.3\n" for w in range(380, 781, 5)))
    proc = run_here(*[str(p) if a == "{csv}" else a for a in args])
    assert_one_line_error(proc, "search grid has too many thicknesses", "at most")
    assert proc.returncode == 2


@pytest.mark.parametrize("value", ["20,,40", "20,40,", ",20"])
def test_issue12_empty_list_elements_are_refused(value):
    proc = run_here("color", "--thickness", value)
    assert_one_line_error(proc, "empty element")
    assert proc.returncode == 2


def test_issue12_metal_overcoat_is_refused():
    proc = run_here("color", "--thickness", "50", "--overcoat", "Ti-Johnson:20")
    assert_one_line_error(proc, "Ti-Johnson", "not a clear film")
    assert proc.returncode == 2
    ok = run_here("color", "--thickness", "50", "--overcoat", "TiO2-Siefke:20", "--json")
    assert ok.returncode == 0, ok.stderr


def test_issue12_deeply_nested_process_profile(tmp_path):
    p = tmp_path / "deep.toml"
    p.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    proc = run_here("color", "--thickness", "50", "--process", p)
    assert_one_line_error(proc, "nested too deeply")
    assert proc.returncode == 2


def test_issue13_every_input_cap_is_defined_once_in_limits():
    """Caps on untrusted input live in swatch.core.limits only (one definition per limit): no other
    module assigns a module-level ``MAX_*``/``MIN_*`` name except the named modelling constants."""
    import ast
    from pathlib import Path

    import swatch
    from swatch.core import limits

    root = Path(swatch.__file__).parent
    allowed = {("result.py", "MIN_COLOUR_SAMPLES")}  # colour-science's interpolation needs 6 samples: not a cap
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "limits.py":
            continue
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
                node, ast.AnnAssign) else []
            for t in targets:
                if isinstance(t, ast.Name) and t.id.startswith(("MAX_", "MIN_")) and (path.name, t.id) not in allowed:
                    found.append(f"{path.relative_to(root)}: {t.id}")
    assert found == []
    assert all(hasattr(limits, n) for n in limits.__all__)
