"""Candidates pooled over voxel grids turned about the viewing axis.

The quadric detector down-samples a cloud on an axis-aligned voxel grid and fits one
neighborhood per voxel, so the same capture with the camera rolled about its optical axis
yields other neighborhoods and, where a handle is resolved by only a few of them (a mug's
strap at close range), another verdict. Detecting on the view turned by ``k / n`` of a turn
(``k = 0 .. n - 1``) about the line from the viewpoint through the cloud's centroid, and
turning every candidate back, gives each part ``n`` samplings instead of one
(measured: ``docs/results/real-detect/``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from simgrasp.handles.core.detection import Candidate, Detection


def roll_about(
    axis: NDArray[np.float64], eye: NDArray[np.float64], angle: float
) -> NDArray[np.float64]:
    """The rigid 4x4 ``rolled_T_view``: a turn by ``angle`` (rad) about the line through
    ``eye`` (m) along the unit ``axis``."""
    cross = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross
    rolled_T_view = np.eye(4)
    rolled_T_view[:3, :3] = rotation
    rolled_T_view[:3, 3] = eye - rotation @ eye
    return rolled_T_view


def moved_candidate(candidate: Candidate, a_T_b: NDArray[np.float64]) -> Candidate:
    """``candidate`` (frame b) in frame a: its points, axis and quadric moved."""
    rotation, translation = a_T_b[:3, :3], a_T_b[:3, 3]
    return replace(
        candidate,
        center=rotation @ candidate.center + translation,
        handle_point=rotation @ candidate.handle_point + translation,
        axis=rotation @ candidate.axis,
        quadric=candidate.quadric.transformed(a_T_b),
    )


def pooled_over_rolls(
    detect: Callable[[NDArray[np.float64]], Detection],
    points_view: NDArray[np.float64],
    eye: NDArray[np.float64],
    rolls: int,
) -> Detection:
    """``detect`` run on ``points_view`` (N, 3, m) and on the view turned ``rolls - 1`` more
    times (evenly over a turn about the viewpoint-to-centroid line), each result's candidates
    and neighborhood centers turned back into the view's frame and pooled; the first run's
    other fields (its down-sampled cloud, timings) are kept."""
    first = detect(points_view)
    axis = points_view.mean(axis=0) - eye
    if rolls <= 1 or not np.linalg.norm(axis) > 0:
        return first
    axis = axis / np.linalg.norm(axis)
    candidates, centers = list(first.candidates), [first.neighborhood_centers.reshape(-1, 3)]
    for k in range(1, rolls):
        rolled_T_view = roll_about(axis, eye, 2 * np.pi * k / rolls)
        rolled = points_view @ rolled_T_view[:3, :3].T + rolled_T_view[:3, 3]
        found = detect(rolled)
        view_T_rolled = np.linalg.inv(rolled_T_view).astype(np.float64)
        candidates += [moved_candidate(c, view_T_rolled) for c in found.candidates]
        seen = found.neighborhood_centers.reshape(-1, 3)
        centers.append(seen @ view_T_rolled[:3, :3].T + view_T_rolled[:3, 3])
    return replace(
        first, candidates=tuple(candidates), neighborhood_centers=np.concatenate(centers)
    )
