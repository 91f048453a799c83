"""Grasp sets from files: our own ``.npz`` / ``.json``, ACRONYM's ``.h5`` and graspnetAPI rows.

Every set is returned in our TCP convention (README): ``object_T_tcp`` (N x 4 x 4, the object's
mesh frame, meters) with the TCP midway between the finger pads, +z the approach direction
(palm toward object) and +y the direction in which the jaws open and close. Every row is
checked; a row that is not a grasp (non-finite numbers, a non-unit quaternion, a rotation that
is not orthonormal with determinant +1, a bad last row, a non-positive width) is kept in place,
marked invalid with the reason and never scored.

Formats (chosen by the file's suffix):

- ``.npz`` / ``.json``: ``object_T_grasp`` (N x 4 x 4) or ``poses`` (N x 7,
  ``[x, y, z, qw, qx, qy, qz]``), already in our TCP convention; optional ``width`` (N, m: the
  jaw opening before closing); ``sample-grasps`` adds ``made_by`` (JSON text: what drew them).
- ``.h5`` / ``.hdf5``: ACRONYM (Eppner et al. 2021): ``grasps/transforms`` (N x 4 x 4) poses
  of the Franka hand's frame: its origin is the hand's base (the flange side), +z the approach,
  the fingers close along its x axis and their pads end 0.112 m along +z (ACRONYM's gripper
  marker draws the fingers at x = +-0.041 m from z = 0.066 to 0.112 m). We put the TCP at the
  Franka hand's documented TCP, :data:`ACRONYM_TCP_OFFSET` = 0.1034 m along +z, and turn the
  frame by -90 degrees about z so that its +y is the Franka x axis (the closing direction):
  ``object_T_tcp = object_T_franka @ FRANKA_T_TCP``. ACRONYM stores no width (the Franka hand
  opens 0.08 m): the gripper's full opening is used.
- GraspGen ``.json`` (``{"object": {...}, "grasps": {"transforms": ...}}``): Franka hand
  poses as ACRONYM's, mapped the same way.
- ``.npy``: graspnetAPI ``GraspGroup`` rows of 17 values ``[score, width, height, depth,
  R (3 x 3, row-major), t (3), object_id]``: the approach is R's x axis, the jaws close along
  its y axis, ``t`` is the grasp center (the fingertips reach ``depth`` beyond it along the
  approach). Our TCP goes to ``t`` with +z = R's x axis and +y = R's y axis (so +x = -R's z
  axis); ``width`` is the jaw opening. graspnetAPI rows are in the camera frame of their scene:
  give them in the object's mesh frame.
"""

from __future__ import annotations

import json
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.grasping.labeling.hdf5_files import open_hdf5
from simgrasp.perception._arrays import float_array
from simgrasp.transforms import pose7_to_matrix

ACRONYM_TCP_OFFSET = 0.1034
"""Distance (m) from the Franka hand's frame (ACRONYM's grasp frame) to the point midway
between its finger pads, along the approach (+z)."""

FRANKA_T_TCP = np.array(
    [
        [0.0, 1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, ACRONYM_TCP_OFFSET],
        [0.0, 0.0, 0.0, 1.0],
    ]
)
"""Our TCP frame in ACRONYM's Franka hand frame: TCP +x = Franka -y, TCP +y = Franka +x (the
closing direction), TCP +z = Franka +z (the approach)."""

GRASPNET_COLUMNS = 17
ROTATION_TOLERANCE = 1e-4
"""Largest deviation of ``R^T R`` from the identity (and of ``det R`` from 1) accepted."""
QUATERNION_TOLERANCE = 1e-3
"""Largest deviation of a pose's quaternion norm from 1 accepted."""
NUMPY_STARTS = {".npz": (b"PK\x03\x04", "no zip archive"), ".npy": (b"\x93NUMPY", "no .npy header")}
"""How an ``.npz`` (a zip archive of ``.npy`` arrays) and an ``.npy`` file begin, and what a
file that begins otherwise is not."""
NUMPY_READ_ERRORS = (
    OSError,
    ValueError,
    EOFError,
    NotImplementedError,
    zipfile.BadZipFile,
    zlib.error,
)
"""What numpy raises reading a damaged, truncated or pickled ``.npz`` / ``.npy`` file."""


@dataclass(frozen=True)
class GraspSet:
    """Grasps of one object, in input order (object frame, meters).

    Attributes:
        object_T_tcp: (N, 4, 4) TCP poses in the object's mesh frame; identity for invalid rows.
        width: (N,) jaw opening before closing (m); NaN where the file gives none.
        problems: index -> why that row is not a grasp (it is never scored).
        fmt: the file format (``"npz"``, ``"json"``, ``"acronym"``, ``"graspgen"``,
            ``"graspnet"``), or ``"arrays"`` (:meth:`from_arrays`).
    """

    object_T_tcp: NDArray[np.float64]
    width: NDArray[np.float64]
    problems: dict[int, str]
    fmt: str

    def __len__(self) -> int:
        return len(self.object_T_tcp)

    def first(self, count: int | None) -> GraspSet:
        """The set's first ``count`` rows (all of them for None)."""
        if count is None or count >= len(self):
            return self
        problems = {i: p for i, p in self.problems.items() if i < count}
        return GraspSet(self.object_T_tcp[:count], self.width[:count], problems, self.fmt)

    @classmethod
    def from_arrays(cls, object_T_grasp: ArrayLike, width: ArrayLike | None = None) -> GraspSet:
        """A grasp set from arrays, checked as the file readers check our ``.npz``:
        ``object_T_grasp`` (N, 4, 4) TCP poses in the object's mesh frame (m), ``width`` (N,)
        jaw openings (m; None: fully open). A row that is not a grasp is kept, marked in
        :attr:`problems` by its index with the reason; a wrong shape raises."""
        matrices, problems = _from_matrices(object_T_grasp, "object_T_grasp")
        widths = _widths(width, len(matrices), problems, "width")
        return cls(matrices, widths, dict(sorted(problems.items())), "arrays")

    @property
    def valid(self) -> NDArray[np.bool_]:
        """(N,) whether each row is a grasp to score."""
        mask = np.ones(len(self), dtype=bool)
        mask[list(self.problems)] = False
        return mask


def rigid_problem(transform: NDArray[np.float64]) -> str | None:
    """Why a 4 x 4 matrix is not a rigid transform, or None."""
    if not np.all(np.isfinite(transform)):
        return "non-finite values"
    rotation = transform[:3, :3]
    if np.abs(rotation.T @ rotation - np.eye(3)).max() > ROTATION_TOLERANCE:
        return "rotation is not orthonormal"
    if abs(np.linalg.det(rotation) - 1.0) > ROTATION_TOLERANCE:
        return "rotation is a reflection (det -1)"
    if np.abs(transform[3] - [0.0, 0.0, 0.0, 1.0]).max() > 1e-9:
        return f"last row {transform[3].tolist()} is not [0 0 0 1]"
    return None


def _first_sentence(exc: BaseException) -> str:
    """The first sentence of an exception's message (its type without one)."""
    text = str(exc).strip()
    return text.splitlines()[0].split(". ")[0] if text else type(exc).__name__


def _from_matrices(matrices: ArrayLike, what: str) -> tuple[NDArray, dict[int, str]]:
    """(N, 4, 4) checked transforms: invalid rows replaced by the identity, with reasons."""
    array = float_array(matrices, what, "numbers")
    if array.ndim != 3 or array.shape[1:] != (4, 4):
        raise SimgraspError(f"{what} must be N x 4 x 4, got shape {array.shape}")
    problems = {}
    for index, transform in enumerate(array):
        problem = rigid_problem(transform)
        if problem is not None:
            problems[index] = problem
    array = array.copy()
    array[list(problems)] = np.eye(4)
    return array, problems


def pose_problem(pose: NDArray[np.float64]) -> str | None:
    """Why a ``[x y z qw qx qy qz]`` pose is no grasp (non-finite values, a quaternion whose
    norm is not 1 within :data:`QUATERNION_TOLERANCE`), or None: the one rule of a file's
    rows, ``simgrasp trial --grasp`` and :func:`simgrasp.run_trial`."""
    if not np.all(np.isfinite(pose)):
        return "non-finite values"
    norm = float(np.linalg.norm(pose[3:]))
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        return f"quaternion norm {norm:.6g} is not 1 (within {QUATERNION_TOLERANCE:g})"
    return None


def _from_poses(poses: ArrayLike, what: str) -> tuple[NDArray, dict[int, str]]:
    """(N, 4, 4) transforms of (N, 7) ``[x y z qw qx qy qz]`` rows; a non-finite row or a
    quaternion whose norm is not 1 (within :data:`QUATERNION_TOLERANCE`) is invalid."""
    array = float_array(poses, what, "numbers")
    if array.ndim != 2 or array.shape[1] != 7:
        raise SimgraspError(f"{what} must be N x 7 [x y z qw qx qy qz], got shape {array.shape}")
    matrices = np.tile(np.eye(4), (len(array), 1, 1))
    problems = {}
    for index, pose in enumerate(array):
        if (problem := pose_problem(pose)) is not None:
            problems[index] = problem
        else:  # as `simgrasp trial --grasp` reads a pose
            matrices[index] = pose7_to_matrix(pose)
    return matrices, problems


def _widths(width: ArrayLike | None, count: int, problems: dict[int, str], what: str) -> NDArray:
    """(N,) widths (NaN without a ``width`` entry); a non-finite or non-positive width makes
    its row invalid; a wrong count is an error naming ``what``."""
    if width is None:
        return np.full(count, np.nan)
    widths = float_array(width, what, "numbers").reshape(-1)
    if len(widths) != count:
        raise SimgraspError(f"{what} has {len(widths)} entries for {count} grasps")
    for index in np.flatnonzero(~(np.isfinite(widths) & (widths > 0))):
        problems.setdefault(int(index), f"width {widths[index]:g} is not a positive length")
    return widths


def _own_format(entries: dict, path: Path, fmt: str) -> GraspSet:
    """Our ``object_T_grasp`` / ``poses`` (+ ``width``) entries."""
    if "object_T_grasp" in entries:
        matrices, problems = _from_matrices(entries["object_T_grasp"], f"{path}: object_T_grasp")
    elif "poses" in entries:
        matrices, problems = _from_poses(entries["poses"], f"{path}: poses")
    else:
        raise SimgraspError(f"{path} has neither 'object_T_grasp' (N x 4 x 4) nor 'poses' (N x 7)")
    widths = _widths(entries.get("width"), len(matrices), problems, f"{path}: width")
    return GraspSet(matrices, widths, dict(sorted(problems.items())), fmt)


def read_acronym(path: Path) -> GraspSet:
    """ACRONYM's ``grasps/transforms``, mapped to our TCP (module docstring)."""
    with open_hdf5(path) as handle:
        if "grasps/transforms" not in handle:
            raise SimgraspError(f"{path} is no ACRONYM grasp file: it has no 'grasps/transforms'")
        franka = np.asarray(handle["grasps/transforms"][()], dtype=float)
    return _franka_poses(franka, path, "acronym")


def _franka_poses(franka: ArrayLike, path: Path, fmt: str) -> GraspSet:
    """Franka hand poses (ACRONYM's, GraspGen's ``grasps/transforms``) mapped to our TCP."""
    matrices, problems = _from_matrices(franka, f"{path}: grasps/transforms")
    tcp = matrices @ FRANKA_T_TCP
    tcp[list(problems)] = np.eye(4)
    return GraspSet(tcp, np.full(len(tcp), np.nan), problems, fmt)


def graspnet_to_tcp(rows: ArrayLike, what: str) -> tuple[NDArray, NDArray, dict[int, str]]:
    """(N, 4, 4) TCP poses, (N,) widths and problems of graspnetAPI's (N, 17) rows; a wrong
    shape is an error naming ``what``."""
    array = float_array(rows, what, "numbers")
    if array.ndim != 2 or array.shape[1] != GRASPNET_COLUMNS:
        raise SimgraspError(f"{what} must be N x 17, got shape {array.shape}")
    matrices = np.tile(np.eye(4), (len(array), 1, 1))
    rotation = array[:, 4:13].reshape(-1, 3, 3)
    matrices[:, :3, 0] = -rotation[:, :, 2]
    matrices[:, :3, 1] = rotation[:, :, 1]
    matrices[:, :3, 2] = rotation[:, :, 0]
    matrices[:, :3, 3] = array[:, 13:16]
    problems = {}
    for index, transform in enumerate(matrices):
        if not np.all(np.isfinite(array[index])):
            problems[index] = "non-finite values"
        elif (problem := rigid_problem(transform)) is not None:
            problems[index] = problem
    widths = _widths(
        np.where(np.isfinite(array[:, 1]), array[:, 1], np.nan), len(array), problems, what
    )
    matrices[list(problems)] = np.eye(4)
    return matrices, widths, problems


def read_grasp_set(path: Path | str) -> GraspSet:
    """The grasps of ``path`` (format by suffix, see the module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"grasp file {path} does not exist")
    if path.stat().st_size == 0:
        raise SimgraspError(f"{path}: empty file")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        return _own_format(_load_numpy(path), path, "npz")
    if suffix == ".json":
        try:
            entries = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise SimgraspError(f"{path} is not JSON: {exc}") from None
        if not isinstance(entries, dict):
            raise SimgraspError(f"{path} must hold a JSON object with 'object_T_grasp' or 'poses'")
        if isinstance(entries.get("grasps"), dict) and "transforms" in entries["grasps"]:
            return _franka_poses(entries["grasps"]["transforms"], path, "graspgen")
        return _own_format(entries, path, "json")
    if suffix in (".h5", ".hdf5"):
        return read_acronym(path)
    if suffix == ".npy":
        matrices, widths, problems = graspnet_to_tcp(_load_numpy(path), f"{path}: graspnet rows")
        return GraspSet(matrices, widths, dict(sorted(problems.items())), "graspnet")
    raise SimgraspError(
        f"{path}: unknown grasp file type {suffix!r}; use .npz/.json (object_T_grasp or "
        "poses), .h5 (ACRONYM) or .npy (graspnetAPI rows)"
    )


def _load_numpy(path: Path) -> Any:
    """The arrays of an ``.npz`` file (name -> array) or the array of an ``.npy`` file, never
    unpickled; a file that is not one (other bytes, truncated, pickled objects) is a
    :class:`SimgraspError` naming it."""
    start, not_one = NUMPY_STARTS[path.suffix.lower()]
    unreadable = f"{path}: not a readable {path.suffix} grasp file"
    with path.open("rb") as handle:
        if handle.read(len(start)) != start:
            raise SimgraspError(f"{unreadable} ({not_one})")
    try:
        loaded = np.load(path, allow_pickle=False)
        if not isinstance(loaded, np.lib.npyio.NpzFile):
            return loaded
        with loaded:
            return {name: loaded[name] for name in loaded.files}
    except NUMPY_READ_ERRORS as exc:
        raise SimgraspError(f"{unreadable} ({_first_sentence(exc)})") from None


def write_grasp_set(
    path: Path | str,
    object_T_tcp: ArrayLike,
    width: ArrayLike,
    made_by: dict[str, Any] | None = None,
) -> Path:
    """Save grasps as our ``.npz`` (``object_T_grasp``, ``width``; with ``made_by``, also
    that JSON text under ``made_by``: the command and settings, seed included, that drew
    them); returns the path."""
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise SimgraspError(f"grasp sets are written as .npz, got {path}")
    path.parent.mkdir(parents=True, exist_ok=True)
    arrays: dict[str, Any] = {
        "object_T_grasp": np.asarray(object_T_tcp),
        "width": np.asarray(width),
    }
    if made_by is not None:
        arrays["made_by"] = np.array(json.dumps(made_by, sort_keys=True))
    np.savez(path, **arrays)
    return path
