"""Core: errors, choice lists, limits, safe paths, atomic file output, process hygiene (imports nothing else of swatch)."""
