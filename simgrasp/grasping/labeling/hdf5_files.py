"""HDF5 grasp files (ACRONYM's) opened so that a file that is not one is one clear line.

``h5py`` raises ``OSError`` for a file that is not HDF5 or is truncated, and ``KeyError`` /
``ValueError`` / ``TypeError`` for a dataset that is missing or of another shape or type than
the reader expects; :func:`open_hdf5` turns each into a :class:`~simgrasp.errors.SimgraspError`
naming the file, as every user-caused error is reported.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from simgrasp.errors import SimgraspError

if TYPE_CHECKING:
    import h5py


@contextmanager
def open_hdf5(path: Path, mode: Literal["r", "r+"] = "r") -> Iterator[h5py.File]:
    """``h5py.File(path, mode)`` as a context; what goes wrong reading it is a
    :class:`SimgraspError` naming ``path`` (errors of our own pass through)."""
    import h5py

    try:
        handle = h5py.File(path, mode)
    except OSError as exc:
        raise SimgraspError(f"{path} is not a readable HDF5 grasp file ({exc})") from None
    with handle:
        try:
            yield handle
        except SimgraspError:
            raise
        except (KeyError, ValueError, TypeError) as exc:
            raise SimgraspError(f"{path}: unexpected content ({exc})") from None
