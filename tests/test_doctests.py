"""The examples in the public API's docstrings run and print what they say (issue 17, item 5).

Each module listed here has ``Examples`` sections in the numpydoc of its public functions and
classes; ``doctest`` runs them against the real library (no mocks).
"""
from __future__ import annotations

import doctest
import importlib

import pytest

MODULES_WITH_EXAMPLES = [
    "swatch",
    "swatch.core.errors",
    "swatch.core.escapes",
    "swatch.core.registry",
    "swatch.physics.materials",
    "swatch.physics.model",
    "swatch.physics.overcoat",
    "swatch.physics.growth",
    "swatch.physics.spread",
    "swatch.physics.process",
    "swatch.colorimetry.appearance",
    "swatch.colorimetry.names",
    "swatch.colorimetry.tolerance",
    "swatch.colorimetry.grid",
    "swatch.catalog.context",
    "swatch.catalog.record",
    "swatch.colorimetry.geometry",
    "swatch.catalog.spec.checks",
    "swatch.catalog.spec.document",
    "swatch.catalog.chip_size",
    "swatch.catalog.explorer",
    "swatch.catalog.exports",
    "swatch.catalog.records",
    "swatch.catalog.layout",
    "swatch.catalog.html",
    "swatch.catalog.words",
    "swatch.presets.files",
    "swatch.catalog.fingerprint",
    "swatch.production.spec",
    "swatch.report.figures",
    "swatch.fit.search",
    "swatch.fit.multi_match",
    "swatch.fit.fitting",
    "swatch.fit.result",
    "swatch.fit.resampling",
    "swatch.io.instruments",
    "swatch.io.cgats",
    "swatch.io.cxf_in",
    "swatch.io.pngmeta",
    "swatch.io.tabular",
    "swatch.io.imageio",
    "swatch.io.spectral_exr",
    "swatch.io.drawing",
    "swatch.io.measurements",
    "swatch.io.measurement_csv",
    "swatch.render.display",
    "swatch.render.studio",
    "swatch.render.metadata",
    "swatch.render.image",
    "swatch.render.builtin.shading",
    "swatch.render.builtin.env_shading",
    "swatch.render.camera",
    "swatch.render.octahedral",
    "swatch.render.hdri",
    "swatch.render.environment",
    "swatch.render.mitsuba.setup",
    "swatch.commands.flags",
    "swatch.presets.anisotropy",
    "swatch.presets.mitsuba_bsdf",
    "swatch.presets.spectral",
    "swatch.presets.preview",
    "swatch.presets.naming",
]


@pytest.mark.parametrize("name", MODULES_WITH_EXAMPLES)
def test_docstring_examples_run_as_written(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 0, f"{name} has no docstring examples"
    assert result.failed == 0


def test_every_public_function_and_class_has_numpydoc():
    """Issue 17, item 5: ``python3 scripts/numpydoc_count.py`` says N / N (the rules are in its docstring:
    Parameters on anything that takes parameters, Returns/Raises otherwise, Attributes on classes)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "scripts" / "numpydoc_count.py"
    spec = importlib.util.spec_from_file_location("numpydoc_count", path)
    assert spec is not None and spec.loader is not None
    count = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(count)
    missing = [name for sub in count.SUBPACKAGES for name, ok in count.items(sub) if not ok]
    assert missing == []
