"""Grasp files that carry their object (ACRONYM ``.h5``, GraspGen ``.json``): the object they
name, the files a ``--grasps`` glob or folder means, and our labels written back into them.

- ACRONYM: ``object/file`` (relative to ``mesh_root``, default the folder holding ``grasps/``:
  ACRONYM's layout; an absolute path as is), ``object/scale`` (mesh units to meters),
  ``object/mass`` (kg) and ``object/friction``; the object becomes the mesh spec of
  :mod:`simgrasp.assets.mesh_object`, so FleX's physics is the simulation's.
- GraspGen (``{"object": {"file", "scale"}, "grasps": {"transforms", "object_in_gripper"}}``):
  the same, without mass or friction (give ``--mass``/``--density``/``--friction``).

Export (``--export acronym|graspgen``) writes a copy of each input file with our labels added
under ``grasps/qualities/simgrasp/``: ``object_in_gripper`` (0/1), ``score`` and ``on_handle``
(0/1: held with the fingers on the handle label, a file's or the automatic one) (ACRONYM: HDF5
datasets; GraspGen: JSON lists under ``grasps.qualities.simgrasp``), for training code that
reads the format.
"""

from __future__ import annotations

import glob
import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.assets.mesh_object import MeshObjectSpec
from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.grasping.labeling.hdf5_files import open_hdf5

GRASP_SUFFIXES = (".h5", ".hdf5", ".json", ".npz", ".npy")
EXPORT_DIR = "export"


def expand_grasp_files(pattern: Path) -> list[Path]:
    """The grasp files of ``pattern``: a file, a folder (its grasp files, sorted) or a glob."""
    if pattern.is_file():
        return [pattern]
    if pattern.is_dir():
        found = sorted(p for p in pattern.iterdir() if p.suffix.lower() in GRASP_SUFFIXES)
    else:
        found = sorted(Path(p) for p in glob.glob(str(pattern)) if Path(p).is_file())
    if not found:
        raise DataNotFoundError(f"--grasps {pattern}: no grasp file there")
    return found


def is_graspgen(path: Path) -> bool:
    """Whether a ``.json`` grasp file is GraspGen's (an ``object`` and ``grasps.transforms``)."""
    if path.suffix.lower() != ".json":
        return False
    entries = _json(path)
    return isinstance(entries.get("grasps"), dict) and "object" in entries


def _json(path: Path) -> dict[str, Any]:
    try:
        entries = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise SimgraspError(f"{path} is not JSON: {exc}") from None
    return entries if isinstance(entries, dict) else {}


def carried_object(path: Path, mesh_root: Path | None = None) -> str | None:
    """The mesh spec of the object a grasp file names, or None for a file that names none."""
    path = Path(path)
    root = mesh_root or path.resolve().parent.parent
    if path.suffix.lower() in (".h5", ".hdf5"):
        with open_hdf5(path) as handle:
            if "object/file" not in handle:
                return None
            values = {
                k: float(handle[f"object/{k}"][()])
                for k in ("scale", "mass", "friction")
                if f"object/{k}" in handle
            }
            file = handle["object/file"][()]
        relative = file.decode() if isinstance(file, bytes) else str(file)
    elif is_graspgen(path):
        relative, values = _graspgen_object(path, _json(path)["object"])
    elif path.suffix.lower() == ".json" and {"object", "grasps"} <= _json(path).keys():
        raise SimgraspError(f"{path}: names an object but its 'grasps' is no GraspGen table")
    else:
        return None
    mesh = Path(relative) if Path(relative).is_absolute() else root / relative
    if not mesh.is_file():
        raise DataNotFoundError(
            f"{path}: its object file {mesh} does not exist (resolve it with --mesh-root DIR)"
        )
    return MeshObjectSpec(mesh, **values).name()  # type: ignore[arg-type]


def _graspgen_object(path: Path, entry: object) -> tuple[str, dict[str, float]]:
    """A GraspGen file's ``object`` entry: its mesh file and, if given, its scale."""
    if not isinstance(entry, dict) or "file" not in entry:
        raise SimgraspError(f"{path}: 'object' must hold a mesh 'file' (and a 'scale')")
    if "scale" not in entry:
        return str(entry["file"]), {}
    try:
        return str(entry["file"]), {"scale": float(entry["scale"])}
    except (TypeError, ValueError):
        raise SimgraspError(
            f"{path}: object scale must be a number, got {entry['scale']!r}"
        ) from None


def reference_labels(path: Path) -> tuple[np.ndarray, np.ndarray | None] | None:
    """(FleX ``object_in_gripper`` as bool, FleX ``object_motion_during_shaking_linear`` or
    None) of an ACRONYM file, or GraspGen's ``object_in_gripper``; None without labels."""
    if path.suffix.lower() in (".h5", ".hdf5"):
        with open_hdf5(path) as handle:
            key = "grasps/qualities/flex/object_in_gripper"
            if key not in handle:
                return None
            motion = "grasps/qualities/flex/object_motion_during_shaking_linear"
            shaking = np.asarray(handle[motion][()], float) if motion in handle else None
            return np.asarray(handle[key][()]).astype(bool), shaking
    if is_graspgen(path):
        grasps = _json(path)["grasps"]
        if "object_in_gripper" in grasps:
            return np.asarray(grasps["object_in_gripper"]).astype(bool), None
    return None


def export_labels(path: Path, out: Path, qualities: dict[str, np.ndarray]) -> Path:
    """A copy of grasp file ``path`` in ``out`` with our labels (``qualities``: name -> one
    value per labeled row) under ``grasps/qualities/simgrasp`` (rows past the labeled ones:
    -1); returns the copy."""
    out.mkdir(parents=True, exist_ok=True)
    target = out / path.name
    if path.suffix.lower() in (".h5", ".hdf5"):
        shutil.copyfile(path, target)
        with open_hdf5(target, "r+") as handle:
            count = len(handle["grasps/transforms"])
            group = handle.require_group("grasps/qualities/simgrasp")
            for name, values in qualities.items():
                if name in group:
                    del group[name]
                group[name] = _padded(values, count)
        return target
    if is_graspgen(path):
        entries = _json(path)
        count = len(entries["grasps"]["transforms"])
        saved = entries["grasps"].setdefault("qualities", {})
        saved["simgrasp"] = {k: _padded(v, count).tolist() for k, v in qualities.items()}
        target.write_text(json.dumps(entries))
        return target
    raise SimgraspError(f"--export writes ACRONYM .h5 or GraspGen .json files, not {path}")


def _padded(values: np.ndarray, count: int) -> np.ndarray:
    """``values`` (float) padded with -1 to ``count`` rows."""
    padded = np.full(count, -1.0)
    padded[: len(values)] = np.asarray(values, dtype=float)
    return padded
