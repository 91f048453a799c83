"""Command-line flags generated from a settings tree, and the tree built back from them.

Every leaf becomes ``--dotted.key`` (underscores as dashes; plus its alias flag, if any) with
its type, choices, default and docstring in ``--help-all``, grouped by settings tree; the short
``--help`` shows the main ones (:mod:`simgrasp.config.help`). Three flags come with every tree:
``--config FILE`` (a TOML or YAML subset), ``--set KEY=VALUE`` (repeatable) and
``--print-config``. Precedence: defaults < ``--config`` < ``--set`` < flags.
"""

from __future__ import annotations

import argparse
import inspect
import re
import sys
import types
import typing
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from simgrasp.config.files import dumps_toml, parse_set_items, read_config_file
from simgrasp.config.help import HelpPlan, add_help_flags, first_paragraph, shown, usage_of
from simgrasp.config.schema import Leaf, flag_name, leaves, trees
from simgrasp.config.tree import build, check_keys, leaf_map
from simgrasp.config.values import convert, parse_text, to_plain, type_name
from simgrasp.errors import SimgraspError

_PREFIX = "setting:"
_POSITIONAL = "positional:"


def add_settings_arguments(
    parser: argparse.ArgumentParser,
    cls: type,
    *,
    examples: Sequence[str] = (),
    listing: str = "",
) -> None:
    """Add a flag (or positional) per leaf of ``cls``, grouped by settings tree, plus
    ``--config``, ``--set``, ``--print-config`` and the two helps (:mod:`simgrasp.config.help`:
    ``-h/--help`` when ``parser`` was made with ``add_help=False``, and ``--help-all``), showing
    ``examples`` and naming ``listing``, a command that lists every setting key."""
    if parser.usage is None:
        parser.usage = usage_of(cls)
    groups: dict[str, Any] = {}
    actions = {}
    for leaf in leaves(cls):
        actions[leaf.key] = _add_leaf(_group(parser, groups, cls, leaf.key), leaf)
    group = parser.add_argument_group("settings files")
    files = (
        group.add_argument(
            "--config",
            type=Path,
            metavar="FILE",
            help="TOML or YAML file setting any subset of the settings, by their dotted keys "
            "(flags and --set win over it)",
        ),
        group.add_argument(
            "--set",
            action="append",
            default=[],
            metavar="KEY=VALUE",
            help="set any setting by its dotted key, e.g. --set detector.quadric.shell_test=false "
            "(repeatable; flags win over it)",
        ),
        group.add_argument(
            "--print-config",
            action="store_true",
            help="print the effective settings as TOML and exit",
        ),
    )
    add_help_flags(parser, HelpPlan(cls, actions, files, tuple(examples), listing))


def _group(parser: argparse.ArgumentParser, groups: dict[str, Any], cls: type, key: str) -> Any:
    """The argument group of setting ``key`` in ``--help-all``: its settings tree's (``--detector.*
    settings``, described by the tree's docstring), else ``parser`` itself."""
    tree = key.split(".")[0] if "." in key else ""
    if not tree:
        return parser
    if tree not in groups:
        doc = first_paragraph(inspect.getdoc(trees(cls)[tree]) or "")
        title = f"{flag_name(tree)}.* settings"
        groups[tree] = parser.add_argument_group(title, doc.replace("%", "%%"))
    return groups[tree]


def _add_leaf(parser: Any, leaf: Leaf) -> argparse.Action:
    """The flag of ``leaf``; its text is converted and checked when the tree is built
    (:func:`given_settings`), so a bad value names the setting's key like ``--set``'s."""
    kwargs: dict[str, Any] = {"help": _help(leaf), "dest": _PREFIX + leaf.key}
    choices = leaf.spec.choices() if callable(leaf.spec.choices) else leaf.spec.choices
    choices = choices or _literal_choices(leaf.annotation)
    arity = _fixed_arity(leaf.annotation)
    if leaf.spec.many:
        kwargs.update(_many_kwargs(leaf))
    elif arity:
        kwargs.update(nargs=arity, metavar=leaf.spec.metavar or "FLOAT")
    elif leaf.annotation is bool:
        kwargs.update(nargs="?", const=True, metavar="{true,false}")
    elif choices and not leaf.spec.metavar:
        kwargs["metavar"] = "{" + ",".join(map(str, choices)) + "}"
    else:
        kwargs["metavar"] = leaf.spec.metavar or _metavar(leaf.annotation)
    if leaf.spec.positional:
        kwargs.pop("dest")
        kwargs["metavar"] = leaf.spec.metavar or leaf.key.upper()
        kwargs.setdefault("nargs", "?")
        return parser.add_argument(_POSITIONAL + leaf.key, default=None, **kwargs)
    names = [flag_name(leaf.key)] + ([leaf.spec.flag] if leaf.spec.flag else [])
    return parser.add_argument(*names, default=argparse.SUPPRESS, **kwargs)


def _many_kwargs(leaf: Leaf) -> dict[str, Any]:
    """The argparse keywords of a ``many`` list setting (``FieldSpec.many``): a positional
    takes any number of values, a flag one or more and may be repeated (``extend``)."""
    if not _is_list(leaf.annotation):
        raise TypeError(f"{leaf.key}: many=True needs a tuple[X, ...] setting")
    if leaf.spec.positional:
        return {"nargs": "*"}
    metavar = leaf.spec.metavar or _metavar(typing.get_args(leaf.annotation)[0])
    return {"nargs": "+", "action": "extend", "metavar": metavar}


def _help(leaf: Leaf) -> str:
    default = "required" if leaf.required else f"default: {shown(leaf.default)}"
    allowed = leaf.allowed
    kind = f"{type_name(leaf.annotation)}{': ' + allowed if allowed else ''}"
    text = f"{leaf.doc} ({kind}; {default})".strip()
    return text.replace("%", "%%")


def _metavar(annotation: Any) -> str:
    """A placeholder naming the value's type (``FLOAT``, ``INT``, ``LIST``, ``TEXT``)."""
    names = type_name(annotation).split(" | ")
    if len(names) > 2 or (len(names) == 2 and names[1] != "none"):
        return "{" + ",".join(names) + "}"  # a choice among literal values (or none)
    name = names[0]
    return (
        "LIST"
        if name.startswith("list")
        else {"str": "TEXT", "Path": "PATH"}.get(name, name.upper())
    )


def _literal_choices(annotation: Any) -> tuple[Any, ...] | None:
    if typing.get_origin(annotation) is typing.Literal:
        return typing.get_args(annotation)
    return None


def _fixed_arity(annotation: Any) -> int | None:
    """How many values a fixed-length tuple of numbers takes on the command line."""
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        arms = [a for a in typing.get_args(annotation) if a is not type(None)]
        annotation = arms[0] if len(arms) == 1 else annotation
    args = typing.get_args(annotation)
    fixed = typing.get_origin(annotation) is tuple and args and Ellipsis not in args
    return len(args) if fixed and all(a in (int, float) for a in args) else None


def _from_flag(leaf: Leaf, value: Any) -> Any:
    """The value of a flag's text (a list of texts for a fixed tuple), as the leaf's type; of a
    ``many`` setting's texts, the items of each (a comma list) joined."""
    if leaf.spec.many:
        return tuple(item for text in value for item in _from_text(leaf, text))
    if isinstance(value, str) or leaf.spec.parse is not None:
        return _from_text(leaf, value)
    return convert(value, leaf.annotation, leaf.key)


def _from_text(leaf: Leaf, value: Any) -> Any:
    """One value as typed (its ``parse``, else its text), as the leaf's type."""
    if leaf.spec.parse is not None:
        try:
            return leaf.spec.parse(value)
        except SimgraspError as exc:
            raise SimgraspError(f"{leaf.key}: {exc}") from None
    if _is_list(leaf.annotation) and not value.replace(",", "").strip():
        # `--osd "$SCENE"` with SCENE unset: an empty list would run the command's default
        what = re.sub(r":\w+:`~?([^`]*)`", r"\1", leaf.doc).rstrip(".")
        raise SimgraspError(f"{flag_name(leaf.key)} is empty: give at least one value ({what})")
    return parse_text(value, leaf.annotation, leaf.key)


def _is_list(annotation: Any) -> bool:
    """Whether ``annotation`` is a tuple of any length (a comma list on the command line)."""
    return typing.get_origin(annotation) is tuple and Ellipsis in typing.get_args(annotation)


def given_settings(cls: type, args: argparse.Namespace) -> dict[str, Any]:
    """Dotted key -> value of every setting in ``args``: ``--config``, then ``--set``, then
    the flags given (each later one wins)."""
    overrides: dict[str, Any] = {}
    if getattr(args, "config", None) is not None:
        from_file = read_config_file(args.config)
        check_keys(cls, from_file, f"--config {args.config}")
        overrides.update(from_file)
    items = parse_set_items(getattr(args, "set", []))
    check_keys(cls, items, "--set")
    known = leaf_map(cls)
    overrides.update({k: parse_text(v, known[k].annotation, k) for k, v in items.items()})
    for dest, value in vars(args).items():
        if dest.startswith(_PREFIX):
            key = dest.removeprefix(_PREFIX)
        elif dest.startswith(_POSITIONAL) and value not in (None, []):  # []: a `many` one, none
            key = dest.removeprefix(_POSITIONAL)
        else:
            continue
        overrides[key] = _from_flag(known[key], value)
    return overrides


def settings_from_args(cls: type, args: argparse.Namespace) -> Any:
    """The settings tree ``cls`` built from the parsed ``args``; a required setting not given
    is an error naming its flag."""
    overrides = given_settings(cls, args)
    for leaf in leaves(cls):
        if leaf.required and leaf.key not in overrides:
            name = leaf.key.upper() if leaf.spec.positional else flag_name(leaf.key)
            raise SimgraspError(f"missing {name} ({leaf.doc.rstrip('.')})")
    return build(cls, overrides)


def effective_config_text(cls: type, args: argparse.Namespace) -> str:
    """The effective settings as TOML (``--print-config``); required settings not given are
    listed as comments."""
    overrides = given_settings(cls, args)
    flat: dict[str, Any] = {}
    for leaf in leaves(cls):
        if leaf.key in overrides:
            flat[leaf.key] = to_plain(convert(overrides[leaf.key], leaf.annotation, leaf.key))
        elif not leaf.required:
            flat[leaf.key] = to_plain(leaf.default)
    missing = [leaf.key for leaf in leaves(cls) if leaf.required and leaf.key not in flat]
    notes = "".join(f"# {key} = (required, not given)\n" for key in missing)
    if not missing:
        build(cls, overrides)  # validates the values together
    return notes + dumps_toml(flat)


def script_main(
    cls: type,
    run: Callable[[Any], str | int | None],
    description: str,
    argv: Sequence[str] | None = None,
) -> int:
    """The entry point of a script whose settings tree is ``cls`` (``scripts/``): flags parsed
    as for a ``simgrasp`` command, ``--print-config`` printed without running, else ``run``
    called on the settings and the text it returns printed (an int it returns is the exit
    status: a check that printed what it found); a :class:`SimgraspError` is one line and exit
    status 2."""
    parser = argparse.ArgumentParser(description=description, add_help=False)
    add_settings_arguments(parser, cls)
    args = parser.parse_args(argv)
    try:
        if args.print_config:
            sys.stdout.write(effective_config_text(cls, args))
            return 0
        result = run(settings_from_args(cls, args))
    except SimgraspError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if isinstance(result, int):
        return result
    if result is not None:
        print(result)
    return 0
