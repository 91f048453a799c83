"""Allowed values declared on the fields of a settings dataclass, and enforced when it is built.

A field declares its range in its type, ``voxel_size: NonNegative = 0.003`` (an ``Annotated``
float carrying a :class:`Range`), its choices as a ``Literal`` or, when a registry holds them,
with ``setting(choices=...)``. A settings class derives from :class:`Checked`, whose
``__post_init__`` checks every field, so a config is checked however it is made: flags,
``--set``, ``--config`` files, :func:`simgrasp.config.build` or plain Python. A value that is
not allowed raises :class:`SettingError`, one line naming the key, the value and what is
allowed; :func:`simgrasp.config.build` names the key from the root of the tree
(``sensor.kind: 'kinnect' is not one of ideal, kinect, stereo``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import types
import typing
from collections.abc import Callable
from typing import Annotated, Any

from simgrasp.config.fields import field_spec
from simgrasp.errors import SimgraspError


@dataclasses.dataclass(frozen=True)
class Range:
    """Bounds of a finite number: ``ge``/``gt`` below, ``le``/``lt`` above (None: unbounded)."""

    ge: float | None = None
    gt: float | None = None
    le: float | None = None
    lt: float | None = None

    def allows(self, value: Any) -> bool:
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            return False
        return (
            (self.ge is None or value >= self.ge)
            and (self.gt is None or value > self.gt)
            and (self.le is None or value <= self.le)
            and (self.lt is None or value < self.lt)
        )

    def describe(self) -> str:
        """``> 0``, ``>= 1``, ``in [0, 1)``."""
        low = (f"{self.ge:g}", "[") if self.ge is not None else None
        low = (f"{self.gt:g}", "(") if self.gt is not None else low
        high = (f"{self.le:g}", "]") if self.le is not None else None
        high = (f"{self.lt:g}", ")") if self.lt is not None else high
        if low and high:
            return f"in {low[1]}{low[0]}, {high[0]}{high[1]}"
        if low:
            return f"{'>=' if low[1] == '[' else '>'} {low[0]}"
        if high:
            return f"{'<=' if high[1] == ']' else '<'} {high[0]}"
        return "any number"


@dataclasses.dataclass(frozen=True)
class MinLength:
    """A list setting needs at least ``count`` items."""

    count: int


Positive = Annotated[float, Range(gt=0)]
"""A float > 0."""
NonNegative = Annotated[float, Range(ge=0)]
"""A float >= 0."""
Fraction = Annotated[float, Range(ge=0, le=1)]
"""A float in [0, 1] (a share or a probability)."""
PositiveInt = Annotated[int, Range(ge=1)]
"""An int >= 1."""
NonNegativeInt = Annotated[int, Range(ge=0)]
"""An int >= 0."""


class SettingError(SimgraspError):
    """A setting's value is not allowed: ``path`` (field names from the class that raised) and
    ``detail`` (the value and what is allowed); ``owner`` names that class until
    :func:`simgrasp.config.build` names the key from the root."""

    def __init__(self, path: tuple[str, ...], detail: str, owner: str = "") -> None:
        self.path, self.detail, self.owner = path, detail, owner
        super().__init__(str(self))

    def __str__(self) -> str:
        key = ".".join(self.path)
        return f"{self.owner}.{key}: {self.detail}" if self.owner else f"{key}: {self.detail}"

    def keyed(self, key: str) -> SettingError:
        """The same error, named by its dotted key from the root of the tree."""
        return SettingError((key,), self.detail)


class Checked:
    """Base of a settings dataclass: every field is checked against what its type and its
    ``setting(choices=...)`` allow when an instance is made; subclasses add checks between
    fields in :meth:`_check` (raising :class:`SettingError` via :meth:`refuse`)."""

    def __post_init__(self) -> None:
        for name, annotation, choices in _rules(type(self)):  # type: ignore[arg-type]
            detail = problem(getattr(self, name), annotation, choices)
            if detail is not None:
                raise SettingError((name,), detail, type(self).__name__)
        self._check()

    def _check(self) -> None:
        """Checks between fields (none by default)."""

    def refuse(self, name: str, detail: str) -> None:
        """Raise a :class:`SettingError` for the field ``name`` of this config."""
        raise SettingError((name,), f"{getattr(self, name)!r} {detail}", type(self).__name__)

    def require_below(self, low: str, high: str, *, strict: bool = True) -> None:
        """Refuse ``low`` unless it is below (``strict``) or at most the field ``high``."""
        below = getattr(self, low) < getattr(self, high)
        if not (below or (not strict and getattr(self, low) == getattr(self, high))):
            self.refuse(low, f"is not {'<' if strict else '<='} {high} ({getattr(self, high)!r})")


Choices = tuple[Any, ...] | Callable[[], tuple[Any, ...]] | None


@functools.cache
def _rules(cls: type) -> tuple[tuple[str, Any, Choices], ...]:
    hints = typing.get_type_hints(cls, include_extras=True)
    return tuple(
        (f.name, hints[f.name], field_spec(f).choices) for f in dataclasses.fields(cls) if f.init
    )


def _choices(choices: Choices) -> tuple[Any, ...] | None:
    return choices() if callable(choices) else choices


def problem(value: Any, annotation: Any, choices: Choices = None) -> str | None:
    """What is wrong with ``value`` for a field of type ``annotation`` (with ``Range`` and
    ``MinLength`` marks) and ``choices`` (for a list setting: of each item), or None."""
    allowed = _choices(choices)
    if allowed is not None:
        items = value if isinstance(value, tuple) else (value,)
        for item in items:
            if item not in allowed and item is not None:
                return f"{item!r} is not one of {', '.join(map(str, allowed))}"
    return _type_problem(value, annotation)


def _type_problem(value: Any, annotation: Any) -> str | None:
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if annotation is int and (isinstance(value, bool) or not isinstance(value, int)):
        return f"{value!r} is not an integer"
    if annotation in _PLAIN:
        return _PLAIN[annotation](value)
    if isinstance(annotation, type) and dataclasses.is_dataclass(annotation):
        kind = annotation.__name__
        return None if isinstance(value, annotation) else f"{value!r} is not a {kind}"
    if origin is Annotated:
        detail = _type_problem(value, args[0])
        for mark in args[1:]:
            if detail is None and isinstance(mark, Range) and not mark.allows(value):
                detail = f"{value!r} is not {mark.describe()}"
            if detail is None and isinstance(mark, MinLength) and len(value) < mark.count:
                detail = f"{value!r} has fewer than {mark.count} item(s)"
        return detail
    if origin is typing.Literal:
        return None if value in args else f"{value!r} is not one of {', '.join(map(str, args))}"
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        details = [_type_problem(value, arm) for arm in args if arm is not type(None)]
        return None if None in details else details[0]
    if origin is tuple:
        return _tuple_problem(value, args)
    return None


def _tuple_problem(value: Any, args: tuple[Any, ...]) -> str | None:
    """A tuple setting's problem: not a sequence (a list is taken as one), the wrong number of
    items for a fixed tuple, or an item's own."""
    if not isinstance(value, tuple | list):
        return f"{value!r} is not a sequence of values"
    if not (len(args) == 2 and args[1] is Ellipsis) and len(value) != len(args):
        return f"{value!r} has {len(value)} values, not {len(args)}"
    arms = [args[0]] * len(value) if len(args) == 2 and args[1] is Ellipsis else list(args)
    return next((d for d in map(_type_problem, value, arms) if d is not None), None)


def _number_problem(value: Any) -> str | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return f"{value!r} is not a number"
    return "nan is not a number" if math.isnan(value) else None


_PLAIN: dict[Any, Callable[[Any], str | None]] = {
    float: _number_problem,
    bool: lambda v: None if isinstance(v, bool) else f"{v!r} is not true or false",
    str: lambda v: None if isinstance(v, str) else f"{v!r} is not text",
}
"""Checks of plain field types (``int``'s is above: a bool is no integer)."""


def describe(annotation: Any, choices: Choices = None) -> str:
    """What a field allows, for ``--help``: ``> 0``, ``in [0, 1)``, ``one of a, b`` (empty
    when its type says it all)."""
    allowed = _choices(choices)
    if allowed is not None:
        return "one of " + ", ".join(map(str, allowed))
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is Annotated:
        ranges = [m.describe() for m in args[1:] if isinstance(m, Range)]
        inner = describe(args[0])
        return " ".join(filter(None, [*ranges, inner]))
    if origin in (typing.Union, types.UnionType):
        return " ".join(filter(None, (describe(a) for a in args if a is not type(None))))
    if origin is tuple and len(args) == 2 and args[1] is Ellipsis:
        inner = describe(args[0])
        return f"each {inner}" if inner else ""
    if origin is tuple:
        inner = describe(args[0]) if args else ""
        return f"each {inner}" if inner and len(set(args)) == 1 else ""
    return ""
