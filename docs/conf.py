"""Sphinx configuration of the swatch user guide (``python3 dev.py docs``; warnings are errors in CI).

Pages are Markdown (MyST); the API reference is generated from the package's numpydoc docstrings
(autodoc + autosummary + numpydoc), its list of names taken from ``swatch.__all__`` so that it follows
the package's public face.
"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import swatch  # noqa: E402

sys.path.insert(0, str(ROOT / "scripts"))
import mitsuba_parameters  # noqa: E402

# the Mitsuba plugin's parameter table, from its one definition (bsdf.PARAMETERS); docs/mitsuba.md includes it
mitsuba_parameters.write(ROOT / "docs" / "generated" / "mitsuba_parameters.md")

project = "swatch"
author = "the swatch authors"
copyright = "the swatch authors, MIT licence"  # (Sphinx's name for it)
release = swatch.__version__
version = release

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "numpydoc", "sphinx.ext.mathjax",
              "sphinxcontrib.bibtex"]
bibtex_bibfiles = ["references.bib"]  # the one bibliography: the pages' {cite} and the docstrings' :cite: keys
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}  # autosummary writes its first: rst
root_doc = "index"
exclude_patterns = ["_build", "generated/*.md"]  # included pages (mitsuba.md), not pages of their own
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
autosummary_generate = True
autodoc_typehints = "none"            # the numpydoc sections say the types and units
numpydoc_show_class_members = False   # a class page lists its documented methods through autodoc
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()
html_theme = "alabaster"
html_title = f"swatch {release}"
html_static_path: list[str] = []
