"""What a terminal may be shown: control characters and bidirectional overrides escaped (issue 49).

A part name read from a CSV, CGATS or CxF file, a file name, a spec's text: any of them may carry a
terminal escape (``ESC [2J`` clears the screen, ``ESC ]0;…BEL`` sets the window title, OSC 52 writes the
clipboard) or a Unicode bidi override that shows the line's characters in another order than they
are. :func:`printable` spells those characters out, so that the text is shown as it is and still reads
as what it was. The CLI applies it to everything it prints (``swatch.commands.terminal``).
"""
from __future__ import annotations

import re

__all__ = ["printable", "UNSAFE"]

#: The characters :func:`printable` escapes: the C0 controls but tab and newline, DEL and the C1 controls
#: (Unicode category Cc), the bidirectional marks, embeddings, overrides and isolates (U+061C, U+200E,
#: U+200F, U+202A–U+202E, U+2066–U+2069) and lone surrogates (a file name's undecodable bytes, which a
#: UTF-8 stream cannot write).
UNSAFE = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069\ud800-\udfff]")


def _spelled(ch: str) -> str:
    code = ord(ch)
    return f"\\u{code:04x}" if code <= 0xFFFF else f"\\U{code:08x}"


def printable(text: str, one_line: bool = False) -> str:
    """``text`` with every :data:`UNSAFE` character written as ``\\uXXXX`` (ESC as ``\\u001b``, a
    right-to-left override as ``\\u202e``): the spelling of JSON and Python, so a JSON text stays valid
    JSON of the same value. Tab and newline are kept (reports are tables of lines).

    Parameters
    ----------
    text : str
        What is to be shown.
    one_line : bool, optional
        Escape every character that is not printable (:meth:`str.isprintable`: tab and newline too,
        zero-width and other invisible characters), for a line that must stay one line and show each
        character it quotes.

    Returns
    -------
    str
        The same text, those characters escaped (``text`` itself when it has none).

    Examples
    --------
    >>> printable("part \\x1b[2J7")
    'part \\\\u001b[2J7'
    """
    if one_line:
        return text if text.isprintable() else "".join(ch if ch.isprintable() else _spelled(ch) for ch in text)
    return UNSAFE.sub(lambda m: _spelled(m.group()), text) if UNSAFE.search(text) else text
