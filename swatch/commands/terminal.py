"""The terminal's side of the CLI: everything a run prints to stdout and stderr (reports, listings, the
``error: …`` lines, warnings, whatever a library prints) goes through
:func:`swatch.core.escapes.printable`, so a name read from a file cannot drive the terminal (issue 49).

:func:`escaped_output` puts escaping streams in place of ``sys.stdout`` and ``sys.stderr`` for a run:
no command can forget it. Two writers take the stream underneath (:func:`unescaped`) on purpose: the
``--json`` printer (JSON escapes what it must itself, and its bytes stay those of the file the command
writes) and the progress bars (their carriage returns and cursor codes are the program's own; their
labels are escaped).
"""
from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO

from swatch.core.escapes import printable

__all__ = ["EscapingStream", "escaped_output", "unescaped"]


class EscapingStream:
    """A text stream that writes to another with :func:`~swatch.core.escapes.printable` applied.

    Everything but ``write`` and ``writelines`` is the underlying stream's (``flush``, ``isatty``,
    ``fileno``, ``encoding``, …) except ``buffer``: bytes written there would pass unescaped (click
    writes bytes to a stream's buffer), so bytes are written as text here or refused.

    Parameters
    ----------
    stream : text stream
        Where the escaped text goes (``sys.stdout``, ``sys.stderr`` or a test's ``StringIO``).
    """

    def __init__(self, stream: TextIO) -> None:
        self.unescaped = stream

    def write(self, text: str) -> int:
        """Write ``text`` escaped.

        Parameters
        ----------
        text : str
            The text (bytes are refused with TypeError, as a text stream refuses them).

        Returns
        -------
        int
            ``len(text)``: the characters taken.
        """
        if not isinstance(text, str):
            raise TypeError(f"write() argument must be str, not {type(text).__name__}")
        self.unescaped.write(printable(text))
        return len(text)

    def writelines(self, lines) -> None:
        """Write each of ``lines`` escaped.

        Parameters
        ----------
        lines : iterable of str
            The texts, each with its own line end if it has one.

        Returns
        -------
        None
        """
        for line in lines:
            self.write(line)

    def __getattr__(self, name: str) -> Any:
        if name == "buffer":
            raise AttributeError(name)
        return getattr(self.unescaped, name)


def unescaped(stream: Any) -> Any:
    """The stream an :class:`EscapingStream` writes to (``stream`` itself when it is not one).

    Parameters
    ----------
    stream : text stream
        ``sys.stdout`` or ``sys.stderr`` during a run, usually.

    Returns
    -------
    text stream
        The stream underneath, for the writers whose text is the program's own (JSON, progress bars).
    """
    return stream.unescaped if isinstance(stream, EscapingStream) else stream


@contextmanager
def escaped_output() -> Iterator[None]:
    """``sys.stdout`` and ``sys.stderr`` escape what they are given over a block (the CLI's run); the
    streams that were there are put back at its end. Nested blocks escape once.

    Yields
    ------
    None
        With the escaping streams in place.
    """
    saved = sys.stdout, sys.stderr
    if saved[0] is not None and not isinstance(saved[0], EscapingStream):
        sys.stdout = EscapingStream(saved[0])
    if saved[1] is not None and not isinstance(saved[1], EscapingStream):
        sys.stderr = EscapingStream(saved[1])
    try:
        yield
    finally:
        sys.stdout, sys.stderr = saved
