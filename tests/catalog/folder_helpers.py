"""Helpers the catalog-folder tests share (#12, #21, #22): a small catalog spec, a digest and a snapshot of a
catalog folder, a crafted journal, and the CLI build refused in one line. The built catalog they start
from is the ``first_build`` fixture (tests/catalog/conftest.py)."""
from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import subprocess
from pathlib import Path

from swatch.catalog.folder import JOURNAL, MANIFEST, META_DIR
from swatch.cli import main
from tests.cli_helpers import assert_one_line_error


def digest(folder: Path) -> dict[str, str]:
    """The catalog's files (the top and its subfolders, #21; not the metadata) by relative name → SHA-256."""
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and META_DIR not in p.relative_to(folder).parts}


SPEC = """
name = "{name}"
[thickness]
list_nm = [{list_nm}]
[render]
size_px = 64
shapes = ["flat"]
angular_map = false
[tolerance]
grade = "{grade}"
[sheet]
columns = 2
rows = 1
"""


def write_spec(path: Path, grade: str = "C", name: str = "Hardening", list_nm=(40, 90, 140)) -> Path:
    """A three-swatch flat catalog spec (64 px tiles, one 2 × 1 sheet) with tolerance ``grade``."""
    text = SPEC.format(name=name, list_nm=", ".join(str(d) for d in list_nm), grade=grade)
    path.write_text(text, encoding="utf-8")
    return path


def tree(folder: Path) -> dict[str, bytes | None]:
    """Every entry under ``folder`` (links not followed) with file contents: a before/after snapshot."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = p.relative_to(folder).as_posix()
        out[rel] = p.read_bytes() if p.is_file() and not p.is_symlink() else os.readlink(p) if p.is_symlink() else None
    return out


def refuse(spec, out, *fragments):
    """The CLI build (in this process: faster) is refused in one line with exit 2."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        rc = main(["catalog", "build", str(spec), "--out", str(out), "-q"])
    proc = subprocess.CompletedProcess([], rc, "", err.getvalue())
    assert_one_line_error(proc, *fragments)
    assert proc.returncode == 2
    return proc


def journal(out: Path, **changes) -> None:
    meta = out / META_DIR
    man = json.loads((meta / MANIFEST).read_text())
    doc = {"phase": "commit", "staging": "staging-x", "files": [], "remove": [], "manifest": man}
    doc.update(changes)
    (meta / JOURNAL).write_text(json.dumps(doc), encoding="utf-8")


@contextlib.contextmanager
def failing_move(monkeypatch, out: Path, nth: int, error, depth: int = 1, staged: bool = True):
    """``os.replace`` that raises ``error(dst)`` on the ``nth`` move into the catalog folder ``out`` (``depth`` 2:
    into one of its subfolders), from a staging folder unless ``staged`` is False; the real one otherwise, and
    back in place on leaving. Yields the count of those moves (``{"n": …}``): a commit killed or failing there."""
    real_replace = os.replace
    calls = {"n": 0}

    def replace(src, dst):
        into = Path(dst).parents[depth - 1] == out
        if into and (not staged or Path(src).parents[depth - 1].name.startswith("staging-")):
            calls["n"] += 1
            if calls["n"] == nth:
                raise error(str(dst))
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    try:
        yield calls
    finally:
        monkeypatch.setattr(os, "replace", real_replace)
