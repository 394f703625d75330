"""Fit each renderer's thin-film parameters to the exact colour of every swatch, vectorised.

For N swatch thicknesses the target is the exact half-vector colour (Airy reflectance of the
film on the substrate at facet angle θ_d, CIELAB under D65 and the CIE 1931 2° observer). The
search compares at :data:`SEARCH_ANGLES_DEG` (0–60° in 10° steps) plus the catalog's own
geometries (weight 2; angles past 45° weigh less, per model: ``_OBJECTIVE``); the errors are then
reported on :data:`FIT_ANGLES_DEG` (0–60° in 5° steps). The parameters of a model are
``(thickness_nm, film_ior, base R, G, B)``; the model's Fresnel factor at cos θ_d (linear Rec.709)
is converted to CIELAB (:func:`swatch.presets.spectral.rgb_to_Lab`) and the residuals are the
per-angle ΔE2000 (raised to a power > 1 for some models, to lean towards the largest error).

Search, all swatches at once: a grid over (thickness offset, film IOR) with the base colour of
bare metal; the best grid point of the best few thickness bands each start a bounded
Levenberg–Marquardt refinement of all five parameters (finite-difference Jacobian, one batched
model call per parameter). Continuity (designers interpolate between neighbours): one solution
per swatch is chosen by a shortest path over the swatches that penalises jumps of thickness
offset and IOR (:func:`_smooth_choice`), then each swatch is re-fitted from its neighbours'
solutions and takes that one when its cost stays within :data:`CONTINUITY_SLACK` and its largest
error at 0–45° within :data:`CONTINUITY_MAX_45`. The models have several equivalent branches
(thickness offset against IOR), so the parameters are continuous in runs with some jumps. The
coupling stays within ``groups`` (the catalog's sheets), so a swatch's preset depends only on
its own sheet's thicknesses.
Bounds keep the parameters plausible: film IOR :data:`FILM_IOR_RANGE`, base colour
:data:`BASE_RANGE`, thickness within :data:`THICKNESS_WINDOW_NM` of the swatch's.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00, get_colorimeter
from swatch.physics.materials import DEFAULT_FILM, DEFAULT_SUBSTRATE, wavelength_grid
from swatch.physics.model import get_coating
from swatch.presets import cycles, gltf, materialx, modelviewer, openpbr, threejs
from swatch.presets.spectral import rgb_to_Lab, rgb_to_xyz_matrix

__all__ = ["MODELS", "FIT_ANGLES_DEG", "FILM_IOR_RANGE", "BASE_RANGE", "THICKNESS_WINDOW_NM", "PresetFit",
           "fit_presets", "model_Lab", "exact_Lab", "errors_delta_E_00"]

FIT_ANGLES_DEG = np.arange(0.0, 60.0 + 1e-9, 5.0)
#: The angles the search evaluates (the errors are then reported on FIT_ANGLES_DEG).
SEARCH_ANGLES_DEG = np.arange(0.0, 60.0 + 1e-9, 10.0)
#: Film IOR bounds (TiO2 is 2.2–2.9 in the visible; renderers accept 1–3).
FILM_IOR_RANGE = (1.5, 3.0)
#: Base colour (linear F0) bounds.
BASE_RANGE = (0.02, 0.98)
#: The model's thickness stays within this distance of the swatch's (nm).
THICKNESS_WINDOW_NM = 120.0
CONTINUITY_SLACK = 1.6
#: A neighbour's solution may not raise a swatch's largest error at 0–45° above this (ΔE2000).
CONTINUITY_MAX_45 = 2.5
NEAR_BEST = 1.3
_STARTS = 4
_GRID_OFFSETS_NM = np.arange(-100.0, 100.0, 4.0)  # 50 offsets = 10 bands of 5
_BAND = 5
_GRID_IOR = np.array([1.8, 2.1, 2.4, 2.7])
_LM_ITERATIONS = 16
_CONTINUITY_ROUNDS = 2
#: Per model: (weight of the angles past 45°, power p of the residual ΔE2000**p). The catalog's
#: geometries weigh 2, the other angles up to 45° weigh 1; p > 1 leans towards the largest errors.
#: glTF cannot follow the exact colour far past 45° (its metal is a real index): it weighs them less.
_OBJECTIVE = {"gltf": (0.2, 1.0), "threejs": (0.2, 1.0), "cycles": (0.5, 1.5), "openpbr": (0.5, 1.5),
              "materialx": (0.2, 1.0), "modelviewer": (0.2, 1.0)}
#: The roughness (glTF ``roughnessFactor``) a model is evaluated at when it depends on it and none is given.
DEFAULT_ROUGHNESS = 0.5477


def _model(name: str):
    plain = {"gltf": gltf.iridescent_fresnel, "cycles": cycles.principled_metal_fresnel,
             "openpbr": openpbr.thin_film_metal_fresnel}
    if name == "threejs":
        return threejs.displayed_fresnel
    if name == "materialx":
        return materialx.displayed_fresnel
    if name == "modelviewer":
        return modelviewer.surround_fresnel
    f = plain[name]
    return lambda c, d, eta, base, roughness: f(c, d, eta, base)


#: Model names (swatch.presets.FORMAT_MODEL maps formats to them). ``threejs`` is what three.js
#: shows of a glTF preset (swatch.presets.threejs); ``gltf`` is the extension as specified; ``modelviewer`` is
#: what <model-viewer> shows in an even white surround (swatch.presets.modelviewer).
MODELS = ("gltf", "threejs", "cycles", "openpbr", "materialx", "modelviewer")


def model_Lab(model: str, params, angles_deg, roughness: float | None = None) -> np.ndarray:
    """CIELAB (D65, 2°) of ``model`` with ``params`` (..., 5) at angles (A,): (..., A, 3).

    The angle is the facet angle (the model's cos θ argument; N·V for ``threejs``, which is the
    facet angle at mirror geometries). ``roughness``: the glTF roughnessFactor (``threejs`` only).

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.
    params : array_like, shape (..., 5)
        ``(thickness_nm, film_ior, base R, G, B)`` (base linear Rec.709).
    angles_deg : array_like, shape (A,)
        Facet angles, degrees.
    roughness : float, optional
        glTF ``roughnessFactor`` (``threejs`` only).

    Returns
    -------
    numpy.ndarray, shape (..., A, 3)
        CIELAB, D65, CIE 1931 2°.
    """

    p = np.asarray(params, dtype=np.float64)
    c = np.cos(np.radians(np.asarray(angles_deg, dtype=np.float64)))
    rough = DEFAULT_ROUGHNESS if roughness is None else float(roughness)
    F = _model(model)(c, p[..., 0:1], p[..., 1:2], p[..., None, 2:5], rough)
    return rgb_to_Lab(F)


def exact_Lab(thickness_nm, angles_deg, film: str | None = None, substrate: str | None = None,
              film_index_scale: float = 1.0, spread=None) -> np.ndarray:
    """The exact colour (N, A, 3): Airy reflectance at facet angle θ_d, CIELAB under D65, 2°
    (``film_index_scale``: a process profile's scale of the film's real index; ``spread``: its
    :class:`swatch.physics.spread.ThicknessSpread`, the colour averaged over it).

    Parameters
    ----------
    thickness_nm : array_like, shape (N,)
        Film thicknesses, nm.
    angles_deg : array_like, shape (A,)
        Facet angles θ_d, degrees.
    film, substrate : str, optional
        Table names (default TiO2 on Ti).
    film_index_scale : float, optional
        Factor on the film's real refractive index (a process profile's; default 1, the table as it is).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread (σ in nm and as a fraction); the colour is averaged over it. None: uniform.

    Returns
    -------
    numpy.ndarray, shape (N, A, 3)
        CIELAB, D65, CIE 1931 2°.
    """

    wl = wavelength_grid(380.0, 780.0, 5.0)
    coating = get_coating(film or DEFAULT_FILM, substrate or DEFAULT_SUBSTRATE, wl, film_index_scale, spread)
    cm = get_colorimeter(wl, "D65", "2")
    d = np.atleast_1d(np.asarray(thickness_nm, dtype=np.float64))
    R = coating.reflectance(d[:, None], np.asarray(angles_deg, dtype=np.float64)[None, :]).R
    return cm.Lab(cm.XYZ(R))


def errors_delta_E_00(model: str, params, thickness_nm, angles_deg=FIT_ANGLES_DEG, film=None,
                      substrate=None, film_index_scale: float = 1.0, spread=None, roughness: float | None = None,
                      model_angles_deg=None) -> np.ndarray:
    """ΔE2000 (N, A) between ``model`` with ``params`` (N, 5) and the exact colour at facet angles
    ``angles_deg``; the model is evaluated at ``model_angles_deg`` (default the same angles: mirror
    geometries; e.g. 0 for three.js at 45:0, whose N·V is 0° where the facet angle is 22.5°).

    Parameters
    ----------
    model : str
        The renderer's model, one of :data:`MODELS`.
    params : array_like, shape (N, 5)
        Each swatch's preset ``(thickness_nm, film_ior, base R, G, B)`` (base linear Rec.709), as :func:`model_Lab`.
    thickness_nm : array_like, shape (N,)
        The swatches' thicknesses, nm.
    angles_deg : array_like, shape (A,), optional
        Facet angles of the exact colour, degrees.
    film, substrate, film_index_scale, spread
        As :func:`exact_Lab`.
    roughness : float, optional
        As :func:`model_Lab`.
    model_angles_deg : array_like, shape (A,), optional
        Where the model is evaluated, degrees.

    Returns
    -------
    numpy.ndarray, shape (N, A)
        ΔE2000 (``swatch.colorimetry.colorimeter.delta_E_00``, i.e. colour-science's CIEDE2000).
    """

    at = angles_deg if model_angles_deg is None else model_angles_deg
    return delta_E_00(model_Lab(model, params, at, roughness),
                      exact_Lab(thickness_nm, angles_deg, film, substrate, film_index_scale, spread))


@dataclass
class PresetFit:
    """Fitted parameters of one model for N swatches, and their errors against the exact colour.

    Attributes
    ----------
    model : str
        The renderer's model (:data:`MODELS`).
    thickness_nm : numpy.ndarray
        The swatches' thicknesses, nm, shape (N,).
    params : numpy.ndarray
        Model thickness (nm), film IOR, base colour linear RGB, shape (N, 5).
    angles_deg : numpy.ndarray
        Facet angles of the errors, degrees, shape (A,).
    delta_E_00 : numpy.ndarray
        ΔE2000 against the exact colour, shape (N, A).
    """

    model: str
    thickness_nm: np.ndarray  # (N,) the swatches'
    params: np.ndarray  # (N, 5): model thickness (nm), film IOR, base colour linear RGB
    angles_deg: np.ndarray  # (A,)
    delta_E_00: np.ndarray  # (N, A)

    def max_delta_E_00(self, up_to_deg: float = 60.0) -> np.ndarray:
        """Each swatch's largest error up to a facet angle.

        Parameters
        ----------
        up_to_deg : float, optional
            The largest facet angle counted, degrees.

        Returns
        -------
        numpy.ndarray, shape (N,)
            ΔE2000.
        """
        return self.delta_E_00[:, self.angles_deg <= up_to_deg + 1e-9].max(axis=1)


def _bounds(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = d.size
    lo = np.column_stack([np.maximum(d - THICKNESS_WINDOW_NM, 0.0), np.full(n, FILM_IOR_RANGE[0]),
                          np.full((n, 3), BASE_RANGE[0])])
    hi = np.column_stack([d + THICKNESS_WINDOW_NM, np.full(n, FILM_IOR_RANGE[1]), np.full((n, 3), BASE_RANGE[1])])
    return lo, hi


def _bare_metal_rgb(substrate: str | None) -> np.ndarray:
    """Linear Rec.709 F0 of the bare substrate (D65, 2°): the starting base colour."""

    wl = wavelength_grid(380.0, 780.0, 5.0)
    coating = get_coating(DEFAULT_FILM, substrate or DEFAULT_SUBSTRATE, wl)
    cm = get_colorimeter(wl, "D65", "2")
    XYZ = cm.XYZ(coating.reflectance(np.array([0.0]), np.array([0.0])).R)[0] / 100.0
    return np.clip(np.linalg.solve(rgb_to_xyz_matrix()[0], XYZ), *BASE_RANGE)


class _Problem:
    def __init__(self, model, target_Lab, weights, angles_deg, power: float = 1.0, model_angles_deg=None,
                 roughness: float | None = None):
        self.model, self.target, self.w, self.angles = model, target_Lab, np.sqrt(weights), angles_deg
        self.model_angles = angles_deg if model_angles_deg is None else model_angles_deg
        self.power, self.roughness = power, roughness
        self._dE = delta_E_00

    def max_45(self, residuals) -> np.ndarray:
        """Largest ΔE2000 at the angles up to 45° from residuals of :meth:`residuals`."""
        dE = (residuals / self.w) ** (1.0 / self.power)
        return dE[:, self.angles <= 45.0].max(axis=1)

    def residuals(self, p, rows):
        """Weighted ΔE2000**power (len(rows), A) for parameter rows p matched to swatch ``rows``."""
        return self._dE(model_Lab(self.model, p, self.model_angles, self.roughness),
                        self.target[rows]) ** self.power * self.w


def _levenberg_marquardt(prob: _Problem, p0, rows, lo, hi, iterations: int = _LM_ITERATIONS):
    """Bounded LM on many independent problems at once; returns (params, cost, residuals).

    Each iteration evaluates the trial point and its forward-difference Jacobian in ONE call of the
    residuals (n (k + 1) rows): a rejected trial leaves the point, and so its Jacobian, as they were, so
    nothing is recomputed for it. The same rows as evaluating the Jacobian at the start of each iteration and
    the trial after, in half the calls (each a fixed overhead of colour-science's CIEDE2000 and the models'
    array set-up, which dominated small catalogs' builds: 0.9 of 1.9 CPU-s for three swatches)."""
    n, k = p0.shape
    step = np.array([0.5, 0.005, 0.002, 0.002, 0.002])
    eye = np.eye(k)
    srows = np.repeat(rows, k + 1)

    def point_and_jacobian(p):
        pp = np.concatenate([p[:, None, :], p[:, None, :] + step[None, :, None] * eye[None]], axis=1)
        both = prob.residuals(pp.reshape(n * (k + 1), k), srows).reshape(n, k + 1, -1)
        r = both[:, 0]
        return r, (both[:, 1:] - r[:, None, :]) / step[None, :, None]

    p = np.clip(p0, lo, hi)
    r, J = point_and_jacobian(p)
    cost = (r ** 2).sum(axis=1)
    lam = np.full(n, 1e-2)
    for _ in range(iterations):  # iterations of the solver, each vectorised over all swatches
        JtJ = np.einsum("npm,nqm->npq", J, J)
        g = np.einsum("npm,nm->np", J, r)
        diag = np.einsum("npp->np", JtJ) + 1e-9
        A = JtJ + lam[:, None, None] * (diag[:, :, None] * eye[None])
        delta = -np.linalg.solve(A, g[..., None])[..., 0]
        pn = np.clip(p + delta, lo, hi)
        rn, Jn = point_and_jacobian(pn)
        cn = (rn ** 2).sum(axis=1)
        better = cn < cost
        p = np.where(better[:, None], pn, p)
        r = np.where(better[:, None], rn, r)
        J = np.where(better[:, None, None], Jn, J)
        cost = np.where(better, cn, cost)
        lam = np.clip(np.where(better, lam * 0.3, lam * 8.0), 1e-7, 1e7)
    return p, cost, r


def _smooth_choice(d, ps, cs, ms, groups) -> np.ndarray:
    """Index (N,) of one candidate per swatch: a Viterbi path over the swatches sorted by thickness.

    Node cost 3·ln(cost / best cost); a candidate whose largest error at 0–45° exceeds both the
    swatch's best and :data:`CONTINUITY_MAX_45` is excluded. Edge cost between neighbours: the
    squared change of thickness offset (per 20 nm) plus film IOR (per 0.15), capped at 4.
    """
    n, k = cs.shape
    best = cs.min(axis=1, keepdims=True)
    node = 3.0 * np.log(np.maximum(cs, 1e-12) / np.maximum(best, 1e-12))
    allowed = (ms <= np.maximum(ms[np.arange(n), cs.argmin(axis=1)][:, None], CONTINUITY_MAX_45)) | (cs == best)
    node = np.where(allowed & (cs <= best * NEAR_BEST * 2.0), node, np.inf)
    offset = ps[..., 0] - d[:, None]
    pick = np.empty(n, dtype=np.int64)
    back = np.zeros((n, k), dtype=np.int64)
    for g in np.unique(groups):  # one path per group of swatches
        order = np.flatnonzero(groups == g)
        order = order[np.argsort(d[order], kind="stable")]
        total = node[order[0]].copy()
        for a, b in itertools.pairwise(order):  # the path's steps: one per neighbouring pair
            edge = np.minimum(((offset[b][None, :] - offset[a][:, None]) / 20.0) ** 2
                              + ((ps[b, :, 1][None, :] - ps[a, :, 1][:, None]) / 0.15) ** 2, 4.0)
            through = total[:, None] + edge  # (from k, to k)
            back[b] = through.argmin(axis=0)
            total = through.min(axis=0) + node[b]
        pick[order[-1]] = int(total.argmin())
        for a, b in zip(order[::-1][1:], order[::-1][:-1], strict=True):
            pick[a] = back[b, pick[b]]
    return pick


def fit_presets(thickness_nm, model: str, extra_angles_deg=(), film: str | None = None,
                substrate: str | None = None, film_index_scale: float = 1.0, groups=None, spread=None,
                roughness: float | None = None, extra_model_angles_deg=None) -> PresetFit:
    """Fit ``model``'s parameters for every thickness (sorted or not); see the module docstring.

    ``film_index_scale``: a process profile's scale of the film's real index (the exact colour);
    ``spread``: its thickness spread (:class:`swatch.physics.spread.ThicknessSpread`; the exact colour averaged over it).
    ``extra_angles_deg``: the catalog's geometries as facet angles (weight 2), at which the model is
    evaluated at ``extra_model_angles_deg`` (same length; default the same angles). ``roughness``:
    the glTF roughnessFactor (models that depend on it: ``threejs``).

    ``groups`` (N,) confines the continuity coupling: a swatch's preset depends only on the
    thicknesses of its own group (the catalog passes its sheets, so that changing one swatch
    leaves the other sheets' presets, and so the sheets, as they were).

    Parameters
    ----------
    thickness_nm : array_like, shape (N,)
        The swatches' thicknesses, nm.
    model : str
        One of :data:`MODELS`.
    extra_angles_deg : sequence of float, optional
        The catalog's geometries as facet angles, degrees.
    film, substrate : str, optional
        Film and substrate table names (default TiO2 on Ti), as :func:`exact_Lab`.
    film_index_scale : float, optional
        Factor on the film's real refractive index for the exact colour (default 1).
    groups : array_like, shape (N,), optional
        Integer group of each swatch (the catalog's sheet); continuity couples swatches of one group only.
        None: one group.
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread the exact colour is averaged over; None: uniform.
    roughness : float, optional
        The glTF ``roughnessFactor`` (0–1) the ``threejs`` model is evaluated with; other models ignore it.
    extra_model_angles_deg : sequence of float, optional
        Where the model is evaluated for each of ``extra_angles_deg``, degrees (same length; default the same angles).

    Returns
    -------
    PresetFit
        Errors on :data:`FIT_ANGLES_DEG`.
    """
    d = np.atleast_1d(np.asarray(thickness_nm, dtype=np.float64))
    groups = np.zeros(d.size, dtype=np.int64) if groups is None else np.asarray(groups, dtype=np.int64)
    extra_model = extra_angles_deg if extra_model_angles_deg is None else extra_model_angles_deg
    pairs = sorted({(float(a), float(b)) for a, b in zip(extra_angles_deg, extra_model, strict=True)
                    if 0.0 <= a <= 60.0})
    extra = np.array([a for a, _ in pairs], dtype=np.float64)
    angles = np.concatenate([SEARCH_ANGLES_DEG, extra])
    model_angles = np.concatenate([SEARCH_ANGLES_DEG, np.array([b for _, b in pairs], dtype=np.float64)])
    beyond_45, power = _OBJECTIVE[model]
    weights = np.concatenate([np.where(SEARCH_ANGLES_DEG <= 45.0, 1.0, beyond_45), np.full(extra.size, 2.0)])
    target = exact_Lab(d, angles, film, substrate, film_index_scale, spread)
    prob = _Problem(model, target, weights, angles, power, model_angles, roughness)
    n = d.size
    rows = np.arange(n)
    lo, hi = _bounds(d)
    # 1. grid over (thickness offset, film IOR), base colour = bare metal; the best point of each
    #    thickness band starts a refinement (multi-start: the cost has many local minima)
    base = _bare_metal_rgb(substrate)
    off, eta = np.meshgrid(_GRID_OFFSETS_NM, _GRID_IOR, indexing="ij")
    g = off.size
    cand = np.empty((n, g, 5))
    cand[..., 0] = d[:, None] + off.ravel()[None, :]
    cand[..., 1] = eta.ravel()[None, :]
    cand[..., 2:] = base
    cand = np.clip(cand, lo[:, None, :], hi[:, None, :])
    cost = (prob.residuals(cand.reshape(n * g, 5), np.repeat(rows, g)).reshape(n, g, -1) ** 2).sum(axis=2)
    bands = cost.reshape(n, -1, _BAND * _GRID_IOR.size)  # (n, bands, candidates in a band)
    best_in_band = bands.argmin(axis=2) + np.arange(bands.shape[1])[None, :] * bands.shape[2]
    band_cost = np.take_along_axis(cost, best_in_band, axis=1)
    top = np.take_along_axis(best_in_band, np.argsort(band_cost, axis=1)[:, :_STARTS], axis=1)
    starts = cand[rows[:, None], top].reshape(-1, 5)  # (n * _STARTS, 5)
    srows = np.repeat(rows, _STARTS)
    # 2. refine everything from every start, keep the best per swatch
    ps, cs, rs = _levenberg_marquardt(prob, starts, srows, lo[srows], hi[srows])
    cs = cs.reshape(n, -1)
    ps = ps.reshape(n, -1, 5)
    ms = prob.max_45(rs).reshape(n, -1)
    #    choose one solution per swatch so that neighbours agree (a shortest path over the
    #    swatches in thickness order), among the solutions close to each swatch's best
    pick = _smooth_choice(d, ps, cs, ms, groups)
    p = ps[rows, pick]
    cost = cs[rows, pick]
    worst = ms[rows, pick]
    # 3. continuity: re-fit from the neighbours' solutions, keep when as good
    order = np.lexsort((d, groups))  # by group, then thickness
    same = groups[order][1:] == groups[order][:-1]
    for _ in range(_CONTINUITY_ROUNDS):
        for i, j in ((order[1:][same], order[:-1][same]), (order[:-1][same], order[1:][same])):
            if i.size == 0:
                continue
            warm = p[j].copy()
            warm[:, 0] += d[i] - d[j]
            pw, cw, rw = _levenberg_marquardt(prob, warm, i, lo[i], hi[i], iterations=_LM_ITERATIONS // 2)
            ww = prob.max_45(rw)
            take = (cw <= cost[i] * CONTINUITY_SLACK) & (ww <= np.maximum(worst[i], CONTINUITY_MAX_45))
            p[i[take]] = pw[take]
            cost[i[take]] = cw[take]
            worst[i[take]] = ww[take]
    report = FIT_ANGLES_DEG
    return PresetFit(model, d, p, report, errors_delta_E_00(model, p, d, report, film, substrate, film_index_scale,
                                                            spread, roughness))
