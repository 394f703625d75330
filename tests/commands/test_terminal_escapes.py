"""Issue 49 item 4: nothing read from a file drives the terminal. `swatch check` printed part names from CSV,
CGATS and CxF raw (a CSV id ``ESC [2J`` cleared the screen, a CGATS name ``ESC ]0;…BEL`` set the window
title, OSC 52 would write the clipboard); now every human-readable line (reports, ``error: …`` lines,
warnings, whatever a library prints) shows C0/C1 controls and bidi overrides escaped, the name still
readable, and ``--json`` stays the bytes of the JSON file the command writes."""
from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from swatch.commands.terminal import EscapingStream, escaped_output, unescaped
from swatch.core.escapes import printable
from tests.cli_helpers import assert_one_line_error, run_swatch

#: What must never reach the terminal raw: C0 controls but tab and newline, DEL, C1 controls, the bidi
#: marks, embeddings, overrides and isolates (written out here, not taken from swatch.core.escapes).
RAW = re.compile("[\x00-\x08\x0b-\x1f\x7f\x80-\x9f\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e"
                 "\u2066\u2067\u2068\u2069]")

CLEAR = "P1\x1b[2J"  # erase the screen
TITLE = "P2\x1b]0;pwned\x07"  # set the window title
CLIPBOARD = "P3\x1b]52;c;aGk=\x07"  # write the clipboard (OSC 52)
CSI8 = "P4\x9b2J"  # the C1 CSI: erase the screen on a terminal that takes 8-bit controls
RLO = "P5\u202egnp.exe"  # shown as "P5exe.png"
ISOLATE = "P6\u2066x\u2069\u200f"
HOSTILE = [CLEAR, TITLE, CLIPBOARD, CSI8, RLO, ISOLATE]


def _shown(name: str) -> str:
    """How the name must read on the terminal: each unsafe character as \\uXXXX."""
    return "".join(f"\\u{ord(c):04x}" if RAW.match(c) else c for c in name)


def _assert_safe(proc: subprocess.CompletedProcess, names=()) -> None:
    for stream in (proc.stdout, proc.stderr):
        found = RAW.findall(stream)
        assert not found, f"raw {sorted(set(found))!r} in {stream!r}"
    for name in names:
        assert _shown(name) in proc.stdout, (_shown(name), proc.stdout)


def _csv(path, names):
    rows = "".join(f'"{n}",45,0,{50 + k},-8,-34\n' for k, n in enumerate(names))
    path.write_text("id,light_deg,view_deg,L,a,b\n" + rows, encoding="utf-8")
    return path


def _cgats(path, names):
    rows = "".join(f'{k + 1} "{n}" {50 + k} -8.5 -34.2\n' for k, n in enumerate(names))
    path.write_text('CGATS.17\nORIGINATOR "test"\nMEASUREMENT_GEOMETRY "45/0"\n'
                    'MEASUREMENT_SOURCE "Illumination=D65 ObserverAngle=10"\nNUMBER_OF_FIELDS 5\n'
                    "BEGIN_DATA_FORMAT\nSampleID SAMPLE_NAME LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\n"
                    f"NUMBER_OF_SETS {len(names)}\nBEGIN_DATA\n{rows}END_DATA\n", encoding="utf-8")
    return path


def _cxf(tmp_path, names):
    """The shipped multi-part CxF3 with its first parts renamed (XML 1.0 allows C1 and bidi characters in a
    name, as character references or raw; it has no C0 but tab and newline)."""
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "examples" / "parts.cxf").read_text(encoding="utf-8")
    for k, n in enumerate(names):
        ref = "".join(f"&#x{ord(c):x};" if RAW.match(c) else c for c in n)
        text = text.replace(f'Name="P{k + 1}" Id="P{k + 1}"', f'Name="{ref}" Id="id{k + 1}"')
    path = tmp_path / "parts.cxf"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("fmt", ["csv", "cgats", "cxf"])
def test_issue49_check_shows_hostile_part_names_escaped(tmp_path, fmt):
    if fmt == "cxf":
        names = [CSI8, RLO, ISOLATE]  # (XML 1.0 has no ESC, BEL or other C0 controls)
        path = _cxf(tmp_path, names)
    else:
        names = HOSTILE
        path = (_csv if fmt == "csv" else _cgats)(tmp_path / f"parts.{'csv' if fmt == 'csv' else 'txt'}", names)
    proc = run_swatch("check", path, "--thickness", "120")
    assert proc.returncode in (0, 1), proc.stderr  # (pass or fail: judged)
    _assert_safe(proc, names)
    parts = 5 if fmt == "cxf" else len(names)  # (the shipped CxF has 5 parts)
    assert len([line for line in proc.stdout.splitlines() if re.match(r"P\d", line)]) == parts


def test_issue49_json_keeps_its_bytes_and_escapes_the_c0_controls_itself(tmp_path):
    """--json is the JSON file's text: C0 controls escaped by JSON, the values (bidi, C1) as they are."""
    path = _csv(tmp_path / "parts.csv", HOSTILE)
    proc = run_swatch("check", path, "--thickness", "120", "--json", "--report", tmp_path / "qc")
    assert proc.stdout == (tmp_path / "qc" / "check.json").read_text(encoding="utf-8")
    assert "\x1b" not in proc.stdout and "\x07" not in proc.stdout
    assert [m["id"] for m in json.loads(proc.stdout)["measurements"]] == HOSTILE


def test_issue49_an_error_naming_a_hostile_file_is_one_escaped_line(tmp_path):
    bad = tmp_path / f"parts{TITLE}{RLO}\n.csv"
    proc = run_swatch("check", bad, "--thickness", "120")
    assert_one_line_error(proc, "no such file")
    _assert_safe(proc)
    assert _shown(TITLE) in proc.stderr and _shown(RLO) in proc.stderr


def test_issue49_a_hostile_value_in_a_usage_error_is_escaped():
    proc = run_swatch("color", "--thickness", f"50{CLEAR}")
    assert_one_line_error(proc)
    _assert_safe(proc)
    proc = run_swatch(f"col{CSI8}")
    assert_one_line_error(proc, "no such command")
    _assert_safe(proc)


#: A command that prints (print(), a warning, a line of a library) what a file gave it.
LOUD = """
import sys, warnings
sys.argv = ["swatch", "materials", "list"]
import swatch.report.tables as tables
from swatch.cli import main
def text(*args):
    warnings.warn("material {name} is odd".format(name=NAME))
    print("library says", NAME)
    print("and to stderr", NAME, file=sys.stderr)
    return [NAME]
tables.materials_text = text
sys.exit(main())
"""


def test_issue49_warnings_and_what_a_library_prints_are_escaped_too():
    code = f"NAME = {TITLE + CSI8 + RLO!r}\n" + LOUD
    proc = subprocess.run([sys.executable, "-W", "always", "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr
    _assert_safe(proc)
    shown = _shown(TITLE + CSI8 + RLO)
    assert proc.stdout.count(shown) == 2  # the report's line and print()'s
    assert f"material {shown} is odd" in proc.stderr and f"and to stderr {shown}" in proc.stderr


def test_printable_escapes_controls_and_bidi_and_keeps_lines():
    text = "a\tb\nc" + "".join(HOSTILE) + "\x00\x7f\ud800é ΔE00 ≤ 2 — 日本"
    shown = printable(text)
    assert not RAW.search(shown)
    assert shown.startswith("a\tb\nc") and shown.endswith("\\ud800é ΔE00 ≤ 2 — 日本")
    assert _shown(CLEAR) in shown and "\\u0000\\u007f" in shown
    assert json.loads(printable(json.dumps({"n": HOSTILE}, ensure_ascii=False))) == {"n": HOSTILE}  # (same value)
    one = printable("x\ty\nz\u200b", one_line=True)
    assert one == "x\\u0009y\\u000az\\u200b"


def test_escaped_output_wraps_the_streams_once_and_puts_them_back(capsys):
    before = sys.stdout, sys.stderr
    with escaped_output():
        assert isinstance(sys.stdout, EscapingStream) and isinstance(sys.stderr, EscapingStream)
        with escaped_output():
            assert unescaped(sys.stdout) is before[0]  # (not wrapped twice)
        print(CLEAR)
        unescaped(sys.stdout).write("raw\n")
        with pytest.raises(TypeError):
            sys.stdout.write(b"bytes")  # type: ignore[arg-type]
        assert not hasattr(sys.stdout, "buffer")  # (bytes written there would pass unescaped)
    assert (sys.stdout, sys.stderr) == before
    assert capsys.readouterr().out == _shown(CLEAR) + "\nraw\n"
