"""Hostile instrument files, round 3 (issue 38 item 1), from the user's side: every case through the
CLI in one subprocess (`fit`, `calibrate`, `match --measurement`, `check`), each answered by one line
`error: …`, exit 2, no xsdata ConverterWarning, nothing written."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.cli_helpers import run_capped_batch

DATA = Path(__file__).resolve().parents[1] / "data" / "instruments"
SRC = (DATA / "colour_cxf_sample_trimmed.cxf").read_text(encoding="utf-8")
FIRST_L = "<cc:L>17.64167</cc:L>"
SPECTRUM = re.compile(r'(<cc:ReflectanceSpectrum StartWL="380" ColorSpecification="CS1">)[^<]*')
LAB_ONLY = re.sub(r"<cc:ReflectanceSpectrum[^>]*>[^<]*</cc:ReflectanceSpectrum>", "", SRC)
CGATS_HEAD = ('CGATS.17\nMEASUREMENT_SOURCE "Illumination=D50 ObserverAngle=2"\nBEGIN_DATA_FORMAT\n'
              "SAMPLE_ID VOLTAGE_V LAB_L LAB_A LAB_B\nEND_DATA_FORMAT\nBEGIN_DATA\n")


def _sub(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


#: name -> (file text, what the one line must say)
CASES = {
    "empty_L.cxf": (_sub(LAB_ONLY, FIRST_L, "<cc:L></cc:L>"), "without L"),
    "empty_L_with_spectra.cxf": (_sub(SRC, FIRST_L, "<cc:L/>"), "without L"),
    "text_L.cxf": (_sub(LAB_ONLY, FIRST_L, "<cc:L>abc</cc:L>"), "`abc` is not a valid `float`"),
    "entity_L.cxf": (_sub(LAB_ONLY, FIRST_L, "<cc:L>&amp;</cc:L>"), "is not a valid `float`"),
    "undefined_entity_L.cxf": (_sub(SRC, FIRST_L, "<cc:L>&x;</cc:L>"), "not well-formed XML"),
    "empty_spectrum.cxf": (SPECTRUM.sub(r"\1", SRC, count=1), "ReflectanceSpectrum of 0 values"),
    "huge_spectrum.cxf": (SPECTRUM.sub(lambda m: m.group(1) + " 0.5" * 1_000_000, SRC, count=1),
                          "ReflectanceSpectrum of 1000000 values; a spectrum has 2 to 10001"),
    "nan_L_with_spectra.cxf": (_sub(SRC, FIRST_L, "<cc:L>NaN</cc:L>"), "not a finite number"),
    "minus_inf_L_with_spectra.cxf": (_sub(SRC, FIRST_L, "<cc:L>-INF</cc:L>"), "not a finite number"),
    "L_out_of_range_with_spectra.cxf": (_sub(SRC, FIRST_L, "<cc:L>170</cc:L>"), "outside [0, 100]"),
    # 70 KB of comment, then a DOCTYPE: the parser reports it wherever it is
    "late_doctype.cxf": (_sub(SRC, "<cc:CxF", "<!--" + "x" * 70_000 + '-->\n<!DOCTYPE cc:CxF SYSTEM '
                                                   '"file:///etc/hostname">\n<cc:CxF'), "document type"),
    "late_entity.cxf": (_sub(SRC, "<cc:CxF", "<!--" + "y" * 70_000 + '-->\n<!DOCTYPE cc:CxF [<!ENTITY e "1">]>'
                                                   "\n<cc:CxF"), "document type"),
    "duplicate_names.cxf": (SRC.replace('Name="2" Id="2"', 'Name="1" Id="2"'), "sample '1' appears twice"),
    "duplicate_names.txt": (CGATS_HEAD + "A 10 50 2 3\nA 20 51 2 3\nB 30 52 2 3\nEND_DATA\n",
                            "sample 'A' appears twice"),
}


@pytest.fixture(scope="module")
def answers(tmp_path_factory):
    """Each case through `fit`, `calibrate`, `match --measurement` and `check`, in one capped subprocess."""
    d = tmp_path_factory.mktemp("hostile")
    argvs, keys = [], []
    for name, (text, _) in CASES.items():
        (d / name).write_text(text, encoding="utf-8")
        for argv in (["fit", d / name], ["calibrate", d / name, "--out", d / f"{name}.toml"],
                     ["match", "--measurement", d / name], ["check", d / name, "--thickness", "120"]):
            argvs.append(argv)
            keys.append((name, argv[0]))
    procs = run_capped_batch(argvs, 2 * 1024**3, timeout=600)
    return d, dict(zip(keys, procs, strict=True))


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_instrument_file_gets_one_line_and_exit_2(answers, name):
    folder, procs = answers
    for command in ("fit", "calibrate", "match", "check"):
        proc = procs[(name, command)]
        assert proc.returncode == 2, (command, proc.stderr)
        assert proc.stderr.startswith("error: ") and proc.stderr.count("\n") == 1, (command, proc.stderr)
        assert CASES[name][1] in proc.stderr, (command, proc.stderr)
        assert "Warning" not in proc.stderr and "internal error" not in proc.stderr
    assert not list(folder.glob(f"{name}.toml*"))  # calibrate wrote nothing


def test_the_untouched_files_are_read(tmp_path):
    """The control: the same file without the defect is read (the refusals above are about the defect)."""
    (tmp_path / "lab.cxf").write_text(LAB_ONLY, encoding="utf-8")
    (tmp_path / "ok.txt").write_text(CGATS_HEAD + "A 10 50 2 3\nB 20 51 2 3\nEND_DATA\n", encoding="utf-8")
    procs = run_capped_batch([["fit", DATA / "colour_cxf_sample_trimmed.cxf"], ["fit", tmp_path / "lab.cxf"],
                              ["match", "--measurement", tmp_path / "ok.txt"]], 2 * 1024**3)
    for proc in procs:
        assert proc.returncode == 0 and "Warning" not in proc.stderr, proc.stderr
