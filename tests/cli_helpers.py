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


#: What :func:`run_capped_batch`'s subprocess runs: each argv in turn through ``swatch.cli.main``, its
#: stdout and stderr captured, the results as one JSON list on stdout.
_BATCH = """
import contextlib, io, json, resource, sys, time
from swatch.cli import main
results = []
for argv in json.loads(sys.stdin.read()):
    out, err = io.StringIO(), io.StringIO()
    t0, r0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    results.append([code, out.getvalue(), err.getvalue(), time.perf_counter() - t0, cpu])
sys.__stdout__.write(json.dumps(results))
"""


def run_capped_batch(argvs: list[list[str]], cap_bytes: int, timeout: float = 300) -> list[subprocess.CompletedProcess]:
    """Each argv through the CLI's entry point, one after the other in ONE subprocess whose address space
    is capped at ``cap_bytes`` (RLIMIT_AS): what a capped run per argv checks (each refusal or run fits
    under the cap, the earlier ones' leftovers included), for one interpreter start-up instead of one each
    (issue 17 item 7: ~2 s CPU a start on this machine). Each result carries ``wall_s`` and ``cpu_s``, the
    seconds its run took (wall clock; CPU of all the process's threads, user + system)."""
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (cap_bytes, cap_bytes))

    proc = subprocess.run([sys.executable, "-c", _BATCH], input=json.dumps([[str(a) for a in argv] for argv in argvs]),
                          capture_output=True, text=True, timeout=timeout, preexec_fn=limit, check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    done = []
    for argv, (code, out, err, wall_s, cpu_s) in zip(argvs, json.loads(proc.stdout), strict=True):
        one = subprocess.CompletedProcess(["swatch", *argv], code, out, err)
        one.wall_s, one.cpu_s = wall_s, cpu_s  # type: ignore[attr-defined]  # (the run's seconds: wall, CPU of all its threads)
        done.append(one)
    return done


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
