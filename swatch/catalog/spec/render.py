"""The ``[render]`` table of a catalog spec: the tiles' renders, the finishes offered, the heroes and the part.

:func:`parse_render` checks the table into the keyword arguments of :class:`swatch.catalog.spec.CatalogSpec`
(``shapes``, ``size_px``, ``model``, ``roughness``, ``finish``, ``finishes``, ``angular_map``, the hero options
and the ``mesh``); :func:`spec_mesh` checks a designer's part named by ``mesh = "part.glb"``: a file inside the
spec's folder, of a mesh format, within the size cap, hashed (its bytes are part of the build's fingerprint).
Light on purpose (no trimesh, no colour-science): a no-op rebuild parses the spec; the mesh itself is read and
checked by :func:`swatch.catalog.execute.check_buildable`, before anything is built.
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Any

from swatch.catalog.spec.checks import SpecChecker
from swatch.core.choices import DEFAULT_ROUGHNESS_ALPHA, FINISHES, MESH_FORMATS, MODELS, SHAPES
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_DENOISE_PX, MAX_MESH_BYTES, MAX_MITSUBA_PX, read_capped
from swatch.core.safepath import inside
from swatch.physics.finishes import get_finish

__all__ = ["RENDER_KEYS", "parse_render", "spec_mesh", "spec_finishes"]

#: The keys of ``[render]``.
RENDER_KEYS = ("shapes", "size_px", "model", "roughness", "finish", "finishes", "angular_map", "hero", "hero_size_px",
               "hero_spp", "hero_cover_px", "denoise", "mesh")


def spec_finishes(c: SpecChecker, ren: dict, model: str) -> tuple[str, ...]:
    """The finishes a spec offers: ``finishes = [...]`` (the first is the one shown first), or ``finish = X``
    alone (one finish), or none (a bare ``roughness``).

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    ren : dict
        The ``[render]`` table (its keys checked).
    model : str
        The tiles' shading model (an anisotropic finish needs ``microfacet``).

    Returns
    -------
    tuple of str
        Finish names of :data:`swatch.core.choices.FINISHES`, each once, in the spec's order; empty without one.

    Raises
    ------
    swatch.core.errors.SwatchError
        An unknown or repeated finish, an empty list, ``finish`` other than ``finishes``' first, a finish with
        ``roughness``, or an anisotropic finish without the microfacet model.

    Examples
    --------
    >>> spec_finishes(SpecChecker("x.toml"), {"finishes": ["polished", "Satin"]}, "microfacet")
    ('polished', 'satin')
    >>> spec_finishes(SpecChecker("x.toml"), {"finish": "satin", "finishes": ["polished", "satin"]}, "microfacet")
    Traceback (most recent call last):
    ...
    swatch.core.errors.SwatchError: x.toml: key render.finish: must be the first of render.finishes, the finish \
shown first ('polished'), or left out (got 'satin')
    """
    if "finishes" not in ren and "finish" not in ren:
        return ()
    if "roughness" in ren:
        key = "render.finishes" if "finishes" in ren else "render.finish"
        c.fail(key, "give either finish or roughness, not both (a finish sets the roughness)",
               ren.get("finishes", ren.get("finish")))
    if "finishes" in ren:
        given = ren["finishes"]
        if not isinstance(given, list) or not 1 <= len(given) <= len(FINISHES):
            c.fail("render.finishes", f"must be a list of one to {len(FINISHES)} of {', '.join(FINISHES)} "
                   "(the first is the one shown first)", given)
        names = tuple(c.string(f, f"render.finishes[{i}]", 20, FINISHES) for i, f in enumerate(given))
        if len(set(names)) != len(names):
            c.fail("render.finishes", "must not repeat a finish", given)
        if "finish" in ren and c.string(ren["finish"], "render.finish", 20, FINISHES) != names[0]:
            c.fail("render.finish", f"must be the first of render.finishes, the finish shown first ({names[0]!r}), "
                   "or left out", ren["finish"])
    else:
        names = (c.string(ren["finish"], "render.finish", 20, FINISHES),)
    for name in names:
        if get_finish(name).anisotropic and model != "microfacet":
            c.fail("render.finishes" if "finishes" in ren else "render.finish",
                   f"{name} is anisotropic: it needs model = \"microfacet\"", name)
    return names


def spec_mesh(c: SpecChecker, value, base_dir: Path | None) -> tuple[str, str, str]:
    """A designer's part, ``mesh = "part.glb"``: a mesh file inside the spec's folder (links resolved), of a
    format :func:`swatch.render.mesh.load_mesh` reads, within :data:`swatch.core.limits.MAX_MESH_BYTES`.

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    value : object
        The value read from the TOML (untrusted: any type): a path relative to the spec's folder.
    base_dir : pathlib.Path or None
        The spec's folder (None: a spec not read from a file, which cannot name a part).

    Returns
    -------
    (str, str, str)
        The name as given, the file's resolved path and the SHA-256 of its bytes (64 hex digits).

    Raises
    ------
    swatch.core.errors.SwatchError
        Not a text, no spec folder, an unknown format, a path outside the spec's folder, no such file, or a
        file over the cap: one line naming the spec and the key ``render.mesh``.
    """
    text = c.string(value, "render.mesh", 200)
    if base_dir is None:
        c.fail("render.mesh", "is a path relative to the spec file; this spec was not read from a file", value)
    suffix = Path(text).suffix.lower().lstrip(".")
    if suffix not in MESH_FORMATS:
        c.fail("render.mesh", f"must name a mesh file ({', '.join('.' + f for f in MESH_FORMATS)})", value)
    root = os.path.realpath(base_dir)
    try:  # the project's rule for a path read from a file (swatch.core.safepath): inside its folder, links resolved
        real = os.path.realpath(inside(os.path.join(root, text), root, "mesh"))
    except SwatchError:
        c.fail("render.mesh", "must lie inside the spec's folder (a path relative to the spec file, links "
               "resolved)", value)
    if real == root:
        c.fail("render.mesh", "must name a mesh file, not the spec's folder", value)
    if not os.path.isfile(real):
        c.fail("render.mesh", "no such file next to the spec", value)
    try:
        data = read_capped(Path(real), MAX_MESH_BYTES, "mesh file")
    except SwatchError as exc:
        c.fail("render.mesh", str(exc), value, show_got=False)
    return text, real, hashlib.sha256(data).hexdigest()


def parse_render(c: SpecChecker, data, base_dir: Path | None) -> dict[str, Any]:
    """The ``[render]`` table, checked, as keyword arguments of :class:`swatch.catalog.spec.CatalogSpec`.

    Parameters
    ----------
    c : SpecChecker
        The checker (it knows the spec file's name for the message).
    data : object
        The table read from the TOML (untrusted: any type; ``{}`` when absent).
    base_dir : pathlib.Path or None
        The spec's folder (a ``mesh`` is looked up inside it).

    Returns
    -------
    dict
        ``shapes``, ``size_px``, ``model``, ``roughness`` (GGX α; the first finish's when finishes are
        offered), ``finish`` (the first finish or None), ``finishes``, ``angular_map``, ``hero``,
        ``hero_size_px``, ``hero_spp``, ``hero_cover_px``, ``denoise``, ``mesh``, ``mesh_path`` and
        ``mesh_sha256`` (None without a part).

    Raises
    ------
    swatch.core.errors.SwatchError
        An unknown key, a wrong type or an impossible value, in one line naming the file and the key.

    Examples
    --------
    >>> r = parse_render(SpecChecker("x.toml"), {"finishes": ["polished", "satin"]}, None)
    >>> r["finish"], r["finishes"], r["roughness"]
    ('polished', ('polished', 'satin'), 0.04)
    """
    ren = c.table(data, "render", RENDER_KEYS)
    shapes = ren.get("shapes", ["flat", "cylinder"])
    if not isinstance(shapes, list) or not 1 <= len(shapes) <= 2:
        c.fail("render.shapes", f"must be a list of one or two of {', '.join(SHAPES)}", shapes)
    shapes = tuple(c.string(s, f"render.shapes[{i}]", 20, SHAPES) for i, s in enumerate(shapes))
    if len(set(shapes)) != len(shapes):
        c.fail("render.shapes", "must not repeat a shape", ren["shapes"])
    size = c.integer(ren.get("size_px", 192), "render.size_px", 64, 512)
    model = c.string(ren.get("model", "microfacet"), "render.model", 20, MODELS)
    rough = c.number(ren.get("roughness", DEFAULT_ROUGHNESS_ALPHA), "render.roughness", 0.01, 1.0)
    finishes = spec_finishes(c, ren, model)
    if finishes:
        rough = get_finish(finishes[0]).roughness_alpha
    amap = c.boolean(ren.get("angular_map", True), "render.angular_map")
    if (hero := c.boolean(ren.get("hero", False), "render.hero")) and model != "microfacet":
        c.fail("render.hero", "hero renders are of the microfacet model (Mitsuba); set model = \"microfacet\"", True)
    denoise = c.boolean(ren.get("denoise", True), "render.denoise")
    # (a denoised picture is at most MAX_DENOISE_PX a side, an undenoised one MAX_MITSUBA_PX: their time and memory)
    top = MAX_DENOISE_PX if denoise else MAX_MITSUBA_PX
    hero_size = c.integer(ren.get("hero_size_px", 256), "render.hero_size_px", 32, min(1024, top))
    hero_spp = c.integer(ren.get("hero_spp", 16), "render.hero_spp", 1, 1024)
    if (cover := c.integer(ren.get("hero_cover_px", 0), "render.hero_cover_px", 0, top)) and not hero:
        c.fail("render.hero_cover_px", "the cover is the most vivid swatch's hero rendered larger: set hero = true", cover)
    mesh, mesh_path, mesh_sha256 = spec_mesh(c, ren["mesh"], base_dir) if "mesh" in ren else (None, None, None)
    return {"shapes": shapes, "size_px": size, "model": model, "roughness": rough,
            "finish": finishes[0] if finishes else None, "finishes": finishes, "angular_map": amap, "hero": hero,
            "hero_size_px": hero_size, "hero_spp": hero_spp, "hero_cover_px": cover, "denoise": denoise,
            "mesh": mesh, "mesh_path": mesh_path, "mesh_sha256": mesh_sha256}
