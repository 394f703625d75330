"""The ``swatch`` command: a thin click layer that parses, calls the library and reports.

Subcommands live in ``swatch/commands/`` and are imported only when used (fast start-up).
Bad input raises :class:`swatch.core.errors.SwatchError` (or a click usage error) and is reported as
one line ``error: ...`` with exit status 2; no traceback (``SWATCH_DEBUG=1`` shows one for bugs).
"""
from __future__ import annotations

import os
import signal
import sys

#: The program (the ``swatch`` script, ``python -m swatch.cli``) holds SIGINT, SIGTERM and SIGHUP from its first
#: statement, before the imports, until :func:`main` has its handlers in place and delivers what came meanwhile:
#: a Ctrl-C during the imports is one line and 130 too (it was Python's traceback and a raw death, issue 49).
#: The mask it replaced, or None (imported by another program, or no signal masks on this system).
_START_MASK = (signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM, signal.SIGHUP})
               if hasattr(signal, "pthread_sigmask")
               and (__name__ == "__main__" or os.path.basename(sys.argv[0] if sys.argv else "") in ("swatch", "swatch.exe"))
               else None)

import difflib
import importlib

import click

from swatch.commands.flags import speak_flags
from swatch.commands.terminal import escaped_output
from swatch.core.errors import SwatchError
from swatch.core.escapes import printable
from swatch.core.heap import keep_freed_memory
from swatch.core.procguard import (
    Terminated,
    guard_exit,
    handle_termination,
    release_signals,
    settle,
    signal_received,
    stop_message,
)
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
    def make_context(self, info_name, args, parent=None, **extra):
        try:  # (parsing runs the --version and --help callbacks: click made a stop there "error: aborted")
            return super().make_context(info_name, args, parent=parent, **extra)
        except KeyboardInterrupt as exc:
            raise _InterruptedError(exc) from None

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


# color=True: click leaves escape sequences in what it is given (off a terminal it deleted the ones it knows,
# silently); the output streams show every one escaped instead (swatch.commands.terminal). swatch prints no styles.
@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"], "color": True})
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
    line = printable(" ".join(words), one_line=True)
    return line if len(line) <= MAX_ERROR_CHARS else line[:MAX_ERROR_CHARS] + f" …[{len(line)} characters]"


def main(argv: list[str] | None = None) -> int:
    """Entry point: run the CLI, turning every expected failure into one line and exit 2, a stop into one
    line and 128 + the signal (130 for Ctrl-C, 143 for SIGTERM).

    Called without ``argv`` it is the program (the ``swatch`` script, ``python -m swatch.cli``): its outcome
    is then settled for the process's exit too (:func:`swatch.core.procguard.settle`: a signal during the
    exit is not a traceback, nor a silent death). Everything the run prints is escaped
    (:mod:`swatch.commands.terminal`).
    """
    global _START_MASK
    held, _START_MASK = _START_MASK, None  # (the program's: main() runs once there)
    handle_termination()  # SIGTERM/SIGHUP unwind like Ctrl-C: temporary files removed, one line
    keep_freed_memory()  # array temporaries reused from the heap, not mapped and faulted in again (swatch.core.heap)
    if argv is None:
        guard_exit()
    with escaped_output():
        status = _outcome(argv, held)
        if argv is None:
            settle(status)  # from here a signal is recorded, not raised (the exit handler reports a late one)
        sig = signal_received()
        if status == 0 and sig is not None:  # a stop lost on its way (a finaliser dropped it): not a success
            line, status = stop_message(sig)
            click.echo(line, err=True)
            if argv is None:
                settle(status)
    return status


def _outcome(argv: list[str] | None, held) -> int:
    """The run's exit status, its line printed: a stop is one line, also one that comes while a failure is
    being reported, and a second one while the first one's line is."""
    try:
        try:
            if held is not None:
                release_signals(held)  # the handlers are in place: a signal held since the start is raised here
            return _run(argv)
        except KeyboardInterrupt as intr:  # (one that came while a failure was being reported)
            return _report_stop(intr)
    except KeyboardInterrupt as again:
        return stop_message(signal_received() or _signum(again))[1]


def _signum(intr: KeyboardInterrupt) -> int:
    return intr.signum if isinstance(intr, Terminated) else signal.SIGINT


def _report_stop(intr: KeyboardInterrupt) -> int:
    line, status = stop_message(_signum(intr))
    click.echo(line, err=True)
    return status


def _stopped() -> int | None:
    """The exit status of a run that a signal stopped, its line printed, or None: an error raised while a
    run is being stopped (a worker gone, a pool broken, a file a stopped library left unread) is the stop."""
    sig = signal_received()
    if sig is None:
        return None
    line, status = stop_message(sig)
    click.echo(line, err=True)
    return status


def _run(argv: list[str] | None) -> int:
    try:
        rv = cli.main(args=argv, prog_name="swatch", standalone_mode=False)
    except SwatchError as exc:  # the library names parameters; the CLI speaks its flags
        if (stop := _stopped()) is not None:
            return stop
        click.echo(f"error: {speak_flags(_one_line(exc))}", err=True)
        return 2
    except click.exceptions.Abort as exc:
        if isinstance(exc.__cause__, KeyboardInterrupt):  # (click's, around what it runs itself)
            return _report_stop(exc.__cause__)
        click.echo("error: aborted", err=True)
        return 130
    except click.ClickException as exc:
        if (stop := _stopped()) is not None:
            return stop
        ctx = getattr(exc, "ctx", None)
        cmd = f" (see 'swatch {ctx.command_path.split(' ', 1)[1]} --help')" if ctx and " " in ctx.command_path else ""
        click.echo(f"error: {_one_line(exc.format_message())}{cmd}", err=True)
        return exc.exit_code if exc.exit_code else 2
    except (KeyboardInterrupt, _InterruptedError) as caught:
        return _report_stop(caught.exc if isinstance(caught, _InterruptedError) else caught)
    except BrokenPipeError:
        return 0
    except OSError as exc:
        if (stop := _stopped()) is not None:
            return stop
        where = printable(str(exc.filename), one_line=True) if exc.filename else ""
        click.echo(f"error: {_one_line(exc.strerror or exc)}: {where}".rstrip(": "), err=True)
        return 2
    except Exception as exc:  # a bug: still one line unless debugging
        if (stop := _stopped()) is not None:  # (a worker gone or a pool broken while the run was being stopped)
            return stop
        if os.environ.get("SWATCH_DEBUG"):
            raise
        click.echo(f"error: internal error ({type(exc).__name__}: {_one_line(exc)}); set SWATCH_DEBUG=1 for a traceback", err=True)
        return 70
    return rv if isinstance(rv, int) else 0


if __name__ == "__main__":
    sys.exit(main())
