"""Caps on untrusted input, defined once: sizes and counts are checked before memory is spent.

Every limit here is quoted in the error that enforces it (what is allowed), so a user who hits
one learns the bound. Light module (no numpy), importable from anywhere.
"""
from __future__ import annotations

__all__ = ["MAX_METADATA_BYTES", "MAX_CACHE_ENTRY_BYTES"]

#: A catalog's own metadata files (``.swatch-catalog/manifest.json``, ``journal.json``); a 400-swatch
#: catalog's manifest is ~20 kB.
MAX_METADATA_BYTES = 16 * 1024 * 1024
#: One cached tile (``.swatch-catalog/cache/*.npz``); the largest spec (two 512 px renders and a map)
#: needs ~5 MB.
MAX_CACHE_ENTRY_BYTES = 64 * 1024 * 1024
