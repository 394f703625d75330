"""Finish specification and quality control (issue 20): ``swatch spec`` and ``swatch check``.

* ``spec_pdf_ms=T`` — one spec (``--hex b08d57``, dE00:2: the match over every interference order,
  the multi-angle colours, the flop, the process window) and its PDF card written (median of repeats);
* ``check_100_parts_ms=T`` — 100 parts of one CSV file (CIELAB at the 6 distinct geometries of the spec, the
  model's colours at thicknesses 120 ± 4 nm) read and judged: ΔE per geometry, a thickness fit per part
  and the voltage correction; ``check_100_parts_failed=N`` says how many the tolerance failed.
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from benchmarks.timing import median_seconds, pick


def run() -> list[str]:
    import swatch  # noqa: F401  (silences colour-science's plotting notice)
    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.colorimetry.tolerance import parse_tolerance
    from swatch.io.instrument_files import read_instrument_file
    from swatch.io.instruments import Request
    from swatch.physics.process import load_process
    from swatch.production.card import write_spec_card
    from swatch.production.qc import check_file, load_spec_json
    from swatch.production.spec import finish_spec

    proc = load_process("titanium-fujii2019")
    tol = parse_tolerance("dE00:2")
    cm = get_colorimeter(proc.coating().wavelength_nm)
    target = {"kind": "hex", "value": "#b08d57"}
    from swatch.colorimetry.colorimeter import hex_to_Lab_2deg

    target["Lab"] = [float(v) for v in hex_to_Lab_2deg("b08d57", cm.display_colorimeter)]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)

        def spec_pdf():
            data = finish_spec(target, proc, tol)
            write_spec_card(data, folder / "spec.pdf")
            return data

        t_spec = median_seconds(spec_pdf, repeats=5)
        import json

        data = finish_spec({"kind": "thickness", "value": 120.0, "thickness_nm": 120.0}, proc, tol)
        (folder / "spec.json").write_text(json.dumps(data.document), encoding="utf-8")
        spec = load_spec_json(folder / "spec.json")
        coating = proc.coating()
        rng = np.random.default_rng(3)
        d = 120.0 + rng.uniform(-4.0, 4.0, pick(100, 5))
        lines = ["id,light_deg,view_deg,L,a,b"]
        seen = set()
        for e in [spec.document["reference"], *spec.document["multi_angle"]]:
            if (e["light_deg"], e["view_deg"], e["view_side"]) in seen:  # 45as45 is 45:0
                continue
            seen.add((e["light_deg"], e["view_deg"], e["view_side"]))
            va = None if e["view_side"] == "opposite" else 0.0
            R = coating.half_vector(d, e["light_deg"], e["view_deg"], 0.0, va)[0].R
            Lab = cm.Lab(cm.XYZ(R))
            signed = e["view_deg"] if e["view_side"] == "opposite" else -e["view_deg"]
            lines += [f"P{i:03d},{e['light_deg']:g},{signed:g},{L:.4f},{a:.4f},{b:.4f}"
                      for i, (L, a, b) in enumerate(Lab)]
        parts = folder / "parts.csv"
        parts.write_text("\n".join(lines) + "\n", encoding="utf-8")
        request = Request(illuminant="D65", observer="10")
        results = check_file(read_instrument_file(parts, request), spec)
        t_check = median_seconds(lambda: check_file(read_instrument_file(parts, request), spec), repeats=3)
    failed = sum(not r["pass"] for r in results)
    return [f"spec_pdf_ms={1000 * t_spec:.0f}", f"check_100_parts_ms={1000 * t_check:.0f} check_100_parts_failed={failed}"]
