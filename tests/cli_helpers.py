"""Run the ``swatch`` CLI as a user would: its entry point, its exit status, its stdout and stderr.

:func:`run_swatch` calls :func:`swatch.cli.main` (what the ``swatch`` console script and
``python -m swatch.cli`` run) in this process, with stdout and stderr captured, so a test pays no
interpreter start-up (numpy, colour-science and OpenImageIO imports: seconds per call on a busy
2-core machine). :func:`run_swatch_process` runs it in a real subprocess; tests of the process
itself (console script, module entry point, signals) use it.
"""
from __future__ import annotations

import contextlib
import io
import json
import subprocess
import sys


def run_swatch(*args: str, cwd=None, timeout: float = 300) -> subprocess.CompletedProcess:
    from swatch.cli import main

    argv = [str(a) for a in args]
    out, err = io.StringIO(), io.StringIO()
    where = contextlib.chdir(cwd) if cwd is not None else contextlib.nullcontext()
    with where, contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return subprocess.CompletedProcess(["swatch", *argv], code, out.getvalue(), err.getvalue())


def run_swatch_process(*args: str, cwd=None, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "swatch.cli", *map(str, args)],
        capture_output=True, text=True, cwd=cwd, timeout=timeout, check=False,
    )


def run_json(*args: str, cwd=None):
    proc = run_swatch(*args, "--json", cwd=cwd)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def assert_one_line_error(proc: subprocess.CompletedProcess, *fragments: str) -> None:
    """Non-zero exit, exactly one line on stderr starting with 'error:', no traceback."""
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: "), proc.stderr
    assert "Traceback" not in proc.stderr
    for frag in fragments:
        assert frag.lower() in lines[0].lower(), lines[0]
