"""The ``anodic_film`` plugin's parameter table has one definition (bsdf.PARAMETERS, issue 48): its keys are
the keys the plugin reads, its defaults the code's, its flags what Mitsuba's ``traverse`` really exposes, and
docs/mitsuba.md shows the table generated from it."""
from __future__ import annotations

import ast
import importlib.util
from pathlib import Path

import pytest

from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE
from tests.mitsuba_setup import mitsuba_variant

ROOT = Path(__file__).resolve().parents[2]
BSDF = ROOT / "swatch" / "render" / "mitsuba" / "bsdf.py"


def _script():
    spec = importlib.util.spec_from_file_location("mitsuba_parameters", ROOT / "scripts" / "mitsuba_parameters.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _keys_read() -> set[str]:
    """Every scene-dictionary key the plugin's source reads: ``props.get("k"…)``, ``"k" in props`` and
    ``_float_or_texture(props, "k", …)`` / ``_flag(props, "k")``."""
    keys = set()
    for node in ast.walk(ast.parse(BSDF.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant):
            f = node.func
            if isinstance(f, ast.Attribute) and f.attr == "get" and getattr(f.value, "id", None) == "props":
                keys.add(node.args[0].value)
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) in ("_float_or_texture", "_flag"):
            keys.add(node.args[1].value)
        if isinstance(node, ast.Compare) and isinstance(node.left, ast.Constant) \
                and isinstance(node.ops[0], ast.In) and getattr(node.comparators[0], "id", None) == "props":
            keys.add(node.left.value)
    return keys


def test_the_table_names_every_key_the_plugin_reads_and_no_other():
    rows = _script().parameters()
    named = [k for r in rows for k in r["keys"]]
    assert len(named) == len(set(named))
    assert set(named) == _keys_read()
    film = next(r for r in rows if r["keys"] == ("film", "substrate"))
    assert film["default"] == f"{DEFAULT_FILM}, {DEFAULT_SUBSTRATE}"


def test_the_docs_show_the_generated_table(tmp_path):
    script = _script()
    text = (ROOT / "docs" / "mitsuba.md").read_text(encoding="utf-8")
    assert "```{include} generated/mitsuba_parameters.md\n```" in text
    assert "| key | value | default |" not in text  # no hand-kept copy beside it
    assert script.write(tmp_path / "t.md") and (tmp_path / "t.md").read_text(encoding="utf-8") == script.markdown_table()
    table = script.markdown_table().splitlines()
    assert table[0] == "| Parameter | Type | Default | Description | Flags |"
    assert len(table) == 2 + len(script.parameters())


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def test_the_flags_are_what_traverse_exposes(mi):
    """Each row's ``exposed`` / ``differentiable`` against ``mi.traverse`` of a loaded plugin (a float thickness
    is a uniform texture: its ``value`` is the exposed leaf)."""
    params = mi.traverse(mi.load_dict({"type": "anodic_film", "thickness_nm": 120.0, "alpha_u": 0.1,
                                       "alpha_v": 0.3, "brush_axis": [1.0, 0.0, 0.0], "spread_nm": 1.0}))
    exposed = {}
    for name in sorted(params.keys()):
        key = name.split(".")[0]
        differentiable = not (params.flags(name) & int(mi.ParamFlags.NonDifferentiable))
        exposed[key] = exposed.get(key, False) or differentiable
    rows = _script().parameters()
    assert exposed == {k: r["differentiable"] for r in rows if r["exposed"] for k in r["keys"]}
