"""Locate data the package ships (`models/` in a checkout, `simgrasp/_models` in a wheel)."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from simgrasp.errors import DataNotFoundError


@cache
def models_dir() -> Path:
    """Return the directory holding the shipped models (grippers, handle labels).

    A wheel carries the repository's ``models/`` as ``simgrasp/_models``; an editable install
    reads ``models/`` beside the package.
    """
    package = Path(__file__).resolve().parent
    for candidate in (package / "_models", package.parent / "models"):
        if candidate.is_dir():
            return candidate
    raise DataNotFoundError(
        f"simgrasp's model data is missing: neither {package / '_models'} nor "
        f"{package.parent / 'models'} exists; reinstall the package"
    )


def model_path(*parts: str) -> Path:
    """Return the path of a shipped model file, failing clearly if it does not exist."""
    path = models_dir().joinpath(*parts)
    if not path.exists():
        raise DataNotFoundError(f"shipped model file {path} does not exist")
    return path
