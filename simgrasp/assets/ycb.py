"""Load YCB objects from a local download laid out as the official archives unpack.

Layout: ``<root>/<object_id>/google_16k/textured.obj`` (+ ``textured.mtl`` and a
``texture_map.png`` or ``.jpg``), or, for objects without a Google scan (the chips can), the
Berkeley ``<root>/<object_id>/poisson/{textured.obj, nontextured.stl, nontextured.ply}``.
Meshes are in meters, in the scan's own frame (z up, resting near z = 0).
"""

from __future__ import annotations

import os
from pathlib import Path

from simgrasp.assets.mesh_check import load_mesh_file
from simgrasp.assets.object import ObjectAsset
from simgrasp.assets.ycb_catalog import find_ycb_entry
from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.labels import ycb_handle_label

YCB_DIR_ENV = "SIMGRASP_YCB_DIR"

# Mesh files to try, best first, relative to the object's folder.
MESH_CANDIDATES: tuple[str, ...] = (
    "google_16k/textured.obj",
    "poisson/textured.obj",
    "poisson/nontextured.stl",
    "poisson/nontextured.ply",
)
TEXTURE_NAMES: tuple[str, ...] = ("texture_map.png", "texture_map.jpg", "textured.png")


def resolve_ycb_root(ycb_dir: str | os.PathLike[str] | None = None) -> Path:
    """The YCB download folder: ``ycb_dir``, else ``$SIMGRASP_YCB_DIR``; it must exist."""
    if ycb_dir is None:
        ycb_dir = os.environ.get(YCB_DIR_ENV) or None
    if ycb_dir is None:
        raise DataNotFoundError(
            f"no YCB folder given: pass --ycb-dir, set {YCB_DIR_ENV} to a YCB download "
            "(the folder holding 025_mug/ etc.), or get one with "
            "`simgrasp fetch-ycb --objects all --dest DIR`"
        )
    root = Path(ycb_dir).expanduser()
    if not root.is_dir():
        raise DataNotFoundError(
            f"YCB folder {root} does not exist; point {YCB_DIR_ENV} or --ycb-dir at a YCB "
            "download, or create one with `simgrasp fetch-ycb --dest DIR`"
        )
    return root


def _find_mesh(object_dir: Path) -> Path | None:
    return next((object_dir / rel for rel in MESH_CANDIDATES if (object_dir / rel).is_file()), None)


def available_ycb_objects(root: str | os.PathLike[str]) -> list[str]:
    """Sorted ids of the objects under ``root`` that have a loadable mesh file."""
    root = Path(root)
    return sorted(d.name for d in root.iterdir() if d.is_dir() and _find_mesh(d) is not None)


def _mtl_texture(mesh_path: Path) -> Path | None:
    """The ``map_Kd`` image named by the OBJ's material file, if it exists.

    Tolerates trailing whitespace after the file name (some mirrors ship it).
    """
    mtl_path = mesh_path.with_suffix(".mtl")
    if not mtl_path.is_file():
        return None
    for line in mtl_path.read_text(errors="replace").splitlines():
        key, _, value = line.strip().partition(" ")
        if key == "map_Kd" and value.strip():
            texture = mesh_path.parent / value.strip()
            return texture if texture.is_file() else None
    return None


def _texture_for(mesh_path: Path) -> Path | None:
    if mesh_path.suffix.lower() != ".obj":
        return None
    texture = _mtl_texture(mesh_path)
    if texture is not None:
        return texture
    return next(
        (mesh_path.parent / n for n in TEXTURE_NAMES if (mesh_path.parent / n).is_file()), None
    )


def ycb_mesh_path(root: str | os.PathLike[str], object_id: str) -> tuple[Path, Path | None]:
    """The mesh file of ``object_id`` under ``root`` and its texture image (or ``None``).

    Prefers ``google_16k/textured.obj``, then the Berkeley Poisson mesh.
    """
    root = Path(root)
    object_dir = root / object_id
    if not object_dir.is_dir():
        present = available_ycb_objects(root) if root.is_dir() else []
        listing = ", ".join(present) if present else "none"
        raise DataNotFoundError(
            f"YCB object {object_id!r} is not in {root} (present: {listing}); get it with "
            f"`simgrasp fetch-ycb --objects {object_id} --dest {root}`"
        )
    mesh_path = _find_mesh(object_dir)
    if mesh_path is None:
        raise DataNotFoundError(
            f"YCB object {object_id!r} in {object_dir} has no mesh file; looked for "
            f"{', '.join(MESH_CANDIDATES)}"
        )
    return mesh_path, _texture_for(mesh_path)


def load_ycb_object(
    name: str,
    ycb_dir: str | os.PathLike[str] | None = None,
    mass_kg: float | None = None,
) -> ObjectAsset:
    """Load a YCB object by id (``"033_spatula"``) or bare name (``"spatula"``).

    The mesh stays in the scan's frame (meters); the mass is the published one from the
    catalog unless ``mass_kg`` overrides it (required for parts without a published mass);
    the handle is the shipped label.
    """
    entry = find_ycb_entry(name)
    mass = entry.mass_kg if mass_kg is None else float(mass_kg)
    if mass is None:
        raise SimgraspError(
            f"YCB object {entry.id!r} has no published mass (it is one part of a set); "
            "pass mass_kg explicitly"
        )
    if not mass > 0:
        raise SimgraspError(f"mass_kg for YCB object {entry.id!r} must be positive, got {mass}")
    root = resolve_ycb_root(ycb_dir)
    mesh_path, texture_path = ycb_mesh_path(root, entry.id)
    mesh = load_mesh_file(mesh_path, entry.id)
    return ObjectAsset(
        name=entry.id,
        mesh=mesh,
        handle=ycb_handle_label(entry.id),
        mass=mass,
        source="ycb",
        mesh_file=mesh_path,
        texture_file=texture_path,
    )
