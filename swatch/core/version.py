"""The package version (the one place; pyproject reads it, ``swatch.__version__`` re-exports it)."""

__version__ = "0.1.0"
