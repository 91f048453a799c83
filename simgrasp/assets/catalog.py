"""The object catalog: user objects by name, from an ``objects.toml`` file.

The catalog is ``$SIMGRASP_OBJECTS`` (a file path) or else ``objects.toml`` in the working
directory, if there is one. Each table is an object::

    [my_mug]
    mesh = "meshes/mug.stl"      # relative to the catalog file, or absolute
    units = "mm"                 # or scale = 0.001 (default: meters)
    mass = 0.3                   # kg; or density = 800 (kg/m^3)
    friction = 0.9               # optional
    handles = "my_handles.json"  # optional handle label file (ycb_handles.json format)

A catalog name resolves to the mesh file spec of :mod:`simgrasp.assets.mesh_object`, so
sweeps, ``label-grasps`` and the env take ``my_mug`` as they take ``025_mug``.
"""

from __future__ import annotations

import os
import tomllib
from functools import cache
from pathlib import Path

from simgrasp.assets.mesh_object import MeshObjectSpec
from simgrasp.errors import SimgraspError

CATALOG_ENV = "SIMGRASP_OBJECTS"
CATALOG_FILE = "objects.toml"
_NUMBERS = ("scale", "mass", "density", "friction")


def catalog_path() -> Path | None:
    """The catalog file in use, or None (no ``$SIMGRASP_OBJECTS``, no ``./objects.toml``)."""
    if os.environ.get(CATALOG_ENV):
        path = Path(os.environ[CATALOG_ENV])
        if not path.is_file():
            raise SimgraspError(f"{CATALOG_ENV}={path} is not a file")
        return path
    local = Path(CATALOG_FILE)
    return local if local.is_file() else None


@cache
def _read(path: Path, mtime_ns: int) -> dict[str, str]:
    """Catalog name -> mesh spec name of one catalog file version."""
    try:
        tables = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise SimgraspError(f"object catalog {path}: {exc}") from None
    return {name: _spec(path, name, entry) for name, entry in tables.items()}


def _spec(path: Path, name: str, entry: object) -> str:
    """The mesh spec name of catalog entry ``name``."""
    if not isinstance(entry, dict) or "mesh" not in entry:
        raise SimgraspError(f'object catalog {path}: [{name}] needs a mesh = "FILE"')
    unknown = set(entry) - {"mesh", "units", "handles", *_NUMBERS}
    if unknown:
        raise SimgraspError(f"object catalog {path}: [{name}] has unknown keys {sorted(unknown)}")
    where = f"object catalog {path}: [{name}]"
    for key in ("mesh", "units", "handles"):
        if key in entry and not isinstance(entry[key], str):
            raise SimgraspError(f"{where} {key} must be text, got {entry[key]!r}")
    for key in _NUMBERS:
        if key in entry and (
            isinstance(entry[key], bool) or not isinstance(entry[key], int | float)
        ):
            raise SimgraspError(f"{where} {key} must be a number, got {entry[key]!r}")
    base = path.resolve().parent
    values: dict[str, object] = {k: float(entry[k]) for k in _NUMBERS if k in entry}
    if "units" in entry:
        values["units"] = entry["units"]
    if "handles" in entry:
        values["handles"] = base / entry["handles"]
    return MeshObjectSpec(base / entry["mesh"], **values).name()  # type: ignore[arg-type]


def catalog_entry(name: str) -> str | None:
    """The mesh spec of catalog object ``name``, or None when it is not in the catalog."""
    path = catalog_path()
    if path is None:
        return None
    return _read(path, path.stat().st_mtime_ns).get(name)
