"""Typed values of settings: text and file values converted to a field's declared type.

Supported types: ``bool``, ``int``, ``float``, ``str``, ``Path``, ``Literal[...]``,
``X | None``, ``tuple[X, ...]``, fixed tuples, and dataclasses given as tables. A value that
does not fit is a :class:`~simgrasp.errors.SimgraspError` naming the setting.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
import types
import typing
from pathlib import Path
from typing import Any

from simgrasp.config.checks import SettingError
from simgrasp.errors import SimgraspError

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def convert(value: Any, annotation: Any, key: str) -> Any:
    """``value`` (from a file, ``--set`` or a flag) as the type ``annotation``."""
    try:
        return _convert(value, annotation, key)
    except SimgraspError:
        raise
    except (TypeError, ValueError):
        raise SettingError((key,), f"expected {type_name(annotation)}, got {value!r}") from None


def _convert(value: Any, annotation: Any, key: str) -> Any:
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if annotation is Any:
        return value
    if origin is typing.Literal:
        matches = [a for a in args if a == value or (isinstance(value, str) and str(a) == value)]
        if not matches:
            raise SettingError((key,), f"{value!r} is not one of {', '.join(map(str, args))}")
        return matches[0]
    if origin in (typing.Union, types.UnionType):
        is_none = value is None or (isinstance(value, str) and value.lower() in ("none", "null"))
        if is_none and type(None) in args:
            return None
        arms = [a for a in args if a is not type(None)]
        errors = []
        for arm in arms:
            try:
                return _convert(value, arm, key)
            except SettingError:  # a number that is NaN: say so, not which types were tried
                raise
            except (TypeError, ValueError) as exc:
                errors.append(exc)
        raise ValueError(errors[0] if errors else "no type")
    if origin is tuple:
        return _tuple(value, args, key)
    if annotation is bool:
        return _bool(value)
    if annotation is int:
        if isinstance(value, bool) or (isinstance(value, float) and not value.is_integer()):
            raise ValueError(value)
        return int(value)
    if annotation is float:
        if isinstance(value, bool):
            raise ValueError(value)
        number = float(value)
        if math.isnan(number):
            raise SettingError((key,), "nan is not a number")
        return number
    if annotation is str:
        if not isinstance(value, str):
            raise ValueError(value)
        return value
    if annotation is Path:
        return Path(value)
    if isinstance(annotation, type) and dataclasses.is_dataclass(annotation):
        return _dataclass(value, annotation, key)
    raise TypeError(f"unsupported settings type {annotation!r}")


def _bool(value: Any) -> bool:
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    raise ValueError(value)


def _tuple(value: Any, args: tuple[Any, ...], key: str) -> tuple[Any, ...]:
    if isinstance(value, str):
        value = [item.strip() for item in value.split(",") if item.strip()]
    if not isinstance(value, list | tuple):
        raise ValueError(value)
    if len(args) == 2 and args[1] is Ellipsis:
        return tuple(_convert(item, args[0], key) for item in value)
    if len(value) != len(args):
        raise SimgraspError(f"{key}: expected {len(args)} values, got {len(value)}: {value!r}")
    return tuple(
        _item(item, arm, key, i) for i, (item, arm) in enumerate(zip(value, args, strict=True))
    )


def _item(value: Any, annotation: Any, key: str, index: int) -> Any:
    """Item ``index`` of a fixed tuple, a NaN named by its position (``value 3 of 7``)."""
    try:
        return _convert(value, annotation, key)
    except SettingError as exc:
        raise SettingError((key,), f"value {index + 1}: {exc.detail}") from None


def _dataclass(value: Any, cls: type, key: str) -> Any:
    if isinstance(value, cls):
        return value
    if not isinstance(value, dict):
        raise ValueError(value)
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(value) - names)
    if unknown:
        raise SimgraspError(f"{key}: unknown field {unknown[0]!r} of {cls.__name__}")
    return cls(**{k: _convert(v, hints[k], f"{key}.{k}") for k, v in value.items()})


def parse_text(text: str, annotation: Any, key: str) -> Any:
    """A value typed on the command line: plain text for text types and comma lists, else a
    TOML value (``0.01``, ``false``, ``[[1, 0, 0]]``)."""
    if _is_text(annotation):
        return convert(text, annotation, key)
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        value = text
    return convert(value, annotation, key)


def _is_text(annotation: Any) -> bool:
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if annotation in (str, Path):
        return True
    if origin is typing.Literal:
        return all(isinstance(a, str) for a in args)
    if origin is tuple and len(args) == 2 and args[1] is Ellipsis:
        return _is_text(args[0]) or args[0] in (int, float)
    if origin in (typing.Union, types.UnionType):
        return all(_is_text(a) for a in args if a is not type(None))
    return False


def type_name(annotation: Any) -> str:
    """A short name of a settings type for messages and ``--help``."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Literal:
        return " | ".join(map(str, args))
    if origin in (typing.Union, types.UnionType):
        return " | ".join(type_name(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"list of {type_name(args[0])}"
        return f"{len(args)} values"
    return getattr(annotation, "__name__", str(annotation)).replace("NoneType", "none")


def to_plain(value: Any) -> Any:
    """A setting's value as plain data for JSON/TOML (tuples as lists, paths as text)."""
    if isinstance(value, tuple | list):
        return [to_plain(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    return value
