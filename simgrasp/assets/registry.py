"""Look objects up by name: a mesh file spec (``PATH.obj?scale=...``), a name in the object
catalog (``objects.toml``), generated tools (``gen_<kind>``) or YCB objects (id or bare name)."""

from __future__ import annotations

import os
import re
from pathlib import Path
from urllib.parse import parse_qsl

import trimesh

from simgrasp.assets.catalog import catalog_entry
from simgrasp.assets.generated import ALL_GENERATED_KINDS, GENERATED_KINDS, generate_tool
from simgrasp.assets.mesh_object import (
    is_mesh_spec,
    load_mesh_object,
    parse_mesh_spec,
    read_mesh,
    relabeled,
    split_spec,
)
from simgrasp.assets.object import ObjectAsset
from simgrasp.errors import SimgraspError

__all__ = [
    "GENERATED_KINDS",
    "handles_file_of",
    "load_object",
    "load_object_mesh",
    "mesh_file_of",
]

_GENERATED_NAMES = ", ".join(f"gen_{kind}" for kind in ALL_GENERATED_KINDS)
"""Every loadable generated tool, for error messages (the ``generated`` set holds fewer)."""

_GENERATED = re.compile(r"^gen_(?P<kind>[a-z]+(?:_[a-z]+)*)(?:_s(?P<seed>\d+))?$")


def load_object(
    name: str, ycb_dir: str | os.PathLike[str] | None = None, *, seed: int = 0
) -> ObjectAsset:
    """Load a mesh file spec (:mod:`simgrasp.assets.mesh_object`), a catalog name
    (:mod:`simgrasp.assets.catalog`), ``gen_<kind>`` (sizes drawn from ``seed``),
    ``gen_<kind>_s<N>`` (seed N), ``NAME?handles=FILE`` (another handle label), or a YCB
    object (``"025_mug"`` or ``"mug"``) from ``ycb_dir`` / ``$SIMGRASP_YCB_DIR``."""
    if is_mesh_spec(name):
        return load_mesh_object(name)
    base, query = split_spec(name)
    if query:  # a named object with a handle label file
        return relabeled(load_object(base, ycb_dir, seed=seed), name)
    if (entry := catalog_entry(name)) is not None:
        return load_mesh_object(entry)
    match = _GENERATED.match(name)
    if match:
        kind = match["kind"]
        if kind not in ALL_GENERATED_KINDS:
            raise SimgraspError(
                f"unknown generated object {name!r}; generated objects are {_GENERATED_NAMES}"
            )
        return generate_tool(kind, int(match["seed"]) if match["seed"] else seed)
    if name.startswith("gen_"):
        raise SimgraspError(
            f"bad generated object name {name!r}: expected gen_<kind> or gen_<kind>_s<seed> "
            f"with kind one of {', '.join(ALL_GENERATED_KINDS)}"
        )
    from simgrasp.assets.ycb import load_ycb_object
    from simgrasp.assets.ycb_catalog import find_ycb_entry

    try:
        find_ycb_entry(name)
    except ValueError as exc:
        raise SimgraspError(
            f"{exc}; generated objects are {_GENERATED_NAMES} (add _s<seed> to pick sizes)"
        ) from None
    return load_ycb_object(name, ycb_dir)


def load_object_mesh(
    name: str, ycb_dir: str | os.PathLike[str] | None = None, *, seed: int = 0
) -> trimesh.Trimesh:
    """The reference surface of object ``name`` (any name :func:`load_object` takes; its own
    frame, meters) without finding its handle: a mesh file spec or catalog entry is read and
    scaled, and its ``handles`` key and automatic label are left alone (what ``simgrasp
    label-handles`` scans; ``seed`` as in :func:`load_object`)."""
    base = split_spec(name)[0]
    spec = name if is_mesh_spec(name) else catalog_entry(base)
    if spec is not None:
        return read_mesh(parse_mesh_spec(spec))
    return load_object(base, ycb_dir, seed=seed).mesh


def handles_file_of(name: str) -> Path | None:
    """The handle label file object ``name`` takes its label from (a mesh file spec's or a
    named object's ``handles``, a catalog entry's), else None (a shipped or automatic label,
    fixed by the package or the mesh). Its contents belong to a run's identity, as the
    mesh's (:func:`mesh_file_of`)."""
    base, query = split_spec(name)
    if is_mesh_spec(name):
        return parse_mesh_spec(name).handles
    if (given := dict(parse_qsl(query)).get("handles")) is not None:
        return Path(given)
    spec = catalog_entry(base)
    return None if spec is None else parse_mesh_spec(spec).handles


def mesh_file_of(name: str) -> Path | None:
    """The mesh file object ``name`` is read from when it is a mesh file spec or a catalog
    name (its contents then belong to a run's identity: the file can change under its name),
    else None (a YCB object or a generated tool)."""
    base = split_spec(name)[0]
    spec = name if is_mesh_spec(name) else catalog_entry(base)
    return None if spec is None else parse_mesh_spec(spec).path
