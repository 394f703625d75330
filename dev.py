#!/usr/bin/env python3
"""Bootstrap a local virtual environment (.venv) and run a project job in it.

Needs nothing but Python 3.11+ and pip:

    python3 dev.py catalog    # build the default catalog (catalog/titanium.toml -> build/catalog)
    python3 dev.py test       # run the test suite
    python3 dev.py bench      # time the project against the reference implementations
    python3 dev.py lint       # ruff and mypy, as CI runs them
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
    subprocess.run([str(PY), "-m", "pip", "install", "-q", "-e", f"{ROOT}[test]"], check=True)
    stamp.write_text(want)


def main(argv: list[str]) -> int:
    if not argv or argv[0] in {"-h", "--help"}:
        print(__doc__)
        return 0 if argv else 2
    job, rest = argv[0], argv[1:]
    ensure_env()
    if job == "catalog":
        cmd = [str(BIN / "swatch"), "catalog", "build", "catalog/titanium.toml", "--out", "build/catalog", *rest]
    elif job == "test":
        cmd = [str(PY), "-m", "pytest", *rest]
    elif job == "lint":
        rc = subprocess.run([str(BIN / "ruff"), "check", ".", *rest], cwd=ROOT).returncode
        return rc or subprocess.run([str(BIN / "mypy")], cwd=ROOT).returncode
    elif job == "bench":
        cmd = [str(PY), "-m", "benchmarks.bench", *rest]
    elif job == "swatch":
        cmd = [str(BIN / "swatch"), *rest]
    else:
        print(f"dev.py: unknown job {job!r}; use catalog, test, lint, bench or swatch", file=sys.stderr)
        return 2
    return subprocess.run(cmd, cwd=ROOT).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
