# Thin wrappers around dev.py, which bootstraps .venv (needs only Python 3.11+ and pip).
PYTHON ?= python3

.PHONY: catalog test quick lint docs bench clean
catalog:
	$(PYTHON) dev.py catalog
test:
	$(PYTHON) dev.py test
quick:  # a local loop: everything but the tests marked slow (CI runs them all)
	$(PYTHON) dev.py test -m "not slow"
lint:
	$(PYTHON) dev.py lint
docs:  # the user guide into build/docs/ (Sphinx, warnings as errors)
	$(PYTHON) dev.py docs
bench:
	$(PYTHON) dev.py bench
clean:
	rm -rf build .pytest_cache .hypothesis docs/generated
