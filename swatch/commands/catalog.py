"""``swatch catalog``: build catalog sheets from a spec, or check a spec.

Kept light: only click and the spec parser are imported until a build really has work to do, so
a rebuild with nothing changed finishes in well under a second.
"""
from __future__ import annotations

from pathlib import Path

import click


@click.group()
def catalog():
    """Catalog sheets (EXR + PNG), catalog.json/.csv, index.html, CxF3 and ASE from a TOML spec."""


@catalog.command()
@click.argument("spec")  # a file or a bundled name (a folder of that name, e.g. a catalog built there, is no spec)
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=str),
              help="output folder (created; a folder a previous catalog build wrote is updated in place)")
@click.option("--jobs", "-j", type=click.IntRange(1, 64), default=None,
              help="parallel render processes [default: the number of CPUs, at most 8]")
@click.option("--scheduler", envvar="SWATCH_SCHEDULER", show_envvar=True, default=None, metavar="ADDRESS",
              help="send the work to this Dask scheduler (tcp://HOST:8786; needs anodic-swatch[distributed]) "
                   "[default: the spec's [build] scheduler, else local processes]")
@click.option("--quiet", "-q", is_flag=True, help="no progress bar or summary")
def build(spec, out, jobs, scheduler, quiet):
    """Build the catalog described by SPEC into --out: a TOML file (e.g. mine.toml) or the name of a
    bundled spec (titanium, niobium, tantalum, paper-samples: `swatch catalog list`).

    Deterministic (the same spec gives byte-identical files), incremental (only what changed is
    rebuilt) and atomic (a failed or interrupted build leaves the previous catalog intact).
    """
    from swatch.catalog.build import build_catalog
    from swatch.commands.progress import terminal_bar_factory

    res = build_catalog(spec, out, jobs=jobs, progress=None if quiet else terminal_bar_factory(),
                        scheduler=scheduler or None)
    if quiet:
        return
    if res.noop:
        click.echo(f"{out}: up to date ({res.swatches} swatches, {res.sheets} sheet(s); {res.seconds:.2f} s)")
    else:
        click.echo(f"{out}: {res.swatches} swatches on {res.sheets} sheet(s) "
                   f"({res.rendered} rendered, {res.composed} sheet(s) written; {res.seconds:.1f} s)")
        click.echo(f"open {Path(out) / 'index.html'}")


@catalog.command()
@click.argument("spec")
def validate(spec):
    """Check a catalog spec (a file or a bundled name) and summarise it (nothing is written)."""
    from swatch.catalog.execute import check_buildable
    from swatch.catalog.layout import extra_hero_files, extra_preset_files, layout_summary
    from swatch.catalog.spec import load_spec, resolve_spec_path, spec_summary

    s, _ = load_spec(resolve_spec_path(spec))
    check_buildable(s)  # validate refuses what build refuses, by the same checks
    click.echo(f"{spec}: ok — {spec_summary(s)}")
    n = len(s.thickness_nm)
    extra = extra_hero_files(bool(s.hero_cover_px), len(s.finishes))
    more = extra_preset_files(n, s.presets_usd, s.presets_physicallybased)
    more += n + 3 if s.ar else 0  # [presets] ar: a viewer file per swatch, their part, the viewer and its licence
    click.echo(f"writes: {layout_summary(n, -(-n // s.per_sheet), s.chips, s.hero, s.presets, extra, more)}")


@catalog.command(name="list")
def list_specs():
    """The catalog specs bundled with swatch (build one by name, or copy it with `swatch catalog init`)."""
    from swatch.catalog.spec import bundled_specs, load_spec

    for name, path in bundled_specs().items():
        s, _ = load_spec(path)
        offered = f", finishes {', '.join(s.finishes)}" if len(s.finishes) > 1 else ""
        click.echo(f"{name:<14} {s.name}: {len(s.thickness_nm)} swatches{offered}")


@catalog.command()
@click.argument("name")
@click.option("--out", "out", type=click.Path(dir_okay=False, path_type=str), default=None,
              help="the file to write [default: NAME.toml in the current folder]")
@click.option("--force", is_flag=True, help="overwrite an existing file")
def init(name, out, force):
    """Write a copy of the bundled spec NAME (e.g. titanium) to edit, then build it with
    `swatch catalog build NAME.toml --out DIR`."""
    from swatch.catalog.spec import bundled_specs
    from swatch.core.errors import SwatchError
    from swatch.core.fileio import atomic_write_bytes, check_creatable_dir, check_new

    bundled = bundled_specs()
    if name not in bundled:
        raise SwatchError(f"{name}: not a bundled catalog spec; bundled: {', '.join(bundled)}")
    target = Path(out if out is not None else f"{name}.toml")
    check_new([target], force)
    check_creatable_dir(target.parent)
    target.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(target, bundled[name].read_bytes())
    click.echo(f"wrote {target} (a copy of the bundled {name!r} spec; edit it, then "
               f"`swatch catalog build {target} --out DIR`)")
