"""Every ``swatch …`` command in the README and the guide (docs/*.md) runs as written.

Each page's commands run in order, through the CLI's entry point, in a fresh temporary folder laid out
as the repository root the pages speak from (``examples/`` and ``catalog/`` copied in): exit 0, or the
status a trailing ``# exit N`` comment documents (``swatch check`` exits 1 when a part fails), and each
``--out``/``--report`` it names exists afterwards. A code block preceded by ``<!-- docs-test: inputs
only (why) -->`` is not run (minutes of path tracing); the files its commands read must still be shipped.

A ``text`` code block preceded by ``<!-- docs-test: output -->`` quotes the output of the command just
before it: each of its lines must be a line that command prints today, in order (so a figure a guide
quotes cannot go stale; ``python scripts/make_examples.py --outputs`` prints them afresh).

One saving, stated: a ``swatch catalog build`` of a spec an earlier page has already built cold starts
from a copy of that build's folder (the build is deterministic, so its output is byte-identical), and
the command as written then runs as the no-op rebuild it is; the default catalog is built cold once.

Also: README.md and docs/ name no machine path, numbered work period or commit hash; the README stays a
landing page (≤ 300 lines) whose links into the guide resolve; docs/api.rst lists ``swatch.__all__``.
"""
from __future__ import annotations

import dataclasses
import re
import shlex
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.cli_helpers import run_swatch

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
INPUTS_ONLY = re.compile(r"<!--\s*docs-test:\s*inputs only\b")
QUOTED_OUTPUT = re.compile(r"<!--\s*docs-test:\s*output\s*-->")
#: Arguments that name a file the command reads (an output is named by --out/--report).
INPUT_SUFFIXES = (".glb", ".gltf", ".obj", ".ply", ".stl", ".cxf", ".csv", ".txt", ".ti3", ".toml", ".hdr", ".exr",
                  ".json")
OUTPUT_OPTIONS = ("--out", "--report")


@dataclass(frozen=True)
class Command:
    page: str
    line: int
    text: str
    argv: tuple[str, ...]
    exit_code: int
    run: bool
    quoted: tuple[str, ...] = ()  # lines of its output the page quotes (a docs-test: output block after it)


def page_commands(page: Path) -> list[Command]:
    """The ``swatch`` commands of a page's fenced code blocks (``sh``, ``console``, ``bash`` or none),
    with ``\\`` continuations joined and the trailing comment read for ``exit N``."""
    lines = page.read_text(encoding="utf-8").splitlines()
    out: list[Command] = []
    fence, run, i = None, True, 0
    while i < len(lines):
        line = lines[i]
        if fence is None:
            m = re.match(r"^(\s*)(```+|~~~+)\s*([\w-]*)", line)
            if m:
                fence = m.group(2)
                lang = m.group(3)
                run = not any(INPUTS_ONLY.search(lines[j]) for j in range(max(0, i - 2), i))
                if lang == "text" and out and any(QUOTED_OUTPUT.search(lines[j]) for j in range(max(0, i - 2), i)):
                    end = next(j for j in range(i + 1, len(lines)) if lines[j].strip().startswith(fence))
                    quoted = tuple(q.rstrip() for q in lines[i + 1:end] if q.strip())
                    out[-1] = dataclasses.replace(out[-1], quoted=quoted)
                if lang not in ("", "sh", "bash", "console", "shell"):
                    fence = "skip:" + fence
        elif line.strip().startswith(fence.removeprefix("skip:")):
            fence = None
        elif not fence.startswith("skip:") and line.lstrip().startswith("swatch "):
            start = i
            text = line.strip()
            while text.endswith("\\") and i + 1 < len(lines):
                i += 1
                text = text[:-1].rstrip() + " " + lines[i].strip()
            code, *comment = re.split(r"\s#(?:\s|$)", text, maxsplit=1)
            m = re.search(r"\bexit (\d)\b", comment[0] if comment else "")
            argv = tuple(shlex.split(code.strip()))
            out.append(Command(page.name, start + 1, text, argv[1:], int(m.group(1)) if m else 0, run))
        i += 1
    return out


def _option(argv: tuple[str, ...], name: str) -> str | None:
    for k, a in enumerate(argv):
        if a == name and k + 1 < len(argv):
            return argv[k + 1]
        if a.startswith(name + "="):
            return a.split("=", 1)[1]
    return None


def _inputs(argv: tuple[str, ...]) -> list[str]:
    outputs = {_option(argv, o) for o in OUTPUT_OPTIONS}
    return [a for a in argv if a.endswith(INPUT_SUFFIXES) and not a.startswith("-") and a not in outputs]


def _repository_like(folder: Path) -> None:
    """The inputs the pages name, where they name them (relative to the repository root)."""
    shutil.copytree(ROOT / "examples", folder / "examples")
    shutil.copytree(ROOT / "catalog", folder / "catalog")


def test_the_guides_quote_the_output_of_the_finishers_commands():
    """The finisher's guide quotes calibrate's outlier and check's verdicts (checked against today's output in
    test_every_documented_command_runs_as_written)."""
    quoted = {c.argv[0]: c.quoted for c in page_commands(ROOT / "docs" / "finisher.md") if c.quoted}
    assert {"calibrate", "check"} <= set(quoted)
    assert any("outlier" in q for q in quoted["calibrate"]) and any(q.startswith("P5: FAIL") for q in quoted["check"])


def test_the_pages_have_commands_and_the_documented_ones_parse():
    commands = [c for p in PAGES for c in page_commands(p)]
    by_page = {c.page for c in commands}
    for page in ("README.md", "getting-started.md", "designer.md", "specifier.md", "finisher.md", "cli.md"):
        assert page in by_page, page
    check = next(c for c in commands if c.page == "README.md" and c.argv[0] == "check")
    assert check.exit_code == 1  # the README says the example parts include a failing one
    for c in commands:
        assert c.argv and not c.argv[0].startswith("-"), c


def test_inputs_only_blocks_read_shipped_files():
    for page in PAGES:
        for c in page_commands(page):
            if c.run:
                continue
            for name in _inputs(c.argv):
                assert (ROOT / name).is_file(), f"{c.page}:{c.line}: {name} is not shipped (examples/)"


_CATALOG_BUILDS: dict[bytes, Path] = {}  # spec bytes -> a folder a cold build of it wrote (this session)


def _spec_bytes(c: Command, cwd: Path) -> bytes:
    """The bytes of the spec ``swatch catalog build SPEC`` reads, SPEC resolved from ``cwd``."""
    from swatch.catalog.spec import resolve_spec_path

    spec = c.argv[2]
    return resolve_spec_path(cwd / spec if (cwd / spec).is_file() else spec).read_bytes()


def _seed_catalog_build(c: Command, cwd: Path) -> None:
    if c.argv[:2] != ("catalog", "build"):
        return
    out = cwd / _option(c.argv, "--out")
    key = _spec_bytes(c, cwd)
    if key in _CATALOG_BUILDS and not out.exists():
        shutil.copytree(_CATALOG_BUILDS[key], out, symlinks=True)


def _remember_catalog_build(c: Command, cwd: Path) -> None:
    if c.argv[:2] != ("catalog", "build"):
        return
    _CATALOG_BUILDS.setdefault(_spec_bytes(c, cwd), cwd / _option(c.argv, "--out"))


@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_every_documented_command_runs_as_written(page, tmp_path_factory):
    commands = [c for c in page_commands(page) if c.run]
    if not commands:
        pytest.skip(f"{page.name}: no swatch command to run")
    cwd = tmp_path_factory.mktemp(page.stem)
    _repository_like(cwd)
    for c in commands:
        for name in _inputs(c.argv):
            assert (cwd / name).is_file(), f"{c.page}:{c.line}: {name} does not exist when `{c.text}` runs"
        _seed_catalog_build(c, cwd)
        proc = run_swatch(*c.argv, cwd=cwd)
        assert proc.returncode == c.exit_code, (f"{c.page}:{c.line}: `{c.text}` exited {proc.returncode}, "
                                                f"documented {c.exit_code}\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
        printed = [ln.rstrip() for ln in proc.stdout.splitlines()]
        at = 0
        for q in c.quoted:  # the page's quoted lines, in order, as the command prints them today
            assert q in printed[at:], (f"{c.page}:{c.line}: the page quotes a line `{c.text}` no longer prints "
                                       f"(python scripts/make_examples.py --outputs):\n{q}\nit prints:\n"
                                       + "\n".join(printed))
            at = printed.index(q, at) + 1
        if c.argv[0] == "spec":  # a documented target is reachable (an unreachable one is exit 1 for spec, #35)
            assert "cannot be reached" not in proc.stdout or c.exit_code == 1, f"{c.page}:{c.line}: {proc.stdout}"
        for option in OUTPUT_OPTIONS:
            target = _option(c.argv, option)
            if target is not None:
                assert (cwd / target).exists(), f"{c.page}:{c.line}: `{c.text}` wrote no {target}"
        _remember_catalog_build(c, cwd)


#: A machine's absolute path, a numbered work period, a commit hash (7–40 hex digits with a letter and a digit).
HISTORY = [re.compile(r"(?<![\w.])/(work|home|tmp|root|Users)/\w"), re.compile(r"\b[Ss]ession \d+"),
           re.compile(r"\bwork period\b", re.I)]
HASH = re.compile(r"(?<![\w#/.-])[0-9a-f]{7,40}(?![\w-])")


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_the_pages_carry_no_history(page):
    text = page.read_text(encoding="utf-8")
    for pattern in HISTORY:
        assert not pattern.search(text), f"{page.name}: {pattern.search(text).group(0)!r}"
    hashes = [h for h in HASH.findall(text) if re.search(r"\d", h) and re.search(r"[a-f]", h)]
    assert not hashes, f"{page.name}: commit-like hashes {hashes}"


def test_the_readme_is_a_landing_page_whose_links_resolve():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 300
    assert "python3 dev.py catalog" in text and "python3 dev.py test" in text
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [link for link in links if "://" not in link]
    assert len(local) >= 10
    for link in local:
        assert (ROOT / link).exists(), link


def test_the_api_page_lists_the_public_names():
    import swatch

    text = (ROOT / "docs" / "api.rst").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\s{3}(swatch\.[\w.]+)$", text, re.M))
    assert listed == {f"{module}.{name}" for name, module in swatch._API.items()}
