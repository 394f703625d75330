"""Issue #22 groups 5 and 8 (what was left): a full disk during `fit --report` or `calibrate` leaves
nothing half-written (no truncated PNG or 0-byte EXR under the final name, no empty folder) and is
one `error:` line, exit 2; an output file's missing folder is created as output folders are, and a
folder that cannot be made is refused before the work; mesh files that are not UTF-8 text, have
coordinates beyond the cap or no area get one clean line (no numpy/trimesh warnings, no
charset_normalizer); a range over its cap states its exact point count."""
from __future__ import annotations

import contextlib
import resource
import signal
from pathlib import Path

import numpy as np
import pytest

from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text, output_batch
from swatch.core.limits import MAX_MESH_COORDINATE, MAX_RANGE_POINTS
from swatch.io.imageio import write_exr, write_png
from tests.cli_helpers import assert_one_line_error, run_swatch

COUPONS = Path(__file__).resolve().parents[1] / "data" / "simulated-line-coupons.csv"
FAST = ("--fixed-tables", "--fixed-scale")  # (the calibration's table ranking is not what these tests are about)
SPECTRUM = Path(__file__).parents[2] / "examples" / "blue_45_0_spectrum.csv"


@contextlib.contextmanager
def file_size_limit(limit_bytes: int):
    """Writes beyond ``limit_bytes`` in any one file fail (EFBIG) in this process, as on a full disk: the
    real write calls of Python, libpng and OpenEXR fail, nothing is mocked. SIGXFSZ is ignored (its
    default ends the process) so that the writes return the error instead."""
    old_limit = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, old_limit[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old_limit)
        signal.signal(signal.SIGXFSZ, old_handler)


def tree(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


@pytest.mark.parametrize("limit", [512, 8192])
def test_issue22_fit_report_on_a_full_disk_leaves_no_folder_and_one_line(tmp_path, limit):
    """Issue #22 group 5: the PNG writer's failure went unnoticed (a truncated delta_e_map.png, a 0-byte .exr,
    exit 70 "not a PNG file") and the folder was left; now nothing of the report remains, exit 2."""
    report = tmp_path / "new" / "report"
    with file_size_limit(limit):
        proc = run_swatch("fit", SPECTRUM, "--report", report)
    assert_one_line_error(proc, "cannot write", "delta_e_map")
    assert proc.returncode == 2
    assert tree(tmp_path) == []


def test_issue22_a_full_disk_keeps_a_forced_reports_previous_files(tmp_path):
    """Issue #22 group 5: with --force, a report that fails half-way replaces none of the previous one's files."""
    report = tmp_path / "report"
    assert run_swatch("fit", SPECTRUM, "--report", report).returncode == 0
    before = {p.name: p.read_bytes() for p in report.iterdir()}
    with file_size_limit(8192):
        proc = run_swatch("fit", SPECTRUM, "--illuminant", "A", "--report", report, "--force")  # other values
    assert_one_line_error(proc, "cannot write")
    assert {p.name: p.read_bytes() for p in report.iterdir()} == before


@pytest.mark.parametrize("writer", ["png", "exr"])
def test_issue22_an_image_cut_short_by_the_disk_is_an_error_not_a_file(tmp_path, writer):
    """Issue #22 group 5: libpng and OpenEXR can stop at the disk's end without an error; the image is checked
    whole (PNG chunks and IEND, EXR's last row read back) before it is renamed into place."""
    rng = np.random.default_rng(1)  # noise: does not compress below the limit
    path = tmp_path / f"x.{writer}"
    with file_size_limit(4096), pytest.raises(SwatchError, match="cannot write"):
        if writer == "png":
            write_png(path, rng.integers(0, 255, (64, 64, 3), dtype=np.uint8))
        else:
            write_exr(path, rng.random((64, 64, 3)), half=False)
    assert list(tmp_path.iterdir()) == []


def test_issue22_calibrate_on_a_full_disk_writes_neither_profile_nor_report(tmp_path):
    with file_size_limit(16384):  # the profile (~3 kB) fits, the figure does not
        proc = run_swatch("calibrate", COUPONS, *FAST, "--out", tmp_path / "line" / "p.toml", "--report",
                          tmp_path / "line" / "report")
    assert_one_line_error(proc, "cannot write", "calibration.png")
    assert proc.returncode == 2
    assert tree(tmp_path) == []


def test_issue22_output_batch_is_all_or_nothing(tmp_path):
    """Issue #22 group 5: a batch that fails after some files are written renames none into place and removes the
    folders it created (deepest first, the outer batch's as well as a nested one's)."""
    out = tmp_path / "a" / "b"
    with pytest.raises(RuntimeError), output_batch(out):
        atomic_write_text(out / "one.txt", "1")
        with output_batch(out / "inner"):
            atomic_write_text(out / "inner" / "two.txt", "2")
        assert not (out / "one.txt").exists()  # staged: not yet under its name
        raise RuntimeError("stop")
    assert tree(tmp_path) == []
    with output_batch(out):
        atomic_write_text(out / "one.txt", "1")
    assert tree(tmp_path) == ["a", "a/b", "a/b/one.txt"]


def test_issue22_calibrate_creates_the_profiles_missing_folder(tmp_path):
    """Issue #22 group 8: `--out new/sub/p.toml` said "No such file or directory … .p.swtmp….tmp.toml" after the
    fit; an output file's folder is created, with its parents, as `--out DIR` and `--report DIR` folders are."""
    out = tmp_path / "new" / "sub" / "p.toml"
    proc = run_swatch("calibrate", COUPONS, *FAST, "--out", out)
    assert proc.returncode == 0, proc.stderr
    assert out.is_file() and tree(tmp_path) == ["new", "new/sub", "new/sub/p.toml"]


@pytest.mark.parametrize("cmd", ["calibrate", "fit"])
def test_issue22_an_output_folder_that_cannot_be_made_is_refused_before_the_work(tmp_path, cmd):
    (tmp_path / "afile").write_text("mine", encoding="utf-8")
    target = tmp_path / "afile" / "sub"
    args = (["calibrate", COUPONS, "--out", target / "p.toml"] if cmd == "calibrate"
            else ["fit", SPECTRUM, "--report", target])
    proc = run_swatch(*args)
    assert_one_line_error(proc, "cannot be created", "afile is a file")
    assert proc.returncode == 2
    assert (tmp_path / "afile").read_text(encoding="utf-8") == "mine"


def test_issue22_range_over_the_cap_gives_its_exact_point_count():
    """Issue #22 group 8: "1e+05 points; at most 100000" for 100,001 points."""
    proc = run_swatch("color", "--thickness", "0:1000:0.01")
    assert_one_line_error(proc, f"has {MAX_RANGE_POINTS + 1} points; at most {MAX_RANGE_POINTS}")
    proc = run_swatch("color", "--thickness", "0:1000:1e-300")
    assert_one_line_error(proc, f"more than {MAX_RANGE_POINTS} points")


STL_TRIANGLE = ("solid {name}\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
                "  endloop\n endfacet\nendsolid\n")


@pytest.mark.parametrize(("name", "content", "fragments"), [
    ("huge.obj", b"v 1e300 0 0\nv 0 1e300 0\nv 0 0 1e300\nf 1 2 3\n", ["1e+300", f"at most {MAX_MESH_COORDINATE:.0e}"]),
    ("overflow.obj", b"v 1e308 1e308 1e308\nv -1e308 -1e308 -1e308\nv 1e308 -1e308 0\nf 1 2 3\n", ["at most"]),
    ("line.obj", b"v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", ["zero area", "at least one triangle with an area"]),
    ("latin1.obj", "v 0 0 0 # café\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode("latin-1"),
     ["not utf-8 text", "0xe9", "an obj file is ascii or utf-8 text"]),
    ("latin1.stl", STL_TRIANGLE.format(name="café").encode("latin-1"),
     ["not utf-8 text", "binary (84 bytes + 50 a triangle) or ascii/utf-8 text"]),
    ("noise.stl", bytes(np.random.default_rng(3).integers(128, 256, 3000, dtype=np.uint8)), ["not utf-8 text"]),
    ("latin1.ply", b"ply\nformat ascii 1.0\ncomment caf\xe9\nelement vertex 0\nend_header\n", ["a ply header is"]),
])
def test_issue22_bad_meshes_get_one_clean_line(tmp_path, recwarn, name, content, fragments):
    """Issue #22 group 8: numpy/trimesh RuntimeWarnings printed before the error for huge or overflowing
    coordinates, which were then called "degenerate"; a non-UTF-8 STL/OBJ mentioned "No module named
    'charset_normalizer'" (trimesh's encoding guesser, not a dependency of ours)."""
    mesh = tmp_path / name
    mesh.write_bytes(content)
    proc = run_swatch("render", "--thickness", "100", "--mesh", mesh, "--size", "16", "--out", tmp_path / "out")
    assert_one_line_error(proc, *fragments)
    assert "charset" not in proc.stderr and "degenerate" not in proc.stderr
    assert proc.returncode == 2
    assert not (tmp_path / "out").exists()
    assert [w for w in recwarn if issubclass(w.category, RuntimeWarning)] == []


def test_issue22_a_utf8_mesh_with_a_byte_order_mark_renders(tmp_path):
    mesh = tmp_path / "bom.stl"
    mesh.write_bytes(b"\xef\xbb\xbf" + STL_TRIANGLE.format(name="caf\u00e9").encode("utf-8"))
    proc = run_swatch("render", "--thickness", "100", "--mesh", mesh, "--size", "16", "--out", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
