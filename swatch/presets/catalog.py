"""Presets of a catalog's swatches: fitted once per content (cached), written next to the catalog.

:func:`catalog_presets` fits the three models for all the catalog's thicknesses (or reads the fit
from the build cache, keyed by the hash of what it depends on), adds a ``presets`` entry to every
record and returns the files to write:

``preset_S001.gltf``, ``preset_S001_blender.py``, ``preset_S001.mtlx`` (flat names in the catalog
folder), and in each record::

    "presets": {"gltf": "preset_S001.gltf", "gltf_max_delta_E_00": 1.9,
                "blender": "preset_S001_blender.py", "blender_max_delta_E_00": 1.4,
                "materialx": "preset_S001.mtlx", "openpbr_max_delta_E_00": 2.2, ...}

The errors are ΔE2000 between the model evaluated with the parameters *as written* (rounded) and
the exact colour, CIE 1931 2° observer under D65, maximum over the facet angles 0–60°
(``*_max_delta_E_00``; ``*_max_delta_E_00_45`` over 0–45°).
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from swatch.presets import FORMAT_MODEL, PRESET_FORMATS

__all__ = ["catalog_presets", "single_preset", "preset_file_name", "round_params", "roughness_factor", "ERROR_KEYS"]

#: catalog.json key of each format's error (max ΔE2000 over 0–60°).
ERROR_KEYS = {"gltf": "gltf_max_delta_E_00", "blender": "blender_max_delta_E_00",
              "materialx": "openpbr_max_delta_E_00"}
_DIGITS = (3, 4, 4, 4, 4)  # thickness nm, IOR, base R G B, as written


def preset_file_name(ident: str, fmt: str) -> str:
    return {"gltf": f"preset_{ident}.gltf", "blender": f"preset_{ident}_blender.py",
            "materialx": f"preset_{ident}.mtlx"}[fmt]


def round_params(params) -> np.ndarray:
    """The parameters as the files carry them (the errors are computed from these)."""
    p = np.asarray(params, dtype=np.float64)
    return np.stack([np.round(p[..., i], nd) for i, nd in enumerate(_DIGITS)], axis=-1)


def roughness_factor(alpha: float) -> float:
    """glTF/Blender/OpenPBR roughness (α = roughness²) for a GGX α."""
    return round(float(np.sqrt(alpha)), 4)


def fit_key(spec, extra_angles) -> str:
    from importlib import metadata

    import swatch

    pkg = Path(swatch.__file__).resolve().parent
    code = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted((pkg / "presets").glob("*.py"))}
    for m in ("optics", "model", "spread", "materials", "colorimetry"):
        code[m] = hashlib.sha256((pkg / f"{m}.py").read_bytes()).hexdigest()
    blob = {"d": [float(x) for x in spec.thickness_nm], "per_sheet": spec.per_sheet, "film": spec.film,
            "film_index_scale": spec.film_index_scale, **spec.spread.metadata(),
            "substrate": spec.substrate,
            "angles": [float(a) for a in extra_angles], "code": code,
            "versions": [metadata.version(x) for x in ("numpy", "scipy", "colour-science")]}
    return hashlib.sha256(json.dumps(blob, sort_keys=True).encode()).hexdigest()[:32]


def _cache_entry_ok(path: Path) -> bool:
    from swatch.limits import MAX_CACHE_ENTRY_BYTES
    from swatch.safepath import is_regular_file

    return is_regular_file(path) and path.stat().st_size <= MAX_CACHE_ENTRY_BYTES


def _read_cache(path: Path, n: int) -> dict | None:
    """The cached fits if the file is well formed for n swatches (it is read back: untrusted)."""
    from swatch.presets.fit import MODELS

    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        out = {m: (np.asarray(data[m]["params"], dtype=np.float64), np.asarray(data[m]["dE60"], dtype=np.float64),
                   np.asarray(data[m]["dE45"], dtype=np.float64)) for m in MODELS}
    except (OSError, ValueError, KeyError, TypeError):
        return None
    for p, e60, e45 in out.values():
        if p.shape != (n, 5) or e60.shape != (n,) or e45.shape != (n,):
            return None
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(e60)) and np.all(np.isfinite(e45))):
            return None
    return out


def _fits(spec, cache: Path | None) -> dict:
    from swatch.presets.fit import fit_presets

    extra = sorted({g.theta_d_deg for g in (spec.reference, *spec.multi_angle) if g.theta_d_deg <= 60.0})
    key = fit_key(spec, extra)
    path = cache / f"presets-{key}.json" if cache is not None else None
    if path is not None and _cache_entry_ok(path):  # the cache is untrusted: checked, else refitted
        cached = _read_cache(path, len(spec.thickness_nm))
        if cached is not None:
            return cached
    out = {}
    for fmt in PRESET_FORMATS:
        model = FORMAT_MODEL[fmt]
        groups = np.arange(len(spec.thickness_nm)) // spec.per_sheet  # coupled within a sheet only
        fit = fit_presets(spec.thickness_nm, model, extra, spec.film, spec.substrate, spec.film_index_scale,
                          groups, spec.spread)
        written = round_params(fit.params)
        from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00

        dE = errors_delta_E_00(model, written, fit.thickness_nm, FIT_ANGLES_DEG, spec.film, spec.substrate,
                               spec.film_index_scale, spec.spread)
        out[model] = (written, dE.max(axis=1), dE[:, FIT_ANGLES_DEG <= 45.0].max(axis=1))
    if path is not None and cache is not None:
        from swatch.fileio import atomic_write_text

        for stale in path.parent.glob("presets-*.json"):
            stale.unlink(missing_ok=True)
        atomic_write_text(path, json.dumps({m: {"params": v[0].tolist(), "dE60": v[1].tolist(),
                                                "dE45": v[2].tolist()} for m, v in out.items()}))
    return out


def preset_bytes(fmt: str, ident: str, title: str, params, alpha: float, max_dE: float, thickness_nm: float) -> bytes:
    from swatch.presets import write

    rough = roughness_factor(alpha)
    note = (f"oxide {thickness_nm:g} nm; max ΔE2000 {max_dE:.2f} over facet angles 0–60° "
            "(D65, CIE 1931 2°)")
    if fmt == "gltf":
        return write.gltf_bytes(title, params, rough, extras={"swatch": {"thickness_nm": thickness_nm,
                                                                       "max_delta_E_00": round(max_dE, 2),
                                                                       "illuminant": "D65", "observer": "2",
                                                                       "facet_angles_deg": [0, 60]}})
    if fmt == "blender":
        return write.blender_bytes(title, params, rough, preset_file_name(ident, fmt), note)
    return write.materialx_bytes(title, params, rough)


def catalog_presets(spec, records: list[dict], cache: Path | None) -> dict[str, bytes]:
    """Add ``presets`` to each record; return {file name: bytes} of the preset files."""
    fits = _fits(spec, cache)
    files: dict[str, bytes] = {}
    for i, rec in enumerate(records):
        entry: dict = {}
        for fmt in PRESET_FORMATS:
            params, dE60, dE45 = (a[i] for a in fits[FORMAT_MODEL[fmt]])
            name = preset_file_name(rec["id"], fmt)
            title = f"{rec['id']} anodised {rec['thickness_nm']:g} nm"
            files[name] = preset_bytes(fmt, rec["id"], title, params, spec.roughness, float(dE60), rec["thickness_nm"])
            entry[fmt] = name
            entry[ERROR_KEYS[fmt]] = round(float(dE60), 2)
            entry[ERROR_KEYS[fmt] + "_45"] = round(float(dE45), 2)
        entry["conditions"] = "ΔE2000 vs exact colour, D65, CIE 1931 2°, facet angles 0–60° (_45: 0–45°)"
        rec["presets"] = entry
    return files


def single_preset(thickness_nm: float, fmt: str, film: str, substrate: str, film_index_scale: float,
                  roughness_alpha: float, spread=None) -> tuple[bytes, str]:
    """One thickness's preset in ``fmt``, fitted to its exact colour (``swatch preset``): the file's
    bytes and a line saying what was fitted and its largest ΔE2000 (D65, CIE 1931 2°)."""
    from swatch.presets import FORMAT_MODEL
    from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00, fit_presets

    d = np.array([float(thickness_nm)])
    model = FORMAT_MODEL[fmt]
    fit = fit_presets(d, model, (22.5,), film, substrate, film_index_scale, spread=spread)
    params = round_params(fit.params)
    dE = errors_delta_E_00(model, params, d, FIT_ANGLES_DEG, film, substrate, film_index_scale, spread)[0]
    data = preset_bytes(fmt, f"{d[0]:g}nm", f"anodised {d[0]:g} nm", params[0], roughness_alpha, float(dE.max()),
                        float(d[0]))
    p = params[0]
    summary = (f"{model} model, thickness {p[0]:g} nm, film IOR {p[1]:g}, base colour {p[2]:g} {p[3]:g} {p[4]:g} "
               f"(linear Rec.709); max ΔE2000 {dE.max():.2f} at 0–60°, {dE[FIT_ANGLES_DEG <= 45].max():.2f} at "
               f"0–45° (D65, 2°)")
    return data, summary
