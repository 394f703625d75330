"""The ``anodic_film`` plugin's parameter table (docs/mitsuba.md) from its one definition, ``PARAMETERS`` in
swatch/render/mitsuba/bsdf.py, read as a literal (no Mitsuba needed): Parameter, Type, Default, Description
and Flags, the columns of Mitsuba's own plugin tables (exposed: ``traverse`` puts it in ``mi.traverse``'s
parameters; ∂: differentiable).

``python3 scripts/mitsuba_parameters.py`` prints the Markdown table; ``docs/conf.py`` writes it into
docs/generated/mitsuba_parameters.md, which docs/mitsuba.md includes.
"""
from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BSDF = ROOT / "swatch" / "render" / "mitsuba" / "bsdf.py"


def parameters(path: Path = BSDF) -> tuple[dict, ...]:
    """``PARAMETERS`` of the plugin's module, read from its source as a literal."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.target.id == "PARAMETERS":
            return ast.literal_eval(node.value)
    raise LookupError(f"{path}: no PARAMETERS")


def flags(row: dict) -> str:
    """The Flags cell: ``exposed``, ``exposed, ∂`` (differentiable) or a dash."""
    if not row["exposed"]:
        return "—"
    return "exposed, ∂" if row["differentiable"] else "exposed"


def markdown_table(rows=None) -> str:
    """The Markdown table, one row per entry of ``PARAMETERS``."""
    rows = parameters() if rows is None else rows
    lines = ["| Parameter | Type | Default | Description | Flags |", "| --- | --- | --- | --- | --- |"]
    for r in rows:
        keys = ", ".join(f"`{k}`" for k in r["keys"])
        lines.append(f"| {keys} | {r['type']} | {r['default']} | {r['description']} | {flags(r)} |")
    return "\n".join(lines) + "\n"


def write(out: Path) -> bool:
    """Write the table to ``out`` when it differs (an unchanged file keeps its time); True when written."""
    text = markdown_table()
    if out.exists() and out.read_text(encoding="utf-8") == text:
        return False
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text, encoding="utf-8")
    return True


if __name__ == "__main__":
    sys.stdout.write(markdown_table())
