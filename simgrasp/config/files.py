"""Config files (TOML, or YAML when PyYAML is installed) and ``--set KEY=VALUE`` items, read
into dotted overrides, and a tree printed back as TOML (``--print-config``)."""

from __future__ import annotations

import json
import tomllib
from collections.abc import Collection, Mapping, Sequence
from pathlib import Path
from typing import Any

from simgrasp.config.tree import flatten_table, nest
from simgrasp.errors import DataNotFoundError, SimgraspError


def read_config_file(path: Path) -> dict[str, Any]:
    """Dotted overrides from a ``.toml`` or ``.yaml``/``.yml`` file."""
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"--config {path}: no such file")
    text = _text(path)
    if path.suffix.lower() in (".yaml", ".yml"):
        table = _yaml(text, path)
    elif path.suffix.lower() == ".toml":
        try:
            table = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SimgraspError(f"--config {path}: not valid TOML ({exc})") from None
    else:
        raise SimgraspError(f"--config {path}: expected a .toml, .yaml or .yml file")
    if not isinstance(table, Mapping):
        raise SimgraspError(f"--config {path}: expected a table of settings at the top level")
    return flatten_table(table)


def _text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SimgraspError(f"--config {path}: cannot read it ({exc})") from None


def _yaml(text: str, path: Path) -> Any:
    try:
        import yaml
    except ImportError:
        raise SimgraspError(
            f"--config {path}: YAML needs PyYAML (`pip install pyyaml`); or use TOML"
        ) from None
    try:
        return yaml.safe_load(text) or {}
    except yaml.YAMLError as exc:
        raise SimgraspError(f"--config {path}: not valid YAML ({exc})") from None


def parse_set_items(items: Sequence[str]) -> dict[str, str]:
    """``KEY=VALUE`` items (values stay text; each field's type parses them)."""
    overrides = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise SimgraspError(f"--set {item!r}: expected KEY=VALUE, e.g. detector.kind=tenpas")
        overrides[key.strip()] = value.strip()
    return overrides


def dumps_toml(flat: Mapping[str, Any]) -> str:
    """A flat ``dotted key -> plain value`` config as TOML text (``None`` values as comments,
    since TOML has no null). A key under another setting (``evaluate``'s ``detector`` list
    beside ``detector.quadric.*``) is written quoted at the top, where no table can hold it."""
    named = {key: toml_key(key, flat) for key in flat}
    table = nest({key: value for key, value in flat.items() if named[key] == key})
    table.update({named[key]: value for key, value in flat.items() if named[key] != key})
    return "\n".join(_table_lines(table, ())).strip() + "\n"


def toml_key(key: str, keys: Collection[str]) -> str:
    """``key`` as a TOML key: dotted, or quoted (one key holding dots) when a prefix of it is
    a setting too."""
    parts = key.split(".")
    under_a_setting = any(".".join(parts[:i]) in keys for i in range(1, len(parts)))
    return f'"{key}"' if under_a_setting else key


def _table_lines(table: Mapping[str, Any], prefix: tuple[str, ...]) -> list[str]:
    scalars = [(k, v) for k, v in table.items() if not isinstance(v, Mapping)]
    lines = [f"[{'.'.join(prefix)}]"] if prefix and scalars else []
    for key, value in scalars:
        lines.append(f"# {key} = none" if value is None else f"{key} = {toml_value(value)}")
    for key, value in table.items():
        if isinstance(value, Mapping):
            lines += ["", *_table_lines(value, (*prefix, key))]
    return lines


def toml_value(value: Any) -> str:
    """A plain value (:func:`~simgrasp.config.values.to_plain`) as TOML text."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, float):
        return repr(value) if value == value and abs(value) != float("inf") else str(value)
    return json.dumps(value)
