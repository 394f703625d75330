"""``make bench`` runs every section to its end: the whole bench at a tiny size (``--tiny``), one process.

The figures of a tiny run mean nothing; what is checked is that each section runs and prints its keys
(bench_exports once wrote chips into a folder without ``chips/`` and the bench stopped there, so the
engine's ratio line, the last one, never printed).
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from benchmarks.bench import SECTIONS

ROOT = Path(__file__).resolve().parents[1]

#: A key each section prints (the first of its lines).
KEYS = {"render": "render_64_s", "environment": "render_env_64_s", "mesh": "render_mesh_64_s",
        "mitsuba": "mitsuba_bsdf_ratio", "mitsuba_cuda": "cuda_hero_s", "catalog": "catalog_cold_s", "explorer": "explorer_frame_ms",
        "exports": "exports_chips_s", "fit": "fit_100_geometries_ms", "calibrate": "calibrate_tables_ms",
        "qc": "check_100_parts_ms", "presets": "presets_fit_s", "engine": "ratio_vs_colour"}


def test_every_section_has_a_key():
    assert sorted(KEYS) == sorted(SECTIONS)


@pytest.mark.slow
def test_the_whole_bench_runs_to_its_end_at_a_tiny_size():
    proc = subprocess.run([sys.executable, "-m", "benchmarks.bench", "--tiny"], cwd=ROOT, capture_output=True,
                          text=True, timeout=600, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = proc.stdout
    assert out.startswith("machine: ")
    for section, key in KEYS.items():
        if section == "explorer" and "explorer: skipped" in out and os.environ.get("SWATCH_REQUIRE_BROWSER") != "1":
            continue
        if section == "mitsuba" and "mitsuba: skipped" in out and os.environ.get("SWATCH_REQUIRE_MITSUBA") != "1":
            continue
        if section == "mitsuba_cuda" and re.search(r"^cuda: not available here \(.+\)$", out, re.M):
            assert not re.search(r"(^| )cuda_\w+=", out, re.M)  # (no figure without a GPU)
            continue
        assert re.search(rf"(^| ){key}=[0-9.]+", out, re.M), f"section {section}: no {key}= in\n{out}"
    assert re.search(r"^ratio_vs_colour=[0-9.]+ ratio_vs_tmm=[0-9]+$", out.splitlines()[-1])


def test_an_unknown_section_is_refused():
    proc = subprocess.run([sys.executable, "-m", "benchmarks.bench", "--tiny", "nope"], cwd=ROOT, capture_output=True,
                          text=True, timeout=120, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert proc.returncode == 2 and "unknown section(s) nope" in proc.stderr
