"""The library speaks parameters, the CLI speaks flags (issue #17): library errors name the Python
parameter in backquotes; the CLI rewrites them as its options before printing the one-line error."""
from __future__ import annotations

import ast
import re
from pathlib import Path

from swatch.commands.flags import PARAMETER_FLAGS, speak_flags
from swatch.core.errors import SwatchError
from swatch.fit.matching import match_colour

PKG = Path(__file__).resolve().parents[2] / "swatch"

#: Library modules whose errors still name CLI flags, each with its reason (to convert with their owners).
STILL_NAMING_FLAGS: dict[str, str] = {}


def test_parameters_are_spoken_as_flags():
    """Issue #17: `size_px` -> --size, `environment='point'` -> --environment point, values kept."""
    assert speak_flags("use a smaller `size_px`, or `environment='point'`") == "use a smaller --size, or --environment point"
    assert speak_flags("use `model='microfacet'` `distribution='ggx'`") == "use --model microfacet --distribution ggx"
    assert speak_flags("fit without it (`fit_scale=False`)") == "fit without it (--fixed-scale)"
    assert speak_flags("`unknown_thing` stays") == "`unknown_thing` stays"
    assert speak_flags("no parameter here") == "no parameter here"


def test_a_library_error_names_the_parameter_and_the_cli_its_flag():
    """Issue #17: the same check reads ``top`` in Python and ``--top`` on the command line."""
    import numpy as np
    import pytest

    from swatch.colorimetry.colorimeter import get_colorimeter
    from swatch.physics.model import get_coating

    coating = get_coating()
    with pytest.raises(SwatchError) as info:
        match_colour(np.array([50.0, 0.0, -20.0]), coating, get_colorimeter(coating.wavelength_nm), top=0)
    assert "`top`" in str(info.value) and "--top" not in str(info.value)
    assert speak_flags(str(info.value)).startswith("--top ")


def _flag_literals(path: Path) -> list[str]:
    """String pieces of ``SwatchError(...)`` calls in a module that name a CLI option (``--word``)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "SwatchError":
            for sub in ast.walk(node):
                if isinstance(sub, ast.Constant) and isinstance(sub.value, str) and re.search(r"(^|\s|\()--[a-z]", sub.value):
                    found.append(sub.value)
    return found


def test_library_errors_name_parameters_not_flags():
    """Issue #17: outside commands/ and the CLI no error names a flag (but the listed modules, for now)."""
    offenders = {}
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG).as_posix()
        if rel.startswith("commands/") or rel == "cli.py" or rel in STILL_NAMING_FLAGS:
            continue
        if lits := _flag_literals(path):
            offenders[rel] = lits
    assert offenders == {}


def test_every_mapped_flag_is_an_option_of_some_command():
    """The table maps to real options (a renamed option would leave a dead entry)."""
    import click

    from swatch.cli import COMMANDS, cli

    ctx = click.Context(cli)
    options = set()
    for name in COMMANDS:
        stack = [cli.get_command(ctx, name)]
        while stack:
            cmd = stack.pop()
            stack += list(getattr(cmd, "commands", {}).values())
            options |= {o for p in cmd.params for o in [*getattr(p, "opts", []), *getattr(p, "secondary_opts", [])]}
    assert set(PARAMETER_FLAGS.values()) - options == set()


def test_thickness_voltage_and_angles_are_checked_once_and_spoken_as_the_callers_words(tmp_path):
    """Issue #17, "one way through the code": the library's one thickness / voltage / angle check names the
    parameter (`thickness_nm`, `voltage_V`, `light_deg`, `view_deg`); ``swatch render`` says --thickness,
    --voltage, --light, --view, checks the whole range before writing anything, and the value out of range is
    in the message."""
    import pytest

    from swatch.physics.growth import voltage_to_thickness_nm
    from swatch.render import render_swatch
    from tests.cli_helpers import assert_one_line_error, run_swatch

    with pytest.raises(SwatchError, match=r"^`thickness_nm` must be a number from 0 to 1000 nm \(got 1200\)$"):
        render_swatch(1200.0, "flat", 8)
    with pytest.raises(SwatchError, match=r"^`light_deg` must be in \[0, 90\) degrees from the normal \(got 95\)$"):
        render_swatch(50.0, "flat", 8, light_deg=95.0, environment="point")
    with pytest.raises(SwatchError, match=r"^`voltage_V` 250 V gives a 1250 nm film by the growth law"):
        voltage_to_thickness_nm(250.0, nm_per_V=5.0)  # within the voltage cap, beyond the thickness cap
    out = tmp_path / "out"
    cases = [(["--thickness", "100,1200"], "--thickness must be a number from 0 to 1000 nm (got 1200)"),
             (["--voltage", "-3"], "--voltage must be a number from 0"),
             (["--thickness", "100", "--light", "95"], "--light must be in [0, 90) degrees from the normal (got 95)"),
             (["--thickness", "100", "--view", "-1"], "--view must be in [0, 90)")]
    for args, words in cases:
        proc = run_swatch("render", *args, "--size", "8", "--out", out)
        assert_one_line_error(proc, words)
        assert "`" not in proc.stderr and not out.exists()


def test_every_cli_option_has_help():
    """Issue #17 item 5: a command's parameters are documented by its options' ``help=`` (its docstring is the
    ``--help`` text), so scripts/numpydoc_count.py counts a click command with a docstring; this keeps that true."""
    import click

    from swatch.cli import COMMANDS, cli

    ctx = click.Context(cli)
    bare = []
    for name in COMMANDS:
        stack = [(name, cli.get_command(ctx, name))]
        while stack:
            path, cmd = stack.pop()
            stack += [(f"{path} {n}", c) for n, c in getattr(cmd, "commands", {}).items()]
            assert (cmd.help or "").strip(), f"{path} has no help text"
            bare += [f"{path} {p.opts[0]}" for p in cmd.params
                     if isinstance(p, click.Option) and not (p.help or "").strip() and p.opts[0] != "--help"]
    assert bare == []
