"""The capped CLI run of the memory tests (issue #22 group 3): a subprocess under an address-space limit of
the run's budget plus the interpreter's baseline."""
from __future__ import annotations

import os
import resource
import subprocess
import sys

from swatch.core.limits import MAX_RUN_BYTES

BASELINE_BYTES = 512 * 1024 ** 2  # the interpreter, numpy, scipy, colour-science, OpenImageIO and thread stacks
CAP_BYTES = MAX_RUN_BYTES + BASELINE_BYTES


def run_capped(*args, timeout: float = 900, budget: int | None = None) -> subprocess.CompletedProcess:
    """The CLI in a subprocess under an address-space limit of the run's budget plus the baseline:
    ``MAX_RUN_BYTES``, or ``budget`` (bytes), which the run is then told to plan for
    (``SWATCH_MAX_RUN_BYTES``, read by swatch.core.limits)."""
    cap = (MAX_RUN_BYTES if budget is None else budget) + BASELINE_BYTES
    env = dict(os.environ, SWATCH_MAX_RUN_BYTES=str(budget)) if budget is not None else None

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))

    return subprocess.run([sys.executable, "-m", "swatch.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=limit, check=False, env=env)
