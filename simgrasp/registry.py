"""A run-time registry: the entries of one kind (detector presets, grasp proposers, sensor
models, grippers) by name, in the order they were added, the first the default.

It is a ``dict`` of name to entry, so reading it is reading a dict (``in``, ``[name]``,
``values()``, iteration in order); :meth:`Registry.entry` looks a name up with an error
naming the choices and :meth:`Registry.register` adds a new name once. Importing it imports
nothing else of simgrasp but its errors.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Protocol, TypeVar

from simgrasp.errors import SimgraspError


class Named(Protocol):
    """An entry of a registry: anything with a ``name``."""

    @property
    def name(self) -> str: ...


Entry = TypeVar("Entry", bound=Named)


class Registry(dict[str, Entry]):
    """Entries by their ``name``. ``kind`` is the word the errors call an entry (``"sensor"``:
    "unknown sensor 'lidar'; choose one of ideal, ...", "sensor 'noisy' is registered
    already"); ``choose`` the words before the list of names."""

    def __init__(self, kind: str, entries: Iterable[Entry], choose: str = "choose one of"):
        super().__init__((entry.name, entry) for entry in entries)
        self.kind = kind
        self.choose = choose

    def names(self) -> tuple[str, ...]:
        """The registered names, in the order they were added (the default first)."""
        return tuple(self)

    def entry(self, name: str) -> Entry:
        """The entry called ``name``, else one line naming the choices."""
        if name not in self:
            raise SimgraspError(f"unknown {self.kind} {name!r}; {self.choose} {', '.join(self)}")
        return self[name]

    def register(self, entry: Entry) -> None:
        """Add ``entry`` (its name must be new)."""
        if entry.name in self:
            raise SimgraspError(f"{self.kind} {entry.name!r} is registered already")
        self[entry.name] = entry
