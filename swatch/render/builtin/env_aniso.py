"""Anisotropic GGX under an environment (brushed finishes): the sample set of
:mod:`swatch.render.builtin.env_shading` for ``α_u ≠ α_v``.

The method is the isotropic one (fixed visible-normal samples per view bin, per-sample blurred
environment, the level fixed by a dense set: :mod:`swatch.render.builtin.env_shading`), with two changes:

* **Bins over the view in the tangent frame.** With anisotropy the lobe depends on the view's
  azimuth to the brushing direction, not only on ``θ_v``: the bins are :data:`THETA_BINS`
  (uniform in ``θ_v``) × :data:`PHI_BINS` (uniform in ``φ_v`` over [0°, 90°]), and a pixel's
  radiance is interpolated bilinearly between the four bins around its view (nearest bins showed
  as fans of streaks; the gather costs four times the isotropic one). Anisotropic GGX is
  symmetric under ``x → −x`` and ``y → −y`` in the tangent frame, so a view in any quadrant uses
  the first quadrant's samples with the frame's axes flipped (:meth:`AnisoSampleSet.frames`).
* **Anisotropic visible-normal sampling**: the renderer's one GGX sampler,
  :func:`swatch.physics.microfacet.sample_vndf_ggx` (Heitz 2018, listing 1, with ``α_x``, ``α_y``), whose
  isotropic case the isotropic set uses; the weight ``G2/G1`` (height-correlated).

Each pixel needs the brushing tangent (:func:`swatch.physics.finishes.brush_tangent`). With
``α_u = α_v`` the result equals the isotropic set's up to the bins (tested).
"""
from __future__ import annotations

import functools

import numpy as np

from swatch.physics import microfacet
from swatch.render.builtin.env_shading import (
    CHUNK,
    SAMPLES,
    SIGMA_PER_FOOTPRINT,
    combine,
    fibonacci_lattice,
    level_table,
)

__all__ = ["THETA_BINS", "PHI_BINS", "AnisoSampleSet", "aniso_sample_set", "gather_aniso", "combine_aniso",
           "shade_aniso"]

#: View bins: polar angle (uniform over 0–90°) × azimuth to the brushing direction (0–90°),
#: interpolated bilinearly between bin centres.
THETA_BINS = 64
PHI_BINS = 12
#: Dense samples per bin for the level (fewer than the isotropic set's: there are 6× the bins).
ANISO_DENSE = 1024


class AnisoSampleSet:
    """The fixed sample set of an anisotropic GGX lobe (the attributes of
    :class:`swatch.render.builtin.env_shading.SampleSet`: ``l`` (M, N, 3), ``w`` (M, N), ``cos_d``,
    ``sigma_deg``, ``dense_w``, ``dense_cos_d``, ``bins``).

    Parameters
    ----------
    alpha_u, alpha_v : float
        GGX α along and across the brushing (checked).
    n : int
        Samples per view bin.
    dense : int
        Dense samples per bin for the level.
    """

    def __init__(self, alpha_u: float, alpha_v: float, n: int = SAMPLES, dense: int = ANISO_DENSE):
        self.alpha_u = microfacet.check_roughness_alpha(alpha_u)
        self.alpha_v = microfacet.check_roughness_alpha(alpha_v)
        self.roughness_alpha = float(np.sqrt(self.alpha_u * self.alpha_v))
        self.n = int(n)
        th = (np.arange(THETA_BINS) + 0.5) / THETA_BINS * (np.pi / 2)
        ph = (np.arange(PHI_BINS) + 0.5) / PHI_BINS * (np.pi / 2)
        T, P = np.meshgrid(th, ph, indexing="ij")
        V = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1).reshape(-1, 3)
        self.bins = V.shape[0]
        l, w, cd, pdf = microfacet.sample_vndf_ggx(V, self.alpha_u, self.alpha_v, *fibonacci_lattice(self.n))
        self.l = l.astype(np.float32)
        self.w = w / self.n
        self.cos_d = cd
        self.sigma_deg = np.degrees(SIGMA_PER_FOOTPRINT * np.sqrt(1.0 / (self.n * np.maximum(pdf, 1e-12))))
        parts = [microfacet.sample_vndf_ggx(V[a:a + 64], self.alpha_u, self.alpha_v, *fibonacci_lattice(int(dense)))
                 for a in range(0, self.bins, 64)]
        self.dense_w = np.concatenate([p[1] for p in parts]) / int(dense)
        self.dense_cos_d = np.concatenate([p[2] for p in parts]).astype(np.float32)
        self.dense_samples = int(dense)
        self.cache: dict = {}

    def frames(self, n, v, tangent):
        """Per point the frame's tangent and bitangent, flipped so that the view lies in their first quadrant,
        and the four view bins around (θ_v, φ_v) with bilinear weights (see the module doc).

        Parameters
        ----------
        n, v : array_like, shape (P, 3)
            Unit normals and views.
        tangent : array_like, shape (P, 3)
            Brushing directions (made orthogonal to ``n``).

        Returns
        -------
        (numpy.ndarray, numpy.ndarray, numpy.ndarray, numpy.ndarray)
            Tangent (P, 3), bitangent (P, 3), bins ``j`` (4, P) and weights (4, P).

        Raises
        ------
        ValueError
            ``tangent`` is None.
        """
        if tangent is None:
            raise ValueError("an anisotropic lobe needs the brushing tangent of every point")
        n = np.asarray(n, dtype=np.float32)
        v = np.asarray(v, dtype=np.float32)
        t = np.asarray(tangent, dtype=np.float32)
        t = t - np.einsum("pi,pi->p", t, n)[:, None] * n
        t /= np.maximum(np.linalg.norm(t, axis=-1, keepdims=True), np.float32(1e-12))
        b = np.cross(n, t)
        vx = np.einsum("pi,pi->p", v, t)
        vy = np.einsum("pi,pi->p", v, b)
        vz = np.einsum("pi,pi->p", v, n)
        t *= np.where(vx < 0, np.float32(-1), np.float32(1))[:, None]
        b *= np.where(vy < 0, np.float32(-1), np.float32(1))[:, None]
        theta = np.arccos(np.clip(vz, 0.0, 1.0))
        phi = np.arctan2(np.abs(vy), np.abs(vx))
        t0, t1, ft = _neighbours(theta, THETA_BINS)
        p0, p1, fp = _neighbours(phi, PHI_BINS)
        j = np.stack([t0 * PHI_BINS + p0, t0 * PHI_BINS + p1, t1 * PHI_BINS + p0, t1 * PHI_BINS + p1])
        weight = np.stack([(1 - ft) * (1 - fp), (1 - ft) * fp, ft * (1 - fp), ft * fp]).astype(np.float32)
        return t, b, j, weight


def _neighbours(angle, bins: int):
    """The two bin centres around ``angle`` (radians, in [0, π/2]; centres at (i + ½)/bins · π/2)
    and the weight of the second (clamped at the ends, where the lobe is mirror-symmetric)."""
    x = np.asarray(angle, dtype=np.float64) * (bins / (np.pi / 2)) - 0.5
    i0 = np.clip(np.floor(x), 0, bins - 1).astype(np.int32)
    i1 = np.minimum(i0 + 1, bins - 1)
    f = np.clip(x - i0, 0.0, 1.0)
    return i0, i1, np.where(i1 == i0, 0.0, f)


def gather_aniso(n, v, maps, samples: AnisoSampleSet, table, tangent, occluded=None):
    """Environment samples for each point's four neighbouring view bins.

    Parameters
    ----------
    n, v, tangent : array_like, shape (P, 3)
        Normals, views and brushing directions.
    maps : swatch.render.octahedral.LevelMaps
        The environment's blurred levels.
    samples : AnisoSampleSet
        The anisotropic lobe's fixed samples per view bin (:func:`aniso_sample_set`).
    table : numpy.ndarray
        :func:`swatch.render.builtin.env_shading.level_table` of ``samples`` on ``maps``.
    occluded : callable, optional
        As :func:`swatch.render.builtin.env_shading.gather`'s: the sample directions the object hides are dark.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        ``E`` (4·P, N, 3) radiance samples, bins ``j`` (4·P,) and bilinear weights (4, P);
        :func:`combine_aniso` turns them into radiance.
    """
    n = np.asarray(n, dtype=np.float32).reshape(-1, 3)
    v = np.asarray(v, dtype=np.float32).reshape(-1, 3)
    tangent = np.asarray(tangent, dtype=np.float32).reshape(-1, 3)
    P = n.shape[0]
    E = np.empty((4, P, samples.n, 3), dtype=np.float32)
    J = np.empty((4, P), dtype=np.int32)
    W = np.empty((4, P), dtype=np.float32)
    for a in range(0, P, CHUNK):
        sl = slice(a, a + CHUNK)
        t, b, j, w = samples.frames(n[sl], v[sl], tangent[sl])
        J[:, sl], W[:, sl] = j, w
        nn = n[sl]
        for q in range(4):
            loc = table[j[q]]
            dirs = [loc[..., 0] * t[:, None, k] + loc[..., 1] * b[:, None, k] + loc[..., 2] * nn[:, None, k]
                    for k in range(3)]
            E[q, sl] = maps.bilinear(*dirs, loc[..., 3], loc[..., 4])
            if occluded is not None:
                E[q, sl] *= ~occluded(sl, np.stack(dirs, -1))[..., None]
    return E.reshape(4 * P, samples.n, 3), J.reshape(-1), W


def combine_aniso(E, j, mix, weights) -> np.ndarray:
    """Radiance from :func:`gather_aniso`'s samples and one thickness's band weights.

    Parameters
    ----------
    E, j, mix
        :func:`gather_aniso`'s output.
    weights : numpy.ndarray
        :func:`swatch.render.builtin.env_shading.band_weights` of the thickness.

    Returns
    -------
    numpy.ndarray, shape (P, 3)
        Reflected radiance, linear RGB (1.0 = a white diffuser facing up under the map).
    """
    r = combine(E, j, weights).reshape(4, -1, 3)
    return np.einsum("qp,qpc->pc", mix, r)


def shade_aniso(n, v, maps, samples: AnisoSampleSet, weights, tangent) -> np.ndarray:
    """Radiance of points under an environment with an anisotropic lobe (gather, then combine).

    Parameters
    ----------
    n, v : array_like, shape (P, 3)
        Unit normals and views (towards the camera).
    maps : swatch.render.octahedral.LevelMaps
        The environment's blurred levels.
    samples : AnisoSampleSet
        The anisotropic lobe's fixed samples per view bin (:func:`aniso_sample_set`).
    weights : numpy.ndarray
        Band weights of the thickness.
    tangent : array_like, shape (P, 3)
        Brushing directions (:func:`swatch.physics.finishes.brush_tangent`).

    Returns
    -------
    numpy.ndarray, shape (P, 3)
        Reflected radiance, linear RGB (1.0 = a white diffuser facing up under the map).
    """
    E, j, mix = gather_aniso(n, v, maps, samples, level_table(samples, maps), tangent)
    return combine_aniso(E, j, mix, weights)


@functools.lru_cache(maxsize=4)
def aniso_sample_set(alpha_u: float, alpha_v: float, n: int = SAMPLES) -> AnisoSampleSet:
    """The anisotropic sample set of ``(α_u, α_v)`` (cached per process).

    Parameters
    ----------
    alpha_u, alpha_v : float
        GGX α along and across the brushing (dimensionless).
    n : int
        Samples per view bin.

    Returns
    -------
    AnisoSampleSet
        The fixed samples and weights per (θ_v, φ_v) view bin, shared by every call with the same arguments.
    """
    return AnisoSampleSet(float(alpha_u), float(alpha_v), int(n))

