"""The one root of every error a user can cause (bad file, parameter, object or missing data).

The command line turns a :class:`SimgraspError` into one line on stderr and exit code 2; any
other exception is a bug and keeps its traceback. It subclasses :class:`ValueError` so callers
that catch bad values keep working. A fix a message suggests is spelled for its reader: a flag
on the command line, an argument in Python (:func:`fix_for_caller`).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Literal


class SimgraspError(ValueError):
    """A problem with what the user asked for or gave us, said in one line naming it."""


class DataNotFoundError(SimgraspError, FileNotFoundError):
    """A file, directory or data set the user named (or that a run needs) is missing."""


_CALLER: ContextVar[Literal["python", "cli"]] = ContextVar("simgrasp_caller", default="python")
"""Who is calling: a fix a message suggests is spelled for them (:func:`fix_for_caller`)."""


def fix_for_caller(cli: str, python: str) -> str:
    """The fix an error suggests, spelled for its reader: ``cli`` (``"pass --units mm"``) inside
    the command line (:func:`command_line_caller`), else ``python`` (``'pass units="mm"'``)."""
    return cli if _CALLER.get() == "cli" else python


@contextmanager
def command_line_caller() -> Iterator[None]:
    """Within this block, errors suggest fixes as command-line flags (the CLI runs each
    command inside it)."""
    token = _CALLER.set("cli")
    try:
        yield
    finally:
        _CALLER.reset(token)
