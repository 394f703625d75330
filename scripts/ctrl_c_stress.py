"""Ctrl-C during a catalog rebuild at random moments (issue 38 item 2): every try must end in one line
`error: interrupted…`, exit 130, and leave no process of its group behind.

Usage: python scripts/ctrl_c_stress.py [TRIES] [--signal INT|TERM] [--seed N] [--min S] [--max S]

Each try rebuilds a small catalog (a 2-worker pool on the fork server; each try shifts the thicknesses
by 0.05 nm, so that every rebuild renders all its tiles) and sends the signal to its process group (SIGINT: a
Ctrl-C on a terminal) at a uniformly random moment in [--min, --max] seconds. A build that was already
done by then (exit 0 before the signal) is counted apart, as "finished first"; a build that gets the
signal and still exits 0 is the bug this looks for ("swallowed"). Prints one line per try and a summary;
exits 1 when any try went wrong.
"""
from __future__ import annotations

import argparse
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's tests package
from tests.core.test_hardening_runs import AS_ON_A_TERMINAL, KILL_SPEC, group_members

#: The small catalog each try rebuilds (the killed-build tests' spec, its first thickness shifted per try).
SPEC = KILL_SPEC.replace("start_nm = 20", "start_nm = {start}")


def exiting(pid: int) -> bool:
    """Whether process ``pid`` is gone or in the kernel's exit (PF_EXITING: it called exit, the kernel is
    tearing its memory down, which takes a while for a build's address space, and it is no zombie yet): a
    signal sent now meets no program, and the build's exit 0 is "finished first", not "swallowed"."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    fields = stat[stat.rindex(")") + 2:].split()
    return fields[0] in ("Z", "X") or bool(int(fields[6]) & 0x4)


def one_try(folder: Path, start_nm: float, delay_s: float, sig: int) -> tuple[str, int, str, float]:
    """(verdict, exit status, stderr, seconds the build ran) of one rebuild signalled after ``delay_s``."""
    spec = folder / "stress.toml"
    spec.write_text(SPEC.format(start=start_nm), encoding="utf-8")
    err = folder / "stderr.txt"
    start = time.monotonic()
    with open(err, "w") as fh:
        proc = subprocess.Popen([sys.executable, "-c", AS_ON_A_TERMINAL, "catalog", "build", str(spec), "--out",
                                 str(folder / "out"), "-j", "2", "-q"], stdout=subprocess.DEVNULL, stderr=fh,
                                start_new_session=True)
    try:
        while proc.poll() is None and time.monotonic() - start < delay_s:
            time.sleep(0.005)
        sent = proc.poll() is None and not exiting(proc.pid)
        if sent:
            os.killpg(proc.pid, sig)
        rc = proc.wait(timeout=120)
        took = time.monotonic() - start
        deadline = time.monotonic() + 20
        while group_members(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.05)
        left = group_members(proc.pid)
    finally:
        for pid in group_members(proc.pid):
            os.kill(pid, signal.SIGKILL)
    text = err.read_text()
    lines = text.strip().splitlines()
    want = 130 if sig == signal.SIGINT else 128 + sig
    if not sent:
        verdict = "finished first" if rc == 0 and not lines else "failed before the signal"
    elif left:
        verdict = f"left {len(left)} processes"
    elif rc == 0:
        verdict = "swallowed"
    elif rc != want:
        verdict = f"exit {rc}"
    elif len(lines) != 1 or not lines[0].startswith("error: "):
        verdict = f"{len(lines)} lines"
    else:
        verdict = "one line"
    return verdict, rc, text, took


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tries", type=int, nargs="?", default=60)
    ap.add_argument("--signal", choices=["INT", "TERM"], default="INT")
    ap.add_argument("--seed", type=int, default=38)
    ap.add_argument("--min", type=float, default=0.3, dest="lo")
    ap.add_argument("--max", type=float, default=6.1, dest="hi")
    args = ap.parse_args()
    sig = getattr(signal, f"SIG{args.signal}")
    rng = random.Random(args.seed)
    counts: dict[str, int] = {}
    with tempfile.TemporaryDirectory(prefix="ctrl-c-") as tmp:
        folder = Path(tmp)
        one_try(folder, 20.0, 1e9, sig)  # the first build: every try after it is a rebuild
        for k in range(args.tries):
            delay = rng.uniform(args.lo, args.hi)
            verdict, rc, text, took = one_try(folder, 20.0 + 0.05 * (k + 1), delay, sig)
            counts[verdict] = counts.get(verdict, 0) + 1
            print(f"try {k + 1:3d} at {delay:4.2f} s: {verdict} (exit {rc}, {took:.2f} s)", flush=True)
            if verdict not in ("one line", "finished first"):
                print("  | " + text.rstrip().replace("\n", "\n  | "), flush=True)
    print("summary: " + ", ".join(f"{n} {v}" for v, n in sorted(counts.items())))
    return 0 if set(counts) <= {"one line", "finished first"} else 1


if __name__ == "__main__":
    sys.exit(main())
