"""Issue #12: killed, interrupted and failed runs leave nothing behind (no process, no temporary
file, no half-written batch); a damaged cache entry is recomputed; report names never collide."""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from swatch.catalog.build import build_catalog
from swatch.catalog.folder import META_DIR
from tests.catalog.folder_helpers import write_spec
from tests.cli_helpers import assert_one_line_error, run_swatch

pytestmark = pytest.mark.slow  # builds catalogs or runs processes (seconds per test)

#: What is killed: a build with a pool of 2 workers. Process handling is the point, not the renders: the
#: paper model (no studio environment to prepare in each worker: ~1.4 CPU-s a worker), 64 px flat tiles,
#: no angular map (issue 17). When the first tile lands the build is surely still running: 28 tiles,
#: the presets' fits of 29 swatches (in the building process, beside the pool), 3 sheets and the page to go.
KILL_SPEC = """
name = "Kill"
[thickness]
start_nm = 20
stop_nm = 300
step_nm = 10
[render]
size_px = 64
model = "paper"
shapes = ["flat"]
angular_map = false
"""


#: The CLI as a terminal's foreground job starts it: SIGINT and SIGHUP at their defaults. A test run
#: started in the background of a script (as CI may be) has SIGINT ignored, and a build inheriting
#: that rightly ignores Ctrl-C (it ran on and exited 0: the flaky SIGINT case).
AS_ON_A_TERMINAL = ("import runpy, signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
                    "signal.signal(signal.SIGHUP, signal.SIG_DFL); runpy.run_module('swatch.cli', run_name='__main__')")


def group_members(pgid: int) -> list[int]:
    """Live (not zombie) processes of a process group, from /proc."""
    out = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        if int(fields[2]) == pgid and fields[0] != "Z":
            out.append(int(entry))
    return out


def ignores(pid: int, sig: int, held: bool = False) -> bool:
    """Whether process ``pid`` ignores signal ``sig`` (or, with ``held``, ignores or blocks it)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True  # already gone
    masks = {line.split(":")[0]: int(line.split()[1], 16) for line in status.splitlines()
             if line.startswith(("SigIgn:", "SigBlk:"))}
    mask = masks["SigIgn"] | (masks["SigBlk"] if held else 0)
    return bool(mask & (1 << (sig - 1)))


def ignores_sigint(pid: int) -> bool:
    return ignores(pid, signal.SIGINT)


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")
@pytest.mark.parametrize("how", ["SIGKILL", "SIGTERM", "SIGINT-group",
                                 pytest.param("SIGHUP-group", marks=pytest.mark.slow)])  # (~15 s each, 30 s busy)
def test_issue12_killed_build_leaves_no_process(tmp_path, how):
    """Issue #12 (#22 group 5: SIGHUP, and a signal sent while the build is surely still running)."""
    spec = tmp_path / "k.toml"
    spec.write_text(KILL_SPEC, encoding="utf-8")
    out = tmp_path / "out"
    err = tmp_path / "stderr.txt"
    with open(err, "w") as fh:
        proc = subprocess.Popen([sys.executable, "-c", AS_ON_A_TERMINAL, "catalog", "build", str(spec), "--out",
                                 str(out), "-j", "2", "-q"], stdout=subprocess.DEVNULL, stderr=fh, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        # build process + resource tracker + fork server + 2 workers, and a first tile in the cache: the
        # pool is rendering (28 tiles, the presets' fits and the sheets to go)
        cache = out / META_DIR / "cache"
        while ((len(group_members(proc.pid)) < 5 or not any(cache.glob("*.npz"))) and proc.poll() is None
               and time.monotonic() < deadline):
            time.sleep(0.05)
        assert proc.poll() is None and len(group_members(proc.pid)) >= 5, "the pool never started"
        if how.endswith("-group"):  # Ctrl-C on a terminal, or the terminal closed: the whole group gets it
            # the fork server, its workers (from birth, before their initializer) and the resource
            # tracker ignore SIGINT and ignore or hold SIGHUP: only the build reports, in one line
            helpers = [p for p in group_members(proc.pid) if p != proc.pid]
            assert helpers and all(ignores_sigint(p) and ignores(p, signal.SIGHUP, held=True) for p in helpers)
            os.killpg(proc.pid, signal.SIGINT if how == "SIGINT-group" else signal.SIGHUP)
        else:
            os.kill(proc.pid, getattr(signal, how))
        rc = proc.wait(timeout=60)
        deadline = time.monotonic() + 20
        while group_members(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert group_members(proc.pid) == [], "processes outlived the build"
    finally:
        for pid in group_members(proc.pid):
            os.kill(pid, signal.SIGKILL)
    text = err.read_text()
    if how == "SIGKILL":
        assert rc == -signal.SIGKILL
    else:
        assert rc == {"SIGTERM": 143, "SIGINT-group": 130, "SIGHUP-group": 129}[how]
        lines = text.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: "), text
        assert not out.exists()  # a first build that was stopped leaves nothing


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    root = tmp_path_factory.mktemp("small")
    spec = root / "s.toml"
    write_spec(spec, "C", name="Small")
    out = root / "built"
    build_catalog(spec, out, jobs=1)
    ref_spec = root / "ref" / "s.toml"  # same file name: the spec's name is part of the outputs
    ref_spec.parent.mkdir()
    write_spec(ref_spec, "A", name="Small")
    build_catalog(ref_spec, root / "ref-out", jobs=1)  # the reference for a rebuild to grade A
    return out, root / "ref-out"


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def _damage(victim: Path, how: str) -> None:
    import numpy as np

    if how == "truncate":
        victim.write_bytes(victim.read_bytes()[:1000])
    elif how == "garbage":
        victim.write_bytes(os.urandom(5000))
    elif how == "dev-zero":
        victim.unlink()
        victim.symlink_to("/dev/zero")
    elif how == "fifo":
        victim.unlink()
        os.mkfifo(victim)
    else:  # a valid .npz with the wrong arrays
        np.savez(victim, r0_linear=np.zeros((3, 3, 3), np.float16))


@pytest.mark.parametrize("damages", [("truncate", "dev-zero", "fifo"), ("garbage", "wrong-shape", None)])
def test_issue12_damaged_cache_entries_are_recomputed(small, tmp_path, damages):
    """Each of the three cached tiles damaged differently (and the cached preset fits): the next build
    renders and fits them again and its files are byte-identical to a clean build's."""
    built, ref = small
    out = tmp_path / "out"
    shutil.copytree(built, out, symlinks=True)
    cache = out / META_DIR / "cache"
    entries = sorted(cache.glob("*.npz"))
    assert len(entries) == 3
    victims = [e for e, how in zip(entries, damages, strict=True) if how is not None]
    for e, how in zip(entries, damages, strict=True):
        if how is not None:
            _damage(e, how)
    (fits,) = cache.glob("presets-*.json")
    fits.write_text('{"gltf": {"params": [[1e308]], "dE60": [1], "dE45": "x"}}')  # wrong shapes
    spec = tmp_path / "s.toml"
    write_spec(spec, "A", name="Small")  # sheets are recomposed from the cache
    res = build_catalog(spec, out, jobs=1)
    assert not res.noop
    assert files(out) == files(ref)  # byte-identical to a clean build
    assert all(v.is_file() and not v.is_symlink() for v in victims)
    assert "1e308" not in fits.read_text()


def test_issue12_stale_temporary_files_are_cleaned(small, tmp_path):
    built, _ = small
    out = tmp_path / "out"
    shutil.copytree(built, out, symlinks=True)
    meta = out / META_DIR
    stale = [meta / ".journal.4194303.abcdefgh.tmp.json", meta / ".manifest.1x2y3z.tmp.json",
             meta / "cache" / ".0123abcd.4194303.tmp.npz"]
    for p in stale:
        p.write_text("left by a killed run")
    (meta / "staging-killed").mkdir()
    (meta / "staging-killed" / "sheet_01.png").write_bytes(b"x")
    spec = tmp_path / "s.toml"
    write_spec(spec, "A", name="Small")
    build_catalog(spec, out, jobs=1)
    assert not any(p.exists() for p in stale)
    assert not (meta / "staging-killed").exists()


def test_issue12_render_cleans_temp_files_of_dead_runs(tmp_path):
    out = tmp_path / "r"
    out.mkdir()
    dead = out / ".flat_050.0nm.swtmp.4194303.abcdefgh.tmp.png"  # pid above the kernel's maximum: never alive
    alive = out / f".flat_050.0nm.swtmp.{os.getppid()}.abcdefgh.tmp.png"  # a live run's: kept
    users = [out / ".flat_050.0nm.4194303.abcdefgh.tmp.png",  # issue 22: a user's files named like dead temps
             out / ".flat_050.0nm.swtmp.4194303.abcdefgh.tmp.png.keep"]
    for p in (dead, alive, *users):
        p.write_bytes(b"x")
        p.chmod(0o600)
    mine = out / ".flat_050.0nm.swtmp.4194304.abcdefgh.tmp.png"  # the marked name, but the user's mode
    mine.write_bytes(b"x")
    mine.chmod(0o644)
    proc = run_swatch("render", "--thickness", "50", "--out", out, "--size", "16")
    assert proc.returncode == 0, proc.stderr
    assert not dead.exists() and alive.exists() and mine.exists() and all(p.exists() for p in users)


def test_issue12_force_with_a_folder_in_the_way_writes_nothing(tmp_path):
    out = tmp_path / "r"
    out.mkdir()
    (out / "flat_060.0nm.png").mkdir()
    proc = run_swatch("render", "--thickness", "50,60", "--out", out, "--size", "16", "--force")
    assert_one_line_error(proc, "flat_060.0nm.png", "folder")
    assert proc.returncode == 2
    assert sorted(p.name for p in out.iterdir()) == ["flat_060.0nm.png"]  # no batch member, no temp file


def test_issue12_report_names_never_collide(tmp_path):
    import numpy as np

    wl = np.arange(380.0, 781.0, 5.0)
    text = "wavelength_nm,reflectance\n" + "".join(
        f"{w:g},{0.3 + 0.2 * np.sin(w / 40.0):.6f}\n" for w in wl)
    paths = [tmp_path / "a" / "x.csv", tmp_path / "b" / "x.csv", tmp_path / "x_2.csv", tmp_path / "c" / "X.csv"]
    for p in paths:
        p.parent.mkdir(exist_ok=True)
        p.write_text(text, encoding="utf-8")
    rep = tmp_path / "rep"
    proc = run_swatch("fit", *paths, "--report", rep)
    assert proc.returncode == 0, proc.stderr
    maps = sorted(p.name for p in rep.glob("delta_e_map_*.png"))
    assert len(maps) == 4 and len({m.lower() for m in maps}) == 4
