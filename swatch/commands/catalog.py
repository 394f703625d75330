"""``swatch catalog``: build catalog sheets from a spec, or check a spec.

Kept light: only click and the spec parser are imported until a build really has work to do, so
a rebuild with nothing changed finishes in well under a second.
"""
from __future__ import annotations

import click


@click.group()
def catalog():
    """Catalog sheets (EXR + PNG), catalog.json/.csv, index.html, CxF3 and ASE from a TOML spec."""


@catalog.command()
@click.argument("spec", type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=str),
              help="output folder (created; a folder a previous catalog build wrote is updated in place)")
@click.option("--jobs", "-j", type=click.IntRange(1, 64), default=None,
              help="parallel render processes [default: the number of CPUs, at most 8]")
@click.option("--quiet", "-q", is_flag=True, help="no progress bar or summary")
def build(spec, out, jobs, quiet):
    """Build the catalog described by SPEC (a TOML file, e.g. catalog/titanium.toml) into --out.

    Deterministic (the same spec gives byte-identical files), incremental (only what changed is
    rebuilt) and atomic (a failed or interrupted build leaves the previous catalog intact).
    """
    from swatch.catalog.build import build_catalog
    from swatch.commands.progress import terminal_bar_factory

    res = build_catalog(spec, out, jobs=jobs, progress=None if quiet else terminal_bar_factory())
    if quiet:
        return
    if res.noop:
        click.echo(f"{out}: up to date ({res.swatches} swatches, {res.sheets} sheet(s); {res.seconds:.2f} s)")
    else:
        click.echo(f"{out}: {res.swatches} swatches on {res.sheets} sheet(s) "
                   f"({res.rendered} rendered, {res.composed} sheet(s) written; {res.seconds:.1f} s)")
        click.echo(f"open {out}/index.html")


@catalog.command()
@click.argument("spec", type=click.Path(dir_okay=False, path_type=str))
def validate(spec):
    """Check a catalog spec and summarise it (nothing is written)."""
    from swatch.catalog.execute import check_buildable
    from swatch.catalog.layout import layout_summary
    from swatch.catalog.spec import load_spec, spec_summary

    s, _ = load_spec(spec)
    check_buildable(s)  # validate refuses what build refuses, by the same checks
    click.echo(f"{spec}: ok — {spec_summary(s)}")
    n = len(s.thickness_nm)
    click.echo(f"writes: {layout_summary(n, -(-n // s.per_sheet), s.chips, s.hero, s.presets)}")
