"""``simgrasp settings COMMAND``: every setting of a command, one line each: its dotted key,
default, type with what it allows, and what it does (``--match`` keeps the keys holding a
text).

Each setting is a flag (``--detector.quadric.shell-test``), a ``--set`` key
(``--set detector.quadric.shell_test=false``) and a key of a ``--config`` file. The listing is
such a file, every setting at its default: save it, edit it and give it back with ``--config``.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

from simgrasp.config import Checked, setting

EXAMPLES = (
    "simgrasp settings detect --match quadric",
    "simgrasp settings trial > trial.toml",
)
"""Command lines shown by ``--help``."""


def _commands() -> tuple[str, ...]:
    from simgrasp.cli import COMMANDS

    return tuple(COMMANDS)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    command: str = setting(positional=True, metavar="COMMAND", choices=_commands)
    """The command whose settings to list."""
    match: str = setting("", metavar="TEXT", main=True)
    """Only the settings whose key holds TEXT (e.g. quadric)."""


def run(options: Options) -> int:
    from simgrasp.cli import command_module
    from simgrasp.config.listing import settings_listing

    listing = settings_listing(command_module(options.command).Options, options.match)
    if not listing:
        print(f"no setting of {options.command} has {options.match!r} in its key", file=sys.stderr)
        return 1
    sys.stdout.write(listing)
    return 0
