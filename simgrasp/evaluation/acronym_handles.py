"""Handle labels checked against ACRONYM grasps: where a Franka hand's pads close on the mesh.

For one ACRONYM file (``grasps/transforms``: poses of the Franka hand base in the scaled mesh
frame, +z approach, x closing) each grasp's finger contacts are approximated geometrically:
of a dense sample of the mesh surface, the points in the pads' sweep (``|y| <= pad half
width``, ``pad_z_low <= z <= pad_z_high``, ``|x| <= open half width``, gripper frame) that
each closing pad reaches first, i.e. within ``contact_depth`` of the outermost such point on
its side. A grasp is on the handle when at least half of those points lie in the label grown
by the trial's margin (:func:`simgrasp.grasping.trials.scoring.handle_fraction`), as a trial scores
``on_handle``. Shares are reported per ``affordance/*`` subset of the file.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.scoring import handle_fraction
from simgrasp.grasping.trials.trial_config import HANDLE_MARGIN, ON_HANDLE_THRESHOLD
from simgrasp.labels import HandleLabel
from simgrasp.perception import sample_surface
from simgrasp.seeding import rng_for


@dataclass(frozen=True)
class PadGeometry:
    """The Franka hand's pads in its base frame (m; ACRONYM's conventions, see
    ``../shared/acronym/README.md``)."""

    open_half_width: float = 0.041
    pad_half_width: float = 0.0105
    pad_z_low: float = 0.066
    pad_z_high: float = 0.112
    contact_depth: float = 0.003
    """Points this close (m, along x) to the first point a pad reaches count as its contacts."""
    surface_points: int = 60000


def pad_contacts(
    points_object: NDArray[np.float64],
    object_T_hand: NDArray[np.float64],
    pads: PadGeometry,
) -> NDArray[np.float64]:
    """The surface points (object frame) the two closing pads touch for one hand pose."""
    rotation, translation = object_T_hand[:3, :3], object_T_hand[:3, 3]
    points_hand = (points_object - translation) @ rotation
    x, y, z = points_hand.T
    between = (
        (np.abs(y) <= pads.pad_half_width)
        & (z >= pads.pad_z_low)
        & (z <= pads.pad_z_high)
        & (np.abs(x) <= pads.open_half_width)
    )
    if not between.any():
        return np.zeros((0, 3))
    xs = x[between]
    touched = (xs >= xs.max() - pads.contact_depth) | (xs <= xs.min() + pads.contact_depth)
    return points_object[between][touched]


def on_handle(
    points_object: NDArray[np.float64],
    object_T_hands: NDArray[np.float64],
    label: HandleLabel,
    pads: PadGeometry,
) -> NDArray[np.bool_]:
    """For each hand pose (K, 4, 4), whether its pad contacts are scored on the handle."""
    return np.array(
        [_contacts_on(pad_contacts(points_object, pose, pads), label) for pose in object_T_hands],
        dtype=bool,
    )


@dataclass(frozen=True)
class AcronymObject:
    """What the measurement needs of one ACRONYM file: the scaled mesh (its frame, m), the
    hand poses and the ``affordance/*`` index arrays."""

    name: str
    mesh: trimesh.Trimesh
    object_T_hands: NDArray[np.float64]
    subsets: dict[str, NDArray[np.int64]]


def read_acronym(path: Path, mesh_root: Path | None = None) -> AcronymObject:
    """Read an ACRONYM ``.h5`` (``object/file`` resolved against ``mesh_root``, by default the
    folder holding ``grasps/``) and its mesh, scaled by ``object/scale``."""
    import h5py

    path = Path(path)
    try:
        with h5py.File(path, "r") as data:
            mesh_file = data["object/file"][()].decode()
            scale = float(data["object/scale"][()])
            poses = np.asarray(data["grasps/transforms"][()], dtype=np.float64)
            group = data.get("affordance", {})
            subsets = {key: np.asarray(group[key][()], dtype=np.int64) for key in group}
    except (OSError, KeyError) as exc:
        raise SimgraspError(f"cannot read ACRONYM file {path}: {exc}") from exc
    root = mesh_root if mesh_root is not None else path.parent.parent
    mesh_path = Path(mesh_file) if Path(mesh_file).is_absolute() else root / mesh_file
    if not mesh_path.is_file():
        raise SimgraspError(f"ACRONYM file {path}: mesh {mesh_path} not found")
    mesh = trimesh.load(mesh_path, force="mesh")
    if not isinstance(mesh, trimesh.Trimesh):
        raise SimgraspError(f"ACRONYM file {path}: mesh {mesh_path} is empty")
    mesh.apply_scale(scale)
    return AcronymObject(path.stem, mesh, poses, subsets)


def subset_shares(
    item: AcronymObject,
    label: HandleLabel,
    pads: PadGeometry | None = None,
    held: NDArray[np.bool_] | None = None,
) -> dict[str, dict[str, float | int]]:
    """Per ``affordance/good_*`` subset: grasps counted and the share scored on the handle.

    ``held`` (one bool per grasp of the file) restricts every subset to those grasps, e.g.
    the ones our simulator held (:func:`held_from_labels`)."""
    pads = pads or PadGeometry()
    rng = rng_for(0, "acronym_handles", item.name)
    points, _ = sample_surface(item.mesh, pads.surface_points, rng)
    shares: dict[str, dict[str, float | int]] = {}
    for key, index in sorted(item.subsets.items()):
        if not key.startswith("good_"):
            continue
        chosen = index if held is None else index[held[index]]
        flags = on_handle(points, item.object_T_hands[chosen], label, pads)
        shares[key] = {"grasps": int(len(chosen)), "on_handle": int(flags.sum())}
    return shares


def held_from_labels(path: Path, grasps: int) -> NDArray[np.bool_]:
    """Which of ``grasps`` grasps a ``labels.jsonl`` of ours says were held (rows with
    ``index`` and ``success``; grasps without a row count as not held)."""
    return trial_labels(path, grasps)[0]


def trial_labels(
    path: Path, grasps: int, label: HandleLabel | None = None
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(held, on_handle), one bool per grasp, as a ``labels.jsonl`` of ours scored them (rows
    with ``index``, ``success`` and ``on_handle``; grasps without a row: False, False). Given
    a ``label``, ``on_handle`` is scored again from the rows' recorded finger contacts
    (``contact_points_object``) against it, as a trial scores it: a labeler's settings can be
    tried on a finished label run without running its trials again."""
    held = np.zeros(grasps, dtype=bool)
    on_handle = np.zeros(grasps, dtype=bool)
    try:
        lines = Path(path).read_text().splitlines()
    except OSError as exc:
        raise SimgraspError(f"cannot read labels file {path}: {exc}") from exc
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
            index, success = int(row["index"]), row["success"] is True
            touched = row.get("on_handle") is True
            if label is not None:
                touched = success and _contacts_on(row["contact_points_object"], label)
        except (json.JSONDecodeError, KeyError, TypeError, ValueError) as exc:
            raise SimgraspError(f"{path}:{number}: not a label row ({exc})") from exc
        if not 0 <= index < grasps:
            raise SimgraspError(f"{path}:{number}: grasp index {index} out of range")
        held[index], on_handle[index] = success, touched
    return held, on_handle


def _contacts_on(points_object: ArrayLike, label: HandleLabel) -> bool:
    """Whether finger contacts (object frame, m; recorded or the pads' sweep) are on the
    handle ``label``, as a trial scores ``on_handle``."""
    points = np.asarray(points_object, dtype=float).reshape(-1, 3)
    return (
        bool(len(points)) and handle_fraction(points, label, HANDLE_MARGIN) >= ON_HANDLE_THRESHOLD
    )


def trial_subset_shares(
    item: AcronymObject, held: NDArray[np.bool_], on_handle: NDArray[np.bool_]
) -> dict[str, dict[str, float | int]]:
    """Per ``affordance/good_*`` subset, among the ``held`` grasps: how many, and how many the
    trials scored ``on_handle`` (the simulator's finger contacts against the object's label,
    e.g. the automatic one of a mesh given no handle file), not the pads' geometric sweep."""
    shares: dict[str, dict[str, float | int]] = {}
    for key, index in sorted(item.subsets.items()):
        if key.startswith("good_"):
            chosen = index[held[index]]
            shares[key] = {"grasps": int(len(chosen)), "on_handle": int(on_handle[chosen].sum())}
    return shares
