"""The package's own source files, for the content hashes that key caches and catalog fingerprints.

A catalog (or a tile, or a preset fit) is up to date only while the code that computed it is unchanged;
these helpers list that code in one place, so a module that moves between subpackages is still hashed.
"""
from __future__ import annotations

import ast
import functools
import hashlib
from pathlib import Path

__all__ = ["package_dir", "source_files", "sha256_file", "imported_modules", "code_hash"]


def package_dir() -> Path:
    """The installed ``swatch/`` folder (resolved).

    Returns
    -------
    pathlib.Path
        The absolute, resolved path of the ``swatch`` package folder (the one this module is in).
    """
    return Path(__file__).resolve().parent.parent


def source_files(exclude: tuple[str, ...] = ()) -> list[Path]:
    """Every ``.py`` file under ``swatch/`` (recursively, sorted by relative path).

    Parameters
    ----------
    exclude
        Top-level subpackage names (e.g. ``("catalog", "commands")``) whose files are left out.
    """
    pkg = package_dir()
    files = [p for p in pkg.rglob("*.py")
             if "__pycache__" not in p.parts and p.relative_to(pkg).parts[0] not in exclude]
    return sorted(files, key=lambda p: p.relative_to(pkg).as_posix())


def sha256_file(path: Path) -> str:
    """The SHA-256 of a file's bytes, read in 1 MiB chunks (the one definition: sources, caches, manifests).

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _module_file(pkg: Path, name: str) -> Path | None:
    """The source file of a ``swatch.*`` module name (a package's ``__init__.py``), or None."""
    rel = Path(*name.split(".")[1:])
    for path in (pkg / rel.with_suffix(".py"), pkg / rel / "__init__.py") if rel.parts else (pkg / "__init__.py",):
        if path.is_file():
            return path
    return None


@functools.lru_cache(maxsize=64)
def _lazy_names(face: Path) -> dict[str, str]:
    """A package face's lazily loaded names (PEP 562): the ``{"name": "swatch.module"}`` entries of its dicts."""
    names: dict[str, str] = {}
    for node in ast.walk(ast.parse(face.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Dict):
            for k, v in zip(node.keys, node.values, strict=True):
                if (isinstance(k, ast.Constant) and isinstance(k.value, str) and isinstance(v, ast.Constant)
                        and isinstance(v.value, str) and v.value.startswith("swatch.")):
                    names[k.value] = v.value
    return names


@functools.lru_cache(maxsize=512)
def _imports_of(pkg: Path, name: str, path: Path) -> frozenset[str]:
    """The ``swatch.*`` modules ``name`` imports (at the top or inside functions), with their packages (each
    module parsed once a process, as :func:`imported_modules` assumes the sources do not change under it)."""
    found: set[str] = set()
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        bases: list[str] = []
        if isinstance(node, ast.Import):
            bases = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                root = package
                for _ in range(node.level - 1):
                    root = root.rsplit(".", 1)[0]
                base = root + ("." + base if base else "")
            # (a name may be a submodule, or a package face's lazily loaded name: PEP 562, its map's module)
            face = _module_file(pkg, base) if base.split(".")[0] == "swatch" else None
            lazy = _lazy_names(face) if face is not None and face.name == "__init__.py" else {}
            bases = [base] + [lazy.get(a.name, f"{base}.{a.name}") for a in node.names]
        for b in bases:
            parts = b.split(".")
            if parts[0] != "swatch":
                continue
            for i in range(1, len(parts) + 1):  # the module and the packages it runs on import
                if _module_file(pkg, ".".join(parts[:i])) is not None:
                    found.add(".".join(parts[:i]))
    return frozenset(found)


@functools.lru_cache(maxsize=32)
def imported_modules(*modules: str) -> tuple[str, ...]:
    """Every ``swatch`` module that ``modules`` import, directly or not (imports inside functions too: the
    lazily loaded Mitsuba engine counts), the modules themselves included.

    Parameters
    ----------
    *modules : str
        Dotted module names (``swatch.catalog.tiles``).

    Returns
    -------
    tuple of str
        The module names, sorted.
    """
    pkg = package_dir()
    seen: set[str] = set()
    todo = list(modules)
    while todo:
        name = todo.pop()
        path = _module_file(pkg, name)
        if name in seen or path is None:
            continue
        seen.add(name)
        todo += sorted(_imports_of(pkg, name, path) - seen)
    return tuple(sorted(seen))


def code_hash(*modules: str, extra: tuple[Path, ...] = ()) -> str:
    """The SHA-256 of the code ``modules`` run (:func:`imported_modules`) and of ``extra`` files: the one
    code key of the caches (tiles, hero renders, preset fits, the page's environment data), so that a cache
    entry is stale as soon as any module its computation imports changes (hand lists missed some).

    Parameters
    ----------
    *modules : str
        Dotted module names whose import closure is hashed.
    extra : tuple of pathlib.Path, optional
        Data files the computation reads (tables), hashed too.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    pkg = package_dir()
    h = hashlib.sha256()
    for name in imported_modules(*modules):
        path = _module_file(pkg, name)
        assert path is not None
        h.update(path.relative_to(pkg).as_posix().encode() + b"\0" + sha256_file(path).encode() + b"\n")
    for path in extra:
        h.update(Path(path).name.encode() + b"\0" + sha256_file(Path(path)).encode() + b"\n")
    return h.hexdigest()
