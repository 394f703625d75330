"""Issue 49 item 5: a Ctrl-C in a run's first tenth of a second, while the CLI imports, is one line and exit
130 like any other (it printed Python's KeyboardInterrupt traceback and ended by the raw signal, status -2,
2 runs of 40); a stop that a library swallowed, then failed for, is reported as the stop.

The program holds SIGINT, SIGTERM and SIGHUP from the first statement of ``swatch.cli`` (its signal mask)
until :func:`swatch.cli.main` has its handlers in place. Before that statement the interpreter itself starts
(and runs ``site``: 10-40 ms here, an editable install's path finder included), where no code of swatch's
runs; the delays below count from the moment the hold is seen in ``/proc/<pid>/status``, so each run tests
swatch's part and none depends on how busy the machine is.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from swatch.core import procguard

pytestmark = [pytest.mark.slow,  # (runs processes: ~15 s in all)
              pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc")]

PY = sys.executable
#: The console script (pyproject's [project.scripts]) next to this interpreter, or the module entry point.
SCRIPT = Path(PY).with_name("swatch")
ENTRY = [str(SCRIPT)] if SCRIPT.is_file() else [PY, "-m", "swatch.cli"]
ONE_LINE = "error: interrupted; nothing half-written was left behind"

#: Started as a terminal's foreground job starts it: SIGINT and SIGHUP at their defaults (a test run in the
#: background of a script has them ignored, and a program rightly keeps an ignored SIGINT ignored), then
#: replaced by the program itself (same process: the test watches its pid).
EXEC = ("import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
        "signal.signal(signal.SIGHUP, signal.SIG_DFL); os.execv(sys.argv[1], sys.argv[1:])")

SMALL_SPEC = """
name = "Early"
[thickness]
list_nm = [60, 120]
[render]
size_px = 64
model = "paper"
shapes = ["flat"]
angular_map = false
"""

#: Milliseconds after the hold is seen (the issue's 0-200 ms after the start: the imports, the parsing, the
#: command's first steps).
DELAYS_MS = (0, 10, 30, 60, 100, 200)


def _status(pid: int) -> dict[str, str]:
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return {}
    return dict(line.split(":\t", 1) for line in text.splitlines() if ":\t" in line)


def _holds_sigint(pid: int) -> bool:
    blocked = _status(pid).get("SigBlk")
    return blocked is not None and bool(int(blocked, 16) & (1 << (signal.SIGINT - 1)))


def _exiting(pid: int) -> bool:
    """Gone, a zombie, or in the kernel's exit (PF_EXITING): a signal now meets no program any more."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    fields = stat[stat.rindex(")") + 2:].split()
    return fields[0] in ("Z", "X") or bool(int(fields[6]) & 0x4)


def _interrupted(args: list[str], delay_s: float, cwd: Path) -> tuple[str, int, str]:
    """("signalled" or "finished first", exit status, stderr) of one run sent SIGINT ``delay_s`` after its
    hold is seen (to its process group, as a terminal's Ctrl-C)."""
    err = cwd / "stderr.txt"
    with open(err, "w") as fh:
        proc = subprocess.Popen([PY, "-c", EXEC, *ENTRY, *args], stdout=subprocess.DEVNULL, stderr=fh, cwd=cwd,
                                start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while not _holds_sigint(proc.pid) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.0005)
        assert proc.poll() is None, f"the program never held SIGINT (exit {proc.returncode}): {err.read_text()}"
        if delay_s:
            time.sleep(delay_s)
        sent = not _exiting(proc.pid)
        if sent:
            os.killpg(proc.pid, signal.SIGINT)
        rc = proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    return ("signalled" if sent else "finished first"), rc, err.read_text()


@pytest.mark.parametrize("args", [["--version"], ["color", "--thickness", "50"], ["catalog", "build"]],
                         ids=["version", "color", "catalog-build"])
def test_issue49_ctrl_c_in_the_first_tenth_of_a_second_is_one_line_and_130(tmp_path, args):
    if args[0] == "catalog":
        (tmp_path / "early.toml").write_text(SMALL_SPEC, encoding="utf-8")
        args = [*args, "early.toml", "--out", "out", "-j", "2", "-q"]
    signalled = 0
    for repeat in range(2):
        for delay_ms in DELAYS_MS:
            verdict, rc, err = _interrupted(args, delay_ms / 1000, tmp_path)
            if verdict == "finished first":  # (--version is done in ~0.05 s once it holds)
                assert rc == 0 and err == "", (delay_ms, rc, err)
                continue
            signalled += 1
            where = f"SIGINT {delay_ms} ms after the hold (try {repeat + 1}): exit {rc}\n{err}"
            assert rc == 130, where
            assert err.splitlines() == [ONE_LINE], where
        if args[0] == "catalog":
            assert not (tmp_path / "out").exists()  # a first build that was stopped leaves nothing
    assert signalled >= (4 if args == ["--version"] else 2 * len(DELAYS_MS))


#: The CLI as the `swatch` script runs it (main() without argv); SETUP patches the command.
PROGRAM = """
import os, signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)
sys.argv = ["swatch", "materials", "list"]
from swatch.cli import main
SETUP
sys.exit(main())
"""

#: A library that catches BaseException (rtree's finder, trimesh's imports) gets the Ctrl-C, then fails.
SWALLOWED = """
import swatch.report.tables as tables
from swatch.core.errors import SwatchError
def text(*args):
    try:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.05)
    except BaseException:
        print("library: unexpected error", file=sys.stderr)  # (what rtree prints: the test keeps it)
    raise SwatchError("the table could not be read")
tables.materials_text = text
"""


def test_issue49_a_stop_a_library_swallowed_then_failed_for_is_the_stop_not_the_failure():
    """A Ctrl-C that a library swallowed, the library then failing: the run is reported as stopped (130, the
    stop's line), not as bad input (exit 2, the library's error)."""
    proc = subprocess.run([PY, "-c", PROGRAM.replace("SETUP", SWALLOWED)], capture_output=True, text=True,
                          timeout=120, check=False)
    assert proc.returncode == 130, proc.stderr
    assert proc.stderr.splitlines() == ["library: unexpected error", ONE_LINE], proc.stderr


def test_issue49_signals_held_together_are_recorded_all_and_raised_once(monkeypatch):
    """Two signals held at once (a closed terminal: SIGHUP, then SIGTERM) are both recorded when the mask
    goes, and one stop is raised: the second one was raised again while the first was being reported."""
    monkeypatch.setattr(procguard, "_RECEIVED", [])
    handlers = {s: signal.getsignal(s) for s in (signal.SIGHUP, signal.SIGTERM)}
    try:
        for s in handlers:
            signal.signal(s, procguard._record_or_raise)
        old = signal.pthread_sigmask(signal.SIG_BLOCK, set(handlers))
        main = threading.main_thread().ident  # (to this thread, which holds them: not to another of pytest's)
        signal.pthread_kill(main, signal.SIGHUP)
        signal.pthread_kill(main, signal.SIGTERM)
        with pytest.raises(procguard.Terminated) as caught:
            procguard.release_signals(old)
        assert caught.value.signum == signal.SIGHUP
        assert sorted(procguard._RECEIVED) == sorted([signal.SIGHUP, signal.SIGTERM])
    finally:
        for s, h in handlers.items():
            signal.signal(s, h)


#: A Ctrl-C while trimesh imports rtree (which trimesh wraps in `except BaseException`, as rtree's finder wraps
#: loading its library): sent by an import hook when `rtree.index` is looked for.
DURING_TRIMESH = """
import importlib.abc, os, signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)
from swatch.core import procguard
procguard.handle_termination()
class CtrlC(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "rtree.index":
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # (the handler runs here, inside trimesh's try)
        return None
sys.meta_path.insert(0, CtrlC())
try:
    import swatch.render.mesh
except KeyboardInterrupt:
    print("raised")
else:
    print("lost")
"""


def test_issue49_a_ctrl_c_while_trimesh_imports_is_raised_not_swallowed():
    """trimesh (and rtree inside it) catch BaseException around their imports: a Ctrl-C there was kept as a
    missing feature (or printed by rtree as "unexpected error") and the run went on. swatch.render.mesh imports
    trimesh with the stops held, and raises the one that came when trimesh is in."""
    proc = subprocess.run([PY, "-c", DURING_TRIMESH], capture_output=True, text=True, timeout=120, check=False)
    assert proc.stdout.split() == ["raised"], proc.stdout + proc.stderr
    assert proc.stderr == ""
