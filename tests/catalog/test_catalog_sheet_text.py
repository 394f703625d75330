"""The sheets' label text fits its tile and says rounded numbers; ``catalog validate`` speaks the same way
(issue 21: ``window −4.0/+12.4 nm dEab≤6.!`` clipped at 295 nm, ``3D glTF11.4`` with no space at
175 nm, ``18.1036 nm · 10.0 V`` on voltage catalogs, ``grade None None`` for a ΔE00 tolerance)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from swatch.catalog.sheet_layout import Layout, chip_line, label_lines, label_width
from swatch.catalog.spec import load_spec
from swatch.io.drawing import text_width
from tests.cli_helpers import run_swatch

ROOT = Path(__file__).resolve().parents[2]

#: The widest a record's numbers get: a wide window, two-digit preset errors, negative a* and b*.
WORST = {"id": "S057", "thickness_nm": 295.04, "voltage_V": 145.2, "Lab": [-0.0, -45.5, -49.9],
         "LCh": [100.0, 67.5, 359.6], "srgb_hex": "#c1b2d3", "colour_name": "silver blue",
         "process_window": {"thickness_minus_nm": 14.0, "thickness_plus_nm": 112.4, "metric": "dEab", "max": 6.5},
         "delta_E_00_to_neighbours": {"previous": 10.5, "next": None},
         "presets": {"threejs_max_delta_E_00": 11.4, "blender_max_delta_E_00": 12.3, "materialx_max_delta_E_00": 10.5}}


def test_every_label_line_fits_its_tile():
    spec, _ = load_spec(ROOT / "catalog" / "titanium.toml")
    w = label_width(Layout(spec))
    title, *lines = label_lines(WORST)
    assert text_width(str(title), 18, "DroidSans-Bold") <= w
    for line in lines:
        text = chip_line(WORST) if line is None else line
        assert text_width(text, 15, "DroidSansMono") + (48 if line is None else 0) <= w, text
    assert "glTF 11.4 Bl 12.3 MtlX 10.5" in lines  # a space before every number
    assert "silver blue" in chip_line(WORST)  # the colour name, as the page and the ASE names say it


def test_voltage_catalogs_print_thickness_to_a_tenth_of_a_nanometre():
    rec = dict(WORST, thickness_nm=18.1036, voltage_V=10.0)
    assert label_lines(rec)[0] == "18.1 nm  ·  10.0 V"


@pytest.mark.parametrize(("tolerance", "want"), [
    ('metric = "dE00"\nmax = 2.0', "tolerance dE00 ≤ 2"),
    ('scheme = "csaj"\ngrade = "C"', "grade csaj C (dEab ≤ 6.5)"),
])
def test_catalog_validate_rounds_thicknesses_and_names_the_tolerance(tmp_path, tolerance, want):
    spec = tmp_path / "v.toml"
    spec.write_text(f'name = "v"\n[voltage]\nlist_V = [8.9, 10, 25.3]\n[tolerance]\n{tolerance}\n', encoding="utf-8")
    r = run_swatch("catalog", "validate", str(spec))
    assert r.returncode == 0, r.stderr
    assert "None" not in r.stdout and want in r.stdout
    assert re.search(r"\b18\.1–51\.4 nm \(8\.9–25\.3 V\)", r.stdout), r.stdout


def test_the_shipped_spec_comment_can_be_uncommented(tmp_path):
    """The comment under [tolerance] showed ``tolerance = {…}``, an error there once uncommented."""
    text = (ROOT / "catalog" / "titanium.toml").read_text(encoding="utf-8")
    text = re.sub(r'(?m)^scheme = "csaj".*\n^grade = "C".*\n', "", text)
    text = re.sub(r"(?m)^# (metric|max) = ", r"\1 = ", text)
    spec = tmp_path / "uncommented.toml"
    spec.write_text(text, encoding="utf-8")
    s, _ = load_spec(spec)
    assert (s.metric, s.max_delta_E, s.grade) == ("dE00", 2.0, None)
