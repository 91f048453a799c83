"""A command's two helps: ``--help``, what a user of the command needs on one screen, and
``--help-all``, every setting (argparse's listing of every flag, grouped by settings tree).

``--help`` lists the command's main settings (:attr:`~simgrasp.config.fields.FieldSpec.main`,
positionals and required ones) each with the first sentence of its docstring and its default,
names the command's other top-level flags, sums up each nested settings tree in one line
(``--detector.* (70)  The handle detector ...``), then the settings-file flags, an
example and how to see every setting. Both are built from the same argparse actions that parse
the command line, so neither can name a flag that does not exist.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import inspect
import re
import shutil
import sys
import textwrap
from collections.abc import Callable, Sequence
from typing import Any

from simgrasp.config.schema import Leaf, flag_name, leaves, trees
from simgrasp.config.values import to_plain

_HELP_COLUMN = 30
"""Where the short help's descriptions start (argparse's ``max_help_position``)."""
_ROLE = re.compile(r":\w+:`~?(?:[\w.]*\.)?([^`.]+)`")
_SENTENCE = re.compile(r"(.+?(?<!e\.g)(?<!i\.e)(?<!et al)[.!?])(?=\s|$)")


@dataclasses.dataclass(frozen=True)
class HelpPlan:
    """What a command's short ``--help`` shows, gathered while its flags are added.

    Attributes:
        cls: the command's settings tree.
        actions: dotted key -> the argparse action of each leaf given as a flag or positional.
        files: the ``--config``, ``--set`` and ``--print-config`` actions.
        examples: command lines shown under "examples" (none: one made from the usage).
        listing: a command that prints every setting key (e.g. ``simgrasp settings detect``).
    """

    cls: type
    actions: dict[str, argparse.Action]
    files: tuple[argparse.Action, ...]
    examples: tuple[str, ...] = ()
    listing: str = ""


class _PrintHelp(argparse.Action):
    """A flag that prints a help text and exits (argparse's ``-h`` with its own text)."""

    def __init__(self, option_strings: Sequence[str], text: Callable[[], str], **kwargs: Any):
        kwargs.update(dest=argparse.SUPPRESS, default=argparse.SUPPRESS, nargs=0)
        super().__init__(option_strings, **kwargs)
        self.text = text

    def __call__(self, parser: argparse.ArgumentParser, *_: Any, **__: Any) -> None:
        sys.stdout.write(self.text())
        parser.exit()


def add_help_flags(parser: argparse.ArgumentParser, plan: HelpPlan) -> None:
    """``-h/--help`` (the short help; unless ``parser`` has argparse's own) and
    ``--help-all`` (every flag, grouped)."""
    group = parser.add_argument_group("help")
    if not parser.add_help:
        text = lambda: short_help(parser, plan)  # noqa: E731
        group.add_argument("-h", "--help", action=_PrintHelp, text=text, help="this help")
    group.add_argument(
        "--help-all",
        action=_PrintHelp,
        text=parser.format_help,
        help="every setting as a flag, grouped, with its default and allowed values",
    )


def short_help(parser: argparse.ArgumentParser, plan: HelpPlan) -> str:
    """The short ``--help`` of ``parser``, whose flags were made from ``plan.cls``."""
    width = shutil.get_terminal_size().columns - 2  # as argparse's own formatter
    text_width = max(width - _HELP_COLUMN, 20)
    formatter = argparse.RawDescriptionHelpFormatter(
        parser.prog, max_help_position=_HELP_COLUMN, width=width
    )
    formatter.add_usage(parser.usage, [], [])
    formatter.add_text(textwrap.fill(first_paragraph(parser.description or ""), width))
    given = list(leaves(plan.cls))
    first = lambda leaf: (not leaf.spec.positional, not leaf.required)  # noqa: E731
    main = sorted((leaf for leaf in given if leaf.main), key=first)
    shorts = [_short_action(plan.actions[leaf.key], leaf, text_width) for leaf in main]
    _section(formatter, "main options", shorts)
    others = [flag_of(plan.actions[leaf.key]) for leaf in given if _other(leaf)]
    if others:
        formatter.start_section("other options")
        formatter.add_text(textwrap.fill(", ".join(others), width - 2, break_on_hyphens=False))
        formatter.end_section()
    tree_lines = _tree_lines(plan.cls, given, width - 2)
    if tree_lines:
        formatter.start_section("settings trees (how many settings; each is a flag --TREE.KEY)")
        formatter.add_text("\n".join(tree_lines))
        formatter.end_section()
    files_title = "settings files (defaults < --config < --set < flags)"
    _section(formatter, files_title, [_file_action(action) for action in plan.files])
    examples = plan.examples or (example_of(parser, given),)
    formatter.start_section("examples" if len(examples) > 1 else "example")
    formatter.add_text("\n".join(examples))
    formatter.end_section()
    every = f"Every setting, grouped, with its default and allowed values: {parser.prog} --help-all"
    every += f"; one line per key: {plan.listing}" if plan.listing else ""
    formatter.add_text(textwrap.fill(every, width, break_on_hyphens=False))
    return formatter.format_help()


_FILE_HELP = {
    "--config": "a TOML or YAML file of settings by their dotted keys",
    "--set": "any setting by its dotted key (repeatable)",
    "--print-config": "print the effective settings as TOML and exit",
}


def _section(formatter: argparse.HelpFormatter, title: str, actions: list[argparse.Action]) -> None:
    if actions:
        formatter.start_section(title)
        formatter.add_arguments(actions)
        formatter.end_section()


def _other(leaf: Leaf) -> bool:
    """A setting of the root (no tree) that is not main: named in one line by ``--help``."""
    return not leaf.main and "." not in leaf.key


def _short_action(action: argparse.Action, leaf: Leaf, width: int) -> argparse.Action:
    """``action`` as the short help shows it: by its alias flag, if it has one, and with the
    first sentence of the setting's docstring (at most two lines) and its default."""
    short = copy.copy(action)
    if len(action.option_strings) > 1:
        short.option_strings = action.option_strings[1:]
    default = "required" if leaf.required else f"default: {shown(leaf.default)}"
    text = fitted(first_sentence(leaf.doc), width, 2, suffix=f" ({default})")
    short.help = text.replace("%", "%%")
    return short


def _file_action(action: argparse.Action) -> argparse.Action:
    short = copy.copy(action)
    short.help = _FILE_HELP.get(action.option_strings[0], action.help)
    return short


def _tree_lines(cls: type, given: list[Leaf], width: int) -> list[str]:
    """One line per settings tree: ``--detector.* (70)  The handle detector and ...``."""
    counted = {}
    for key in trees(cls):
        count = sum(leaf.key.startswith(key + ".") for leaf in given)
        if count:
            counted[f"{flag_name(key)}.* ({count})"] = inspect.getdoc(trees(cls)[key]) or ""
    column = max(map(len, counted), default=0) + 2
    return [f"{name:<{column}}{_gist(doc, width - column)}" for name, doc in counted.items()]


def _gist(doc: str, width: int) -> str:
    """A docstring's headline in one line of ``width``: without its parentheses if it is
    longer, then cut at a word."""
    text = headline(doc)
    if len(text) > width:
        text = re.sub(r"\s*\([^()]*\)", "", text)
    return fitted(text, width, 1)


def example_of(parser: argparse.ArgumentParser, all_leaves: list[Leaf]) -> str:
    """A command line made from the usage: the positionals and required flags by their
    placeholders (for a command that gives no example of its own)."""
    words = [parser.prog]
    for leaf in all_leaves:
        if leaf.required:
            words.append(_placeholder(leaf))
    return " ".join(words)


def _placeholder(leaf: Leaf) -> str:
    name = leaf.spec.metavar if isinstance(leaf.spec.metavar, str) else leaf.key.upper()
    return name if leaf.spec.positional else f"{flag_name(leaf.key)} {name}"


def flag_of(action: argparse.Action) -> str:
    """The first flag of ``action`` (its placeholder for a positional)."""
    if action.option_strings:
        return action.option_strings[0]
    return str(action.metavar)


def usage_of(cls: type) -> str:
    """``%(prog)s [OPTIONS] CLOUD [MORE ...]``: the positionals, the flags summed up."""
    words = ["%(prog)s", "[OPTIONS]"]
    for leaf in leaves(cls):
        if leaf.spec.positional:
            name = leaf.spec.metavar if isinstance(leaf.spec.metavar, str) else leaf.key.upper()
            name = f"{name} ..." if leaf.spec.many else name
            words.append(name if leaf.required else f"[{name}]")
    return " ".join(words)


def plain(text: str) -> str:
    """Docstring markup made plain: ``:func:`x.y``` -> ``y``, backquotes dropped."""
    return _ROLE.sub(r"\1", text).replace("`", "")


def first_paragraph(text: str) -> str:
    """The first paragraph of a docstring, plain, on one line."""
    return " ".join(plain(inspect.cleandoc(text)).split("\n\n")[0].split())


def first_sentence(text: str) -> str:
    """The first sentence of a docstring, plain (or its first paragraph when it has no full
    stop)."""
    paragraph = " ".join(inspect.cleandoc(text).split("\n\n")[0].split())
    found = _SENTENCE.match(paragraph)
    return plain(found.group(1) if found else paragraph)


def headline(text: str) -> str:
    """What a docstring is about: its first sentence up to a colon or semicolon outside
    parentheses."""
    sentence, depth = first_sentence(text), 0
    for i, char in enumerate(sentence):
        depth += {"(": 1, ")": -1}.get(char, 0)
        if char in ":;" and depth == 0 and sentence[i + 1 : i + 2] == " ":
            return sentence[:i]
    return sentence.rstrip(".")


def fitted(text: str, width: int, lines: int, suffix: str = "") -> str:
    """``text`` then ``suffix`` in at most ``lines`` lines of ``width`` characters (as
    argparse wraps them): ``text`` cut at a word, with an ellipsis, if they do not fit."""
    if len(textwrap.wrap(text + suffix, width)) <= lines:
        return text + suffix
    words = text.split()
    while len(words) > 1:
        words.pop()
        cut = " ".join(words).rstrip(",;:(") + "..."
        if len(textwrap.wrap(cut + suffix, width)) <= lines:
            return cut + suffix
    return "..." + suffix


def shown(value: Any) -> str:
    """A default as ``--help`` shows it (lists comma-joined, an empty one as none)."""
    plain_value = to_plain(value)
    if plain_value == "":
        return '""'
    if isinstance(plain_value, list):
        return ",".join(map(str, plain_value)) if plain_value else "none"
    return str(plain_value)
