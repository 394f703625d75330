"""Named choices with their implementations: one small case-insensitive registry (issue 48).

A :class:`Registry` maps a name to an implementation and a one-line description, as colour-science's
``*_METHODS`` mappings with ``validate_method``: :meth:`Registry.validate` takes a name in any case (and
surrounding blanks) and returns its registered spelling, or raises :class:`swatch.core.errors.SwatchError`
naming the parameter and the choices; :meth:`Registry.names` is what a ``click.Choice`` offers; the
description is what ``--help`` and the documentation show. Unknown names are refused, never filtered.

The names and descriptions are declared where the choice is defined (the render engines, lightings and
models in :mod:`swatch.core.choices`, the tolerance metrics in :mod:`swatch.colorimetry.tolerance`); an
implementation is registered next to its definition (:meth:`Registry.implement`), so that a declaration
needs no import of what implements it (the Mitsuba engine stays an optional, lazily imported dependency).

Examples
--------
>>> shapes = Registry("shape", "shape", {"flat": (None, "a plate"), "sphere": (None, "a ball")})
>>> shapes.validate(" Sphere ")
'sphere'
>>> shapes.names()
('flat', 'sphere')
"""
from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any, Generic, TypeVar

from swatch.core.errors import SwatchError

__all__ = ["Registry"]

T = TypeVar("T")

#: The implementation of a declared name not yet registered (:meth:`Registry.implement`).
_UNSET = object()


class Registry(Mapping[str, T], Generic[T]):
    """Name → (implementation, description), looked up case-insensitively; iterates over the names in order.

    Parameters
    ----------
    what : str
        What a name names, for messages (``render engine``, ``lighting``).
    parameter : str
        The library parameter that takes a name (``engine``); messages name it in backquotes, which the CLI
        rewrites as its option (:mod:`swatch.commands.flags`).
    entries : mapping of str to (implementation, str)
        Each name (lower case unless the name is a symbol such as ``dE00``) with its implementation and its
        one-line description. An implementation may be None (a name that selects data, not code) or
        :meth:`implement`-ed later where it is defined (:meth:`declare`).

    Examples
    --------
    >>> r = Registry.declare("metric", "metric", {"dEab": "CIE 1976", "dE00": "CIEDE2000"})
    >>> r.implement("dEab", abs)
    >>> r["DEAB"] is abs
    True
    >>> r.description("de00")
    'CIEDE2000'
    """

    def __init__(self, what: str, parameter: str, entries: Mapping[str, tuple[T, str]]) -> None:
        self.what = what
        self.parameter = parameter
        self._entries: dict[str, list] = {name: [impl, desc] for name, (impl, desc) in entries.items()}
        self._keys = {name.lower(): name for name in self._entries}
        if len(self._keys) != len(self._entries):
            raise ValueError(f"{what}: two names differ only in case: {list(self._entries)}")

    @classmethod
    def declare(cls, what: str, parameter: str, descriptions: Mapping[str, str]) -> Registry:
        """Names and descriptions whose implementations are registered where they are defined.

        Parameters
        ----------
        what, parameter : str
            As the constructor.
        descriptions : mapping of str to str
            Each name and its one-line description, in the order the choices are offered.

        Returns
        -------
        Registry
            The names, each waiting for :meth:`implement`.
        """
        unset: Any = _UNSET
        return cls(what, parameter, {name: (unset, desc) for name, desc in descriptions.items()})

    def implement(self, name: str, implementation: T) -> None:
        """Register the implementation of a declared name (once, where it is defined).

        Parameters
        ----------
        name : str
            A declared name, in its registered spelling.
        implementation : object
            What the name selects (a function, a record).

        Raises
        ------
        KeyError
            For a name that was not declared (a programming error, not bad input).
        """
        if name not in self._entries:
            raise KeyError(f"{self.what} {name!r} is not declared; declared: {', '.join(self._entries)}")
        self._entries[name][0] = implementation

    def validate(self, name: object) -> str:
        """The registered spelling of ``name`` (case and surrounding blanks ignored).

        Parameters
        ----------
        name : object
            A name as given (its ``str``).

        Returns
        -------
        str
            The name as registered (``dE00``, ``studio``).

        Raises
        ------
        SwatchError
            For an unknown name, naming the parameter and the choices.
        """
        key = self._keys.get(str(name).strip().lower())
        if key is None:
            raise SwatchError(f"unknown {self.what} {str(name)[:60]!r} for `{self.parameter}`; use one of "
                              f"{', '.join(self._entries)}")
        return key

    def names(self) -> tuple[str, ...]:
        """The names, in their order (a ``click.Choice``'s choices).

        Returns
        -------
        tuple of str
            The registered spellings.
        """
        return tuple(self._entries)

    def description(self, name: str) -> str:
        """The one-line description of a name (what ``--help`` and the documentation show).

        Parameters
        ----------
        name : str
            A name, in any case.

        Returns
        -------
        str
            Its description.
        """
        return str(self._entries[self.validate(name)][1])

    def help(self) -> str:
        """Every name with its description, for ``--help``: ``name: description; …``.

        Returns
        -------
        str
            One line.
        """
        return "; ".join(f"{name}: {desc}" for name, (_, desc) in self._entries.items())

    def __getitem__(self, name: str) -> T:
        impl = self._entries[self.validate(name)][0]
        if impl is _UNSET:
            raise LookupError(f"{self.what} {name!r} has no implementation registered (its module is not imported)")
        return impl

    def __contains__(self, name: object) -> bool:
        return str(name).strip().lower() in self._keys

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __repr__(self) -> str:
        return f"Registry({self.what!r}: {', '.join(self._entries)})"
