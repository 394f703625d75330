"""Progress bars on stderr for the commands: the library reports progress through callbacks and
factories and draws nothing itself (issue 17: the library speaks parameters, the CLI speaks the terminal).

:func:`terminal_bar_factory` gives ``swatch catalog build`` its bars (one per step), :class:`PassBar`
turns the Mitsuba engine's ``progress(done, total)`` calls into one bar per render. Both draw only when
stderr is a terminal. Light (click only): ``swatch catalog build`` with nothing to do stays quick.
"""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

import click

from swatch.commands.terminal import unescaped
from swatch.core.escapes import printable

if TYPE_CHECKING:  # the type only: `swatch render` does not load the catalog build
    from swatch.catalog.build import ProgressBarFactory

__all__ = ["terminal_bar_factory", "PassBar"]


def terminal_bar_factory() -> ProgressBarFactory | None:
    """A progress-bar factory for :func:`swatch.catalog.build.build_catalog`, or None off a terminal.

    Returns
    -------
    callable(label, total) or None
        ``click.progressbar(length=total, label=label)`` on stderr, with the position shown; None when
        stderr is not a terminal (a log file or a pipe gets no bar).
    """
    if not sys.stderr.isatty():
        return None
    # (the bar's carriage returns and cursor codes are its own: it draws on the stream underneath the escaping
    # one, its label escaped; swatch.commands.terminal)
    return lambda label, total: click.progressbar(length=total, label=printable(label), file=unescaped(sys.stderr),
                                                  show_pos=True)


class PassBar:
    """A bar on stderr driven by ``progress(done, total)`` calls (the Mitsuba engine's, after each pass).

    Drawn from the first call on, only when stderr is a terminal and there is more than one pass;
    :meth:`close` ends the line. Use as a context manager around the render.

    Parameters
    ----------
    label : str
        The bar's label (``mitsuba sphere``).
    """

    def __init__(self, label: str) -> None:
        self.label = label
        self._bar: Any = None
        self._done = 0

    def __call__(self, done: int, total: int) -> None:
        if total <= 1 or not sys.stderr.isatty():
            return
        if self._bar is None:
            self._bar = click.progressbar(length=total, label=printable(self.label), file=unescaped(sys.stderr))
        self._bar.update(done - self._done)
        self._done = done

    def close(self) -> None:
        """End the bar's line (when one was drawn); a later call starts a new bar.

        Returns
        -------
        None
        """
        if self._bar is not None:
            self._bar.render_finish()
        self._bar, self._done = None, 0

    def __enter__(self) -> PassBar:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
