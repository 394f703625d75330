"""The thin-film microfacet BRDF integrated over an environment (image-based lighting).

A pixel that sees the surface point with normal ``n`` from direction ``v`` has radiance

    L(n, v) = ∫ L_env(l) f(l, v) cos θ_l dω_l,   f = D G F(λ; d, θ_d) / (4 cos θ_l cos θ_v),

GGX ``D``, height-correlated Smith ``G`` (:mod:`swatch.physics.microfacet`), ``F`` the Airy thin-film
reflectance at the facet incidence ``cos θ_d = v·h`` (:mod:`swatch.physics.optics`). The colour depends
on ``θ_d``, which changes across the lobe, so the integral is taken with ``F`` inside, sample by
sample: no Fresnel-agnostic prefiltered map.

**Method (importance sampling with a fixed sample set).** Directions are drawn from the GGX
distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible
Normals"), for which ``f cos θ_l / pdf = F(θ_d) G2(l, v) / G1(v)``. The sample set is fixed: a
Fibonacci lattice of ``N`` points per bin of ``θ_v`` (:data:`VIEW_BINS` bins uniform in θ_v), laid out in
the local frame (normal = z, view in the xz plane) and rotated into each pixel's frame. Then

    L(n, v) ≈ Σ_i a_i(cos θ_v) ⊙ E(R_{n,v} l_i),   a_i = w_i (RGB(F(θ_d,i)) + δ(cos θ_v)),  w_i = G2/G1 / N

with ``E`` the environment blurred on the sphere by the samples' footprint (σ from the lobe's
solid angle / N, so a few samples give a smooth image: filtered importance sampling, Křivánek &
Colbert 2008), looked up bilinearly. A correction (per colour channel, spread over the samples
in proportion to their weights, :func:`band_weights`) makes the sum under a uniform environment
equal the directional albedo ``∫ f cos θ_l dω_l`` computed with :data:`DENSE_SAMPLES` samples:
the few-sample set only distributes the light, the dense set fixes the level (exact in the
furnace test).

Because ``E(R l_i)`` does not depend on the thickness, a series of thicknesses rendered with one
scene (a catalog) gathers the environment once (:func:`gather`) and re-weights it per thickness
(:func:`combine`).

:func:`shade_reference` is the brute force used to measure the error: 4096 samples per pixel on
the unfiltered map, ``F`` at every sample's own ``θ_d``. Light colour: the environment's RGB
multiplies the RGB of ``F`` channel by channel (exact for neutral light such as ``uniform`` and
``studio``, whose spectrum is the colorimeter's illuminant).
"""
from __future__ import annotations

import functools

import numpy as np

from swatch.physics import microfacet

__all__ = [
    "SAMPLES",
    "DENSE_SAMPLES",
    "VIEW_BINS",
    "SampleSet",
    "sample_set",
    "filter_sigma_deg",
    "band_weights",
    "gather",
    "combine",
    "shade",
    "shade_reference",
    "directional_albedo",
    "albedo_matrix",
    "local_frame",
    "fibonacci_lattice",
]

#: Fixed samples per view bin. 128 (issue 23; was 24): at the sphere centre under the studio the lobe's
#: tails reach soft boxes 20 × brighter than the wall it faces, and 24 samples with their wide blur read
#: 7.5 % bright there (ΔE00 1.5); with 128 and the narrower blur below, plate and sphere centres are within
#: ΔE00 0.65 of the brute force at α 0.12–0.5 (docs/mitsuba.md, scripts/env_fastpath_sweep.py).
SAMPLES = 128
DENSE_SAMPLES = 4096
VIEW_BINS = 256
#: Environment blur per sample / the side of its solid-angle footprint (chosen by the error against the
#: brute force: smaller leaves sample patterns, larger widens the lobe onto bright surroundings; 0.35 with
#: 24 samples).
SIGMA_PER_FOOTPRINT = 0.25
_PHI = (np.sqrt(5.0) - 1.0) / 2.0


def fibonacci_lattice(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A 2-D Fibonacci lattice of ``n`` points in [0, 1)² (deterministic, well stratified).

    Parameters
    ----------
    n : int
        Number of directions.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        u1 = (i + ½)/n and u2 = frac((i + ½) φ⁻¹), each shape (n,).

    Examples
    --------
    >>> [round(float(x), 3) for x in fibonacci_lattice(2)[1]]
    [0.309, 0.927]
    """
    i = np.arange(n, dtype=np.float64)
    return (i + 0.5) / n, np.mod((i + 0.5) * _PHI, 1.0)


def _vndf(cos_v: np.ndarray, roughness_alpha: float, u1: np.ndarray, u2: np.ndarray):
    """Isotropic GGX visible-normal samples for views ``v = (sin θ_v, 0, cos θ_v)`` (B,) and lattice
    points (N,): (l (B, N, 3), weight G2/G1 (B, N), cos θ_d (B, N), pdf (B, N)), by the one sampler
    :func:`swatch.physics.microfacet.sample_vndf_ggx` (the anisotropic set's)."""
    cv = np.clip(np.asarray(cos_v, dtype=np.float64), 1e-6, 1.0)
    views = np.stack([np.sqrt(1.0 - cv * cv), 0.0 * cv, cv], -1)
    return microfacet.sample_vndf_ggx(views, roughness_alpha, roughness_alpha, u1, u2)


class SampleSet:
    """The fixed local sample set of one roughness (see the module doc).

    Attributes: per view bin (M) and sample (N) the light direction ``l`` (M, N, 3), weight
    ``w = G2/G1 / N`` (M, N), ``cos_d`` (M, N), the blur ``sigma_deg`` (M, N); for the level, the
    dense set's ``dense_w`` and ``dense_cos_d`` (M, DENSE); ``cos_v`` (M,) the bins' view cosines.

    Parameters
    ----------
    roughness_alpha : float
        GGX α.
    n : int
        Samples per bin.
    bins : int
        View bins, uniform in θ_v.
    dense : int
        Dense samples per bin (the level).

    References
    ----------
    :cite:`Heitz2018` (visible-normal sampling); :cite:`Krivanek2008` (filtered importance sampling).
    """

    def __init__(self, roughness_alpha: float, n: int = SAMPLES, bins: int = VIEW_BINS, dense: int = DENSE_SAMPLES):
        self.roughness_alpha = float(roughness_alpha)
        self.n = int(n)
        self.bins = int(bins)
        self.cos_v = np.cos((np.arange(self.bins) + 0.5) / self.bins * (np.pi / 2))[::-1].copy()
        l, w, cd, pdf = _vndf(self.cos_v, self.roughness_alpha, *fibonacci_lattice(self.n))
        self.l = l.astype(np.float32)
        self.w = w / self.n
        self.cos_d = cd
        #: blur per sample (degrees): SIGMA_PER_FOOTPRINT × the side of its footprint 1/(N pdf), rounded
        #: up to the next level of the environment
        self.sigma_deg = np.degrees(SIGMA_PER_FOOTPRINT * np.sqrt(1.0 / (self.n * np.maximum(pdf, 1e-12))))
        parts = [_vndf(self.cos_v[a:a + 32], self.roughness_alpha, *fibonacci_lattice(int(dense)))
                 for a in range(0, self.bins, 32)]
        self.dense_w = np.concatenate([p[1] for p in parts]) / int(dense)
        self.dense_cos_d = np.concatenate([p[2] for p in parts]).astype(np.float32)
        self.cache: dict = {}

    def footprint_sr(self) -> float:
        """Median solid angle per sample at normal view, ``1/(N pdf)``.

        Returns
        -------
        float
            sr.
        """
        cl = self.l[self.bins - 1, :, 2].astype(np.float64)
        h = self.l[self.bins - 1] + np.array([0.0, 0.0, 1.0], dtype=np.float32)
        h = h / np.linalg.norm(h, axis=-1, keepdims=True)
        ch = np.clip(h[:, 2].astype(np.float64), 0, 1)
        cv = self.cos_v[-1]
        d = microfacet.D_ggx(ch, self.roughness_alpha)
        g1 = 1.0 / (1.0 + microfacet.smith_lambda(cv, self.roughness_alpha))
        pdf = g1 * d / (4.0 * cv)  # D_v(h)/(4 v·h) with v·h cancelling
        ok = (cl > 0) & (pdf > 0)
        return float(np.median(1.0 / (self.n * pdf[ok])))


@functools.lru_cache(maxsize=8)
def sample_set(roughness_alpha: float, n: int = SAMPLES) -> SampleSet:
    """The sample set of a roughness (cached per process).

    Parameters
    ----------
    roughness_alpha : float
        GGX α (checked).
    n : int
        Samples per bin.

    Returns
    -------
    SampleSet
        The fixed GGX visible-normal samples per view bin and their weights (cached per α).
    """
    return SampleSet(microfacet.check_roughness_alpha(roughness_alpha), int(n))


def filter_sigma_deg(samples: SampleSet) -> float:
    """Angular width of the environment blur matched to the samples' footprint.

    Parameters
    ----------
    samples : SampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`).

    Returns
    -------
    float
        Degrees.
    """
    return float(np.degrees(0.5 * np.sqrt(samples.footprint_sr())))


def _lookup_table(table, cos_d):
    """Linear interpolation of a uniform table over [0, 1] (``table`` (K, 3)) at ``cos_d``."""
    k = table.shape[0] - 1
    x = np.clip(np.asarray(cos_d, dtype=np.float64) * k, 0.0, k)
    i = np.minimum(x.astype(np.int64), k - 1)
    f = (x - i)[..., None]
    return table[i] * (1.0 - f) + table[i + 1] * f


def albedo_matrix(samples, k: int) -> np.ndarray:
    """The dense set's weights spread onto the K nodes of a uniform cos θ_d table by the
    linear-interpolation weights, so that the level is one product with any table (cached).

    Parameters
    ----------
    samples : SampleSet or swatch.render.builtin.env_aniso.AnisoSampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`, :func:`swatch.render.builtin.env_aniso.aniso_sample_set`).
    k : int
        Table nodes.

    Returns
    -------
    numpy.ndarray, shape (M, K)
        Directional albedo per view bin (M) and F-table node (K), dimensionless (≤ 1).
    """
    key = ("albedo", int(k))
    if key not in samples.cache:
        x = np.clip(samples.dense_cos_d.astype(np.float64) * (k - 1), 0.0, k - 1)
        i = np.minimum(x.astype(np.int64), k - 2)
        f = x - i
        rows = np.arange(samples.bins)[:, None] * k
        H = np.bincount((rows + i).ravel(), (samples.dense_w * (1.0 - f)).ravel(), samples.bins * k)
        H += np.bincount((rows + i + 1).ravel(), (samples.dense_w * f).ravel(), samples.bins * k)
        samples.cache[key] = H.reshape(samples.bins, k)
    return samples.cache[key]


def directional_albedo(samples, f_table) -> np.ndarray:
    """The directional albedo ``∫ f cos θ_l dω_l`` per view bin, from the dense set.

    Parameters
    ----------
    samples : SampleSet or swatch.render.builtin.env_aniso.AnisoSampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`, :func:`swatch.render.builtin.env_aniso.aniso_sample_set`).
    f_table : array_like, shape (K, 3)
        ``F``'s linear RGB, uniform over cos θ_d in [0, 1] (linear interpolation).

    Returns
    -------
    numpy.ndarray, shape (M, 3)
        Directional albedo per view bin, linear RGB (≤ 1).
    """
    f_table = np.asarray(f_table, dtype=np.float64)
    return albedo_matrix(samples, f_table.shape[0]) @ f_table


def band_weights(samples, f_table) -> np.ndarray:
    """The per-bin, per-sample RGB weights ``a`` for one thickness (module doc).

    ``a_i = w_i F(θ_d,i) + w_i (A − Σ_i w_i F(θ_d,i)) / Σ_i w_i`` per bin and channel, ``A`` the dense
    directional albedo: additive, so it stays finite where a channel of F's linear RGB changes sign
    across the lobe (saturated cyans' red); a ratio would blow up.

    Parameters
    ----------
    samples : SampleSet or swatch.render.builtin.env_aniso.AnisoSampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`, :func:`swatch.render.builtin.env_aniso.aniso_sample_set`).
    f_table : array_like, shape (K, 3)
        As :func:`directional_albedo`.

    Returns
    -------
    numpy.ndarray of float32, shape (M, N, 3)
        Each sample's weight per view bin: its F (linear RGB) times the lobe's estimator weight.
    """
    a = samples.w[..., None] * _lookup_table(f_table, samples.cos_d)
    level = directional_albedo(samples, f_table)
    W = samples.w.sum(axis=1)
    delta = np.where(W[:, None] > 0, (level - a.sum(axis=1)) / np.where(W > 0, W, 1.0)[:, None], 0.0)
    return (a + samples.w[..., None] * delta[:, None, :]).astype(np.float32)


def local_frame(n, v):
    """The local frame of each point: ``v`` lies in the (t, n) plane on the +t side (along the normal any
    perpendicular t is used).

    Parameters
    ----------
    n, v : array_like, shape (P, 3)
        Unit normals and views.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        cos θ_v (P,), tangent t (P, 3), bitangent b (P, 3).
    """
    n = np.asarray(n, dtype=np.float32)
    v = np.asarray(v, dtype=np.float32)
    cv = np.einsum("pi,pi->p", n, v)
    t = v - cv[:, None] * n
    tl = np.linalg.norm(t, axis=-1)
    alt = np.cross(n, np.where(np.abs(n[:, :1]) < 0.9, np.array([1, 0, 0], dtype=np.float32), np.array([0, 1, 0], dtype=np.float32)))
    small = tl < 1e-6
    t = np.where(small[:, None], alt, t)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(n, t)
    return cv, t, b


def _bins(samples: SampleSet, cv):
    """View bin of each ``cos θ_v``: bins are uniform in θ_v, ordered by increasing cos θ_v."""
    theta = np.arccos(np.clip(np.asarray(cv, dtype=np.float32), 0.0, 1.0))
    k = (theta * np.float32(samples.bins / (np.pi / 2))).astype(np.int32)
    return samples.bins - 1 - np.clip(k, 0, samples.bins - 1)


#: Points per chunk of the gather (and of combine): ~256 k sample lookups a chunk keeps the temporaries
#: in cache (8192 points × 128 samples took twice the CPU time of 2048); results do not depend on it.
CHUNK = 2048


def level_table(samples, maps) -> np.ndarray:
    """Per bin and sample: the local direction, the blur level's resolution and its offset in ``maps``.

    Parameters
    ----------
    samples : SampleSet or swatch.render.builtin.env_aniso.AnisoSampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`, :func:`swatch.render.builtin.env_aniso.aniso_sample_set`).
    maps : swatch.render.octahedral.LevelMaps
        The environment's blur levels (:func:`swatch.render.environment.levels`).

    Returns
    -------
    numpy.ndarray of float32, shape (M, N, 5)
        Per view bin and sample: the local direction (3), the blur level's texel resolution and its offset in
        ``maps`` (texels).
    """
    k = maps.level_for(samples.sigma_deg)
    return np.concatenate([samples.l, maps.res[k][..., None].astype(np.float32),
                           maps.offset[k][..., None].astype(np.float32)], -1)


def gather(n, v, maps, samples: SampleSet, table=None, occluded=None) -> tuple[np.ndarray, np.ndarray]:
    """Environment samples in each pixel's sample directions, and its view bin.

    Parameters
    ----------
    n, v : array_like, shape (P, 3)
        Unit normals and views (towards the camera).
    maps : swatch.render.octahedral.LevelMaps
        The environment's blur levels (:func:`swatch.render.environment.levels`), looked up bilinearly
        in each sample's level.
    samples : SampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`).
    table : numpy.ndarray, optional
        :func:`level_table` (computed when None).
    occluded : callable, optional
        ``occluded(rows, directions)``: for the points ``rows`` (a slice) and their sample directions (p, N, 3),
        which the object itself hides (bool (p, N)); those samples are dark (no interreflection). None: nothing
        is hidden (a convex shape).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``E`` (P, N, 3) linear RGB radiance and the bins ``j`` (P,).
    """
    n = np.asarray(n, dtype=np.float32).reshape(-1, 3)
    v = np.asarray(v, dtype=np.float32).reshape(-1, 3)
    if table is None:
        table = level_table(samples, maps)
    P = n.shape[0]
    out = np.empty((P, samples.n, 3), dtype=np.float32)
    j_all = np.empty(P, dtype=np.int32)
    for a in range(0, P, CHUNK):
        sl = slice(a, a + CHUNK)
        cv, t, b = local_frame(n[sl], v[sl])
        j = _bins(samples, cv)
        j_all[sl] = j
        loc = table[j]  # (p, N, 5)
        dirs = [loc[..., 0] * t[:, None, k] + loc[..., 1] * b[:, None, k] + loc[..., 2] * n[sl][:, None, k]
                for k in range(3)]
        out[sl] = maps.bilinear(*dirs, loc[..., 3], loc[..., 4])
        if occluded is not None:
            out[sl] *= ~occluded(sl, np.stack(dirs, -1))[..., None]
    return out, j_all


def combine(E, j, weights) -> np.ndarray:
    """Pixel radiance from gathered samples and one thickness's weights.

    Parameters
    ----------
    E : numpy.ndarray, shape (P, N, 3)
        Gathered environment radiance per shading point and sample (linear RGB).
    j : numpy.ndarray of int, shape (P,)
        Each point's view bin.
    weights : numpy.ndarray, shape (M, N, 3)
        :func:`band_weights`.

    Returns
    -------
    numpy.ndarray of float32, shape (P, 3)
        Reflected radiance, linear RGB (1.0 = a white diffuser facing up under the map).
    """
    out = np.empty((E.shape[0], 3), dtype=np.float32)
    for a in range(0, E.shape[0], CHUNK):
        sl = slice(a, a + CHUNK)
        out[sl] = np.einsum("pnc,pnc->pc", E[sl], weights[j[sl]])
    return out


def shade(n, v, maps, samples: SampleSet, weights) -> np.ndarray:
    """Pixel radiance: :func:`gather` and :func:`combine` chunk by chunk (bounded memory).

    Parameters
    ----------
    n, v : array_like, shape (P, 3)
        Unit normals and views (towards the camera).
    maps : swatch.render.octahedral.LevelMaps
        The environment's blur levels (:func:`swatch.render.environment.levels`).
    samples : SampleSet
        The lobe's fixed samples per view bin (:func:`sample_set`).
    weights : numpy.ndarray, shape (M, N, 3)
        :func:`band_weights` of the thickness.

    Returns
    -------
    numpy.ndarray of float32, shape (P, 3)
        Reflected radiance, linear RGB (1.0 = a white diffuser facing up under the map).
    """
    table = level_table(samples, maps)
    n = np.asarray(n, dtype=np.float32).reshape(-1, 3)
    v = np.asarray(v, dtype=np.float32).reshape(-1, 3)
    out = np.empty((n.shape[0], 3), dtype=np.float32)
    for a in range(0, n.shape[0], CHUNK):
        sl = slice(a, a + CHUNK)
        E, j = gather(n[sl], v[sl], maps, samples, table)
        out[sl] = combine(E, j, weights)
    return out


def shade_reference(n, v, env, roughness_alpha: float, f_table, samples: int = DENSE_SAMPLES,
                    chunk: int = 256) -> np.ndarray:
    """Brute force (the error reference): ``samples`` VNDF samples per pixel at the pixel's own view
    angle, the unfiltered environment map, ``F`` at each sample's ``θ_d``.

    Parameters
    ----------
    n, v : array_like, shape (P, 3)
        Unit normals and views (towards the camera).
    env : swatch.render.environment.Environment
        The environment map, sampled unfiltered.
    roughness_alpha : float
        GGX α, dimensionless.
    f_table : array_like, shape (K, 3)
        ``F``'s linear RGB over cos θ_d in [0, 1].
    samples : int
        Samples per point of the brute-force estimate.
    chunk : int
        Pixels per chunk.

    Returns
    -------
    numpy.ndarray, shape (P, 3)
        Reflected radiance, linear RGB, in the renderer's unit.
    """
    n = np.asarray(n, dtype=np.float64).reshape(-1, 3)
    v = np.asarray(v, dtype=np.float64).reshape(-1, 3)
    u1, u2 = fibonacci_lattice(int(samples))
    pad = env.padded()
    out = np.empty((n.shape[0], 3))
    for a in range(0, n.shape[0], chunk):
        sl = slice(a, a + chunk)
        cv, t, b = local_frame(n[sl], v[sl])
        l, w, cd, _ = _vndf(cv.astype(np.float64), float(roughness_alpha), u1, u2)
        nn = n[sl]
        dirs = [l[..., 0] * t[:, None, k] + l[..., 1] * b[:, None, k] + l[..., 2] * nn[:, None, k] for k in range(3)]
        E = pad.bilinear(*(d.astype(np.float32) for d in dirs)).astype(np.float64)
        out[sl] = np.einsum("pn,pnc,pnc->pc", w / int(samples), _lookup_table(f_table, cd), E)
    return out
