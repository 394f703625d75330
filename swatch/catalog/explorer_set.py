"""The live view's studio: the path tracer's set (the heroes' studio) baked for the page.

The heroes are path-traced in a photo studio (:mod:`swatch.render.studio_set`: a grey cyclorama, three soft
boxes, a dim fill). So that turning the part on the page keeps the look of that picture, the page draws the
same set: the build bakes the cyclorama's radiance around each shape the page shows, with the object's shadow
and the light it throws onto the floor (:func:`swatch.render.dispatch.studio_lightmap`, Mitsuba), and embeds

* the set's geometry (cyclorama profile, soft boxes, fill) and per shape the floor's height, the render's
  radiance scale and the two lightmaps (``shadow``: the set with a black object; ``bounce``: what a white metal
  object adds, which the page multiplies by the film's albedo), as half floats: the page's backdrop, floor,
  horizon and contact shadow are a ray through each pixel onto the cyclorama and a lookup;
* per shape the set seen from the object's centre as an environment (:func:`swatch.render.environment.set_environment`),
  whose blur levels light the part exactly as the built-in studio's did (:mod:`swatch.catalog.explorer_env`), so
  the soft boxes, the horizon and the floor are what the part reflects.

Without a usable Mitsuba the page keeps the built-in studio and a plain background (the build says so in one line).
Bakes are cached in the catalog's cache (``studio-set-<key>.json``, keyed by the shape, the mesh's bytes, the
code and Mitsuba's version; an entry that does not decode to the expected shapes is baked again).
"""
from __future__ import annotations

import base64
import hashlib
import json
import math
from pathlib import Path

import numpy as np

from swatch.catalog.folder import read_cache_json, remove_tree
from swatch.core.fileio import atomic_write_text
from swatch.core.sources import code_hash
from swatch.render import studio_set as ss
from swatch.render.dispatch import engine_unavailable, engine_version, studio_lightmap
from swatch.render.environment import Environment, set_environment

__all__ = ["SET_SHAPES", "baked_set", "set_geometry"]

#: The shapes of the live view the set is baked around (page names: plate, bent sheet, sphere), and the mesh.
SET_SHAPES = ("flat", "cylinder", "sphere")
_FORMAT = "swatch-studio-set-bake"


def set_geometry() -> dict:
    """The set's geometry for the page (world frame, y up), JSON-ready.

    Returns
    -------
    dict
        ``cyclorama`` (its profile's constants and the lightmap warp: :func:`swatch.render.studio_set.lightmap_axes`),
        ``boxes`` (centre, half axes, the normal each emits along, radiance before the scale) and ``fill``.
    """
    floor_len = ss.FRONT_Z - (ss.WALL_Z + ss.COVE_RADIUS)
    frames = ss.box_frames()
    return {
        "frame": "world: y up, the camera on the +z side; a page direction (x, y, z) is (-y, z, -x) here",
        "cyclorama": {"albedo": ss.CYCLORAMA_ALBEDO, "cove_radius": ss.COVE_RADIUS, "wall_z": ss.WALL_Z,
                      "front_z": ss.FRONT_Z, "half_width": ss.HALF_WIDTH, "wall_height": ss.WALL_HEIGHT,
                      "floor_length": floor_len, "cove_length": 0.5 * math.pi * ss.COVE_RADIUS,
                      "warp": ss.LIGHTMAP_WARP, "s0": ss.FRONT_Z, "span_front": ss.FRONT_Z,
                      "span_back": ss.profile_length() - ss.FRONT_Z},
        "boxes": [{"name": b.name, "centre": f[0].tolist(), "half_u": f[1].tolist(), "half_v": f[2].tolist(),
                   "normal": f[3].tolist(), "radiance": b.radiance} for b, f in zip(ss.SOFT_BOXES, frames, strict=True)],
        "fill": ss.FILL_RADIANCE,
    }


def _b64(a: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype="<f4").tobytes()).decode("ascii")


def _unb64(text: str, shape: tuple[int, int]) -> np.ndarray | None:
    try:
        a = np.frombuffer(base64.b64decode(text, validate=True), dtype="<f4")
    except (ValueError, TypeError):
        return None
    if a.size != shape[0] * shape[1] or not np.all(np.isfinite(a)) or np.any(a < 0):
        return None
    return a.reshape(shape).copy()


def _key(shape: str, mesh_sha256: str | None) -> str:
    blob = {"shape": shape, "code": code_hash(__name__, "swatch.render.mitsuba.bake"), "mitsuba": engine_version("mitsuba"),
            "mesh": mesh_sha256}
    return hashlib.sha256(json.dumps(blob, sort_keys=True).encode()).hexdigest()[:32]


#: Bakes made in this process, by key (a series of builds, the test suite's catalogs: the same set is baked once).
_BAKED: dict[str, dict] = {}


def _bake(shape: str, mesh, mesh_sha256: str | None, cache: Path | None, used: set[str]) -> dict:
    """One shape's bake (``shadow``, ``bounce``, ``scale``, ``floor_y``), from the cache when it holds it."""
    key = _key(shape, mesh_sha256)
    path = None
    if cache is not None:
        name = f"studio-set-{key}.json"
        used.add(name)
        path = cache / name
        doc = read_cache_json(path)
        if isinstance(doc, dict) and doc.get("format") == _FORMAT:
            try:
                ns, nx = int(doc["ns"]), int(doc["nx"])
                scale, floor = float(doc["scale"]), float(doc["floor_y"])
                shadow, bounce = _unb64(doc["shadow"], (ns, nx)), _unb64(doc["bounce"], (ns, nx))
                if (shadow is not None and bounce is not None and 2 <= nx <= 1024 and 2 <= ns <= 1024
                        and math.isfinite(scale) and scale > 0 and math.isfinite(floor)):
                    return {"shadow": shadow, "bounce": bounce, "scale": scale, "floor_y": floor}
            except (KeyError, TypeError, ValueError):
                pass
    if key in _BAKED:
        shadow, bounce, scale, floor = (_BAKED[key][k] for k in ("shadow", "bounce", "scale", "floor_y"))
    else:
        shadow, bounce, scale, floor = studio_lightmap(shape, mesh)
        if len(_BAKED) >= 8:
            _BAKED.pop(next(iter(_BAKED)))
        _BAKED[key] = {"shadow": shadow, "bounce": bounce, "scale": scale, "floor_y": floor}
    if path is not None:
        ns, nx = shadow.shape
        atomic_write_text(path, json.dumps({"format": _FORMAT, "ns": ns, "nx": nx, "scale": scale, "floor_y": floor,
                                            "shadow": _b64(shadow), "bounce": _b64(bounce)}))
    return {"shadow": shadow, "bounce": bounce, "scale": scale, "floor_y": floor}


#: The grey the reflections' environment puts on the bounce map (the films' reflectance is about this).
BOUNCE_GREY = 0.4


def baked_set(mesh=None, mesh_sha256: str | None = None, cache: Path | None = None,
              used: set[str] | None = None) -> tuple[dict, dict[str, Environment]] | None:
    """The set baked around each shape of the live view (module doc), or None when Mitsuba cannot run here.

    Parameters
    ----------
    mesh : swatch.render.mesh.MeshShape, optional
        The catalog's part (baked as shape ``mesh`` too).
    mesh_sha256 : str, optional
        The SHA-256 of the part's file (it keys the cache).
    cache : pathlib.Path, optional
        The catalog's cache folder; None bakes without caching.
    used : set of str, optional
        Filled with the cache entries in use (the build prunes the rest).

    Returns
    -------
    (dict, dict) or None
        The page's per-shape data (``floor_y``, ``scale``, ``texels`` [nx, ns], the raw ``shadow`` and ``bounce``
        lightmaps as arrays) and per shape the set seen from the object's centre as an :class:`Environment`.
    """
    if engine_unavailable("mitsuba") is not None:
        return None
    used = set() if used is None else used
    shapes, envs = {}, {}
    for shape in SET_SHAPES + (("mesh",) if mesh is not None else ()):
        b = _bake(shape, mesh if shape == "mesh" else None, mesh_sha256 if shape == "mesh" else None, cache, used)
        ns, nx = b["shadow"].shape
        shapes[shape] = {"floor_y": b["floor_y"], "scale": b["scale"], "texels": [nx, ns],
                         "shadow": b["shadow"], "bounce": b["bounce"]}
        envs[shape] = set_environment(f"studio set ({shape})", b["floor_y"], b["shadow"] + BOUNCE_GREY * b["bounce"],
                                      b["scale"])
    if cache is not None:
        for stale in cache.glob("studio-set-*.json"):
            if stale.name not in used:
                remove_tree(stale)
    return shapes, envs
