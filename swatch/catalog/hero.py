"""Per-swatch hero renders (#23 item 4): each swatch as a sphere in the studio, path-traced by
Mitsuba 3 with the exact thin-film BSDF (:mod:`swatch.render.mitsuba.engine`), written as
``hero_S001.png`` beside the chips and named in the swatch's record (``hero``).

A catalog spec turns them on with ``[render] hero = true`` (the default catalog, catalog/titanium.toml,
does; the spec's default is off, so small catalogs stay quick). They are pictures at ``hero_size_px``
(default :data:`HERO_SIZE_PX`: a 128 CSS px picture on a 2× display) and ``hero_spp`` samples per pixel
(default :data:`HERO_SPP`), denoised by Intel Open Image Denoise unless ``denoise = false``
(:mod:`swatch.render.mitsuba.denoise`), seed 0 (the same inputs give the same bytes), in the engine's
studio with the spec's finish (anisotropic with hairlines for ``brushed``). Renders are cached in the catalog folder's cache as
``hero-<key>.png``, keyed by everything they depend on (the film, finish, thickness, Mitsuba's
version and the engine's code); a cached file is used only if it is a regular file of bounded
size that reads back as an RGB PNG of the expected size (the cache is untrusted). With ``hero_cover_px``
the most vivid swatch's hero is made again at that side, ``cover_S027.png``: the page's first view
(:func:`cover_index`); every hero's entry carries its picture's edge colours (:func:`edge_colours`), with
which the page fills its wider frame. Without a usable Mitsuba (not installed, or no libLLVM for its JIT) the build skips them and says so in
one line.
"""
from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import io
import json
from pathlib import Path

import numpy as np
from PIL import Image

from swatch.catalog.folder import remove_tree
from swatch.catalog.layout import HEROES
from swatch.core.limits import MAX_CACHE_ENTRY_BYTES
from swatch.core.safepath import is_regular_file
from swatch.core.sources import code_hash
from swatch.io.imageio import write_png
from swatch.render.dispatch import ENGINES, engine_unavailable, engine_version
from swatch.render.request import render_request

__all__ = ["HERO_SIZE_PX", "HERO_SPP", "HERO_DENOISE", "hero_name", "cover_name", "cover_index", "edge_colours",
           "hero_unavailable", "hero_key", "hero_files", "catalog_heroes", "prune_heroes"]

HERO_SIZE_PX = 256
HERO_SPP = 16
HERO_SEED = 0
#: OIDN's quality for heroes (``balanced``: about half the filter's time of ``high`` at 256²; at 256 px and
#: 16 spp the picture is clean either way, docs/catalog.md).
HERO_DENOISE = "balanced"


def hero_name(rec: dict) -> str:
    """The name of a swatch's hero render in the catalog folder (in its ``heroes/``).

    Parameters
    ----------
    rec : dict
        The swatch's record (its ``id``).

    Returns
    -------
    str
        ``heroes/hero_<id>.png``.
    """
    return f"{HEROES}/hero_{rec['id']}.png"


def cover_name(rec: dict) -> str:
    """The name of the page's cover (the first view's picture: :func:`cover_index`'s hero, larger).

    Parameters
    ----------
    rec : dict
        The cover swatch's record (its ``id``).

    Returns
    -------
    str
        ``heroes/cover_<id>.png``.
    """
    return f"{HEROES}/cover_{rec['id']}.png"


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


def _lobe(spec):
    f = spec.finish_spec
    return (f.alpha_u, f.alpha_v) if f is not None and f.anisotropic else float(spec.roughness)


def hero_key(spec, thickness_nm: float, size_px: int) -> str:
    """Content hash of everything a hero render depends on (film, finish, thickness, size, Mitsuba's version,
    the engine's code).

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec. (film, finish, spread).
    thickness_nm : float
        The swatch's film thickness, nm.
    size_px : int
        The render's side in pixels (the spec's ``hero_size_px``, or ``hero_cover_px`` for the cover).

    Returns
    -------
    str
        40 hex digits (the cache entry's name).
    """
    doc = {"d": float(thickness_nm), "film": spec.film, "substrate": spec.substrate,
           "scale": spec.film_index_scale, "lobe": _lobe(spec),
           "size": int(size_px), "spp": spec.hero_spp,
           "seed": HERO_SEED, "spread": [spec.spread.spread_nm, spec.spread.spread_fraction],
           "mitsuba": engine_version("mitsuba"), "code": _code_hash(),
           "denoise": [importlib.metadata.version("mitsuba-oidn"), HERO_DENOISE] if spec.denoise else False}
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


def _request(spec, size_px: int):
    """The render request of the spec's heroes at ``size_px`` (thickness 0: each swatch sets its own)."""
    return render_request(0.0, "sphere", size_px, engine="mitsuba", spp=spec.hero_spp, seed=HERO_SEED,
                          environment="studio", roughness_alpha=_lobe(spec),
                          coating=spec.coating(None),  # film, substrate, index scale, spread
                          denoise=HERO_DENOISE if spec.denoise else False)


def _render(spec, request, rec: dict, cache: Path, used: set[str]) -> bytes:
    """One swatch's hero as ``request`` renders it (from the cache, else path-traced and cached); its cache
    entry added to ``used``."""
    d = float(rec["thickness_nm"])
    entry = f"hero-{hero_key(spec, d, request.size_px)}.png"
    used.add(entry)
    path = cache / entry
    blob = _cached(path, request.size_px)
    if blob is None:
        img = ENGINES["mitsuba"](request.with_thickness(d), None)
        meta = {k: img.metadata[k] for k in ("engine", "bsdf", "lighting", "units", "film", "substrate",
                                             "thickness_nm", "spp", "denoise") if k in img.metadata}
        meta["swatch"] = rec["id"]
        if spec.finish_spec is not None:
            meta["finish"] = spec.finish_spec.label()
        write_png(path, np.ascontiguousarray(img.display_rgb[..., :3]), meta)  # atomic
        blob = path.read_bytes()
    return blob


def hero_files(spec, records: list[dict], cache: Path,
               say=None) -> tuple[dict[str, bytes], set[str], list[dict | None]]:
    """The hero renders of ``records`` (cached), the cache entries in use and each record's ``hero`` entry;
    nothing (and a line through ``say``) when Mitsuba is unusable. ``records`` are read only.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (``id``, ``thickness_nm``).
    cache : pathlib.Path
        The catalog's build cache (untrusted: entries are checked before use).
    say : callable, optional
        Receives one line.

    Returns
    -------
    (dict, set of str, list of dict or None)
        {name: PNG bytes}, the cache entries used, the entries.
    """
    why = hero_unavailable(spec)
    if why is not None:
        if say is not None:
            say(why)
        return {}, set(), [None] * len(records)
    files: dict[str, bytes] = {}
    used: set[str] = set()
    entries: list[dict | None] = []
    request = _request(spec, spec.hero_size_px)
    for rec in records:
        files[hero_name(rec)] = _render(spec, request, rec, cache, used)
        entries.append({"png": hero_name(rec), "edges": edge_colours(files[hero_name(rec)]), "engine": "mitsuba",
                        "shape": "sphere", "lighting": "studio",
                        "size_px": spec.hero_size_px, "spp": spec.hero_spp, "denoised": spec.denoise,
                        "denoise_quality": HERO_DENOISE if spec.denoise else None,
                        "css_px": spec.hero_size_px // 2})
    first = cover_index(records) if spec.hero_cover_px else None
    if first is not None:  # the page's first view: the same picture, sharp at the live view's size on a 2x display
        files[cover_name(records[first])] = _render(spec, _request(spec, spec.hero_cover_px), records[first], cache, used)
        entries[first] = dict(entries[first] or {}, cover={"png": cover_name(records[first]),
                                                            "size_px": spec.hero_cover_px})
    return files, used, entries


def catalog_heroes(spec, records: list[dict], cache: Path,
                   say=None) -> tuple[dict[str, bytes], set[str], list[dict | None]]:
    """:func:`hero_files` when the spec asks for hero renders (``hero = true``), else nothing.

    Parameters
    ----------
    spec, records, cache, say
        As :func:`hero_files`.

    Returns
    -------
    (dict, set of str, list of dict or None)
        {name: PNG bytes}, the cache entries used, each swatch's hero entry; without heroes
        ({}, an empty set, None per swatch).
    """
    return hero_files(spec, records, cache, say) if spec.hero else ({}, set(), [None] * len(records))


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
