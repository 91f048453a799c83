"""Settings trees: build a frozen dataclass tree from dotted overrides, flatten it back, and
say how it differs from its defaults.

Overrides come from a config file, ``--set KEY=VALUE`` and flags, in that order of precedence
(later wins); an unknown key is a :class:`~simgrasp.errors.SimgraspError` naming it.
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Mapping
from typing import Any

from simgrasp.config.checks import SettingError
from simgrasp.config.schema import MISSING, Leaf, is_branch, leaves, type_hints
from simgrasp.config.values import convert, to_plain
from simgrasp.errors import SimgraspError


def leaf_map(cls: type, default: Any = MISSING) -> dict[str, Leaf]:
    """Dotted key -> leaf of the tree rooted at ``cls``."""
    return {leaf.key: leaf for leaf in leaves(cls, default)}


def check_keys(cls: type, keys: Any, source: str) -> None:
    """Raise naming the first key of ``keys`` that is no setting of ``cls`` (and the nearest
    known ones)."""
    known = leaf_map(cls)
    for key in keys:
        if key not in known:
            close = difflib.get_close_matches(key, list(known), n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise SimgraspError(f"{source}: unknown setting {key!r}{hint}")


def build(cls: type, overrides: Mapping[str, Any], base: Any = None, source: str = "") -> Any:
    """An instance of ``cls`` with ``overrides`` (dotted key -> value, converted to each
    field's type) applied to ``base`` (or to the class defaults). A value a field does not
    allow is a :class:`~simgrasp.config.checks.SettingError` naming its dotted key."""
    check_keys(cls, overrides, source or cls.__name__)
    known = leaf_map(cls)
    by_path = {known[key].path: convert(value, known[key].annotation, key)
               for key, value in overrides.items()}  # fmt: skip
    try:
        return _build(cls, by_path, (), base)
    except SettingError as exc:
        if not exc.owner:
            raise
        keys = {leaf.path: leaf.key for leaf in known.values()}
        raise exc.keyed(keys.get(exc.path, ".".join(exc.path))) from None


def _build(
    cls: type, values: dict[tuple[str, ...], Any], prefix: tuple[str, ...], base: Any
) -> Any:
    kwargs: dict[str, Any] = {}
    for field in dataclasses.fields(cls):
        path = (*prefix, field.name)
        annotation = type_hints(cls)[field.name]
        if is_branch(annotation):
            if any(p[: len(path)] == path for p in values):
                nested_base = getattr(base, field.name) if base is not None else None
                if nested_base is None and callable(field.default_factory):
                    nested_base = field.default_factory()
                kwargs[field.name] = _build(annotation, values, path, nested_base)
        elif path in values:
            kwargs[field.name] = values[path]
    try:
        if base is not None:
            return dataclasses.replace(base, **kwargs)
        missing = [f.name for f in dataclasses.fields(cls) if _required(f) and f.name not in kwargs]
        if missing:
            raise SimgraspError(f"missing required setting {'.'.join((*prefix, missing[0]))!r}")
        return cls(**kwargs)
    except SettingError as exc:
        if not exc.owner:  # named from a deeper branch already
            raise
        raise SettingError((*prefix, *exc.path), exc.detail, exc.owner) from None


def _required(field: dataclasses.Field[Any]) -> bool:
    return field.default is MISSING and field.default_factory is MISSING


def flatten(instance: Any) -> dict[str, Any]:
    """Dotted key -> plain value of every leaf of ``instance``'s tree."""
    return {
        leaf.key: to_plain(_get(instance, leaf.path)) for leaf in leaves(type(instance), instance)
    }


def diff(instance: Any, default: Any) -> dict[str, Any]:
    """The leaves of ``instance`` whose value differs from ``default``'s (dotted keys, plain
    values, in field order)."""
    base = flatten(default)
    return {key: value for key, value in flatten(instance).items() if base.get(key) != value}


def nest(flat: Mapping[str, Any]) -> dict[str, Any]:
    """Dotted keys -> nested tables (for printing a config as TOML)."""
    tree: dict[str, Any] = {}
    for key, value in flat.items():
        *parents, name = key.split(".")
        node = tree
        for part in parents:
            node = node.setdefault(part, {})
        node[name] = value
    return tree


def flatten_table(table: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested tables (a parsed TOML/YAML file) -> dotted keys; a table whose key names a
    dataclass-typed leaf is kept whole by the caller's conversion."""
    flat: dict[str, Any] = {}
    for key, value in table.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, Mapping):
            flat.update(flatten_table(value, f"{dotted}."))
        else:
            flat[dotted] = value
    return flat


def _get(instance: Any, path: tuple[str, ...]) -> Any:
    for name in path:
        instance = getattr(instance, name)
    return instance
