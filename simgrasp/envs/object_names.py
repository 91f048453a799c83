"""Object names checked when an env is made, so that a bad one is refused there and not at
the reset that first draws it; nothing is read from disk or simulated."""

from __future__ import annotations

from simgrasp.assets.catalog import catalog_entry
from simgrasp.assets.mesh_object import is_mesh_spec, parse_mesh_spec, split_spec
from simgrasp.assets.registry import load_object
from simgrasp.assets.ycb_catalog import find_ycb_entry
from simgrasp.errors import DataNotFoundError, SimgraspError


def check_object_names(names: tuple[object, ...]) -> None:
    """A :class:`SimgraspError` naming ``objects`` and the first name in ``names`` that
    :func:`~simgrasp.assets.registry.load_object` would not find: a mesh file spec whose file
    is missing, a catalog entry whose mesh is missing, an unknown generated tool or a name in
    no catalog (a YCB object's files are looked for when an episode first uses it)."""
    for name in names:
        if not isinstance(name, str):
            raise SimgraspError(f"objects must be object names (str), got {type(name).__name__}")
        try:
            _check_name(name)
        except SimgraspError as exc:
            raise SimgraspError(f"objects: {exc}") from None


def _check_name(name: str) -> None:
    """Refuse ``name`` as :func:`check_object_names` says, looking it up as ``load_object``
    does (a generated tool is made: milliseconds, no model)."""
    if is_mesh_spec(name):
        path = parse_mesh_spec(name).path
        if not path.is_file():
            raise DataNotFoundError(f"object mesh {path} does not exist")
        return
    base = split_spec(name)[0]
    if (entry := catalog_entry(base)) is not None:
        _check_name(entry)
    elif base.startswith("gen_"):
        load_object(base)
    else:
        find_ycb_entry(base)
