"""The stored tmm answers (tests/tmm_reference.py, issue 17) are tmm's: a sample of the store is asked of
``tmm.coh_tmm`` again and must agree to rounding (1e-13 relative: numpy's complex arithmetic takes
other SIMD paths on other CPUs, and the store recorded on one machine differed from tmm on an AVX-512
machine by one unit in the last place), and a question not in the store goes to tmm."""
from __future__ import annotations

import numpy as np
import tmm

from tests import tmm_reference


def test_stored_spectra_are_what_tmm_answers_now():
    entries = tmm_reference.stored_entries()
    assert len(entries) > 100, "tests/data/tmm_reference.npz is missing or nearly empty: record it (see its module)"
    for n, d, theta, wl, R in entries[:: max(1, len(entries) // 12)]:
        np.testing.assert_allclose(tmm_reference.live_R(n, d, theta, wl), R, rtol=1e-13, atol=0)


def test_a_question_not_in_the_store_is_asked_of_tmm(monkeypatch):
    """Any change of an input (here the last bit of the angle) is another digest, so a miss, answered by tmm
    one wavelength and polarisation at a time, as the callers did before the store; the stored question
    itself is a hit (tmm not called)."""
    n, d, theta, wl, R = tmm_reference.stored_entries()[0]
    calls = []
    live = tmm_reference.live_R
    monkeypatch.setattr(tmm_reference, "live_R", lambda *a: calls.append(a) or live(*a))
    np.testing.assert_array_equal(tmm_reference.unpolarised_R(list(n), d, theta, wl), R)
    assert calls == []
    nudged = float(np.nextafter(theta, 1.0))
    got = tmm_reference.unpolarised_R(list(n), d, nudged, wl)
    assert len(calls) == 1
    want = [0.5 * sum(tmm.coh_tmm(p, [complex(x) for x in n[:, j]], list(d), nudged, float(wl[j]))["R"] for p in "sp")
            for j in range(wl.size)]
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=0)
