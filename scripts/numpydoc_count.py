#!/usr/bin/env python3
"""Count the public functions and classes of swatch's subpackages and how many carry numpydoc (issue 17 item 5).

Public: a module-level ``def`` or ``class`` without a leading underscore (listed in ``__all__`` or not), and
the public methods of those classes (no leading underscore; properties included). A function has numpydoc
when its docstring has a numpydoc section (a ``Parameters``, ``Returns``, ``Yields``, ``Raises``,
``Attributes`` or ``Examples`` header underlined with dashes) and, if it takes parameters beyond
``self``/``cls``, a ``Parameters`` section (a property or a parameterless function needs ``Returns``); a class
when its own docstring has a ``Parameters`` or ``Attributes`` section, or it has no fields to describe.
A click command or group (``@click.command()``, ``@<group>.command()``, ``@click.group()``) counts when it
has a docstring: that docstring is its ``--help`` text (a numpydoc block would print there), and its
parameters are documented by its options' ``help=`` (tests/commands/test_flags.py checks every option has one).

    python3 scripts/numpydoc_count.py                 # the figures per subpackage
    python3 scripts/numpydoc_count.py --missing io    # the names still without, in swatch/io/
"""
from __future__ import annotations

import argparse
import ast
import re
from pathlib import Path

PKG = Path(__file__).resolve().parent.parent / "swatch"
SUBPACKAGES = ("render", "fit", "io", "catalog", "production", "report", "presets", "physics", "colorimetry",
               "core", "commands")
SECTION = re.compile(r"^\s*(Parameters|Returns|Yields|Raises|Attributes|Examples|Other Parameters)\s*\n\s*-{3,}\s*$",
                     re.M)


def _sections(doc: str | None) -> set[str]:
    return set(SECTION.findall(doc or ""))


def _params(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    a = fn.args
    names = [x.arg for x in [*a.posonlyargs, *a.args, *a.kwonlyargs]]
    names += [x.arg for x in (a.vararg, a.kwarg) if x is not None]
    return [n for n in names if n not in ("self", "cls")]


def _is_click_command(fn) -> bool:
    for d in fn.decorator_list:
        f = d.func if isinstance(d, ast.Call) else d
        if isinstance(f, ast.Attribute) and f.attr in ("command", "group"):
            return True
    return False


def _function_ok(fn) -> bool:
    if _is_click_command(fn):
        return bool(ast.get_docstring(fn))
    s = _sections(ast.get_docstring(fn))
    if not s:
        return False
    if _params(fn):
        return "Parameters" in s or "Other Parameters" in s
    return bool(s & {"Returns", "Yields", "Raises", "Examples"})


def _class_ok(cls: ast.ClassDef) -> bool:
    s = _sections(ast.get_docstring(cls))
    if s & {"Parameters", "Attributes"}:
        return True
    fields = [n for n in cls.body if isinstance(n, ast.AnnAssign)]
    init = next((n for n in cls.body if isinstance(n, ast.FunctionDef) and n.name == "__init__"), None)
    if init is not None and _params(init):
        return _function_ok(init)
    return not fields and bool(ast.get_docstring(cls))


def items(sub: str):
    """(qualified name, ok) of every public function, class and public method in ``swatch/<sub>/``."""
    for path in sorted((PKG / sub).rglob("*.py")):
        mod = ".".join(path.relative_to(PKG.parent).with_suffix("").parts).removesuffix(".__init__")
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
                yield f"{mod}.{node.name}", _function_ok(node)
            elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                yield f"{mod}.{node.name}", _class_ok(node)
                for m in node.body:
                    if isinstance(m, (ast.FunctionDef, ast.AsyncFunctionDef)) and not m.name.startswith("_"):
                        yield f"{mod}.{node.name}.{m.name}", _function_ok(m)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--missing", metavar="SUBPACKAGE", help="list the items without numpydoc in one subpackage")
    args = ap.parse_args()
    if args.missing:
        for name, ok in items(args.missing):
            if not ok:
                print(name)
        return 0
    total = done = 0
    for sub in SUBPACKAGES:
        got = list(items(sub))
        n_ok = sum(ok for _, ok in got)
        total, done = total + len(got), done + n_ok
        print(f"{sub:12s} {n_ok:4d} / {len(got):4d}")
    print(f"{'all':12s} {done:4d} / {total:4d}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
