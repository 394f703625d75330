"""``swatch catalog build``: outputs, metadata, determinism, incremental and atomic behaviour."""
from __future__ import annotations

import csv
import json
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import colour
import numpy as np
import pytest

import swatch  # (first: silences colour-science's plotting notice)
from swatch.catalog import build as buildmod
from swatch.catalog import sheets as sheetmod
from swatch.catalog.build import META_DIR, build_catalog
from swatch.core.errors import SwatchError
from tests.catalog.folder_helpers import digest, failing_move
from tests.cli_helpers import run_swatch

pytestmark = pytest.mark.slow  # builds catalogs or runs processes (seconds per test)

SPEC = """
name = "Test catalog"
film = "TiO2-Siefke"
substrate = "Ti-Johnson"
[thickness]
list_nm = [{thicknesses}]
[render]
size_px = 64
[tolerance]
grade = "{grade}"
[sheet]
columns = 2
rows = 2
"""
THICKNESSES = [30, 50.8, 87.5, 121.4, 160.6, 200]


def write_spec(path: Path, thicknesses=THICKNESSES, grade="C") -> Path:
    path.write_text(SPEC.format(thicknesses=", ".join(f"{t:g}" for t in thicknesses), grade=grade), encoding="utf-8")
    return path


def outputs(folder: Path) -> list[Path]:
    """The catalog's files: the top and its subfolders (sheets/, chips/, presets/), not its metadata."""
    return sorted(p for p in folder.rglob("*") if p.is_file() and META_DIR not in p.relative_to(folder).parts)


def copy_of_built(built, tmp_path: Path) -> tuple[Path, Path]:
    """(spec, out): a private copy of the module's built catalog and its spec (same file name: the spec's
    name is part of the outputs), for a test that changes an existing catalog. Copying instead of
    building again saves one full build a test (issue 17 item 7: the suite's time); the copy is a
    catalog like any other (``test_deterministic_and_independent_of_jobs`` pins that a fresh build
    gives the same bytes, and each test below checks the copy's state it starts from)."""
    spec, out, _ = built
    mine = tmp_path / "cat"
    mine.mkdir()
    shutil.copytree(out, mine / "out", symlinks=True)
    return write_spec(mine / spec.name), mine / "out"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("cat")
    spec = write_spec(root / "test.toml")
    out = root / "out"
    res = build_catalog(spec, out, jobs=2)
    return spec, out, res


EXPECTED_FILES = {"index.html", "catalog.json", "catalog.csv", "test-catalog.cxf", "test-catalog.ase",
                  "test-catalog-srgb.ase",
                  "sheets/sheet_01.png", "sheets/sheet_01.exr", "sheets/sheet_02.png", "sheets/sheet_02.exr"}
EXPECTED_FILES |= {f"presets/preset_S{i + 1:03d}{end}" for i in range(len(THICKNESSES))
                   for end in (".gltf", "_blender.py", ".mtlx", "_mitsuba.xml", "_mitsuba.json",
                               "_viewer.gltf")}  # 3-D material presets, the page's <model-viewer> files
EXPECTED_FILES |= {"presets/viewer_part.bin", "presets/model-viewer-4.4.0.min.js", "presets/model-viewer-4.4.0-LICENSE.txt"}
EXPECTED_FILES |= {f"chips/chip_S{i:03d}.{ext}" for i in range(1, len(THICKNESSES) + 1) for ext in ("png", "tif")}


def test_outputs_and_records(built):
    _, out, res = built
    assert not res.noop and res.rendered == len(THICKNESSES) and res.sheets == 2
    assert set(digest(out)) == EXPECTED_FILES
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    assert doc["catalog"]["name"] == "Test catalog"
    assert doc["catalog"]["reference_geometry"]["name"] == "45:0"
    recs = doc["swatches"]
    assert [r["thickness_nm"] for r in recs] == THICKNESSES
    for r in recs:
        for key in ("thickness_nm", "voltage_V", "Lab", "LCh", "srgb_hex", "multi_angle",
                    "delta_E_00_to_neighbours", "process_window"):
            assert key in r
        assert set(r["process_window"]) >= {"grade", "thickness_minus_nm", "thickness_plus_nm",
                                            "voltage_minus_V", "voltage_plus_V"}
        assert len(r["multi_angle"]) == 6 and all(len(v) == 3 for v in r["multi_angle"].values())
    rows = list(csv.DictReader((out / "catalog.csv").open(encoding="utf-8")))
    assert [float(r["thickness_nm"]) for r in rows] == THICKNESSES
    assert [r["srgb_hex"] for r in rows] == [r["srgb_hex"] for r in recs]
    assert float(rows[2]["L_D65_10_45as110"]) == pytest.approx(recs[2]["multi_angle"]["45as110"][0])
    assert [float(rows[2][k]) for k in ("L_D65_10", "a_D65_10", "b_D65_10")] == pytest.approx(recs[2]["Lab"])
    assert float(rows[2]["h_D65_10_deg"]) == pytest.approx(recs[2]["LCh"][2])
    assert [float(rows[2][k]) for k in ("L_D50_2", "a_D50_2", "b_D50_2")] == pytest.approx(recs[2]["Lab_D50_2"])
    # LCh at each multi-angle geometry too, consistent with that geometry's Lab
    a, b = float(rows[2]["a_D65_10_45as-15"]), float(rows[2]["b_D65_10_45as-15"])
    assert float(rows[2]["C_D65_10_45as-15"]) == pytest.approx(np.hypot(a, b), abs=1e-3)
    assert float(rows[2]["h_D65_10_deg_45as-15"]) == pytest.approx(np.degrees(np.arctan2(b, a)) % 360, abs=1e-2)
    # #18: every number of catalog.json: XYZ, the colour name, the multi-angle hex codes, the presets'
    # errors and the swatch's files
    for row, rec in zip(rows, recs, strict=True):
        assert [float(row[k]) for k in ("X_D65_10", "Y_D65_10", "Z_D65_10")] == pytest.approx(rec["XYZ"])
        assert row["colour_name"] == rec["colour_name"]
        assert all(row[f"srgb_hex_{g}"] == h for g, h in rec["multi_angle_srgb_hex"].items())
        figures = [k for k in rec["presets"] if "delta_E_00" in k]
        assert len(figures) == 17 and all(float(row[k]) == rec["presets"][k] for k in figures)  # with the <model-viewer> pair
        assert (row["chip_png"], row["chip_tiff"]) == (rec["print_chip"]["png"], rec["print_chip"]["tiff"])
        kinds = ("gltf", "blender", "materialx", "mitsuba", "mitsuba_json")
        assert [row[f"preset_{f}"] for f in kinds] == [rec["presets"][f] for f in kinds]
        assert all((out / row[k]).is_file() for k in ("sheet_png", "chip_png", "chip_tiff",
                                                       *(f"preset_{f}" for f in kinds)))


def test_sheet_metadata_and_pixels(built):
    import OpenImageIO as oiio

    from swatch.io.imageio import read_metadata

    _, out, _ = built
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    by_id = {r["id"]: r for r in doc["swatches"]}
    for name in ("sheets/sheet_01", "sheets/sheet_02"):
        for ext in ("png", "exr"):
            meta = read_metadata(out / f"{name}.{ext}")
            assert meta["catalog"]["name"] == "Test catalog"
            assert meta["catalog"]["illuminant"] == "D65"
            ids = meta["sheet"]["swatches"]
            assert ids == [r["id"] for r in doc["swatches"] if r["sheet_png"] == f"{name}.png"]
            for i in ids:
                assert meta[i] == by_id[i]  # the full record, identical to catalog.json
        png = oiio.ImageBuf(str(out / f"{name}.png"))
        exr = oiio.ImageBuf(str(out / f"{name}.exr"))
        assert png.spec().format == oiio.UINT8 and exr.spec().format == oiio.HALF
        assert (png.spec().width, png.spec().height) == (exr.spec().width, exr.spec().height)
        # the flat chip in a tile shows the record's sRGB colour (PNG) and its linear value (EXR)
        tiles = read_metadata(out / f"{name}.png")["sheet"]["tiles"]
        assert len(tiles) == len(ids)
    # The EXR is the PNG in linear light (outside the renders): compare the page background.
    p = oiio.ImageBuf(str(out / "sheets/sheet_01.png")).get_pixels(oiio.FLOAT)[5, 5]
    e = oiio.ImageBuf(str(out / "sheets/sheet_01.exr")).get_pixels(oiio.FLOAT)[5, 5]

    assert np.allclose(colour.models.eotf_sRGB(p), e, atol=2e-3)


def test_deterministic_and_independent_of_jobs(built, tmp_path):
    spec, out, _ = built
    other = tmp_path / "again"
    res = build_catalog(spec, other, jobs=1)
    assert not res.noop
    assert digest(other) == digest(out)


def test_noop_rebuild_is_fast_and_touches_nothing(built):
    spec, out, _ = built
    before = {p: p.stat().st_mtime_ns for p in outputs(out)}
    res = build_catalog(spec, out)
    assert res.noop
    # The 2 s budget is judged in the child's CPU seconds (user + system): on a loaded machine its
    # wall time measures the load (8 s at load 16 with the same 0.8 s of CPU); a hung rebuild
    # still fails the generous wall bound.
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "swatch.cli", "catalog", "build", str(spec), "--out", str(out)],
                          capture_output=True, text=True)
    wall = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    assert proc.returncode == 0, proc.stderr
    assert "up to date" in proc.stdout
    assert cpu <= 2.0, cpu
    assert wall <= 30.0, wall
    assert {p: p.stat().st_mtime_ns for p in outputs(out)} == before


def test_fingerprint_covers_every_engine_module_a_build_uses(built):
    """Regression: the no-op check hashed a hand-kept list of modules, which missed the
    environment-lighting, process and export modules, so changing them left a catalog 'up to
    date'. Every top-level swatch module loaded by a build must be in the fingerprint."""
    pkg = Path(swatch.__file__).resolve().parent
    used = {Path(m.__file__).resolve().relative_to(pkg).as_posix() for name, m in list(sys.modules.items())
            if name.startswith("swatch.") and getattr(m, "__file__", None)}
    code = buildmod.code_fingerprint()["code"]
    assert "physics/model.py" in used  # modules in subpackages count too (#17)
    assert used - set(code) == set()
    # the tiles may be rendered in worker processes: every engine module counts
    assert {p.relative_to(pkg).as_posix() for p in pkg.rglob("*.py")} - set(code) == set()


def test_incremental_rebuilds_only_what_changed(built, tmp_path):
    spec, out = copy_of_built(built, tmp_path)
    assert build_catalog(spec, out, jobs=1).noop  # the copy is up to date as it stands
    first = digest(out)
    # a tolerance change: no render, both sheets recomposed (their labels changed)
    write_spec(spec, grade="B")
    res = build_catalog(spec, out, jobs=1)
    assert (res.noop, res.rendered, res.composed) == (False, 0, 2)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    assert all(r["process_window"]["grade"] == "B" for r in doc["swatches"])
    # one thickness on the second sheet changed: one render, one sheet; sheet 1 untouched
    inode = (out / "sheets/sheet_01.png").stat().st_ino
    write_spec(spec, [*THICKNESSES[:-1], 210], grade="B")
    res = build_catalog(spec, out, jobs=1)
    assert (res.rendered, res.composed) == (1, 1)
    assert (out / "sheets/sheet_01.png").stat().st_ino == inode
    # back to the first spec: the outputs are the first build's, byte for byte
    write_spec(spec)
    build_catalog(spec, out, jobs=1)
    assert digest(out) == first
    # a deleted output is noticed and restored
    (out / "sheets/sheet_02.png").unlink()
    res = build_catalog(spec, out, jobs=1)
    assert not res.noop and res.rendered == 0
    assert digest(out) == first


def test_fewer_sheets_removes_old_ones(built, tmp_path):
    spec, out = copy_of_built(built, tmp_path)
    assert (out / "sheets/sheet_02.png").exists()
    write_spec(spec, THICKNESSES[:3])
    build_catalog(spec, out, jobs=1)
    assert not (out / "sheets/sheet_02.png").exists() and not (out / "sheets/sheet_02.exr").exists()
    assert (out / "sheets/sheet_01.png").exists()


def test_failed_build_leaves_previous_catalog(built, tmp_path, monkeypatch):
    spec, out = copy_of_built(built, tmp_path)
    before = digest(out)
    manifest = (out / META_DIR / "manifest.json").read_bytes()

    def boom(*args, **kwargs):
        raise SwatchError("simulated failure while writing a sheet")

    monkeypatch.setattr(sheetmod, "compose_sheet", boom)
    write_spec(spec, grade="A")
    with pytest.raises(SwatchError, match="simulated"):
        build_catalog(spec, out, jobs=1)
    assert digest(out) == before
    assert (out / META_DIR / "manifest.json").read_bytes() == manifest
    assert not list((out / META_DIR).glob("staging-*"))


def test_interrupted_commit_is_completed_by_the_next_build(built, tmp_path, monkeypatch):
    spec, out = copy_of_built(built, tmp_path)
    write_spec(spec, grade="A")
    # killed in the middle of moving files into place
    with failing_move(monkeypatch, out, 3, lambda dst: KeyboardInterrupt()), pytest.raises(KeyboardInterrupt):
        build_catalog(spec, out, jobs=1)
    assert (out / META_DIR / "journal.json").exists()
    res = build_catalog(spec, out, jobs=1)  # replays the journal; then everything is up to date
    assert res.noop
    manifest = json.loads((out / META_DIR / "manifest.json").read_text())
    assert {k: v["sha256"] for k, v in manifest["files"].items()} == digest(out)
    doc = json.loads((out / "catalog.json").read_text(encoding="utf-8"))
    assert doc["swatches"][0]["process_window"]["grade"] == "A"
    assert not (out / META_DIR / "journal.json").exists()


def test_never_writes_outside_the_output_folder(built):
    """The module's build (two workers) and every rebuild of it in this file left nothing beside the output
    folder, in the folder that holds it and the spec (issue 17: this was one more build of its own)."""
    spec, out, _ = built
    assert out.parent == spec.parent
    assert sorted(p.name for p in spec.parent.iterdir()) == ["out", spec.name]


def test_refuses_foreign_folders(tmp_path):
    spec = write_spec(tmp_path / "s.toml")
    foreign = tmp_path / "photos"
    foreign.mkdir()
    (foreign / "holiday.jpg").write_bytes(b"x")
    with pytest.raises(SwatchError, match="not a swatch catalog"):
        build_catalog(spec, foreign)
    assert sorted(p.name for p in foreign.iterdir()) == ["holiday.jpg"]
    (tmp_path / "file").write_text("x")
    with pytest.raises(SwatchError, match="is a file"):
        build_catalog(spec, tmp_path / "file")


def test_cli_reports_bad_specs_in_one_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[thickness]\nstart_nm = 20\nstop_nm = 30\nstep_nm = "a"\n', encoding="utf-8")
    proc = run_swatch("catalog", "build", bad, "--out", tmp_path / "o")
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"error: {bad}: key thickness.step_nm: must be a number > 0 (got 'a')"
    assert not (tmp_path / "o").exists()
    ill = write_spec(tmp_path / "ill.toml").read_text().replace("[render]", '[colour]\nilluminant = "D99"\n[render]')
    (tmp_path / "ill.toml").write_text(ill)
    proc = run_swatch("catalog", "build", tmp_path / "ill.toml", "--out", tmp_path / "o2")
    assert proc.returncode == 2 and "key colour.illuminant" in proc.stderr and "D65" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o2").exists()  # a failed first build leaves no folder behind
