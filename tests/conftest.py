"""Test-suite configuration: the fixtures every browser test shares (issue 17 item 7).

One Chromium for all browser tests (``chromium``, session-scoped, SwiftShader WebGL2) and one small
catalog built once for the page tests (``small_catalog``, :data:`tests.browser.SMALL_CATALOG_SPEC`):
before, each browser file launched its own Chromium and built its own copy of the same catalog.
Under pytest-xdist (``python3 dev.py test`` runs the whole suite on two workers, ``--dist loadfile``)
each worker starts them at most once, when it runs a browser file.

Under xdist the longest files run first (:data:`LONGEST_FIRST`, :func:`pytest_collection_modifyitems`;
dev.py passes ``--no-loadscope-reorder`` so that xdist keeps that order instead of ordering files by their
number of tests): with ``--dist loadfile`` a long file started last kept one worker busy while the other
idled (issue 17 item 7).

Markers are set in each test file (``pytestmark = pytest.mark.slow``: builds catalogs, drives
Chromium or runs processes; ``pytest -m "not slow"`` leaves them out, CI runs every test).
"""
from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from tests.browser import CHROMIUM, SMALL_CATALOG_SPEC, WEBGL_ARGS, require_chromium

#: The suite's longest files, longest first: seconds per file (sum of its tests' durations; the first six from
#: ``python3 dev.py test --durations=0`` on 2026-12-07, the others from a cold run on 2026-12-02, 2 workers).
#: Files not named run after these, in collection order. A name that no longer exists is harmless; a new long
#: file belongs here. The two long browser files are not side by side: started together, both build
#: tests.browser's small catalog at once and one worker waits ~4 s for the other's (its lock).
LONGEST_FIRST = (
    "tests/test_docs_commands.py",  # ~190 s (#47-#50 run, loaded VM: the README's default catalog cold 138 s)
    "tests/catalog/test_live_studio_browser.py",  # ~105 s (#46: two catalogs with heroes, the set baked)
    "tests/commands/test_hardening_memory_caps.py",  # ~75 s (calibrate at 1,000 coupons among the cases)
    "tests/fit/test_calibration_leave_one_out.py",  # ~60 s (scipy's converged refits, the reference)
    "tests/test_bench.py",  # ~55 s (every bench section at a tiny size)
    "tests/catalog/test_catalog_ar.py",  # ~47 s (<model-viewer> in Chromium over the default catalog's 57)
    "tests/mitsuba/test_mitsuba_checks.py",  # 38 s (below: the 2026-12-02 cold run)
    "tests/catalog/test_catalog_explorer_env_browser.py",  # 26 (the two browser files apart: see above)
    "tests/presets/test_presets.py",  # 28
    "tests/core/test_hardening_runs.py",  # 27
    "tests/catalog/test_catalog_layout_browser.py",  # 26
    "tests/catalog/test_catalog_build.py",  # 17
    "tests/catalog/test_catalog_hero.py",  # 14
    "tests/mitsuba/test_mitsuba_render.py",  # 11
    "tests/catalog/test_catalog_explorer_browser.py",  # 10
    "tests/mitsuba/test_mitsuba_plugin.py",  # 9
    "tests/mitsuba/test_mitsuba_determinism.py",  # 9
    "tests/catalog/test_hardening_escape.py",  # 7
    "tests/fit/test_fit.py",  # 7
    "tests/commands/test_hardening_inputs.py",  # 6
    "tests/catalog/test_hardening.py",  # 6
    "tests/catalog/test_catalog_browser.py",  # 5
    "tests/catalog/test_catalog_layout.py",  # 5
    "tests/commands/test_hardening_memory.py",  # 5
    "tests/presets/test_presets_mitsuba.py",  # 4
    "tests/physics/test_spread.py",  # 4
    "tests/fit/test_calibration.py",  # 4
    "tests/fit/test_calibration_search.py",  # 4
    "tests/physics/test_process.py",  # 4
)


def pytest_collection_modifyitems(config, items):
    """In an xdist worker, put the files of :data:`LONGEST_FIRST` first, in its order (a stable sort: the
    tests of a file keep their order, the other files theirs). Every worker sorts alike, so their
    collections stay identical; a run in one process keeps the collection order."""
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::", 1)[0], len(rank)))


@pytest.fixture(scope="session")
def playwright_session():
    """Playwright's sync API, started once (a second ``sync_playwright()`` in the same thread while
    one runs is refused by Playwright: everything that drives Chromium goes through this one)."""
    require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        yield p


@pytest.fixture(scope="session")
def chromium(playwright_session):
    """The one headless Chromium of the suite (Debian's, :data:`tests.browser.CHROMIUM`; SwiftShader WebGL2).
    Tests open their own context or page on it and close it."""
    browser = playwright_session.chromium.launch(executable_path=CHROMIUM, args=WEBGL_ARGS)
    yield browser
    browser.close()


@pytest.fixture(scope="session")
def small_catalog(tmp_path_factory):
    """The small page-test catalog (20–300 nm every 70 nm, 64 px, one sheet of 4), built once per
    session; its output folder. Tests read it and never write into it (screenshots go to its parent).

    Under xdist the workers share one: the first to need it builds it in the run's common temporary
    folder under an exclusive lock (``fcntl.flock``), the others wait and read it (issue 17: each worker
    built its own, ~3 CPU-s)."""
    import fcntl

    from swatch.catalog.build import build_catalog

    require_chromium()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = tmp_path_factory.getbasetemp().parent / "small-catalog"  # the workers' basetemps' parent
        root.mkdir(exist_ok=True)
    else:
        root = tmp_path_factory.mktemp("small-catalog")
    with open(root / "build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (root / "built").is_file():  # written after a build that finished
            spec = root / "spec.toml"
            spec.write_text(SMALL_CATALOG_SPEC.format(name="page test"), encoding="utf-8")
            build_catalog(spec, root / "out", jobs=1)
            (root / "built").touch()
    return root / "out"


@pytest.fixture(scope="session")
def xvfb_display():
    """A virtual X display for an OpenGL context (Debian's Xvfb, Mesa's llvmpipe), started once per session
    (per xdist worker) and stopped by its PID at the end: MaterialX's GLSL renderer keeps its X connection
    for the life of the process, so a display stopped after one test kills the next renderer of the same
    process ("XIO: fatal IO error"). ``DISPLAY`` is set while it runs. Missing: skip, or fail with
    ``SWATCH_REQUIRE_TOOLS=1`` (CI)."""
    exe = shutil.which("Xvfb")
    if exe is None:
        if os.environ.get("SWATCH_REQUIRE_TOOLS") == "1":
            pytest.fail("SWATCH_REQUIRE_TOOLS=1 but Xvfb is missing (Debian: xvfb, libgl1-mesa-dri)")
        pytest.skip("Xvfb not installed")
    r, w = os.pipe()
    proc = subprocess.Popen([exe, "-displayfd", str(w), "-screen", "0", "64x64x24", "-nolisten", "tcp"],
                            pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(w)
    before = os.environ.get("DISPLAY")
    try:
        with os.fdopen(r) as fh:
            number = fh.readline().strip()
        assert number.isdigit(), "Xvfb did not report its display"
        os.environ["DISPLAY"] = f":{number}"
        yield f":{number}"
    finally:
        if before is None:
            os.environ.pop("DISPLAY", None)
        else:
            os.environ["DISPLAY"] = before
        proc.terminate()
        proc.wait(timeout=10)
