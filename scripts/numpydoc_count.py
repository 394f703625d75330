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

An entry is *bare* (issue 36) when a ``Parameters``, ``Other Parameters``, ``Returns``, ``Yields`` or
``Attributes`` entry gives only a name and/or a type (``thickness_nm : float``, ``numpy.ndarray``) with no
indented line under it saying what the value means, its unit and shape (a ``Returns`` of ``None`` needs
none). ``--bare`` counts them in every
docstring of the package (public or private functions, classes, methods) and lists them for one subpackage.

    python3 scripts/numpydoc_count.py                 # the figures per subpackage
    python3 scripts/numpydoc_count.py --missing io    # the names still without, in swatch/io/
    python3 scripts/numpydoc_count.py --bare          # bare entries / entries, per subpackage and section
    python3 scripts/numpydoc_count.py --bare physics  # the bare entries in swatch/physics/, file:line
"""
from __future__ import annotations

import argparse
import ast
import re
from pathlib import Path

PKG = Path(__file__).resolve().parent.parent / "swatch"
SUBPACKAGES = ("render", "fit", "io", "catalog", "production", "report", "presets", "physics", "colorimetry",
               "core", "commands")
ENTRY_SECTIONS = ("Parameters", "Other Parameters", "Returns", "Yields", "Attributes")
_DASHES = re.compile(r"^\s*-{3,}\s*$")
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


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def doc_entries(doc: str | None):
    """(section, entry line, described) of every entry in the entry sections of one (cleaned) docstring.

    A section is a header line underlined with dashes; it runs to the next such header. Its entries are
    its lines at the header's indentation; an entry is described when the next non-blank line is indented
    deeper than the entry.
    """
    lines = (doc or "").splitlines()
    heads = [i for i in range(len(lines) - 1)
             if lines[i].strip() and _DASHES.match(lines[i + 1]) and not _DASHES.match(lines[i])]
    for k, h in enumerate(heads):
        section = lines[h].strip()
        if section not in ENTRY_SECTIONS:
            continue
        base = _indent(lines[h])
        body = lines[h + 2:heads[k + 1] if k + 1 < len(heads) else len(lines)]
        for j, line in enumerate(body):
            if not line.strip() or _indent(line) != base:
                continue
            after = next((m for m in body[j + 1:] if m.strip()), None)
            described = after is not None and _indent(after) > base
            yield section, line.strip(), described or (section == "Returns" and line.strip() == "None")


def bare_entries(sub: str):
    """(``path:line``, qualified name, section, entry) of every bare entry in ``swatch/<sub>/``'s docstrings."""
    for path in sorted((PKG / sub).rglob("*.py")):
        rel = path.relative_to(PKG.parent).as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                for section, entry, described in doc_entries(ast.get_docstring(node)):
                    if not described:
                        yield f"{rel}:{node.lineno}", node.name, section, entry


def entry_counts(sub: str) -> dict[str, tuple[int, int]]:
    """Per entry section: (bare entries, all entries) in ``swatch/<sub>/``'s docstrings."""
    out: dict[str, tuple[int, int]] = {}
    for path in sorted((PKG / sub).rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                for section, _, described in doc_entries(ast.get_docstring(node)):
                    bare, total = out.get(section, (0, 0))
                    out[section] = (bare + (not described), total + 1)
    return out


def _bare_report(sub: str | None) -> int:
    if sub:
        found = list(bare_entries(sub))
        for where, name, section, entry in found:
            print(f"{where}  {name}  {section}: {entry}")
        print(f"{len(found)} bare entries in swatch/{sub}/")
        return 0
    sums: dict[str, list[int]] = {}
    print(f"{'':12s} " + "  ".join(f"{s:>16s}" for s in ENTRY_SECTIONS) + "   (bare / entries)")
    for s in SUBPACKAGES:
        got = entry_counts(s)
        cells = []
        for sec in ENTRY_SECTIONS:
            b, t = got.get(sec, (0, 0))
            acc = sums.setdefault(sec, [0, 0])
            acc[0], acc[1] = acc[0] + b, acc[1] + t
            cells.append(f"{b:>7d} / {t:<6d}")
        print(f"{s:12s} " + "  ".join(cells))
    print(f"{'all':12s} " + "  ".join(f"{b:>7d} / {t:<6d}" for b, t in (sums[sec] for sec in ENTRY_SECTIONS)))
    print("bare: " + ", ".join(f"{sec} {100 * b / t:.1f} %" for sec, (b, t) in sums.items() if t))
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--missing", metavar="SUBPACKAGE", help="list the items without numpydoc in one subpackage")
    ap.add_argument("--bare", metavar="SUBPACKAGE", nargs="?", const="",
                    help="count the entries with only a name/type and no description; with a subpackage, list them")
    args = ap.parse_args()
    if args.bare is not None:
        return _bare_report(args.bare)
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
