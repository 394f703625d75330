"""The command line takes what users type (issue 21): unit suffixes, ``A:B`` with the unit's default step,
whitespace-separated L*a*b*, ``colour`` for ``color``, and near-miss names answered with a suggestion."""
from __future__ import annotations

import json

import numpy as np
import pytest

from swatch.core.errors import SwatchError
from swatch.core.ranges import DEFAULT_STEP, parse_range
from tests.cli_helpers import run_json, run_swatch


@pytest.mark.parametrize("text", ["50", "50nm", "50 nm", " 50NM ", "50.0 nm"])
def test_thickness_takes_its_unit(text):
    assert parse_range(text, "thickness", "nm").tolist() == [50.0]


@pytest.mark.parametrize(("text", "want"), [("25V", [25.0]), ("25 V", [25.0]), ("20V,25V", [20.0, 25.0]),
                                            ("20V:21V:0.5V", [20.0, 20.5, 21.0])])
def test_voltage_takes_its_unit(text, want):
    assert parse_range(text, "voltage", "V").tolist() == want


def test_a_range_without_step_takes_the_units_default():
    assert DEFAULT_STEP == {"nm": 1.0, "V": 0.5, "deg": 1.0}
    d = parse_range("20:300", "thickness", "nm")
    assert d[0] == 20 and d[-1] == 300 and len(d) == 281 and np.allclose(np.diff(d), 1.0)
    assert parse_range("10V:12V", "voltage", "V").tolist() == [10.0, 10.5, 11.0, 11.5, 12.0]


@pytest.mark.parametrize("text", ["50 V", "50mm", "nm", "5:6:7:8"])
def test_a_wrong_unit_or_shape_is_still_refused(text):
    with pytest.raises(SwatchError):
        parse_range(text, "thickness", "nm")


def test_colour_is_color_and_takes_the_suffixes():
    a = run_json("colour", "--thickness", "50nm")["rows"]
    b = run_json("color", "--thickness", "50")["rows"]
    assert a == b
    v = run_json("color", "--voltage", "25V")["rows"]
    assert v[0]["voltage_V"] == 25.0


def test_color_voltage_prints_a_voltage_column():
    r = run_swatch("color", "--voltage", "20,25")
    assert r.returncode == 0, r.stderr
    head, *rows = r.stdout.splitlines()[1:]
    assert head.split()[:2] == ["d_nm", "volt_V"]
    assert [float(x.split()[1]) for x in rows] == [20.0, 25.0]


def test_match_takes_whitespace_separated_lab():
    a = run_json("match", "--lab", "60 5 30", "--top", "1")["candidates"]
    b = run_json("match", "--lab", "60,5,30", "--top", "1")["candidates"]
    assert a == b


@pytest.mark.parametrize(("args", "hint"), [
    (["colr", "--thickness", "50"], "did you mean 'color'?"),
    (["rendr"], "did you mean 'render'?"),
    (["color", "--illuminant", "F11", "--thickness", "50"], "did you mean 'FL11'?"),
])
def test_near_misses_get_a_suggestion(args, hint):
    r = run_swatch(*args)
    assert r.returncode == 2
    assert r.stderr.startswith("error: ") and hint in r.stderr and r.stderr.count("\n") == 1, r.stderr


def test_an_unknown_command_lists_the_commands():
    r = run_swatch("xyzzy")
    assert r.returncode == 2 and "no such command 'xyzzy'; the commands: angular," in r.stderr


def test_top_level_help_lists_whole_summaries_that_fit_80_columns():
    """Issue 21: ``swatch --help`` cut the commands' first sentences with "..."; each has a short summary."""
    from swatch.cli import COMMANDS, SUMMARIES

    assert set(SUMMARIES) == set(COMMANDS)
    proc = run_swatch("--help")
    assert proc.returncode == 0
    listed = proc.stdout.split("Commands:")[1].splitlines()
    for name in COMMANDS:
        line = next(x for x in listed if x.split()[:1] == [name])
        assert line.split(None, 1) == [name, SUMMARIES[name]]
    assert not any("..." in x or "…" in x for x in listed)
    assert max(len(x) for x in proc.stdout.splitlines()) <= 80


@pytest.mark.parametrize("width", [40, 50, 60, 72, 80, 100])
def test_fit_help_never_breaks_a_column_name(width):
    """Issue 21: ``fit --help`` broke a column name mid-word (the names were one long comma-joined word)."""
    from click.testing import CliRunner

    from swatch.commands.fit import fit

    text = CliRunner().invoke(fit, ["--help"], terminal_width=width).output
    words = set(text.replace(",", " ").replace("[", " ").replace("]", " ").split())
    for column in ("wavelength_nm", "reflectance", "light_deg", "view_deg", "light_azimuth_deg", "view_azimuth_deg"):
        assert column in words, (width, column)


def test_preset_roughness_defaults_to_the_process_profiles(tmp_path):
    """Issue 21: ``preset --roughness`` defaulted to 0.3 where render and angular take the profile's."""
    profile = tmp_path / "line.toml"
    profile.write_text('name = "rough-line"\nfilm = "TiO2-Siefke"\nsubstrate = "Ti-Johnson"\nnm_per_V = 2.0\n'
                       "roughness = 0.5\n", encoding="utf-8")
    args = ("preset", "--thickness", "80", "--format", "gltf", "--process", str(profile))
    assert run_swatch(*args, "--out", tmp_path / "a").returncode == 0
    assert run_swatch(*args, "--roughness", "0.5", "--out", tmp_path / "b").returncode == 0
    a, b = (tmp_path / d / "preset_80nm.gltf" for d in "ab")
    assert a.read_bytes() == b.read_bytes()
    material = json.loads(a.read_text())["materials"][0]
    assert material["pbrMetallicRoughness"]["roughnessFactor"] == pytest.approx(0.5 ** 0.5, abs=1e-4)
