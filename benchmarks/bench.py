"""``make bench``: time the project against the reference implementations in the same run.

Runs each section (benchmarks/bench_<area>.py, ``run() -> list[str]``) and prints its lines.
The engine section runs last, so the final line is ``ratio_vs_colour=X ratio_vs_tmm=Y``.
``--tiny`` (or ``SWATCH_BENCH_TINY=1``) runs each section at a tiny size, one repeat: a smoke test whose
figures mean nothing (tests/test_bench.py). Section names pick sections: ``python3 dev.py bench render qc``.
Machines here are noisy: every figure is a median of repeats, and ratios are measured in one run.
``mitsuba_cuda`` times the Mitsuba engine on an NVIDIA GPU beside the CPU where Dr.Jit and OIDN find one, and
says ``cuda: not available here`` otherwise (``python3 dev.py bench mitsuba_cuda`` on a GPU machine).
"""
from __future__ import annotations

import importlib
import os
import platform
import sys

import numpy as np

SECTIONS = ["render", "environment", "mesh", "mitsuba", "mitsuba_cuda", "catalog", "explorer", "exports", "fit", "calibrate", "qc", "presets",
            "engine"]


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"machine: {cpu}; {os.cpu_count()} cores; Python {platform.python_version()}; "
            f"numpy {np.__version__}")


def main(argv: list[str]) -> int:
    if "--tiny" in argv:
        os.environ["SWATCH_BENCH_TINY"] = "1"  # for the processes the sections start
        from benchmarks import timing

        timing.TINY = True
        argv = [a for a in argv if a != "--tiny"]
    unknown = sorted(set(argv) - set(SECTIONS))
    if unknown:
        print(f"bench: unknown section(s) {', '.join(unknown)}; sections: {' '.join(SECTIONS)}", file=sys.stderr)
        return 2
    wanted = argv or SECTIONS
    print(machine(), flush=True)
    for name in SECTIONS:
        if name not in wanted:
            continue
        module = importlib.import_module(f"benchmarks.bench_{name}")
        for line in module.run():
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
