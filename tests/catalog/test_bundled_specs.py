"""The catalog specs ship inside the package: built by name in an empty folder, copied by ``catalog init``."""
from __future__ import annotations

import tomllib
from pathlib import Path

from swatch.catalog.spec import SPECS_DIR, bundled_specs, load_spec, resolve_spec_path
from tests.cli_helpers import run_swatch

ROOT = Path(__file__).resolve().parents[2]


def test_the_bundled_specs_are_the_repository_catalog_folder():
    """The package's specs are the repository's catalog/*.toml (one copy: a link), each a valid spec."""
    assert sorted(bundled_specs()) == sorted(p.stem for p in (ROOT / "catalog").glob("*.toml"))
    for name, path in bundled_specs().items():
        assert path.read_bytes() == (ROOT / "catalog" / f"{name}.toml").read_bytes()
        load_spec(path)
    assert SPECS_DIR.is_dir()


def test_a_name_resolves_to_the_bundled_spec_and_a_file_wins(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert resolve_spec_path("titanium") == bundled_specs()["titanium"]
    (tmp_path / "titanium").mkdir()  # a catalog built with --out titanium/: the name still means the spec
    assert resolve_spec_path("titanium") == bundled_specs()["titanium"]
    (tmp_path / "titanium").rmdir()
    (tmp_path / "titanium").write_text('name = "mine"\n', encoding="utf-8")
    assert resolve_spec_path("titanium") == Path("titanium")  # a file of that name here is what the user meant
    assert resolve_spec_path("other.toml") == Path("other.toml")  # a path is a path (load_spec reports it missing)


def test_an_unknown_name_is_one_line_listing_the_bundled_ones(tmp_path):
    r = run_swatch("catalog", "build", "titanum", "--out", tmp_path / "c", cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.startswith("error: titanum: no such file here, nor a bundled catalog spec")
    assert "titanium" in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / "c").exists()


def test_a_folder_is_no_spec(tmp_path):
    (tmp_path / "mine").mkdir()
    r = run_swatch("catalog", "validate", "mine", cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.startswith("error: mine is a folder, not a catalog spec")


def test_validate_and_list_take_bundled_names(tmp_path):
    r = run_swatch("catalog", "validate", "paper-samples", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "10 swatches" in r.stdout
    r = run_swatch("catalog", "list", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert [line.split()[0] for line in r.stdout.splitlines()] == sorted(bundled_specs())


def test_init_writes_a_copy_and_never_overwrites_without_force(tmp_path):
    r = run_swatch("catalog", "init", "titanium", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    copy = tmp_path / "titanium.toml"
    assert copy.read_bytes() == (ROOT / "catalog" / "titanium.toml").read_bytes()
    copy.write_text(copy.read_text(encoding="utf-8").replace("step_nm = 5", "step_nm = 10"), encoding="utf-8")
    edited = copy.read_bytes()
    r = run_swatch("catalog", "init", "titanium", cwd=tmp_path)
    assert r.returncode == 2 and "already exists" in r.stderr
    assert copy.read_bytes() == edited
    assert tomllib.loads(edited.decode())["thickness"]["step_nm"] == 10
    r = run_swatch("catalog", "init", "titanium", "--force", cwd=tmp_path)
    assert r.returncode == 0 and copy.read_bytes() == (ROOT / "catalog" / "titanium.toml").read_bytes()
    r = run_swatch("catalog", "init", "titanium", "--out", "specs/mine.toml", cwd=tmp_path)
    assert r.returncode == 0 and (tmp_path / "specs" / "mine.toml").is_file()
    r = run_swatch("catalog", "init", "nope", cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.startswith("error: nope: not a bundled catalog spec")
