#!/usr/bin/env python3
"""Bootstrap a local virtual environment (.venv) and run a project job in it.

Needs nothing but Python 3.11+ and pip:

    python3 dev.py catalog    # build the default catalog (catalog/titanium.toml -> build/catalog)
    python3 dev.py test       # run the test suite
    python3 dev.py bench      # time the project against the reference implementations (--tiny: a smoke run)
    python3 dev.py lint       # ruff and mypy, as CI runs them
    python3 dev.py docs       # the user guide (Sphinx) into build/docs/, warnings as errors
    python3 dev.py swatch ARGS...   # run the CLI inside the environment

The environment is (re)installed when pyproject.toml changes (a stamp file records its hash).
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PY = BIN / "python"


def ensure_libllvm() -> None:
    """Mitsuba's LLVM backend (render --engine mitsuba) loads a system libLLVM 17+: on Debian/Ubuntu,
    as root, install libllvm19 when none is there (swatch then finds it); otherwise say what to do."""
    import glob
    import re
    import shutil

    libs = glob.glob("/usr/lib/*/libLLVM*.so*") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*")
    if any(int(m.group(1)) >= 17 for p in libs if (m := re.search(r"(?:LLVM\.so\.|LLVM-|llvm-)(\d+)", p))):
        return
    if os.environ.get("DRJIT_LIBLLVM_PATH") or not sys.platform.startswith("linux"):
        return
    if hasattr(os, "geteuid") and os.geteuid() == 0 and shutil.which("apt-get"):
        print("dev.py: installing libllvm19 (Mitsuba's JIT) with apt-get", file=sys.stderr)
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        ok = subprocess.run(["apt-get", "update", "-qq"], env=env).returncode == 0 and subprocess.run(
            ["apt-get", "install", "-y", "-qq", "--no-install-recommends", "libllvm19"], env=env,
            stdout=subprocess.DEVNULL).returncode == 0
        if ok:
            return
    print("dev.py: no libLLVM 17+ found; `swatch render --engine mitsuba` needs one (apt-get install libllvm19)",
          file=sys.stderr)


def ensure_env() -> None:
    stamp = VENV / ".swatch-stamp"
    want = hashlib.sha256((ROOT / "pyproject.toml").read_bytes()).hexdigest()
    if stamp.exists() and stamp.read_text() == want and PY.exists():
        return
    if not PY.exists():
        print(f"dev.py: creating {VENV}", file=sys.stderr)
        venv.EnvBuilder(with_pip=True).create(VENV)
    print("dev.py: installing the project and its test dependencies", file=sys.stderr)
    subprocess.run([str(PY), "-m", "pip", "install", "-q", "--upgrade", "pip"], check=True)
    subprocess.run([str(PY), "-m", "pip", "install", "-q", "-e", f"{ROOT}[test,docs]"], check=True)
    ensure_libllvm()
    stamp.write_text(want)


def test_workers(args: list[str]) -> list[str]:
    """pytest-xdist options for a whole-suite run: two worker processes, ``--dist loadfile`` (a test
    file runs on one worker, so its module-scoped catalogs are built once; each worker starts the
    suite's one Chromium and small catalog only if it runs a browser file). ``loadgroup`` would keep
    every browser test on one worker, but pytest-xdist 3.8 cannot tag groups under pytest 9 (it sets
    ``item._nodeid``, which pytest 9 no longer reads). ``--no-loadscope-reorder``: xdist hands the files
    out in the order the workers collected them, which tests/conftest.py sets longest first (xdist's own
    order, most tests first, put the longest file near the end). A run of named files or tests, or one that
    says ``-n``/``--dist``/``-p no:xdist`` itself, stays as asked; ``SWATCH_TEST_WORKERS=0`` runs the
    suite in one process."""
    workers = os.environ.get("SWATCH_TEST_WORKERS", "2")
    named = any(not a.startswith("-") and Path(a.split("::")[0]).exists() for a in args)
    asked = any(a.startswith(("-n", "--numprocesses", "--dist")) or a == "no:xdist" for a in args)
    if named or asked or workers in {"", "0", "1"}:
        return []
    return ["-n", workers, "--dist", "loadfile", "--no-loadscope-reorder"]


def test_env() -> dict[str, str]:
    """The test run's environment: this one, but with bytecode caching on. With PYTHONDONTWRITEBYTECODE set
    (some shells and CI images set it) every interpreter of the run — the two xdist workers and the ~50
    processes the tests start — compiled swatch and re-rewrote the test modules' asserts from source:
    collection took 10.4 s CPU a process instead of 5.4 s (measured 2026-12-02). The caches are the usual
    ``__pycache__`` folders (ignored by git)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def main(argv: list[str]) -> int:
    if not argv or argv[0] in {"-h", "--help"}:
        print(__doc__)
        return 0 if argv else 2
    job, rest = argv[0], argv[1:]
    ensure_env()
    env = None
    if job == "catalog":
        cmd = [str(BIN / "swatch"), "catalog", "build", "catalog/titanium.toml", "--out", "build/catalog", *rest]
    elif job == "test":
        cmd = [str(PY), "-m", "pytest", *test_workers(rest), *rest]
        env = test_env()
    elif job == "lint":
        rc = subprocess.run([str(BIN / "ruff"), "check", ".", *rest], cwd=ROOT).returncode
        return rc or subprocess.run([str(BIN / "mypy")], cwd=ROOT).returncode
    elif job == "docs":  # the guide: Markdown pages (MyST) and the API from the numpydoc docstrings
        cmd = [str(PY), "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "docs", "build/docs", *rest]
    elif job == "bench":
        cmd = [str(PY), "-m", "benchmarks.bench", *rest]
    elif job == "swatch":
        cmd = [str(BIN / "swatch"), *rest]
    else:
        print(f"dev.py: unknown job {job!r}; use catalog, test, lint, docs, bench or swatch", file=sys.stderr)
        return 2
    return subprocess.run(cmd, cwd=ROOT, env=env).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
