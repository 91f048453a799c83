"""The ``simgrasp`` command line: one sub-command per user task, one module per command.

Each command module holds an ``Options`` frozen dataclass, from whose fields (its own and the
settings trees it nests) the flags are generated (:mod:`simgrasp.config.arguments`), and
``run(options) -> int``. Only the chosen command's module is imported, so ``simgrasp detect``
does not pay for MuJoCo. A :class:`~simgrasp.errors.SimgraspError` becomes one line on stderr
and exit code 2; any other exception is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import NoReturn

from simgrasp.config.arguments import (
    add_settings_arguments,
    effective_config_text,
    settings_from_args,
)
from simgrasp.errors import SimgraspError, command_line_caller
from simgrasp.runs.out_dir import check_outputs, remove_empty

# name -> one-line help; the module is simgrasp.cli.<name with - as _>
COMMANDS: dict[str, str] = {
    "demo": "run the main job on the embedded default",
    "detect": "detect handles in a point cloud file (or in each object of a scene)",
    "segment": "find the table and the objects on it in a sensor scene cloud",
    "scenes": "export cluttered scenes as labeled organized PCD files",
    "detect-eval": "detection accuracy on YCB meshes (paper Tables I and II)",
    "labels": "render objects with their labeled handles",
    "fetch-ycb": "download YCB objects from the official site",
    "object": "show or export an object model",
    "trial": "run one grasp trial in MuJoCo",
    "evaluate": "sweep objects x detectors x grippers",
    "sample-grasps": "sample antipodal grasps on an object's mesh",
    "label-grasps": "score every grasp of a file: does it hold, by the handle?",
    "compare-labels": "confusion matrix of two label-grasps runs",
    "label-handles": "find the handle regions of any mesh, as a label file",
    "view": "interactive 3D view of a label-grasps folder (served or exported as HTML)",
    "settings": "list every setting of a command: key, default, type and what it does",
}


def command_module(name: str) -> ModuleType:
    """The module of command ``name``."""
    return importlib.import_module(f"simgrasp.cli.{name.replace('-', '_')}")


class UsageError(SimgraspError):
    """A command line argparse rejects (its message names the command)."""


class _Parser(argparse.ArgumentParser):
    """An argparse parser whose errors are one line (no usage dump of hundreds of flags)."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{self.prog}: error: {message} (see {self.prog} --help)")


def build_parser(command: str | None) -> argparse.ArgumentParser:
    """The parser of every command, with the flags of ``command`` (only its module is
    imported)."""
    parser = _Parser(
        prog="simgrasp",
        description=__doc__.splitlines()[0],
        epilog="simgrasp COMMAND --help: a command's main options and an example; "
        "simgrasp COMMAND --help-all: every setting.",
        allow_abbrev=False,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, help_text in COMMANDS.items():
        # no abbreviations: `--detector` on a command without it would match every
        # `--detector.*` flag of another, and a typo must not pick a flag silently
        chosen = name == command  # its -h is the short help of its settings
        cmd = sub.add_parser(
            name, help=help_text, description=help_text, allow_abbrev=False, add_help=not chosen
        )
        if chosen:
            module = command_module(name)
            cmd.description = (module.__doc__ or help_text).strip()
            cmd.formatter_class = argparse.RawDescriptionHelpFormatter
            examples = getattr(module, "EXAMPLES", ())
            listing = f"simgrasp settings {name}" if "settings" in COMMANDS else ""
            add_settings_arguments(cmd, module.Options, examples=examples, listing=listing)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    _INVOCATION[:] = argv
    command = next((a for a in argv if not a.startswith("-")), None)
    try:
        args = build_parser(command if command in COMMANDS else None).parse_args(argv)
    except UsageError as exc:
        print(exc, file=sys.stderr)
        return 2
    module = command_module(args.command)
    made: list[Path] = []
    try:
        if args.print_config:
            sys.stdout.write(effective_config_text(module.Options, args))
            return 0
        options = settings_from_args(module.Options, args)
        made = check_outputs(options)  # a run never works for minutes, then fails to save
        with command_line_caller():  # errors suggest flags, not Python arguments
            code = int(module.run(options) or 0)
        sys.stdout.flush()  # a closed pipe shows here, inside the handler below
        return code
    except SimgraspError as exc:
        remove_empty(made)
        print(f"simgrasp {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return _reader_gone()


def _reader_gone() -> int:
    """The reader of stdout has gone (``simgrasp detect c.npy | head -1``): end quietly with
    exit status 1, as the Python docs recommend (SIGPIPE), pointing stdout at /dev/null so the
    interpreter's final flush raises nothing either."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    return 1


def invocation() -> list[str]:
    """The command line of the running command (``["simgrasp", "evaluate", ...]``), e.g. for
    the lock file naming the run that holds an output directory."""
    return ["simgrasp", *_INVOCATION]


_INVOCATION: list[str] = []
