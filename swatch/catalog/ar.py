"""AR on the catalog page (``[presets] ar``): ``<model-viewer>`` files fitted to what it shows, and the page's control.

:func:`viewer_presets` fits the ``modelviewer`` model (:mod:`swatch.presets.modelviewer`: Google's
``<model-viewer>`` 4.4.0, its bundled three.js r183, in an even white surround) for every swatch and returns
the files to write — one shared part ``presets/viewer_part.bin`` (the catalog's ``[render] mesh``, else a
sphere; :mod:`swatch.presets.viewer`), one small glTF per swatch ``presets/preset_S001_viewer.gltf``, and the
vendored script and its licence beside them (:data:`SCRIPT`, :data:`LICENCE`) — and each record's
additions to its ``presets`` entry::

    "viewer": "presets/preset_S001_viewer.gltf", "modelviewer_max_delta_E_00": 1.9,
    "modelviewer_max_delta_E_00_45": 1.2

(ΔE2000 against the exact colour, D65, CIE 1931 2°, the model evaluated with the parameters as written, max over
view angles 0–60° / 0–45° from the normal, compared with the exact colour at that facet angle).
:func:`ar_control_html` writes a card's "see it in your room" control; web/ar.js loads the script on first use.
"""
from __future__ import annotations

import html
import re
from importlib import resources

import numpy as np

from swatch.catalog.layout import PRESETS
from swatch.catalog.preset_fit import fit_model
from swatch.presets import modelviewer
from swatch.presets.files import roughness_factor, round_params
from swatch.presets.fit import FIT_ANGLES_DEG, errors_delta_E_00
from swatch.presets.naming import preset_file_name
from swatch.presets.viewer import PART_BIN, mesh_part, part_bin, sphere_part, viewer_gltf_bytes

__all__ = ["SCRIPT", "LICENCE", "RENDERER", "STYLE", "viewer_fit", "viewer_presets", "ar_control_html", "ar_csp",
           "has_viewer", "vendored_files"]

#: The vendored ``<model-viewer>`` (an ES module bundling three.js r183, lit), beside the viewer files.
SCRIPT = f"{PRESETS}/model-viewer-{modelviewer.VERSION}.min.js"
#: Its licence (Apache-2.0), beside it.
LICENCE = f"{PRESETS}/model-viewer-{modelviewer.VERSION}-LICENSE.txt"
#: How the ``modelviewer_*`` figures are measured (the record's ``renderers``).
RENDERER = (f"<model-viewer> {modelviewer.VERSION} (three.js {modelviewer.THREE_REVISION} "
            "MeshPhysicalMaterial), even white surround, tone mapping off, relative to a white metal; "
            "view 0–60° from the normal against the exact colour at that facet angle")

#: The control's style (the page's stylesheet gets it only with AR, so a page without is unchanged).
STYLE = """
.ar { margin-top: .35em; font-size: .8rem; }
.ar-open, .ar-place { font: inherit; padding: .25em .6em; border: 1px solid #888; border-radius: 4px;
  background: #fff; color: #111; cursor: pointer; }
.ar-note { display: block; color: #555; margin-top: .2em; }
.ar model-viewer { display: block; width: 100%; height: 240px; margin-top: .35em; background: #eee; }
.ar-place { position: absolute; bottom: 8px; right: 8px; }
"""


def has_viewer(swatches: list[dict]) -> bool:
    """Whether the catalog's records name viewer files (the build wrote them: ``[presets] ar`` on).

    Parameters
    ----------
    swatches : list of dict
        ``catalog.json``'s swatch records.

    Returns
    -------
    bool
        True when any record's ``presets`` entry has a ``viewer`` file name.
    """
    return any(isinstance((s.get("presets") or {}).get("viewer"), str) for s in swatches)


def vendored_files() -> dict[str, bytes]:
    """The vendored ``<model-viewer>`` script and its licence, as the catalog folder carries them.

    Returns
    -------
    dict
        {:data:`SCRIPT`: bytes, :data:`LICENCE`: bytes}, copied unmodified from the npm package.
    """
    base = resources.files("swatch.catalog").joinpath("web", "model-viewer")
    return {SCRIPT: base.joinpath("model-viewer.min.js").read_bytes(),
            LICENCE: base.joinpath("LICENSE").read_bytes()}


def viewer_fit(spec) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``modelviewer`` model fitted for every swatch of ``spec`` (coupled within a sheet, as the other presets;
    the catalog's geometries up to 60° weigh in), rounded as written, and its errors.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Parameters (N, 5) (thickness nm, film IOR, base linear Rec.709) and each swatch's largest ΔE2000 (D65,
        CIE 1931 2°) over view angles 0–60° and 0–45° (N,), against the exact colour at that facet angle.
    """
    d = np.asarray(spec.thickness_nm, dtype=np.float64)
    rough = roughness_factor(spec.roughness)
    fit = fit_model(spec, "modelviewer")
    params = round_params(fit.params)
    dE = errors_delta_E_00("modelviewer", params, d, FIT_ANGLES_DEG, spec.film, spec.substrate,
                           spec.film_index_scale, spec.spread, rough)
    return params, dE.max(axis=1), dE[:, FIT_ANGLES_DEG <= 45.0].max(axis=1)


def viewer_presets(spec, records: list[dict], mesh=None) -> tuple[dict[str, bytes], list[dict]]:
    """The viewer files of a catalog and each record's additions to its ``presets`` entry.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (JSON view; read only).
    mesh : swatch.render.mesh.MeshShape, optional
        The catalog's part (None: a sphere).

    Returns
    -------
    (dict, list of dict)
        {file name: bytes} (the part, the viewer files, the script and licence) and one entry per record.
    """
    params, worst60, worst45 = viewer_fit(spec)
    rough = roughness_factor(spec.roughness)
    blob, part = part_bin(*(sphere_part() if mesh is None else mesh_part(*mesh.triangle_soup())))
    files = {f"{PRESETS}/{PART_BIN}": blob, **vendored_files()}
    entries = []
    for i, rec in enumerate(records):
        name = f"{PRESETS}/{preset_file_name(rec['id'], 'viewer')}"
        extras = {"fitted_to": RENDERER, "max_delta_E_00": round(float(worst60[i]), 2),
                  "thickness_nm": rec["thickness_nm"]}
        files[name] = viewer_gltf_bytes(f"{rec['id']} anodised {rec['thickness_nm']:g} nm", params[i],
                                        rough, part, extras)
        entries.append({"viewer": name, "modelviewer_max_delta_E_00": round(float(worst60[i]), 2),
                        "modelviewer_max_delta_E_00_45": round(float(worst45[i]), 2)})
    return files, entries


def ar_csp(csp: str) -> str:
    """The page's content security policy with what the viewer needs: the vendored script (``'self'``), the
    WebAssembly it compiles on loading (three.js's meshopt decoder, embedded in the script:
    ``'wasm-unsafe-eval'``, which allows no JavaScript ``eval``), its requests for the viewer files
    (``connect-src 'self'``) and the textures it makes (``blob:``).

    Parameters
    ----------
    csp : str
        The page's policy without AR (``script-src`` and ``img-src`` present).

    Returns
    -------
    str
        The policy with those sources added.
    """
    return (csp.replace("script-src ", "script-src 'self' 'wasm-unsafe-eval' ", 1).replace("img-src 'self'", "img-src 'self' blob: data:", 1)
            + "; connect-src 'self' blob: data:")


#: A file the control names: a relative path of plain characters (as the build writes ``presets/…``).
_FILE = re.compile(r"[A-Za-z0-9_-]+(/[A-Za-z0-9_-]+)*\.[a-z]+")


def _num(x) -> str:
    return f"{x:.1f}" if isinstance(x, (int, float)) else "–"


def ar_control_html(s: dict) -> str:
    """A card's "see it in your room" control: a button that opens the ``<model-viewer>`` (AR on phones; Quick
    Look's USDZ when the record has one), with the measured colour error and the Quick Look note beside it.

    Parameters
    ----------
    s : dict
        A swatch record (``catalog.json``); its ``presets`` entry names the viewer file.

    Returns
    -------
    str
        The control's HTML ("" when the record has no viewer file).
    """
    p = s.get("presets") or {}
    viewer, usdz = p.get("viewer"), p.get("usdz")
    if not (isinstance(viewer, str) and _FILE.fullmatch(viewer) and viewer.endswith(".gltf")):
        return ""  # none, or not a plain relative path (a record read back is not trusted to name anything else)
    usdz = usdz if isinstance(usdz, str) and _FILE.fullmatch(usdz) and usdz.endswith(".usdz") else None
    e = html.escape
    note = (f'colour error of the 3-D view: ΔE00 ≤ {_num(p.get("modelviewer_max_delta_E_00_45"))} at 0–45°, '
            f'≤ {_num(p.get("modelviewer_max_delta_E_00"))} at 0–60° (measured in &lt;model-viewer&gt; '
            f"{modelviewer.VERSION}, even white light)")
    if usdz:
        ql = p.get("usd_preview_max_delta_E_00")
        note += ("; iPhone and iPad (Quick Look) show a fixed colour that does not change with the angle"
                 + (f", ΔE00 ≤ {_num(ql)}" if isinstance(ql, (int, float)) else ""))
    data = f' data-ios-src="{e(usdz)}"' if usdz else ""
    return (f'<div class="ar"><button type="button" class="ar-open" data-viewer="{SCRIPT}" data-src="{e(viewer)}"{data} '
            f'aria-label="see it in your room: {e(s["id"])} in 3-D (AR on phones)">see it in your room</button>'
            f'<span class="ar-note">{note}</span></div>')
