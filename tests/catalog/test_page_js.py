"""The page's JavaScript under ``node --test`` (tests/js/), so CI runs it with the Python suite (issue 17
item 6): CIEDE2000 on the published pairs of Sharma, Wu & Dalal 2005 and on a fixture of colour-science values
written here, the chip-label ink, and find by colour (match) and the process window of colour.js against what
the Python side computes for the same catalog (swatch.fit.matching.match_colour, judge_candidates and
swatch.catalog.records.process_window, written into the fixture here); the page's address (link.js: the view a
fragment such as ``#thickness=140&lighting=point`` opens, what it leaves out)."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import colour
import numpy as np
import pytest

from swatch.catalog.context import catalog_context
from swatch.catalog.explorer import explorer_data
from swatch.catalog.spec import parse_spec
from swatch.colorimetry.observers import hex_to_document_Lab
from swatch.colorimetry.tolerance import get_tolerance
from swatch.colorimetry.window import process_window
from swatch.fit.matching import judge_candidates, match_colour
from swatch.physics.microfacet import D_ratio, ggx_reflectance_factor_cos

ROOT = Path(__file__).resolve().parents[2]


def _node() -> str:
    exe = shutil.which("node")
    if exe:
        return exe
    if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
        pytest.fail("node is missing and SWATCH_REQUIRE_TOOLS=1 (.ci/run installs nodejs)")
    pytest.skip("node not installed (Debian: nodejs)")


#: Targets of the find-by-colour fixture: L*a*b* in the catalog's observer and sRGB hex codes (2°), two of them
#: outside what the film shows (a saturated green, an L*a*b* outside sRGB).
MATCH_TARGETS = ({"Lab": [70.0, 5.0, 30.0]}, {"Lab": [40.0, 10.0, -40.0]}, {"Lab": [50.0, -90.0, 60.0]},
                 {"hex": "#2275b5"}, {"hex": "#c65ebf"}, {"hex": "#00ff00"})
#: Tolerances of the fixture, each in its own metric (the same bound 2 in ΔE*ab and in ΔE2000, and two more).
TOLERANCES = (("dEab", 2.0), ("dE00", 2.0), ("dEab", 4.0), ("dE00", 1.0))
#: Nominal thicknesses of the process-window fixture (nm); the first and the last lie within a window of the
#: catalog's range ends (20 and 300 nm), where the page's table stops.
WINDOW_NM = (20.3, 25.0, 50.8, 90.0, 140.0, 200.0, 299.6)


def _search_fixture() -> dict:
    """The page's colour table of a small catalog (20–300 nm) and what the Python side answers on it: the
    match candidates of each target (as ``swatch match`` over the catalog's range at the reference geometry,
    a hex in 2° colorimetry as ``swatch match --hex``) with their within-tolerance flags, and the process
    windows of :data:`WINDOW_NM` in each tolerance's metric."""
    spec = parse_spec({"name": "node fixture", "thickness": {"start_nm": 20, "stop_nm": 300, "step_nm": 70}})
    ctx = catalog_context(spec)
    table = explorer_data(ctx)
    ref = spec.reference
    col = table["reference"]["thickness_nm"]
    lo, hi = col["start"], col["start"] + col["step"] * (col["count"] - 1)
    matches = []
    for target in MATCH_TARGETS:
        cm = ctx.colorimeter  # a hex in the catalog's observer (swatch.colorimetry.observers), as a Lab target
        Lab = np.asarray(target["Lab"]) if "Lab" in target else hex_to_document_Lab(target["hex"], cm)
        res = match_colour(Lab, ctx.coating, cm, ref.light_deg, ref.view_deg, 0.0, ref.view_azimuth_deg,
                           thickness_range=(lo, hi), step_nm=col["step"], top=5)
        within = {}
        for metric, bound in TOLERANCES:
            judge_candidates(res, spec.voltage_of, get_tolerance(metric=metric, max=bound))
            within[f"{metric}<={bound:g}"] = [c["within_grade"] for c in res.candidates]
        matches.append({"target": target, "target_Lab": [float(v) for v in Lab], "within": within,
                        "candidates": [{k: c[k] for k in ("thickness_nm", "voltage_V", "delta_E_00", "delta_E_ab")}
                                       for c in res.candidates]})
    windows = []
    d = np.asarray(WINDOW_NM)
    for metric, bound in TOLERANCES:
        minus, plus, mcap, pcap = process_window(ctx.coating, ctx.colorimeter, d, ref, bound, spec.search_nm, metric)
        windows.append({"metric": metric, "bound": bound, "search_nm": spec.search_nm, "thickness_nm": d.tolist(),
                        "minus_nm": minus.tolist(), "plus_nm": plus.tolist(),
                        "minus_capped": mcap.tolist(), "plus_capped": pcap.tolist()})
    rng = np.random.default_rng(21)
    cl, cv, ch = rng.uniform(0.01, 1.0, (3, 300))
    alpha = rng.uniform(0.02, 1.0, 300)
    ggx = [[float(x) for x in (l, v, h, a, ggx_reflectance_factor_cos(l, v, h, a), D_ratio(h, a))]
           for l, v, h, a in zip(cl, cv, ch, alpha, strict=True)]
    return {"table": table, "range_nm": [lo, hi], "match": matches, "window": windows, "ggx": ggx}


def _growth_fixture() -> list[dict]:
    """swatch.physics.growth's answers (one slope with an offset; two slopes with a knee), for colour.js's
    voltageOf / thicknessOf, the page's one growth law (#36)."""
    from swatch.physics.growth import thickness_to_voltage_V, voltage_to_thickness_nm

    laws = [{"nm_per_V": 2.032, "offset_nm": 3.0, "knee_V": None, "nm_per_V_above_knee": None},
            {"nm_per_V": 2.5, "offset_nm": 0.0, "knee_V": 40.0, "nm_per_V_above_knee": 1.2}]
    out = []
    for law in laws:
        volts = np.linspace(0.0, 120.0, 25)
        knee = {} if law["knee_V"] is None else {"knee_V": law["knee_V"],
                                                 "nm_per_V_above_knee": law["nm_per_V_above_knee"]}
        d = voltage_to_thickness_nm(volts, law["nm_per_V"], law["offset_nm"], **knee)
        back = thickness_to_voltage_V(d, law["nm_per_V"], law["offset_nm"], **knee)
        out.append({"law": law, "voltage_V": volts.tolist(), "thickness_nm": np.asarray(d).tolist(),
                    "voltage_back_V": np.asarray(back).tolist()})
    return out


@pytest.mark.slow  # 6.5 s: the small catalog's table and the Python matches and windows of the fixture
def test_page_colorimetry_passes_node_test(tmp_path):
    node = _node()
    rng = np.random.default_rng(17)
    lab1 = np.column_stack([rng.uniform(0, 100, 300), rng.uniform(-90, 90, 300), rng.uniform(-90, 90, 300)])
    lab2 = lab1 + rng.normal(0, 6, lab1.shape)  # near pairs, where the hue branches of the formula switch
    lab2[:100] = np.column_stack([rng.uniform(0, 100, 100), rng.uniform(-90, 90, 100), rng.uniform(-90, 90, 100)])
    lab2[:, 0] = np.clip(lab2[:, 0], 0, 100)
    want = colour.delta_E(lab1, lab2, method="CIE 2000")
    fixture = tmp_path / "fixture.json"
    fixture.write_text(json.dumps({"delta_E_00": [[a.tolist(), b.tolist(), float(d)]
                                                  for a, b, d in zip(lab1, lab2, want, strict=True)],
                                   "growth": _growth_fixture(), **_search_fixture()}), encoding="utf-8")
    tests = sorted(str(p) for p in (ROOT / "tests" / "js").glob("*.test.mjs"))
    run = subprocess.run([node, "--test", *tests], capture_output=True,
                         text=True, timeout=120, env={**os.environ, "SWATCH_JS_FIXTURE": str(fixture)})
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert "# pass 16" in run.stdout and "# skipped 0" in run.stdout, run.stdout[-1500:]


def test_page_script_comments_name_code_that_exists():
    """Issue 17 item 6: the page's comments cited pre-restructure names (swatch.microfacet..., swatch.env_shading,
    swatch.fitting.match_colour); every dotted ``swatch.…`` name in swatch/catalog/web/*.js must resolve (a
    module, then attributes)."""
    import importlib
    import re

    missing = []
    for path in sorted((ROOT / "swatch" / "catalog" / "web").glob("*.js")):
        for name in sorted(set(re.findall(r"\bswatch(?:\.[A-Za-z_][A-Za-z0-9_]*)+", path.read_text(encoding="utf-8")))):
            parts = name.split(".")
            for cut in range(len(parts), 0, -1):  # the longest importable module, then attributes
                try:
                    obj = importlib.import_module(".".join(parts[:cut]))
                except ImportError:
                    continue
                try:
                    for attr in parts[cut:]:
                        obj = getattr(obj, attr)
                except AttributeError:
                    missing.append(f"{path.name}: {name}")
                break
            else:
                missing.append(f"{path.name}: {name}")
    assert missing == []


def test_ggx_is_written_once_in_the_page_javascript():
    """Issue 17 item 6: GGX once per language. The page had it twice (the point-light shader and the exposure rule
    in view.js); now only microfacet.js writes its terms, in JavaScript and in GLSL, and view.js calls them."""
    import re

    web = ROOT / "swatch" / "catalog" / "web"
    ggx_terms = re.compile(r"a2\s*-\s*1(\.0)?\b|1(\.0)?\s*-\s*a2\b|\ba2\s*\*\s*a2\b")
    for path in sorted(web.glob("*.js")):
        hits = ggx_terms.findall(path.read_text(encoding="utf-8"))
        assert (len(hits) > 0) == (path.name == "microfacet.js"), (path.name, hits)
    view = (web / "view.js").read_text(encoding="utf-8")
    assert "${GGX_GLSL}" in view and "ggxReflectanceFactorCos(cl, cv, ch, alpha)" in view and "ggxDRatio(" in view


def test_the_growth_law_is_written_once_in_the_page_javascript():
    """Issue 36: page.js and colour.js both wrote the two-slope growth law; now colour.js alone (voltageOf,
    thicknessOf: swatch.physics.growth's law, checked against it by the node test above) and page.js calls it."""
    web = ROOT / "swatch" / "catalog" / "web"
    for path in sorted(web.glob("*.js")):
        hits = path.read_text(encoding="utf-8").count("nm_per_V_above_knee")
        assert (hits > 0) == (path.name == "colour.js"), (path.name, hits)
    page = (web / "page.js").read_text(encoding="utf-8")
    assert "voltageOf(cat.catalog.process, d)" in page and "thicknessOf(cat.catalog.process, v)" in page
