"""The explorer's environment lighting: what the page needs to integrate the thin-film BRDF over
an environment, computed by the engine (:mod:`swatch.render.builtin.env_shading`, :mod:`swatch.render.environment`).

The page's live view under ``studio`` or ``uniform`` is the method of
:mod:`swatch.render.builtin.env_shading` ported to WebGL: per pixel a fixed set of GGX visible-normal samples
(``SAMPLES`` per view bin, the renderer's own set), the environment blurred per sample
(octahedral maps, the renderer's blur levels), ``F`` at every sample's own ``θ_d`` from the
explorer's colour table and the per-bin, per-channel level ``c = A / Σ w F`` with the dense
directional albedo ``A = H F`` (``H``: the renderer's dense sample set spread onto the table's
``cos θ_d`` nodes, :func:`swatch.render.builtin.env_shading.directional_albedo`). The browser re-implements none
of it: it reads the samples, ``H`` and the maps from here and only multiplies and adds.

**The page's split (so that a thickness change is one cheap pass).** The radiance of a pixel in
view bin ``j`` is ``Σ_i w_i (F(x_i) + δ_j) E_i`` (``x_i = cos θ_d`` of sample ``i``, ``E_i`` the
environment in its direction, ``δ_j`` the level correction of
:func:`swatch.render.builtin.env_shading.band_weights`). The environment part does not depend on the thickness, ``F`` only
through ``x_i``, which is fixed per bin. ``F`` is replaced by its weighted least-squares
projection onto polynomials of degree ``BASIS − 1`` in ``x`` over the bin's samples (weights
``w_i``; orthonormal basis ``q_k`` from a QR factorisation per bin, embedded as ``u_ik = w_i
q_k(x_i)``), so

    radiance ≈ Σ_k (p_jk + δ_j s_jk) M_k,   M_k = Σ_i u_ik E_i (per pixel),   p_jk = Σ_i u_ik F(x_i),
    s_jk = Σ_i u_ik (per bin; Σ_i w_i E_i = Σ_k s_jk M_k exactly, the constants lying in the basis).

The page stores the ``BASIS`` moments ``M_k`` per pixel when the view, the shape or the lighting
changes (one pass over the samples) and, per thickness, computes ``p_jk + δ_j s_jk`` for the 256 bins
in JavaScript (a few thousand products) and shades every pixel with ``BASIS`` products. Constant
functions lie in the basis, so a uniform environment gives exactly the directional albedo (the
furnace test holds as in the renderer). Measured against the renderer's per-sample sum on 4 000
random normal/view pairs in the studio, 20–300 nm (``tests/catalog/test_catalog_explorer_env.py``):
ΔE2000 max 0.16 with ``BASIS = 4`` in the first (bright-walled) studio (α = 0.3; 0.62 with 3, 0.06
with 5); see docs/catalog.md for the figures in the present one.

**Frames.** The page's world has the plate's normal along +z and its camera azimuth 180° at the
renderer's azimuth 0 (the +z side of :mod:`swatch.render.scene`); a page direction ``(x, y, z)`` is the
environment direction ``(−y, z, −x)`` (a rotation), so the studio's soft boxes sit where they
sit in ``swatch render``.

**Encodings** (base64, little-endian): sample directions as int16 (``code / 32767``, angle
error < 4e-5 rad), ``cos θ_d`` and ``w`` as uint16 with a per-channel scale (< 1e-3 / 65 of
their maximum), ``u`` as int16 with a per-channel scale, ``H`` as uint16 with a per-column
scale, levels as uint8, maps as IEEE half floats (relative error < 4.9e-4; the page uploads them
as they are). Only neutral (grey) environments are embedded (the built-ins are): one channel.
"""
from __future__ import annotations

import base64
import hashlib
import json
from importlib import metadata
from pathlib import Path

import numpy as np

from swatch.catalog.explorer_set import set_geometry
from swatch.catalog.folder import read_cache_json, remove_tree
from swatch.core.choices import lightings_of
from swatch.core.errors import SwatchError
from swatch.core.fileio import atomic_write_text
from swatch.core.sources import code_hash
from swatch.render.builtin import env_shading
from swatch.render.environment import LEVELS, get_environment, levels

__all__ = ["BASIS", "PAGE_LIGHTINGS", "FORMAT", "environment_data", "environment_data_cached", "decode_block",
           "moment_weights"]

#: Polynomial degree + 1 of the per-bin projection of F (module doc).
BASIS = 4
FORMAT = "swatch-explorer-environment"
#: The live view's lightings: the built-in engine's (:data:`swatch.core.choices.LIGHTINGS`), the point light first.
PAGE_LIGHTINGS = lightings_of("builtin")
_VERSION = 1


# -- encodings ------------------------------------------------------------------------------
def _b64(a: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(a).tobytes()).decode("ascii")


def _block(values, kind: str) -> dict:
    """One array as a block: ``int16`` / ``uint16`` codes with a per-channel (last axis) scale,
    ``uint8`` integers or ``float16`` bits."""
    v = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(v)):
        raise SwatchError("explorer environment: values must be finite")
    out: dict = {"type": kind, "shape": list(v.shape)}
    if kind == "uint8":
        out["data"] = _b64(v.astype(np.uint8))
        return out
    if kind == "float16":
        out["data"] = _b64(v.astype("<f2"))
        return out
    top = np.abs(v.reshape(-1, v.shape[-1])).max(axis=0)
    full = 32767.0 if kind == "int16" else 65535.0
    scale = np.where(top > 0, top / full, 1.0)
    codes = np.round(v / scale)
    out["scale"] = [float(s) for s in scale]
    out["data"] = _b64(codes.astype("<i2" if kind == "int16" else "<u2"))
    return out


def decode_block(block: dict) -> np.ndarray:
    """The values of an embedded block (the page's decoder, in Python for tests and the cache check).

    Parameters
    ----------
    block : dict
        ``{"type": "int16" | "uint16" | "uint8" | "float16", "shape", "data"`` (base64) and, for the
        16-bit integer types, ``"scale"`` (one factor per channel of the last axis)``}``.

    Returns
    -------
    numpy.ndarray of float64, shape ``block["shape"]``
        ``code × scale`` (integer types) or the half floats' values, in the block's own units.
    """
    kind = block["type"]
    dtype = {"int16": "<i2", "uint16": "<u2", "uint8": "u1", "float16": "<f2"}[kind]
    a = np.frombuffer(base64.b64decode(block["data"], validate=True), dtype=dtype).astype(np.float64)
    a = a.reshape([int(s) for s in block["shape"]])
    if "scale" in block:
        a = a * np.asarray(block["scale"], dtype=np.float64)
    return a


# -- the sample set and its projection ---------------------------------------------------------
def moment_weights(cos_d: np.ndarray, w: np.ndarray, basis: int = BASIS) -> np.ndarray:
    """The weights of the per-bin projection of F (module doc).

    ``Σ_k (Σ_i u_ik F_i)(Σ_i u_ik E_i)`` is ``Σ_i w_i P(x_i) E_i`` with ``P`` the weighted
    least-squares projection of ``F`` on polynomials of degree < ``basis`` in ``x`` (``cos θ_d``
    mapped to [−1, 1] over each bin's samples).

    Parameters
    ----------
    cos_d : array_like, shape (M, N)
        ``cos θ_d`` of each bin's samples (dimensionless).
    w : array_like, shape (M, N)
        The samples' weights ``G2/G1 / N`` (≥ 0, dimensionless).
    basis : int
        Number of polynomials (degree + 1).

    Returns
    -------
    numpy.ndarray, shape (M, N, basis)
        ``u_ik = w_i q_k(x_i)``, ``q_k`` orthonormal under the weights ``w`` (QR per bin).
    """
    cd = np.asarray(cos_d, dtype=np.float64)
    wt = np.asarray(w, dtype=np.float64)
    lo = cd.min(axis=1, keepdims=True)
    span = np.maximum(cd.max(axis=1, keepdims=True) - lo, 1e-9)
    x = 2.0 * (cd - lo) / span - 1.0
    sw = np.sqrt(np.maximum(wt, 0.0))
    A = sw[..., None] * x[..., None] ** np.arange(basis)  # (M, N, K)
    Q, _ = np.linalg.qr(A)
    return sw[..., None] * Q


def _sample_levels(roughness_alpha: float, maps) -> np.ndarray:
    """The blur level of every sample of the renderer's set at ``roughness_alpha`` (an index into LEVELS)."""
    return maps.level_for(env_shading.sample_set(roughness_alpha).sigma_deg)


def _sample_blocks(roughness_alpha: float, maps, cos_nodes: int, used: list[int]) -> dict:
    ss = env_shading.sample_set(roughness_alpha)
    level = maps.level_for(ss.sigma_deg)  # (M, N) index into the environment's LEVELS
    local = np.searchsorted(np.asarray(used), level)  # index into the embedded levels
    u = moment_weights(ss.cos_d, ss.w)
    H = env_shading.albedo_matrix(ss, int(cos_nodes))  # (M, K): albedo = H @ F table
    return {
        "bins": int(ss.bins), "samples": int(ss.n), "basis": BASIS, "roughness": float(roughness_alpha),
        "bin_rule": "bins uniform in theta_v over [0, 90] deg; bin j = bins - 1 - floor(theta_v / (90 deg / bins)) "
                    "(increasing cos theta_v)",
        "directions": _block(ss.l.astype(np.float64), "int16"),
        "level": _block(local, "uint8"),
        "cos_theta_d": _block(ss.cos_d[..., None], "uint16"),
        "weight": _block(ss.w[..., None], "uint16"),
        "moment_weights": _block(u, "int16"),
        "albedo_matrix": _block(H, "uint16"),
        "cos_theta_d_nodes": int(cos_nodes),
    }


def _environment_block(env, used: list[int]) -> dict:
    """The environment's blur levels ``used`` as one half-float atlas (padded maps side by side)."""

    maps = levels(env)
    rad = env.radiance.reshape(-1, 3)
    if not np.all(rad == rad[:, :1]):
        raise SwatchError(f"environment {env.name!r} is not neutral; the explorer embeds grey environments only")
    parts, meta, x0 = [], [], 0
    for k in used:
        n = int(maps.res[k])
        off = int(maps.offset[k])
        flat = maps.flat[off:off + (n + 2) ** 2].view(np.float32).reshape(n + 2, n + 2, 4)
        parts.append(flat[..., 0])
        meta.append({"sigma_deg": float(LEVELS[k][0]), "res": n, "x0": x0})
        x0 += n + 2
    height = max(p.shape[0] for p in parts)
    atlas = np.zeros((height, x0), dtype=np.float32)
    for p, m in zip(parts, meta, strict=True):
        atlas[:p.shape[0], m["x0"]:m["x0"] + p.shape[1]] = p
    return {"name": env.name, "description": env.description, "levels": meta, "atlas": _block(atlas, "float16")}


def environment_data(roughness_alpha: float, cos_nodes: int, studio: tuple | None = None,
                     finishes: dict[str, float] | None = None) -> dict:
    """The JSON block the page reads for its environment lighting (module doc).

    Parameters
    ----------
    roughness_alpha : float
        GGX ``α`` of the catalog's renders (in (0, 1]).
    cos_nodes : int
        Nodes of the colour table's uniform ``cos θ_d`` axis on [0, 1]
        (:data:`swatch.catalog.explorer.COS_NODES`): the albedo matrix maps the table's row to the
        directional albedo per view bin.
    studio : tuple, optional
        :func:`swatch.catalog.explorer_set.baked_set`'s result: the heroes' studio set baked around each shape
        (embedded as ``set``: its geometry, per shape the lightmaps and the set seen from the object as an
        environment); None: the built-in studio alone.
    finishes : dict, optional
        The catalog's offered finishes and their GGX ``α`` (the first is ``roughness_alpha``'s): a sample set per
        finish (``finish_samples``), so the page's live view changes finish without a rebuild.

    Returns
    -------
    dict
        ``samples`` (bins, samples, basis, the encoded sample set, projection weights and albedo
        matrix), ``environments`` (per built-in environment its blur levels and half-float
        atlas, radiance with 1 = a white diffuser facing the normal reflects 1) and, with ``studio``, ``set``,
        JSON-ready.
    """

    envs = {}
    for name in PAGE_LIGHTINGS[1:]:
        env = get_environment(name)
        assert env is not None, "PAGE_LIGHTINGS[1:] are environments"
        envs[name] = env
    # the blur level of a sample depends on its footprint only, not on the map: any environment gives it; the levels
    # embedded are those any finish's samples use
    maps = levels(next(iter(envs.values())))
    alphas = [float(roughness_alpha)] + [float(a) for a in (finishes or {}).values()]
    used = sorted({int(k) for a in alphas for k in np.unique(_sample_levels(a, maps))})
    samples = _sample_blocks(roughness_alpha, maps, cos_nodes, used)
    doc = {
        "format": FORMAT, "format_version": _VERSION,
        "method": "GGX visible-normal samples per view bin (swatch.render.builtin.env_shading), F at each sample's theta_d from the "
                  "colour table, per-sample blurred environment, level fixed by the dense directional albedo; F "
                  f"projected per bin on polynomials of degree {BASIS - 1} (weighted least squares)",
        "frame": "page direction (x, y, z) -> environment direction (-y, z, -x); the environment's +y is the plate's "
                 "normal",
        "units": "radiance; 1 = white diffuser facing the normal under the same environment (exposure 1)",
        "lightings": list(PAGE_LIGHTINGS),
        "samples": samples,
        "environments": {name: _environment_block(env, used) for name, env in envs.items()},
    }
    if finishes:
        doc["finish_samples"] = {name: samples if float(a) == float(roughness_alpha) else
                                 _sample_blocks(float(a), maps, cos_nodes, used) for name, a in finishes.items()}
    if studio is not None:
        shapes, set_envs = studio
        doc["set"] = set_geometry() | {"shapes": {
            name: {"floor_y": v["floor_y"], "scale": v["scale"], "texels": v["texels"],
                   "shadow": _block(v["shadow"], "float16"), "bounce": _block(v["bounce"], "float16"),
                   "environment": _environment_block(set_envs[name], used)} for name, v in shapes.items()}}
    return doc


# -- the build cache ---------------------------------------------------------------------------
def _key(roughness_alpha: float, cos_nodes: int, studio: tuple | None, finishes: dict[str, float] | None) -> str:
    code = code_hash(__name__)  # this module and every module it imports
    bakes = None if studio is None else {
        name: hashlib.sha256(v["shadow"].tobytes() + v["bounce"].tobytes() + repr((v["scale"], v["floor_y"])).encode()).hexdigest()
        for name, v in studio[0].items()}
    blob = {"alpha": float(roughness_alpha), "nodes": int(cos_nodes), "code": code,
            "numpy": metadata.version("numpy"), "set": bakes, "finishes": finishes}
    return hashlib.sha256(json.dumps(blob, sort_keys=True).encode()).hexdigest()[:32]


def _atlas_ok(e: dict, n_levels: int) -> bool:
    atlas = decode_block(e["atlas"])
    if atlas.ndim != 2 or len(e["levels"]) != n_levels or not np.all(np.isfinite(atlas)):
        return False
    for lv in e["levels"]:
        x0, res = lv["x0"], lv["res"]
        if not (isinstance(x0, int) and isinstance(res, int) and x0 >= 0 and res >= 1):
            return False
        if x0 + res + 2 > atlas.shape[1] or res + 2 > atlas.shape[0]:
            return False
    return True


def _samples_ok(s: dict) -> bool:
    m, n = int(s["bins"]), int(s["samples"])
    want = {"directions": (m, n, 3), "level": (m, n), "cos_theta_d": (m, n, 1), "weight": (m, n, 1),
            "moment_weights": (m, n, BASIS), "albedo_matrix": (m, int(s["cos_theta_d_nodes"]))}
    for name, shape in want.items():
        a = decode_block(s[name])
        if a.shape != shape or not np.all(np.isfinite(a)):
            return False
    return True


def _valid(doc, shapes: set[str] | None, finishes: list[str]) -> bool:
    """Whether a cached document (untrusted: read back from the catalog folder) is well formed, with the set
    baked around ``shapes`` (None: no set)."""
    try:
        if doc["format"] != FORMAT or doc["format_version"] != _VERSION or doc["lightings"] != list(PAGE_LIGHTINGS):
            return False
        s = doc["samples"]
        if not _samples_ok(s) or list(doc.get("finish_samples", {})) != finishes:
            return False
        if not all(_samples_ok(f) for f in doc.get("finish_samples", {}).values()):
            return False
        n_levels = len(doc["environments"][PAGE_LIGHTINGS[1]]["levels"])
        if any(int(decode_block(f["level"]).max()) >= n_levels for f in [s, *doc.get("finish_samples", {}).values()]):
            return False
        if not all(_atlas_ok(e, n_levels) for e in doc["environments"].values()):
            return False
        if ("set" in doc) != (shapes is not None):
            return False
        if shapes is not None:
            baked = doc["set"]["shapes"]
            if set(baked) != shapes:
                return False
            for v in baked.values():
                nx, ns = (int(t) for t in v["texels"])
                if not _atlas_ok(v["environment"], n_levels):
                    return False
                for k in ("shadow", "bounce"):
                    a = decode_block(v[k])
                    if a.shape != (ns, nx) or not np.all(np.isfinite(a)):
                        return False
        return set(doc["environments"]) == set(PAGE_LIGHTINGS[1:])
    except (KeyError, TypeError, ValueError):
        return False


def environment_data_cached(roughness_alpha: float, cos_nodes: int, cache: Path | None, studio: tuple | None = None,
                            finishes: dict[str, float] | None = None) -> dict:
    """:func:`environment_data`, from the build cache when it holds a well-formed entry.

    Parameters
    ----------
    roughness_alpha, cos_nodes, studio, finishes
        As :func:`environment_data`.
    cache : pathlib.Path or None
        The catalog's cache folder (``explorer-env-<key>.json``, the key a hash of the inputs,
        the code it depends on and numpy's version); None computes without caching.

    Returns
    -------
    dict
        The same document as :func:`environment_data` (read back with its key order, so the page
        is byte-identical whether computed or cached). An entry that does not decode to the
        expected shapes (the folder is untrusted) is recomputed and replaced.
    """

    if cache is None:
        return environment_data(roughness_alpha, cos_nodes, studio, finishes)
    path = cache / f"explorer-env-{_key(roughness_alpha, cos_nodes, studio, finishes)}.json"
    doc = read_cache_json(path)
    if doc is not None and _valid(doc, None if studio is None else set(studio[0]), list(finishes or ())):
        return doc
    doc = environment_data(roughness_alpha, cos_nodes, studio, finishes)

    for stale in cache.glob("explorer-env-*.json"):
        remove_tree(stale)
    atomic_write_text(path, json.dumps(doc, separators=(",", ":")))  # key order kept: the page is byte-identical
    return doc
