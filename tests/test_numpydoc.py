"""Numpydoc that says what a value is (issue 36): no bare entries, and the science modules cite their sources.

A *bare* entry gives only a name and/or a type (``thickness_nm : float``, ``numpy.ndarray``) with no
indented line under it saying what the value means, its unit and shape; ``python3 scripts/numpydoc_count.py
--bare [SUBPACKAGE]`` counts and lists them (the rules are in its docstring).
"""
from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: The subpackages whose every Parameters / Returns / Yields / Attributes entry is described; add one when it is.
DESCRIBED = ("physics", "colorimetry", "report", "presets", "core", "production", "commands", "catalog",
             "render", "fit", "io")

#: The subpackages whose modules cite their references as colour-science's do (a numbered References section).
CITING = ("physics", "colorimetry")


def _count_module():
    spec = importlib.util.spec_from_file_location("numpydoc_count", ROOT / "scripts" / "numpydoc_count.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


COUNT = _count_module()


@pytest.mark.parametrize("sub", DESCRIBED)
def test_no_bare_numpydoc_entries(sub):
    bare = [f"{where} {name} {section}: {entry}" for where, name, section, entry in COUNT.bare_entries(sub)]
    assert bare == [], f"entries with only a type in swatch/{sub}/ (say what the value means, unit, shape):\n" + \
        "\n".join(bare)


def _flags(doc: str) -> list[tuple[str, str, bool]]:
    return list(COUNT.doc_entries(doc))


def test_the_checker_finds_bare_entries_and_passes_described_ones():
    doc = """Summary.

    Parameters
    ----------
    thickness_nm : float
    light_deg, view_deg : array_like, degrees
        Polar angles from the normal.
    flag : bool

    Returns
    -------
    numpy.ndarray, shape (..., 3)

    Raises
    ------
    SwatchError
    """
    import inspect

    got = _flags(inspect.cleandoc(doc))
    assert got == [
        ("Parameters", "thickness_nm : float", False),
        ("Parameters", "light_deg, view_deg : array_like, degrees", True),
        ("Parameters", "flag : bool", False),
        ("Returns", "numpy.ndarray, shape (..., 3)", False),
    ]  # Raises is not an entry section: an exception type alone is fine there


def test_the_checker_reads_named_returns_none_and_attributes():
    doc = ("Summary.\n\nReturns\n-------\nencoded : numpy.ndarray\n    Display RGB, 0–1.\nin_gamut : bool\n\n"
           "Attributes\n----------\nR_s : numpy.ndarray\n    Reflectance.\n")
    assert _flags(doc) == [("Returns", "encoded : numpy.ndarray", True), ("Returns", "in_gamut : bool", False),
                           ("Attributes", "R_s : numpy.ndarray", True)]
    assert _flags("Write it.\n\nReturns\n-------\nNone\n") == [("Returns", "None", True)]


def test_the_bare_count_covers_every_subpackage_and_lists_its_own_finds(tmp_path, monkeypatch):
    """The checker run on a made-up package: it reports the bare entry (file:line) of a private method too."""
    pkg = tmp_path / "swatch" / "demo"
    pkg.mkdir(parents=True)
    (pkg / "m.py").write_text('class A:\n    def _f(self, x):\n        """F.\n\n        Parameters\n'
                              '        ----------\n        x : float\n        """\n', encoding="utf-8")
    monkeypatch.setattr(COUNT, "PKG", tmp_path / "swatch")
    assert list(COUNT.bare_entries("demo")) == [("swatch/demo/m.py:2", "_f", "Parameters", "x : float")]
    assert COUNT.entry_counts("demo") == {"Parameters": (1, 1)}


def _module_docstrings(sub: str):
    for path in sorted((ROOT / "swatch" / sub).glob("*.py")):
        if path.name != "__init__.py":
            yield path.relative_to(ROOT).as_posix(), ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))


@pytest.mark.parametrize("where,doc", [pair for sub in CITING for pair in _module_docstrings(sub)])
def test_science_modules_cite_numbered_references(where, doc):
    """Each module's docstring ends with a numpydoc ``References`` section of numbered entries (``.. [1]``, …)."""
    assert doc, f"{where} has no module docstring"
    parts = re.split(r"^References\n-{10}\n", doc, flags=re.M)
    assert len(parts) == 2, f"{where}: no module References section"
    numbers = [int(n) for n in re.findall(r"^\.\. \[(\d+)\] ", parts[1], flags=re.M)]
    assert numbers and numbers == list(range(1, len(numbers) + 1)), f"{where}: references not numbered 1, 2, …"
    # each entry cites a key of the one bibliography (docs/references.bib), each source once per module
    keys = re.findall(r"^\.\. \[\d+\] :cite:`([^`]+)`", parts[1], flags=re.M)
    assert len(keys) == len(numbers), f"{where}: a reference that is not a :cite: key of docs/references.bib"
    assert set(keys) <= set(BIBLIOGRAPHY), f"{where}: keys not in docs/references.bib: {set(keys) - set(BIBLIOGRAPHY)}"
    assert len(set(keys)) == len(keys), f"{where}: a source cited twice"


#: The one bibliography's entries (docs/references.bib): key -> DOI (None without one).
BIBLIOGRAPHY = {m[1]: (re.search(r"^\s*doi = \{([^}]+)\}", m[2], flags=re.M) or [None, None])[1]
                for m in re.finditer(r"^@\w+\{([^,]+),\n(.*?)^\}", (ROOT / "docs" / "references.bib").read_text(
                    encoding="utf-8"), flags=re.M | re.S)}
#: Every DOI of the bibliography, each checked against a source we did not write (the tables' headers from
#: refractiveindex.info, colour-science's own references, the paper itself).
KNOWN_DOIS = {
    "10.14923/transinfj.2018JDP7030",  # H. Fujii et al. 2019 (printed on the paper itself)
    "10.2312/EGWR/EGSR07/195-206",  # Walter et al. 2007, GGX
    "10.25039/TR.015.2018",  # CIE 015:2018 (colour-science's reference Carter2018)
    "10.1002/col.20070",  # Sharma, Wu, Dalal 2005, CIEDE2000
    "10.1111/cgf.12676",  # Meng et al. 2015 (colour-science's Meng2015c)
    "10.1103/PhysRevB.9.5056",  # Johnson & Christy 1974 (tables/optical/Ti-Johnson.csv)
    "10.1002/adom.201600250",  # Siefke et al. 2016 (tables/optical/TiO2-Siefke.csv)
    "10.1038/s41597-023-02898-2",  # Polyanskiy 2024, refractiveindex.info (every table's header)
    "10.1145/3072959.3073620",  # Belcour & Barla 2017, ACM TOG 36(4) 65 (the presets' thin-film Fresnel)
}


def test_science_modules_cite_only_checked_dois():
    """A DOI added to the bibliography is one someone checked (add it above with its source); the modules cite
    keys, never a DOI of their own; the paper, CIE 015 and CIEDE2000 are cited."""
    assert {d for d in BIBLIOGRAPHY.values() if d} == KNOWN_DOIS
    cited, written = set(), set()
    for sub in CITING:
        for path in sorted((ROOT / "swatch" / sub).glob("*.py")):
            text = path.read_text(encoding="utf-8")
            cited |= set(re.findall(r":cite:`([^`]+)`", text))
            written |= set(re.findall(r"doi:(\S+)", text))
    assert written == set() and cited <= set(BIBLIOGRAPHY)
    assert {"Fujii2019", "Carter2018", "Sharma2005b"} <= cited
