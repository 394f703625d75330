# Thin wrappers around dev.py, which bootstraps .venv (needs only Python 3.11+ and pip).
PYTHON ?= python3

.PHONY: catalog test bench clean
catalog:
	$(PYTHON) dev.py catalog
test:
	$(PYTHON) dev.py test
bench:
	$(PYTHON) dev.py bench
clean:
	rm -rf build .pytest_cache .hypothesis
