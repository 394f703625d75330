"""swatch.core.heap: with the thresholds set, array temporaries freed and allocated again are reused from the heap
(few page faults); without them glibc hands the memory back and faults it in again each time."""
from __future__ import annotations

import subprocess
import sys

import pytest

# six 8 MB temporaries alive at once, freed, again and again (the calibration's residual steps, in small);
# prints the minor page faults of the loop
CHURN = """
import resource, sys
import numpy as np
if sys.argv[1] == "tuned":
    from swatch.core.heap import keep_freed_memory
    assert keep_freed_memory()
x = np.ones(1_000_000)
r0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(40):
    parts = [x * k for k in range(6)]
    del parts
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - r0)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's mallopt")
def test_freed_array_memory_is_reused_not_faulted_in_again():
    def faults(mode: str) -> int:
        proc = subprocess.run([sys.executable, "-c", CHURN, mode], capture_output=True, text=True, check=True)
        return int(proc.stdout)

    default, tuned = faults("default"), faults("tuned")
    pages = 40 * 6 * 8_000_000 // 4096  # every temporary faulted in afresh: ~470 000 pages
    assert default > pages // 8, default  # the behaviour the thresholds are for (else this test proves nothing)
    assert tuned < pages // 100, (tuned, default)
