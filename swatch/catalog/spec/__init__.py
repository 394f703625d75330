"""Catalog specs: the TOML file describing one catalog, read, checked and typed.

Modules: :mod:`~swatch.catalog.spec.document` (:class:`CatalogSpec`, the typed spec, and :func:`parse_spec` /
:func:`load_spec`, which build it from a decoded or stored TOML file), :mod:`~swatch.catalog.spec.checks`
(the checks of each value, every message naming the file, the key and what is allowed),
:mod:`~swatch.catalog.spec.render` (the ``[render]`` table: shapes, finishes, heroes, the designer's mesh) and
:mod:`~swatch.catalog.spec.files` (where a spec is found: a path, or a bundled spec by name). The format:
docs/catalog.md. The package is light (no colour-science import), so that a no-op rebuild starts quickly.
"""
from __future__ import annotations

from swatch.catalog.spec.document import RENDER_MODELS, RENDER_SHAPES, CatalogSpec, load_spec, parse_spec, spec_summary
from swatch.catalog.spec.files import SPECS_DIR, bundled_specs, resolve_spec_path

__all__ = ["CatalogSpec", "load_spec", "parse_spec", "spec_summary", "RENDER_SHAPES", "RENDER_MODELS", "SPECS_DIR",
           "bundled_specs", "resolve_spec_path"]
