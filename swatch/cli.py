"""The ``swatch`` command: a thin click layer that parses, calls the library and reports.

Subcommands live in ``swatch/commands/`` and are imported only when used (fast start-up).
Bad input raises :class:`swatch.core.errors.SwatchError` (or a click usage error) and is reported as
one line ``error: ...`` with exit status 2; no traceback (``SWATCH_DEBUG=1`` shows one for bugs).
"""
from __future__ import annotations

import difflib
import importlib
import os
import signal
import sys

import click

from swatch.commands.flags import speak_flags
from swatch.core.errors import SwatchError
from swatch.core.heap import keep_freed_memory
from swatch.core.procguard import Terminated, guard_exit, handle_termination, settle, signal_received, stop_message
from swatch.core.version import __version__

#: command name -> "module:attribute"
COMMANDS = {
    "spectrum": "swatch.commands.engine:spectrum",
    "color": "swatch.commands.engine:color",
    "materials": "swatch.commands.engine:materials",
    "roughness": "swatch.commands.engine:roughness",
    "angular": "swatch.commands.render:angular",
    "render": "swatch.commands.render:render",
    "catalog": "swatch.commands.catalog:catalog",
    "fit": "swatch.commands.fit:fit",
    "match": "swatch.commands.fit:match",
    "preset": "swatch.commands.preset:preset",
    "calibrate": "swatch.commands.calibrate:calibrate",
    "spec": "swatch.commands.spec:spec",
    "check": "swatch.commands.check:check",
}


#: what ``swatch --help`` lists beside each command: short enough for an 80-column terminal (click cut the
#: docstrings' first sentences with "..."; tests/test_cli_habits.py checks them)
SUMMARIES = {
    "angular": "Colour over light × view angle (EXR and PNG maps)",
    "calibrate": "Fit a line's process profile to its coupons",
    "catalog": "Build or check a catalog (sheets, page, exports)",
    "check": "Judge measured parts against a finish spec",
    "color": "Colour of thicknesses at one geometry (Lab, hex)",
    "fit": "Oxide thickness from measured spectra or Lab",
    "match": "Thicknesses whose colour matches a target",
    "materials": "The optical-constant tables shipped",
    "preset": "A 3-D material preset for one thickness",
    "render": "Render swatches of a shape (EXR and PNG)",
    "roughness": "Rayleigh smoothness criterion, 380–780 nm",
    "spec": "A finish specification for a fabricator",
    "spectrum": "Spectral reflectance of one thickness",
}


#: other spellings of a command (British spelling is the project's own)
ALIASES = {"colour": "color"}


class _InterruptedError(Exception):
    """A KeyboardInterrupt carried past click (which would print a blank line and raise Abort)."""

    def __init__(self, exc: KeyboardInterrupt):
        super().__init__()
        self.exc = exc


class LazyGroup(click.Group):
    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt as exc:
            raise _InterruptedError(exc) from None

    def list_commands(self, ctx):
        return sorted(COMMANDS)

    def format_commands(self, ctx, formatter):
        """The command list from :data:`SUMMARIES` (whole sentences, and no command imported to list them)."""
        with formatter.section("Commands"):
            formatter.write_dl([(name, SUMMARIES[name]) for name in self.list_commands(ctx)])

    def get_command(self, ctx, name):
        target = COMMANDS.get(ALIASES.get(name, name))
        if target is None:
            return None
        module, attr = target.split(":")
        return getattr(importlib.import_module(module), attr)

    def resolve_command(self, ctx, args):
        name = args[0] if args else ""
        if name and not name.startswith("-") and self.get_command(ctx, name) is None:
            near = difflib.get_close_matches(name.lower(), [*COMMANDS, *ALIASES], n=1, cutoff=0.6)
            hint = f"; did you mean '{near[0]}'?" if near else f"; the commands: {', '.join(sorted(COMMANDS))}"
            ctx.fail(f"no such command {name!r}{hint}")
        return super().resolve_command(ctx, args)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="swatch")
def cli():
    """Physics-based colour swatches for anodised titanium.

    Thin-film interference of the anodic oxide, evaluated on the half-vector facet
    (Fujii et al.), in spectra, CIELAB values, renders and catalog sheets.
    """


def _one_line(text: object) -> str:
    """One line, at most MAX_ERROR_CHARS characters (an error may quote what it was given: 100 kB of input
    must not make a 100 kB line); control characters are shown escaped."""
    from swatch.core.limits import MAX_ERROR_CHARS, MAX_ERROR_WORD_CHARS

    words = [w if len(w) <= MAX_ERROR_WORD_CHARS else f"{w[:MAX_ERROR_WORD_CHARS]}…[{len(w)} characters]"
             for w in str(text).split()]  # a quoted huge input is cut, what follows it (what is allowed) kept
    line = "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in " ".join(words))
    return line if len(line) <= MAX_ERROR_CHARS else line[:MAX_ERROR_CHARS] + f" …[{len(line)} characters]"


def main(argv: list[str] | None = None) -> int:
    """Entry point: run the CLI, turning every expected failure into one line and exit 2, a stop into one
    line and 128 + the signal (130 for Ctrl-C, 143 for SIGTERM).

    Called without ``argv`` it is the program (the ``swatch`` script, ``python -m swatch.cli``): its outcome
    is then settled for the process's exit too (:func:`swatch.core.procguard.settle`: a signal during the
    exit is not a traceback, nor a silent death).
    """
    handle_termination()  # SIGTERM/SIGHUP unwind like Ctrl-C: temporary files removed, one line
    keep_freed_memory()  # array temporaries reused from the heap, not mapped and faulted in again (swatch.core.heap)
    if argv is None:
        guard_exit()
    try:
        status = _run(argv)
    except KeyboardInterrupt as intr:  # (one that came while a failure was being reported)
        status = _report_stop(intr)
    sig = signal_received()
    if status == 0 and sig is not None:  # a stop lost on its way (a finaliser dropped it): not a success
        line, status = stop_message(sig)
        click.echo(line, err=True)
    if argv is None:
        settle(status)
    return status


def _report_stop(intr: KeyboardInterrupt) -> int:
    line, status = stop_message(intr.signum if isinstance(intr, Terminated) else signal.SIGINT)
    click.echo(line, err=True)
    return status


def _run(argv: list[str] | None) -> int:
    try:
        rv = cli.main(args=argv, prog_name="swatch", standalone_mode=False)
    except SwatchError as exc:  # the library names parameters; the CLI speaks its flags
        click.echo(f"error: {speak_flags(_one_line(exc))}", err=True)
        return 2
    except click.exceptions.Abort:
        click.echo("error: aborted", err=True)
        return 130
    except click.ClickException as exc:
        ctx = getattr(exc, "ctx", None)
        cmd = f" (see 'swatch {ctx.command_path.split(' ', 1)[1]} --help')" if ctx and " " in ctx.command_path else ""
        click.echo(f"error: {_one_line(exc.format_message())}{cmd}", err=True)
        return exc.exit_code if exc.exit_code else 2
    except (KeyboardInterrupt, _InterruptedError) as caught:
        return _report_stop(caught.exc if isinstance(caught, _InterruptedError) else caught)
    except BrokenPipeError:
        return 0
    except OSError as exc:
        click.echo(f"error: {_one_line(exc.strerror or exc)}: {exc.filename or ''}".rstrip(": "), err=True)
        return 2
    except Exception as exc:  # a bug: still one line unless debugging
        sig = signal_received()
        if sig is not None:  # (a worker gone or a pool broken while the run was being stopped)
            line, status = stop_message(sig)
            click.echo(line, err=True)
            return status
        if os.environ.get("SWATCH_DEBUG"):
            raise
        click.echo(f"error: internal error ({type(exc).__name__}: {_one_line(exc)}); set SWATCH_DEBUG=1 for a traceback", err=True)
        return 70
    return rv if isinstance(rv, int) else 0


if __name__ == "__main__":
    sys.exit(main())
