"""The one root of every error a user can cause (bad file, parameter, object or missing data).

The command line turns a :class:`SimgraspError` into one line on stderr and exit code 2; any
other exception is a bug and keeps its traceback. It subclasses :class:`ValueError` so callers
that catch bad values keep working.
"""

from __future__ import annotations


class SimgraspError(ValueError):
    """A problem with what the user asked for or gave us, said in one line naming it."""


class DataNotFoundError(SimgraspError, FileNotFoundError):
    """A file, directory or data set the user named (or that a run needs) is missing."""
