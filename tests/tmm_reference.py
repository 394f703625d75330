"""Byrnes' ``tmm.coh_tmm``, the suite's optics reference, with the answers it gave kept in
``tests/data/tmm_reference.npz`` (issue 17: the suite's time).

tmm takes one wavelength and one polarisation a call (~0.1 ms): the suite asked it ~185,000 times, about
20 CPU-s of a ~400 CPU-s run. :func:`unpolarised_R` looks each spectrum up by a digest of its exact inputs
(every layer's complex index at every wavelength, the thicknesses, the angle and the wavelengths, as
complex128 / float64 bytes), so a stored spectrum is tmm's answer to exactly that question (bit for bit
on the machine that recorded it; numpy's SIMD paths on another CPU may round the last bit otherwise): a
changed optical table, angle or thickness is a miss and is computed by tmm there and then. The store
holds the inputs too, and ``tests/test_tmm_reference.py`` asks tmm again for a sample of its entries.

To record the store again (after a change of the tables or of the tests' cases; a miss is only slower)::

    rm tests/data/tmm_reference.npz
    SWATCH_TMM_RECORD=$PWD/tests/data/tmm_reference.npz python3 dev.py test

Each test process then asks tmm for everything and, when it exits, adds what it asked to that file (under
a lock, so the two pytest-xdist workers and the processes they start can share it).
"""
from __future__ import annotations

import atexit
import fcntl
import functools
import hashlib
import os
from pathlib import Path

import numpy as np
import tmm

STORE = Path(__file__).resolve().parent / "data" / "tmm_reference.npz"
#: Set to a file name: record every spectrum asked into it (see the module docstring), store unread.
RECORD_ENV = "SWATCH_TMM_RECORD"


def _inputs(stack, thickness_nm, theta_rad, wavelength_nm):
    wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=np.float64))
    n = np.stack([np.broadcast_to(np.asarray(layer, dtype=np.complex128), wl.shape) for layer in stack])
    d = np.asarray(thickness_nm, dtype=np.float64)
    if d.shape != (n.shape[0],):
        raise ValueError(f"{n.shape[0]} layers but thicknesses {d.tolist()}")
    return n, d, np.float64(theta_rad), wl


def _digest(n: np.ndarray, d: np.ndarray, theta: np.float64, wl: np.ndarray) -> str:
    h = hashlib.sha256()
    for part in (np.int64(n.shape[0]), n, d, theta, wl):
        h.update(np.ascontiguousarray(part).tobytes())
    return h.hexdigest()


def live_R(n: np.ndarray, d: np.ndarray, theta: float, wl: np.ndarray) -> np.ndarray:
    """``0.5 (R_s + R_p)`` (W,) from ``tmm.coh_tmm``, one call per wavelength and polarisation (tmm is
    scalar: reference code, not ours). ``n``: (L, W) complex; ``d``: (L,) nm, ``inf`` outermost."""
    out = np.empty(wl.size)
    d_list = d.tolist()
    for j, lam in enumerate(wl):
        n_list = n[:, j].tolist()
        out[j] = 0.5 * (tmm.coh_tmm("s", n_list, d_list, theta, lam)["R"]
                        + tmm.coh_tmm("p", n_list, d_list, theta, lam)["R"])
    return out


@functools.cache
def _store() -> dict[str, np.ndarray]:
    """digest → stored R (W,); empty while recording."""
    if os.environ.get(RECORD_ENV):
        return {}
    return {key: entry[4] for key, entry in _entries_in(STORE).items()}


#: What this process asked, while recording: digest → (n, d, theta, wl, R).
_ASKED: dict[str, tuple] = {}


def unpolarised_R(stack, thickness_nm, theta_rad: float, wavelength_nm) -> np.ndarray:
    """Unpolarised reflectance of a layer stack, by tmm (or its stored answer to the same inputs).

    Parameters
    ----------
    stack : sequence of complex or array_like, shape (W,)
        Each layer's complex index ``n + i k`` from the incidence medium to the substrate; a scalar is the
        same at every wavelength.
    thickness_nm : sequence of float
        Each layer's thickness, nm: ``inf`` for the first and the last.
    theta_rad : float
        Angle of incidence in the first medium, radians.
    wavelength_nm : array_like, shape (W,)
        Vacuum wavelengths, nm.

    Returns
    -------
    numpy.ndarray, shape (W,)
        ``0.5 (R_s + R_p)``.
    """
    n, d, theta, wl = _inputs(stack, thickness_nm, theta_rad, wavelength_nm)
    key = _digest(n, d, theta, wl)
    found = _store().get(key)
    if found is not None:
        return found.copy()
    R = live_R(n, d, float(theta), wl)
    if os.environ.get(RECORD_ENV):
        _ASKED.setdefault(key, (n, d, theta, wl, R))
    return R


def _entries_in(path: Path) -> dict[str, tuple[np.ndarray, np.ndarray, float, np.ndarray, np.ndarray]]:
    """digest → (n (L, W), d (L,), theta, wl (W,), R (W,)) for every entry of the store at ``path``."""
    if not path.exists():
        return {}
    with np.load(path) as z:
        keys, n_all, d_all, theta, wl_all, R_all = z["keys"], z["n"], z["d"], z["theta"], z["wl"], z["R"]
        w_off, n_off, d_off = z["offsets"], z["n_offsets"], z["d_offsets"]
    out = {}
    for i, key in enumerate(keys):
        wl = wl_all[w_off[i]:w_off[i + 1]]
        n = n_all[n_off[i]:n_off[i + 1]].reshape(-1, wl.size)
        out[str(key)] = (n, d_all[d_off[i]:d_off[i + 1]], float(theta[i]), wl, R_all[w_off[i]:w_off[i + 1]])
    return out


def stored_entries() -> list[tuple[np.ndarray, np.ndarray, float, np.ndarray, np.ndarray]]:
    """Every entry of the store as (n (L, W), d (L,), theta, wl (W,), R (W,)), in the store's order."""
    return list(_entries_in(STORE).values())


def _offsets(sizes) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(np.asarray(sizes, dtype=np.int64))]).astype(np.int64)


def _write(path: Path, entries: dict[str, tuple]) -> None:
    keys = sorted(entries)
    rows = [entries[k] for k in keys]
    arrays = {
        "keys": np.array(keys),
        "offsets": _offsets([r[3].size for r in rows]),
        "n_offsets": _offsets([r[0].size for r in rows]),
        "d_offsets": _offsets([r[1].size for r in rows]),
        "n": np.concatenate([r[0].ravel() for r in rows]),
        "d": np.concatenate([r[1] for r in rows]),
        "theta": np.array([r[2] for r in rows], dtype=np.float64),
        "wl": np.concatenate([r[3] for r in rows]),
        "R": np.concatenate([r[4] for r in rows]),
    }
    tmp = path.with_name(path.name + f".{os.getpid()}.tmp.npz")
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


@atexit.register
def _record() -> None:
    target = os.environ.get(RECORD_ENV)
    if not target or not _ASKED:
        return
    path = Path(target)
    folder = os.open(path.parent, os.O_RDONLY)  # the lock: the folder itself (no lock file left behind)
    try:
        fcntl.flock(folder, fcntl.LOCK_EX)
        entries = _entries_in(path)
        entries.update(_ASKED)
        _write(path, entries)
    finally:
        os.close(folder)
