"""Small helpers the tests share: unit vectors and random directions."""
from __future__ import annotations

import numpy as np


def unit(v) -> np.ndarray:
    """``v`` normalised along its last axis."""
    v = np.asarray(v)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def random_directions(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` directions uniform on the sphere, shape (n, 3): normalised standard normals from ``rng`` (one
    ``rng.normal(size=(n, 3))`` draw, so a test's later draws from ``rng`` are the same as before)."""
    return unit(rng.normal(size=(n, 3)))
