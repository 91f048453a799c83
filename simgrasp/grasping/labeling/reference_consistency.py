"""How consistent a grasp file's own labels are: the ceiling beside an agreement figure.

A reference labeler (FleX in ACRONYM files) turns its verdict over under small changes of
pose; a labeler whose physics differs from it cannot be expected to agree with it more often
than it agrees with itself. For each grasp we scored, the nearest *other* grasp of the same
file within :data:`NEIGHBOUR_MM` of TCP position and :data:`NEIGHBOUR_DEG` of rotation (a half
turn about the approach counting as the same grasp: the jaws are symmetric) is found among
all of the file's grasps, and the reference's label of that neighbour is taken as a prediction
of the reference's label of the grasp. Its accuracy over the grasps that have a neighbour is
the reference's own consistency; our accuracy is reported on the same grasps beside it.

The floor beside it is the majority-class baseline: the accuracy of a labeler that gives every
grasp the reference's more common label.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from simgrasp.grasping.labeling.grasp_sets import GraspSet

NEIGHBOUR_MM = 8.0
"""A neighbour's TCP is at most this far (mm) from the grasp's."""
NEIGHBOUR_DEG = 15.0
"""A neighbour's rotation is at most this far (degrees) from the grasp's."""
HALF_TURN = np.diag([-1.0, -1.0, 1.0])
"""A parallel-jaw grasp turned half a turn about its approach (TCP z) is the same grasp."""


def turn_degrees(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle (degrees) between TCP rotations ``a`` and ``b`` ((3, 3) or (N, 3, 3) each, the
    same frame), a half turn about the approach counting as no turn."""
    relative = np.swapaxes(a, -1, -2) @ b
    return np.minimum(
        np.degrees(Rotation.from_matrix(relative).magnitude()),
        np.degrees(Rotation.from_matrix(relative @ HALF_TURN).magnitude()),
    )


def nearest_neighbours(
    object_T_tcp: NDArray[np.float64],
    rows: NDArray[np.int_],
    valid: NDArray[np.bool_] | None = None,
    mm: float = NEIGHBOUR_MM,
    deg: float = NEIGHBOUR_DEG,
) -> NDArray[np.int_]:
    """For each of ``rows``, the index of the nearest other grasp of ``object_T_tcp``
    ``(N, 4, 4)`` (TCP poses, m) within ``mm`` and ``deg`` (nearest by distance / ``mm`` +
    angle / ``deg``) among the ``valid`` ones (all by default), or -1 where there is none."""
    positions, rotations = object_T_tcp[:, :3, 3], object_T_tcp[:, :3, :3]
    candidates = np.flatnonzero(np.ones(len(positions), bool) if valid is None else valid)
    tree = cKDTree(positions[candidates])
    found = np.full(len(rows), -1, dtype=int)
    for k, i in enumerate(np.asarray(rows, dtype=int).tolist()):
        near_i = candidates[tree.query_ball_point(positions[i], mm / 1000)]
        others = near_i[near_i != i]
        if others.size == 0:
            continue
        angle = turn_degrees(rotations[i], rotations[others])
        near = angle < deg
        if not near.any():
            continue
        distance = np.linalg.norm(positions[others] - positions[i], axis=1) * 1000 / mm
        found[k] = int(others[near][np.argmin((distance + angle / deg)[near])])
    return found


def neighbour_agreement(
    grasps: GraspSet,
    reference: NDArray[np.bool_],
    rows: NDArray[np.int_],
    ours: NDArray[np.bool_],
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(the reference's neighbour label equals its own label, our label equals the
    reference's) for the grasps of ``rows`` that have a neighbour (:func:`nearest_neighbours`)
    among all of the file's valid grasps; ``reference`` labels every grasp of ``grasps``,
    ``ours`` each of ``rows``."""
    neighbours = nearest_neighbours(grasps.object_T_tcp, rows, grasps.valid)
    has = neighbours >= 0
    rows = np.asarray(rows, dtype=int)[has]
    truth = reference[rows]
    return reference[neighbours[has]] == truth, np.asarray(ours, dtype=bool)[has] == truth


def ceiling_and_floor(
    truth: NDArray[np.bool_], reference_right: NDArray[np.bool_], ours_right: NDArray[np.bool_]
) -> dict[str, Any]:
    """The figures beside an accuracy: ``majority`` (the majority-class baseline over the
    scored grasps' reference labels ``truth``), ``consistency`` (the reference's neighbour
    agreement ``reference_right``, None where no grasp has a neighbour), ``consistency_grasps``
    (how many have one) and ``ours_on_consistency_grasps`` (our accuracy on them)."""
    share = float(np.mean(truth)) if len(truth) else None
    has = len(reference_right) > 0
    return {
        "majority": None if share is None else max(share, 1.0 - share),
        "consistency": float(np.mean(reference_right)) if has else None,
        "consistency_grasps": int(len(reference_right)),
        "ours_on_consistency_grasps": float(np.mean(ours_right)) if has else None,
    }
