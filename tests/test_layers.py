"""The package's layers (issue #17): no import cycle, no private name imported across modules, every
arrow downwards, imports at module top in the library, a short top level and no oversized module.

The import graph is read from the source (``ast``), counting imports inside functions, so a cycle kept
alive by a function-level import is found too (the four of issue #17 were).
"""
from __future__ import annotations

import ast
import collections
import warnings
from pathlib import Path

PKG = Path(__file__).resolve().parent.parent / "swatch"

#: The layers, lowest first; a module may import from its own subpackage and from lower layers only.
#: Subpackages on one line are siblings (neither imports the other).
LAYERS: tuple[tuple[str, ...], ...] = (
    ("core",),
    ("physics",),
    ("colorimetry",),
    ("io",),
    ("render", "fit", "presets"),
    ("mitsuba",),  # the face of the Mitsuba plugin (swatch.mitsuba.register); the engine is swatch.render.mitsuba
    ("report",),
    ("catalog",),
    ("production",),  # the finish spec, its card and QC: on the catalog's process window
    ("commands",),
    ("cli",),
)

#: Function-level imports of swatch modules outside commands/ and the package faces, each with its reason.
ALLOWED_FUNCTION_IMPORTS = {
    ("swatch.colorimetry.tolerance", "swatch.colorimetry.colorimeter"):
        "colour-science (seconds to import) only when a ΔE is computed: a no-op catalog rebuild parses tolerances",
    ("swatch.catalog.build", "swatch.catalog.execute"):
        "the one seam of a build (#36): the plan (fingerprint, up-to-date check) imports the execute side (the "
        "stages: colour-science, OpenImageIO) once, after the no-op check: no-op rebuild ≤ 2 s",
    ("swatch.catalog.build", "swatch.catalog.cluster"):
        "Dask's distributed client (optional: `anodic-swatch[distributed]`) only for a build given a scheduler (#50)",
    ("swatch.catalog.spec.document", "swatch.physics.model"):
        "the optics (0.1 s) only when a coating or a voltage is asked for: a no-op rebuild parses the spec without",
    ("swatch.physics.process", "swatch.physics.model"): "as above (a profile parses without the optics)",
    ("swatch.render.dispatch", "swatch.render.mitsuba.engine"):
        "Mitsuba and Dr.Jit (optional; a JIT on libLLVM, seconds to load) only for `engine='mitsuba'` (#23)",
    ("swatch.catalog.presets", "swatch.catalog.presets_usd"):
        "usd-core (pxr: ~0.5 GB of address space mapped on import) only for a catalog whose spec asks for USD or "
        "physicallybased.info presets (#47): the commands at their memory caps stay under them",
    ("swatch.render.dispatch", "swatch.render.mitsuba.bake"):
        "as above: the path tracer's studio set baked for the catalog page only when a catalog asks for it (#46)",
}

#: At most this many function-level import statements in the library (outside commands/, the CLI and the
#: package faces), all of them in ALLOWED_FUNCTION_IMPORTS (#36).
MAX_FUNCTION_IMPORTS = 10
#: No library function takes more parameters than this (a parameter object where more belong together;
#: the click commands in commands/ are excepted: a command's parameters are its options) (#36).
MAX_PARAMETERS = 12
#: Functions over MAX_PARAMETERS, each with its reason (the list only shrinks; empty since #36).
OVER_PARAMETER_CAP: dict[str, str] = {}
#: The engines' render functions (swatch.render.dispatch.ENGINES): they render a checked
#: swatch.render.request.RenderRequest and check none of its fields again (#36).
ENGINE_FUNCTIONS = {
    "swatch.render.dispatch": ("render_builtin",),
    "swatch.render.builtin.pointlight": ("render_pointlight",),
    "swatch.render.builtin.env_render": ("render_swatch_environment",),
    "swatch.render.mitsuba.engine": ("render_mitsuba",),
}

MAX_TOP_LEVEL_MODULES = 8
#: A module is as long as its concept. Past this many lines the suite warns (``LongModuleWarning``: a
#: prompt to ask whether the module holds one concept, not a failure); a module that is long for a reason
#: goes into LONG_MODULES with that reason, and the warning stops.
LONG_MODULE_LINES = 800
#: Past this a module fails the suite whatever its reason: nobody reads 1 200 lines as one concept.
MAX_LIBRARY_LINES = 1200
#: Modules past LONG_MODULE_LINES, each with the reason it is one concept.
LONG_MODULES: dict[str, str] = {}


class LongModuleWarning(UserWarning):
    """A library module past LONG_MODULE_LINES without a reason in LONG_MODULES."""


def _modules() -> dict[str, Path]:
    mods = {}
    for p in sorted(PKG.rglob("*.py")):
        parts = list(p.relative_to(PKG.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = p
    return mods


MODULES = _modules()


def _resolve(name: str) -> str:
    while name and name not in MODULES:
        name = name.rsplit(".", 1)[0] if "." in name else ""
    return name


def _imports(module: str) -> list[tuple[str, str | None, bool]]:
    """(imported swatch module, imported name or None, inside a function) for every import of ``module``."""
    path = MODULES[module]
    out = []

    def visit(node, in_function):
        for child in ast.iter_child_nodes(node):
            inside = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(child, ast.Import):
                out.extend((_resolve(a.name), None, inside) for a in child.names if a.name.split(".")[0] == "swatch")
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    pkg = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
                    for _ in range(child.level - 1):
                        pkg = pkg.rsplit(".", 1)[0]
                    base = pkg + ("." + base if base else "")
                if base.split(".")[0] == "swatch":
                    for a in child.names:
                        sub = f"{base}.{a.name}"
                        target = sub if sub in MODULES else _resolve(base)
                        out.append((target, None if sub in MODULES else a.name, inside))
            visit(child, inside)

    visit(ast.parse(path.read_text(encoding="utf-8")), False)
    return [(t, n, f) for t, n, f in out if t and t != module]


class _Graph(dict):
    """module → its imports, parsed when a test first asks (parsing every module at import cost each pytest
    worker ~1 s of collection, issue 17)."""

    def __missing__(self, module: str) -> list[tuple[str, str | None, bool]]:
        self[module] = found = _imports(module)
        return found


GRAPH = _Graph()


def _layer(module: str) -> int | None:
    """The index in LAYERS of a module's subpackage (None for the face ``swatch``)."""
    parts = module.split(".")
    if len(parts) == 1:
        return None
    for i, names in enumerate(LAYERS):
        if parts[1] in names:
            return i
    raise AssertionError(f"{module} is in no layer; add its subpackage to LAYERS and to docs/DEVNOTES.md")


def _is_face(module: str) -> bool:
    return MODULES[module].name == "__init__.py"


def _is_lazy_zone(module: str) -> bool:
    """Where imports may be deferred into functions: commands/, the CLI and the package faces."""
    return module.startswith("swatch.commands") or module == "swatch.cli" or _is_face(module)


def test_every_module_is_in_a_layer():
    """Issue #17: a reader finds a concern by its folder."""
    for m in MODULES:
        _layer(m)


def test_import_graph_has_no_cycle_counting_function_level_imports():
    """Issue #17: no import cycle, counting imports inside functions."""
    edges = {m: {t for t, _, _ in GRAPH[m]} for m in MODULES}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles = []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in MODULES:
        if v not in index:
            strong(v)
    assert cycles == []


def test_no_private_name_is_imported_across_modules():
    """Issue #17: ``from swatch.x import _name`` reaches into another module's internals."""
    private = [(m, t, n) for m in MODULES for t, n, _ in GRAPH[m]
               if n is not None and n.startswith("_") and not n.startswith("__")]
    assert private == []


def test_every_import_points_down_the_layers():
    """Issue #17: a module imports from its own subpackage and from the layers before it, never up or sideways."""
    wrong = []
    for m in MODULES:
        lm = _layer(m)
        for t, _, _ in GRAPH[m]:
            lt = _layer(t)
            if lm is None or t.split(".")[:2] == m.split(".")[:2]:
                continue  # the face sees everything; a subpackage sees itself
            if lt is None or lt >= lm:
                wrong.append(f"{m} -> {t}")
    assert wrong == []


def _allowed(module: str, target: str) -> bool:
    return any(m == module and (t == target or (t.endswith(".*") and target.startswith(t[:-1])))
               for m, t in ALLOWED_FUNCTION_IMPORTS)


def test_library_imports_are_at_module_top():
    """Issue #17: function-level imports only in commands/, the CLI, the package faces and the allow-list."""
    lazy = [f"{m} -> {t}" for m in MODULES if not _is_lazy_zone(m)
            for t, _, in_function in GRAPH[m] if in_function and not _allowed(m, t)]
    assert lazy == []


def test_allow_list_entries_are_used():
    """An allow-list entry that no longer matches an import is stale (issue #17)."""
    used = {(m, t) for m in MODULES for t, _, f in GRAPH[m] if f}
    for (m, t) in ALLOWED_FUNCTION_IMPORTS:
        assert any(um == m and (ut == t or (t.endswith(".*") and ut.startswith(t[:-1]))) for um, ut in used), (m, t)


def test_top_level_of_the_package_is_short():
    """Issue #17: at most a handful of modules directly in swatch/ (the rest are in subpackages)."""
    top = sorted(p.name for p in PKG.glob("*.py"))
    assert len(top) <= MAX_TOP_LEVEL_MODULES, top


def test_library_modules_are_as_long_as_their_concept():
    """A module past LONG_MODULE_LINES warns unless LONG_MODULES gives its reason; none passes
    MAX_LIBRARY_LINES; a reason whose module is short again is dropped (the list only names long ones)."""
    lines = {m: len(p.read_text(encoding="utf-8").splitlines()) for m, p in MODULES.items()}
    too_long = {m: n for m, n in lines.items() if n > MAX_LIBRARY_LINES}
    assert not too_long, too_long
    long = {m: n for m, n in lines.items() if n > LONG_MODULE_LINES}
    for module in sorted(set(long) - set(LONG_MODULES)):
        warnings.warn(LongModuleWarning(f"{module} has {long[module]} lines (> {LONG_MODULE_LINES}): one concept? "
                                        "split it by meaning, or give its reason in LONG_MODULES"), stacklevel=1)
    assert set(LONG_MODULES) <= set(long), "a module in LONG_MODULES is short again: drop its entry"


def _defined_names(module: str) -> set[str]:
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names |= {t.id for t in targets if isinstance(t, ast.Name)}
    return names


def test_the_face_lists_names_its_modules_define():
    """Issue #17: ``swatch.__all__`` is the public API, each name defined where the face loads it from
    (read from the source: importing it would load every layer)."""
    import swatch

    api = swatch._API
    assert set(swatch.__all__) == {"__version__", *api}
    missing = [f"{mod}.{name}" for name, mod in api.items() if name not in _defined_names(mod)]
    assert missing == []


def test_importing_the_face_loads_no_layer_beyond_core():
    """Issue #17: ``import swatch`` is lazy (PEP 562), so ``swatch --help`` stays fast."""
    import subprocess
    import sys

    code = "import sys, swatch; print(sorted(m for m in sys.modules if m.startswith('swatch')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert ast.literal_eval(out) == ["swatch", "swatch.core", "swatch.core.version"]


def test_function_import_counts_are_in_the_graph():
    """Sanity of the reader itself: it sees top-level and function-level imports of a known module (#17)."""
    graph = collections.defaultdict(set)
    for t, _, f in GRAPH["swatch.catalog.build"]:
        graph[f].add(t)
    assert "swatch.catalog.spec" in graph[False]
    assert "swatch.catalog.execute" in graph[True]


def test_the_builtin_render_path_never_loads_mitsuba():
    """Issue #17/#23: the dispatcher reaches the Mitsuba engine, but a built-in render (and ``swatch
    --help``) imports neither Mitsuba nor Dr.Jit."""
    import subprocess
    import sys

    code = ("import sys; from swatch.render import render_swatch; render_swatch(50.0, 'flat', 8, environment=None); "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('mitsuba', 'drjit') "
            "or m.startswith('swatch.render.mitsuba')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert ast.literal_eval(out) == []


def test_only_the_commands_import_click():
    """Issue #17 item 4: the library speaks parameters and reports progress through callbacks; click (flags,
    prompts, progress bars) is the CLI's: no module outside ``commands/`` and the CLI imports it (the
    catalog build and the Mitsuba engine drew their own click bars before)."""
    found = []
    for m, path in MODULES.items():
        if m.startswith("swatch.commands") or m == "swatch.cli":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level
                     else [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            found += [f"{m} -> {n}" for n in names if n.split(".")[0] == "click"]
    assert found == []


def test_no_test_module_imports_another_test_module():
    """Issue #17 item 7: tests share helpers through helper modules and conftest.py fixtures
    (tests/catalog/folder_helpers.py, tests/render/env_reference.py, ...), never by importing another
    ``test_*.py`` (which drags its fixtures and private names along)."""
    tests = Path(__file__).resolve().parent
    found = []
    for path in sorted(tests.rglob("*.py")):
        if "vendor" in path.relative_to(tests).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([node.module or ""] if isinstance(node, ast.ImportFrom)
                     else [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            found += [f"{path.relative_to(tests)} -> {n}" for n in names
                      if n.split(".")[0] == "tests" and n.rsplit(".", 1)[-1].startswith("test_")]
    assert found == []


def _function_imports() -> list[str]:
    """Every function-level import statement in the library (outside the lazy zone), as "module:line"."""
    found = []
    for m, path in MODULES.items():
        if _is_lazy_zone(m):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for fn in ast.walk(tree):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found += [f"{m}:{n.lineno}" for n in ast.walk(fn) if isinstance(n, (ast.Import, ast.ImportFrom))]
    return sorted(set(found))


def test_few_function_level_imports_in_the_library():
    """Issue #36: the deferred imports of the library are a handful of seams (the catalog build's plan →
    execute, the optional Mitsuba engine, colour-science off the no-op rebuild), not one per stage."""
    found = _function_imports()
    assert len(found) <= MAX_FUNCTION_IMPORTS, found


def test_no_dynamic_imports_outside_the_faces():
    """Issue #36: no ``importlib.import_module``/``__import__`` in the library outside the package faces and the
    CLI (a dynamic import is unseen by the import graph above: the hero renders reached the Mitsuba engine so)."""
    found = []
    for m, path in MODULES.items():
        if _is_face(m) or m == "swatch.cli":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call):
                f = node.func
                name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
                if name in ("import_module", "__import__"):
                    found.append(f"{m}:{node.lineno}")
            elif ((isinstance(node, ast.Import) and any(a.name == "importlib" for a in node.names))
                  or (isinstance(node, ast.ImportFrom) and node.module == "importlib"
                      and any(a.name == "import_module" for a in node.names))):
                found.append(f"{m}:{node.lineno}")
    assert found == []


def _parameter_count(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    a = fn.args
    names = [x.arg for x in (*a.posonlyargs, *a.args, *a.kwonlyargs) if x.arg not in ("self", "cls")]
    return len(names) + (a.vararg is not None) + (a.kwarg is not None)


def test_no_library_function_takes_more_than_12_parameters():
    """Issue #36: a parameter object (swatch.render.request.RenderRequest, …) where more belong together;
    click commands (commands/) are excepted."""
    long = []
    for m, path in MODULES.items():
        if m.startswith("swatch.commands"):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and _parameter_count(node) > MAX_PARAMETERS:
                long.append(f"{m}.{node.name}")
    assert set(long) - set(OVER_PARAMETER_CAP) == set()
    assert set(OVER_PARAMETER_CAP) <= set(long), "a listed function is back under the cap: drop it from the list"


def test_no_engine_re_validates_a_request_field():
    """Issue #36: a render's inputs are checked once, by swatch.render.request.render_request; the engines'
    render functions call no check (``check_*``), resolve no lighting, build no coating or scene, and raise
    no SwatchError of their own about an input (what they raise comes from the scene: a sun below the horizon)."""
    checks = {"resolve_lighting", "lighting_for", "coating_and_colorimeter", "make_scene", "render_request",
              "check_finish_lighting", "get_coating", "get_colorimeter"}
    found = []
    for m, names in ENGINE_FUNCTIONS.items():
        tree = ast.parse(MODULES[m].read_text(encoding="utf-8"))
        fns = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
        assert set(names) <= set(fns), (m, names)
        for name in names:
            for node in ast.walk(fns[name]):
                if isinstance(node, ast.Call):
                    f = node.func
                    called = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
                    if called.startswith("check_") or called in checks:
                        found.append(f"{m}.{name} calls {called}")
                elif isinstance(node, ast.Raise):
                    found.append(f"{m}.{name} raises (line {node.lineno})")
            args = [a.arg for a in fns[name].args.args]
            assert args[0] == "request", (m, name, args)


def test_the_engine_registry_covers_the_engine_choices():
    """Issue #36: swatch.render.ENGINES has one engine per name of swatch.core.choices.ENGINES (the CLI's
    ``--engine`` choices), each taking (request, progress)."""
    import inspect

    from swatch.core.choices import ENGINES as NAMES
    from swatch.render import ENGINES

    assert tuple(ENGINES) == tuple(NAMES)
    for engine in ENGINES.values():
        assert list(inspect.signature(engine).parameters) == ["request", "progress"]


def test_production_and_the_preset_command_do_not_reach_into_the_catalog():
    """Issue #36: the measuring geometry and the process window are colorimetry's, the preset files the
    presets' (swatch.presets.files); the finish specification, QC and ``swatch preset`` need no catalog."""
    found = [f"{m} -> {t}" for m in MODULES if m.startswith("swatch.production") or m == "swatch.commands.preset"
             for t, _, _ in GRAPH[m] if t.startswith("swatch.catalog")]
    assert found == []


def test_code_hash_follows_imports():
    """Issue #36: the caches' code key (swatch.core.sources.code_hash) covers what a computation imports,
    through package faces (PEP 562) and lazy imports: a tile's key covers the dispatcher and both engines,
    a preset fit's the geometry the presets' models import (a hand list missed physics/geometry.py)."""
    from swatch.core.sources import imported_modules

    tiles = imported_modules("swatch.catalog.tiles")
    assert {"swatch.render.dispatch", "swatch.render.request", "swatch.render.builtin.pointlight",
            "swatch.render.builtin.env_render", "swatch.render.mitsuba.engine", "swatch.physics.optics"} <= set(tiles)
    assert "swatch.physics.geometry" in imported_modules("swatch.catalog.presets")
    assert "swatch.commands.render" not in tiles


def test_the_render_command_parses_without_the_mitsuba_engine():
    """Issue #36: ``swatch render`` imported ``Sun`` from the Mitsuba scene module while parsing; ``Sun`` lives in
    swatch.render.lighting, and parsing the sun options (or printing --help) loads no swatch.render.mitsuba
    module, nor Mitsuba or Dr.Jit."""
    import subprocess
    import sys

    code = ("import sys, contextlib, io\n"
            "from swatch.commands.render import _sun, render\n"
            "sun = _sun(30.0, 10.0, None, None, None, None, None)\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
            "    render.main(['--help'], standalone_mode=True)\n"
            "print(type(sun).__module__, sorted(m for m in sys.modules if m.split('.')[0] in ('mitsuba', 'drjit') "
            "or m.startswith('swatch.render.mitsuba')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split(" ", 1)
    assert out[0] == "swatch.render.lighting" and ast.literal_eval(out[1]) == []
