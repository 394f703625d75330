"""Issue #22 group 3: every command plans against MAX_RUN_BYTES (2 GB) before it allocates; at its
largest allowed input each one runs (or is refused in one line) under a 2 GB address-space limit
plus the interpreter's baseline (imports alone map 300–500 MB of address space: measured, a
``swatch color`` run fails at 300 MB and runs at 500 MB)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_FIT_GEOMETRIES, MAX_RUN_BYTES, plan_rows
from tests.cli_helpers import assert_one_line_error
from tests.commands.memory_helpers import run_capped


def lab_file(path, n: int):
    """``n`` distinct in-plane geometries (light, view on a 0.01° lattice) with one colour each."""
    rows = [f"{(i // 8900) / 100:g},{(i % 8900) / 100:g},40,-1,-30" for i in range(n)]
    path.write_text("light_deg,view_deg,L,a,b\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_issue22_plan_rows_refuses_what_one_chunk_cannot_hold():
    """Issue #22 group 3: chunks are sized from the budget; a row larger than it is one line, not an allocation."""
    assert plan_rows(1024, "x") == MAX_RUN_BYTES // 2 // 1024
    with pytest.raises(SwatchError, match="more than a run may plan for"):
        plan_rows(MAX_RUN_BYTES, "the thickness search")


def test_issue22_more_geometries_than_the_cap_are_refused_in_one_line(tmp_path):
    """Issue #22 group 3: a 15 MB file of 768k Lab rows needed 23 GB; the count of geometries is capped."""
    from tests.cli_helpers import run_swatch

    proc = run_swatch("fit", lab_file(tmp_path / "many.csv", MAX_FIT_GEOMETRIES + 1))
    assert_one_line_error(proc, f"at most {MAX_FIT_GEOMETRIES}")
    assert proc.returncode == 2


def test_issue22_the_largest_sheet_is_composed_alone_and_a_bigger_one_refused(tmp_path, monkeypatch):
    """Issue #22 group 3: 512 px tiles 8 × 8 (~3 GB a worker × --jobs before) get one worker; a sheet beyond the
    budget (here: the plan's bytes per pixel raised) is refused by validate and build alike, nothing written."""
    from swatch.catalog import sheets
    from swatch.catalog.sheets import plan_jobs
    from swatch.catalog.spec import load_spec
    from tests.cli_helpers import run_swatch

    spec = tmp_path / "big.toml"
    spec.write_text('name = "Big"\n[thickness]\nstart_nm = 20\nstop_nm = 335\nstep_nm = 5\n[render]\n'
                    'size_px = 512\nshapes = ["flat", "sphere"]\nangular_map = true\n[sheet]\ncolumns = 8\nrows = 8\n',
                    encoding="utf-8")
    assert plan_jobs(load_spec(spec)[0], 64) == 1
    assert run_swatch("catalog", "validate", spec).returncode == 0
    monkeypatch.setattr(sheets, "SHEET_BYTES_PER_PX", 64)
    for args in (["catalog", "validate", spec], ["catalog", "build", spec, "--out", tmp_path / "out"]):
        proc = run_swatch(*args)
        assert_one_line_error(proc, "GB", "fewer [sheet] columns or rows")
        assert proc.returncode == 2
    assert not (tmp_path / "out").exists()


def test_issue22_sheet_workers_are_chosen_from_the_budget():
    """Issue #22 group 3: the build's workers × one sheet each, plus the building process, stay within the budget."""
    from swatch.catalog.sheets import PARENT_BYTES, plan_jobs, sheet_bytes
    from swatch.catalog.spec import load_spec

    spec, _ = load_spec("catalog/titanium.toml")
    jobs = plan_jobs(spec, 64)
    assert 1 <= jobs < 64 and PARENT_BYTES + jobs * sheet_bytes(spec) <= MAX_RUN_BYTES


def test_issue22_the_budget_can_be_lowered_for_a_run_never_raised():
    """Issue 17 item 7: ``SWATCH_MAX_RUN_BYTES`` lowers the budget a run plans for (the chunked commands'
    memory test below runs under it); a larger, a tiny or an unreadable value does not widen it."""
    default = 2 * 1024 ** 3
    for text, want in (("268435456", 256 * 1024 ** 2), (str(4 * default), default), ("1", 64 * 1024 ** 2),
                       ("lots", default)):
        proc = subprocess.run([sys.executable, "-c", "from swatch.core.limits import MAX_RUN_BYTES, plan_rows; "
                               "print(MAX_RUN_BYTES, plan_rows(1024, 'x'))"], capture_output=True, text=True,
                              env=dict(os.environ, SWATCH_MAX_RUN_BYTES=text), check=True)
        assert proc.stdout.split() == [str(want), str(want // 2 // 1024)], text


@pytest.mark.slow
def test_issue22_the_colour_table_is_chunked_within_a_lowered_budget():
    """Issue #22 group 3: `color` over 1000 nm at 0.01 nm under 10 overcoats (the caps) needed 8.7 GB at once;
    it plans its table in chunks against the budget (0.90 GB peak at the caps: the memory table of docs/cli.md).
    Issue 17 item 7: pinned at a quarter of the rows (25,000 thicknesses, 10 overcoats) under a budget lowered
    to 256 MiB and an address-space limit of 256 MiB + the baseline: measured, the table computed in one
    piece fails there (MemoryError) and the planned chunks pass, in about half the CPU of the run at the caps."""
    proc = run_capped("color", "--thickness", "0.01:1000:0.04", *["--overcoat", "1.5:10"] * 10, "--json",
                      budget=256 * 1024 ** 2)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert len(json.loads(proc.stdout)["rows"]) == 25_000
