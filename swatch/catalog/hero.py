"""Per-swatch hero renders (#23 item 4): each swatch as a sphere (or the spec's part, ``[render] mesh``) in the
studio, path-traced by Mitsuba 3 with the exact thin-film BSDF (:mod:`swatch.render.mitsuba.engine`), written as
``heroes/hero_S001.png`` and named in the swatch's record (``hero``).

A catalog spec turns them on with ``[render] hero = true`` (the default catalog, catalog/titanium.toml,
does; the spec's default is off, so small catalogs stay quick). They are pictures at ``hero_size_px``
(default :data:`HERO_SIZE_PX`: a 128 CSS px picture on a 2× display) and ``hero_spp`` samples per pixel
(default :data:`HERO_SPP`), denoised by Intel Open Image Denoise unless ``denoise = false``
(:mod:`swatch.render.mitsuba.denoise`), seed 0 (the same inputs give the same bytes), in the engine's
studio with the spec's first finish (anisotropic with hairlines for ``brushed``). With ``hero_cover_px``
the most vivid swatch's hero is made again at that side, ``cover_S027.png``: the page's first view
(:func:`cover_index`). That swatch also has a hero (and a cover, at most :data:`OTHER_FINISH_COVER_PX`) in
every other finish the spec offers (``finishes``), ``hero_S027_satin.png``, listed with the first in its
record's ``hero_finishes``. Every hero's entry carries its picture's edge colours (:func:`edge_colours`), with
which the page fills its wider frame. Renders are cached in the catalog folder's cache as ``hero-<key>.png``,
keyed by everything they depend on (:func:`hero_key`: the film, finish, part, thickness, size, Mitsuba's version
and the engine's code); a cached file is used only if it is a regular file of bounded size that reads back as an
RGB PNG of the expected size (the cache is untrusted). Without a usable Mitsuba (not installed, or no libLLVM for
its JIT) the build skips them and says so in one line.
"""
from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import io
import json
from pathlib import Path
from typing import NamedTuple

import numpy as np
from PIL import Image

from swatch.catalog.folder import remove_tree
from swatch.catalog.layout import HEROES
from swatch.core.fileio import atomic_write_bytes
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES
from swatch.core.safepath import is_regular_file
from swatch.core.sources import code_hash
from swatch.io.imageio import write_png
from swatch.physics.finishes import get_finish
from swatch.render.dispatch import ENGINES, engine_unavailable, engine_version
from swatch.render.request import render_request

__all__ = ["HERO_SIZE_PX", "HERO_SPP", "HERO_DENOISE", "OTHER_FINISH_COVER_PX", "HeroRenders", "hero_name", "render_hero",
           "cover_name", "cover_index", "edge_colours", "hero_unavailable", "hero_key", "hero_files", "catalog_heroes",
           "prune_heroes"]

HERO_SIZE_PX = 256
HERO_SPP = 16
HERO_SEED = 0
#: OIDN's quality for heroes (``balanced``: about half the filter's time of ``high`` at 256²; at 256 px and
#: 16 spp the picture is clean either way, docs/catalog.md).
HERO_DENOISE = "balanced"


def hero_name(rec: dict, finish: str | None = None) -> str:
    """The name of a swatch's hero render in the catalog folder (in its ``heroes/``).

    Parameters
    ----------
    rec : dict
        The swatch's record (its ``id``).
    finish : str, optional
        A finish other than the spec's first (the first's hero has no suffix).

    Returns
    -------
    str
        ``heroes/hero_<id>.png``, or ``heroes/hero_<id>_<finish>.png``.

    Examples
    --------
    >>> hero_name({"id": "S027"}), hero_name({"id": "S027"}, "bead-blasted")
    ('heroes/hero_S027.png', 'heroes/hero_S027_bead-blasted.png')
    """
    return f"{HEROES}/hero_{rec['id']}{'' if finish is None else '_' + finish}.png"


def cover_name(rec: dict, finish: str | None = None) -> str:
    """The name of the page's cover (the first view's picture: :func:`cover_index`'s hero, larger).

    Parameters
    ----------
    rec : dict
        The cover swatch's record (its ``id``).
    finish : str, optional
        A finish other than the spec's first (the first's cover has no suffix).

    Returns
    -------
    str
        ``heroes/cover_<id>.png``, or ``heroes/cover_<id>_<finish>.png``.
    """
    return f"{HEROES}/cover_{rec['id']}{'' if finish is None else '_' + finish}.png"


def cover_index(records: list[dict]) -> int | None:
    """The swatch the page opens on: the most vivid one, the largest CIE LCh chroma at the reference geometry
    among the swatches inside sRGB (the first of equals; the page's own ``vivid`` rule, swatch/catalog/web/page.js).

    Parameters
    ----------
    records : list of dict
        The swatches' records (``LCh``, ``in_srgb_gamut``).

    Returns
    -------
    int or None
        Its index in ``records`` (the first swatch when none is inside sRGB), or None when there are none.
    """
    best = None
    for i, rec in enumerate(records):
        lch = rec.get("LCh")
        if rec.get("in_srgb_gamut") and isinstance(lch, (list, tuple)) and len(lch) == 3 and lch[1] is not None and (
                best is None or lch[1] > records[best]["LCh"][1]):
            best = i
    return best if best is not None else (0 if records else None)


def edge_colours(png: bytes, bands: int = 16) -> dict[str, list[str]]:
    """The colours of a hero's left and right edges, top to bottom: the page continues the square picture's
    backdrop with them where its 4:3 frame is wider (swatch/catalog/web/page.js).

    Parameters
    ----------
    png : bytes
        The hero's RGB PNG (its display colours).
    bands : int, optional
        Horizontal bands, each the mean of its rows over the outermost 1/64 of the width (at least 2 px).

    Returns
    -------
    dict
        ``{"left": [hex, ...], "right": [hex, ...]}``, ``bands`` sRGB hex colours each (``#rrggbb``).
    """
    with Image.open(io.BytesIO(png)) as im:
        rgb = np.asarray(im.convert("RGB"), dtype=np.float64)
    h, w, _ = rgb.shape
    k = max(2, w // 64)
    starts = np.array([r[0] for r in np.array_split(np.arange(h), bands)])  # np.array_split's bands of rows
    counts = np.diff(np.append(starts, h))[:, None] * k

    def column(x: slice) -> list[str]:
        means = np.rint(np.add.reduceat(rgb[:, x].sum(axis=1), starts, axis=0) / counts).astype(int)
        return ["#{:02x}{:02x}{:02x}".format(*c) for c in means]

    return {"left": column(slice(0, k)), "right": column(slice(w - k, w))}


class HeroRenders(NamedTuple):
    """What the hero stage gives the build.

    Attributes
    ----------
    files : dict of str to bytes
        Catalog-relative name (``heroes/…``) to PNG bytes.
    used : set of str
        The cache entries in use (the others are pruned after the commit).
    entries : list of dict or None
        Each record's ``hero`` entry (its first finish), None without one.
    finish_entries : list of dict or None
        Each record's ``hero_finishes``: finish name to an entry shaped as ``hero``'s, every finish it has a hero
        in (the first included); None without a hero or without named finishes.
    """

    files: dict[str, bytes]
    used: set[str]
    entries: list[dict | None]
    finish_entries: list[dict | None]


def hero_unavailable(spec) -> str | None:
    """Why hero renders cannot be made here (one line), or None when they can.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    str or None
        Why not (Mitsuba missing, no usable libLLVM), or None when hero renders can be made.
    """
    why = engine_unavailable("mitsuba")
    return None if why is None else f"hero renders skipped: {why}"


@functools.lru_cache(maxsize=1)
def _code_hash() -> str:
    return code_hash(__name__)  # this module and what it imports: the request, the Mitsuba engine (lazily)


def _lobe(spec, finish: str | None):
    """GGX α of a finish (α_u, α_v when anisotropic), or the spec's bare roughness (``finish`` None)."""
    if finish is None:
        return float(spec.roughness)
    f = get_finish(finish)
    return (f.alpha_u, f.alpha_v) if f.anisotropic else f.roughness_alpha


def hero_key(spec, thickness_nm: float, size_px: int, finish: str | None = None, mesh_key: str | None = None) -> str:
    """Content hash of everything a hero render depends on (film, finish, the part, thickness, size, Mitsuba's
    version, the engine's code).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec (film, substrate, index scale, spread, samples, denoising).
    thickness_nm : float
        The swatch's film thickness, nm.
    size_px : int
        The render's side in pixels (the spec's ``hero_size_px``, or a cover's side).
    finish : str, optional
        The finish rendered (None: the spec's bare roughness).
    mesh_key : str, optional
        The part's :attr:`swatch.render.mesh.MeshShape.key` (None: the sphere).

    Returns
    -------
    str
        40 hex digits (the cache entry's name).
    """
    doc = {"d": float(thickness_nm), "film": spec.film, "substrate": spec.substrate,
           "scale": spec.film_index_scale, "lobe": _lobe(spec, finish),
           "size": int(size_px), "spp": spec.hero_spp,
           "seed": HERO_SEED, "spread": [spec.spread.spread_nm, spec.spread.spread_fraction],
           "mitsuba": engine_version("mitsuba"), "code": _code_hash(),
           "denoise": [importlib.metadata.version("mitsuba-oidn"), HERO_DENOISE] if spec.denoise else False}
    if finish is not None:  # the label in the picture's metadata (a bare roughness: the keys of before)
        doc["finish"] = finish
    if mesh_key is not None:
        doc["mesh"] = mesh_key
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:40]


def _cached(path: Path, size_px: int) -> bytes | None:
    if not is_regular_file(path) or path.stat().st_size > MAX_CACHE_ENTRY_BYTES:
        return None
    blob = path.read_bytes()
    try:
        with Image.open(path) as im:
            ok = im.format == "PNG" and im.size == (size_px, size_px) and im.mode == "RGB"
    except (OSError, ValueError):
        ok = False
    return blob if ok else None


def _request(spec, size_px: int, finish: str | None, mesh):
    """The render request of the spec's heroes in ``finish`` at ``size_px`` (thickness 0: each swatch sets its
    own): the sphere, or the part."""
    return render_request(0.0, "sphere", size_px, engine="mitsuba", spp=spec.hero_spp, seed=HERO_SEED,
                          environment="studio", roughness_alpha=_lobe(spec, finish), mesh=mesh,
                          coating=spec.coating(None),  # film, substrate, index scale, spread
                          denoise=HERO_DENOISE if spec.denoise else False)


def _entry_file(spec, request, finish: str | None, rec: dict) -> str:
    """The cache entry of one swatch's hero as ``request`` renders it (``hero-<key>.png``)."""
    mesh_key = request.mesh.key if request.mesh is not None else None
    return f"hero-{hero_key(spec, float(rec['thickness_nm']), request.size_px, finish, mesh_key)}.png"


def render_hero(request, finish: str | None, rec: dict, path: Path) -> None:
    """Path-trace one swatch's hero and write it as an RGB PNG with its metadata (atomic): the same bytes wherever
    it runs (seed :data:`HERO_SEED`; the build's process, or a worker of a cluster, swatch.catalog.cluster).

    Parameters
    ----------
    request : swatch.render.request.RenderRequest
        The hero's checked request, at the swatch's thickness.
    finish : str or None
        The finish rendered (its label goes into the metadata), None for the spec's bare roughness.
    rec : dict
        The swatch's record (its ``id`` goes into the metadata).
    path : pathlib.Path
        The PNG to write.

    Returns
    -------
    None
        Returns when the file is written.
    """
    img = ENGINES["mitsuba"](request, None)
    meta = {k: img.metadata[k] for k in ("engine", "bsdf", "lighting", "units", "film", "substrate",
                                         "thickness_nm", "spp", "denoise", "mesh") if k in img.metadata}
    meta["swatch"] = rec["id"]
    if finish is not None:
        meta["finish"] = get_finish(finish).label()
    write_png(path, np.ascontiguousarray(img.display_rgb[..., :3]), meta)  # atomic


def _render(spec, request, finish: str | None, rec: dict, cache: Path, used: set[str]) -> bytes:
    """One swatch's hero as ``request`` renders it (from the cache, else path-traced and cached); its cache
    entry added to ``used``."""
    entry = _entry_file(spec, request, finish, rec)
    used.add(entry)
    path = cache / entry
    blob = _cached(path, request.size_px)
    if blob is None:
        render_hero(request.with_thickness(float(rec["thickness_nm"])), finish, rec, path)
        blob = path.read_bytes()
    return blob


#: The side of the cover in a finish other than the first (at most ``hero_cover_px``): the picture the page shows
#: when the designer picks that finish, kept smaller than the first finish's cover so that the default catalog's
#: cold build stays within its budget (docs/catalog.md).
OTHER_FINISH_COVER_PX = 480


def _entry(spec, name: str, blob: bytes, finish: str | None, mesh) -> dict:
    """A hero's entry in its record (``hero``, and each of ``hero_finishes``)."""
    return {"png": name, "edges": edge_colours(blob), "engine": "mitsuba",
            "shape": "sphere" if mesh is None else "mesh", "lighting": "studio",
            "size_px": spec.hero_size_px, "spp": spec.hero_spp, "denoised": spec.denoise,
            "denoise_quality": HERO_DENOISE if spec.denoise else None,
            "css_px": spec.hero_size_px // 2, "finish": finish}


def hero_files(spec, records: list[dict], cache: Path, say=None, mesh=None, render_many=None) -> HeroRenders:
    """The hero renders of ``records`` (cached), the cache entries in use and each record's entries; nothing (and a
    line through ``say``) when Mitsuba is unusable. ``records`` are read only.

    Every swatch has its hero in the spec's first finish (``hero``); the cover swatch (:func:`cover_index`) has one
    in every other finish offered too, each with its cover when the spec asks for one (``hero_cover_px``; the other
    finishes' covers at most :data:`OTHER_FINISH_COVER_PX`).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (``id``, ``thickness_nm``, ``LCh``, ``in_srgb_gamut``).
    cache : pathlib.Path
        The catalog's build cache (untrusted: entries are checked before use).
    say : callable, optional
        Receives one line.
    mesh : swatch.render.mesh.MeshShape, optional
        The spec's part (rendered instead of the sphere).
    render_many : callable, optional
        Renders the heroes the cache lacks, all at once, elsewhere (a cluster's workers,
        :meth:`swatch.catalog.cluster.Cluster.render_heroes`): given a list of ``(request, finish, record)`` it
        returns each one's PNG bytes (:func:`render_hero`'s file), in order; they are written into the cache here.
        None: each is path-traced here, one after the other.

    Returns
    -------
    HeroRenders
        {name: PNG bytes}, the cache entries used, each record's ``hero`` entry and its ``hero_finishes``.
    """
    none = HeroRenders({}, set(), [None] * len(records), [None] * len(records))
    why = hero_unavailable(spec)
    if why is not None:
        if say is not None:
            say(why)
        return none
    out = HeroRenders({}, set(), [], [])
    finishes: tuple[str | None, ...] = spec.finishes or (None,)
    first = cover_index(records)
    requests: dict = {}

    def request(side: int, finish: str | None):
        if (side, finish) not in requests:
            requests[side, finish] = _request(spec, side, finish, mesh)
        return requests[side, finish]

    plan = []  # (swatch, finish's place, finish, request, its cover's request or None), in the pictures' order
    for k, _rec in enumerate(records):
        for j, finish in enumerate(finishes if k == first else finishes[:1]):  # the cover swatch: every finish
            side = (spec.hero_cover_px if j == 0 else min(spec.hero_cover_px, OTHER_FINISH_COVER_PX))
            plan.append((k, j, finish, request(spec.hero_size_px, finish),
                         request(side, finish) if k == first and spec.hero_cover_px else None))
    if render_many is not None:  # the renders the cache lacks, made elsewhere at once; cached here
        todo = {}
        for k, _j, finish, *reqs in plan:
            for req in (r for r in reqs if r is not None):
                file = _entry_file(spec, req, finish, records[k])
                if file not in todo and _cached(cache / file, req.size_px) is None:
                    todo[file] = (req.with_thickness(float(records[k]["thickness_nm"])), finish, records[k])
        for file, blob in zip(todo, render_many(list(todo.values())), strict=True):
            atomic_write_bytes(cache / file, blob)
    by_finish: dict[str, dict] = {}
    for p, (k, j, finish, req, cover_req) in enumerate(plan):
        rec = records[k]
        suffix = None if j == 0 else finish
        name = hero_name(rec, suffix)
        out.files[name] = _render(spec, req, finish, rec, cache, out.used)
        entry = _entry(spec, name, out.files[name], finish, mesh)
        if cover_req is not None:  # the page's first view: sharp at the live view's size on a 2x display
            cover = cover_name(rec, suffix)
            out.files[cover] = _render(spec, cover_req, finish, rec, cache, out.used)
            entry["cover"] = {"png": cover, "size_px": cover_req.size_px}
        if finish is not None:
            by_finish[finish] = entry
        if j == 0:
            out.entries.append(entry)
        if p + 1 == len(plan) or plan[p + 1][0] != k:
            out.finish_entries.append(by_finish or None)  # the swatch's last hero
            by_finish = {}
    return out


def catalog_heroes(spec, records: list[dict], cache: Path, say=None, mesh=None, render_many=None) -> HeroRenders:
    """:func:`hero_files` when the spec asks for hero renders (``hero = true``), else nothing.

    Parameters
    ----------
    spec, records, cache, say, mesh, render_many
        As :func:`hero_files`.

    Returns
    -------
    HeroRenders
        As :func:`hero_files`; without heroes: no files, no cache entries, None per swatch.
    """
    if spec.hero:
        return hero_files(spec, records, cache, say, mesh, render_many)
    return HeroRenders({}, set(), [None] * len(records), [None] * len(records))


def prune_heroes(cache: Path, used: set[str]) -> None:
    """Remove the cached hero renders not in ``used`` (after a build's commit).

    Parameters
    ----------
    cache : pathlib.Path
        The catalog's build cache.
    used : set of str
        The cache entries the build used (kept).

    Returns
    -------
    None
        Returns when the unused entries are removed.
    """
    for p in cache.glob("hero-*.png"):
        if p.name not in used:
            remove_tree(p)
