"""The page's JavaScript under ``node --test`` (tests/js/), so CI runs it with the Python suite (issue 17
item 6): CIEDE2000 on the published pairs of Sharma, Wu & Dalal 2005 and on a fixture of colour-science values
written here, and the chip-label ink."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import colour
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def _node() -> str:
    exe = shutil.which("node")
    if exe:
        return exe
    if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
        pytest.fail("node is missing and SWATCH_REQUIRE_TOOLS=1 (.ci/run installs nodejs)")
    pytest.skip("node not installed (Debian: nodejs)")


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
                                                  for a, b, d in zip(lab1, lab2, want, strict=True)]}), encoding="utf-8")
    run = subprocess.run([node, "--test", str(ROOT / "tests" / "js" / "colour.test.mjs")], capture_output=True,
                         text=True, timeout=120, env={**os.environ, "SWATCH_JS_FIXTURE": str(fixture)})
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert "# pass 3" in run.stdout and "# skipped 0" in run.stdout, run.stdout[-1500:]


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
