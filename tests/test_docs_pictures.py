"""The pictures in docs/ are made by scripts/docs_pictures.py from the current code, and none is stale.

``docs/pictures.json`` records, per picture, the fingerprint of what made it (the code of the modules it
depends on without comments or docstrings, its inputs, the script) and the picture's SHA-256. This test
recomputes the fingerprints without rendering anything: a change to that code or those inputs, a
picture edited by hand, or a picture no script makes fails here. Remake them with
``python scripts/docs_pictures.py [NAME …]``.
"""
from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import docs_pictures  # noqa: E402

RECORD = json.loads((ROOT / "docs" / "pictures.json").read_text(encoding="utf-8"))


def test_every_picture_in_docs_is_made_by_the_script():
    pictures = sorted(p.name for p in (ROOT / "docs").glob("*.png"))
    assert pictures == sorted(docs_pictures.PICTURES) == sorted(RECORD)


@pytest.mark.parametrize("name", sorted(docs_pictures.PICTURES))
def test_the_picture_is_what_the_script_made_from_the_current_code(name):
    recorded = RECORD[name]
    assert hashlib.sha256((ROOT / "docs" / name).read_bytes()).hexdigest() == recorded["sha256"], (
        f"docs/{name} is not the picture scripts/docs_pictures.py made")
    assert docs_pictures.fingerprint(name) == recorded["fingerprint"], (
        f"docs/{name} is stale: the code or inputs that make it changed; run "
        f"`python scripts/docs_pictures.py {name}`")


def test_the_fingerprint_follows_code_not_comments(tmp_path, monkeypatch):
    """A docstring or comment edit leaves a fingerprint alone; a code edit changes it."""
    src = tmp_path / "m.py"
    src.write_text('"""doc"""\nX = 1  # one\n', encoding="utf-8")
    a = docs_pictures._source_digest(src)
    src.write_text('"""other doc"""\n\nX = 1\n', encoding="utf-8")
    assert docs_pictures._source_digest(src) == a
    src.write_text('"""doc"""\nX = 2\n', encoding="utf-8")
    assert docs_pictures._source_digest(src) != a
