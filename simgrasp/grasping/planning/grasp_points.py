"""Where on a handle the planner closes the jaws (world frame, m): points on the handle's axis
line (its center, and its point nearest the cloud's centroid) and, on a curved handle, its
root, each with the direction the jaws close across and the jaws that are checked and
opened there."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.handles.core.detection import Handle


@dataclass(frozen=True)
class GraspPoint:
    """Where and across what a pass tries grasps on one handle: the TCP ``position`` (world
    frame, m), the handle's local direction ``axis`` there (unit; the jaws close across it),
    the ``lever`` (m) penalized in the rank and the ``jaws`` checked and opened."""

    position: NDArray[np.float64]
    axis: NDArray[np.float64]
    lever: float
    jaws: GripperGeometry


def axis_points(
    handle: Handle,
    centroid: NDArray[np.float64] | None,
    geometry: GripperGeometry,
    jaws: GripperGeometry,
) -> list[GraspPoint]:
    """The grasp points on ``handle``'s axis line (:func:`_grasp_offsets`), closed across its
    axis with ``jaws``."""
    return [
        GraspPoint(handle.center + offset * handle.axis, handle.axis, lever, jaws)
        for offset, lever in _grasp_offsets(handle, centroid, geometry)
    ]


def _grasp_offsets(
    handle: Handle, centroid: NDArray[np.float64] | None, geometry: GripperGeometry
) -> list[tuple[float, float]]:
    """``(offset, lever)`` pairs: grasp points as offsets (m) along the handle axis from its
    center, with their distance (m) along the axis from the centroid's projection. The center,
    and the point of the handle nearest the centroid that keeps the pads on the stretch the
    candidates cover, with a pad width to spare (the stretch's ends are its least certain
    part)."""
    if centroid is None:
        return [(0.0, 0.0)]
    target = float((centroid - handle.center) @ handle.axis)
    margin = geometry.finger_width
    low, high = handle.span[0] + margin, handle.span[1] - margin
    nearest = float(np.clip(target, low, high)) if low <= high else 0.5 * sum(handle.span)
    offsets = [(0.0, abs(target))]
    if abs(nearest) > 0.005:
        offsets.append((nearest, abs(target - nearest)))
    return offsets


def root_point(
    handle: Handle,
    centroid: NDArray[np.float64] | None,
    geometry: GripperGeometry,
    config: PlannerConfig,
) -> GraspPoint | None:
    """A curved handle's root: the point of its trace nearest the centroid (where a loop meets
    the body), stepped a pad width along the handle's local direction away from the
    centroid, the direction the dominant one of the trace's axes within a pad width; jaws
    opened to the handle's width plus ``config.root_opening_margin`` on each side (fully
    open, they reach the body beside the root). None when the handle has no trace, or when
    the root lies within half the handle's width of the line through its center along its
    axis and the handle turns there less than ``config.root_min_turn`` from that axis (a
    straight handle: the grasps on the line close there already). A mug lying on its side
    with its loop flat on the table: the loop's axis points (the whole D) give one handle
    whose center lies on the loop's outer bar and whose axis runs along its two arms, so
    every grasp on the line closes along the bar; held by the lower arm at its root, the mug
    lifts by its handle."""
    if centroid is None or not len(handle.trace):
        return None
    nearest = handle.trace[np.argmin(np.linalg.norm(handle.trace - centroid, axis=1))]
    local = handle.trace_axes[
        np.linalg.norm(handle.trace - nearest, axis=1) <= geometry.finger_width
    ]
    axis = np.linalg.eigh(local.T @ local)[1][:, -1]
    axis = axis if (nearest - centroid) @ axis >= 0 else -axis
    position = nearest + geometry.finger_width * axis
    offset = position - handle.center
    on_line = np.linalg.norm(offset - (offset @ handle.axis) * handle.axis) <= handle.width / 2
    if on_line and abs(float(axis @ handle.axis)) >= np.cos(config.root_min_turn):
        return None
    return GraspPoint(
        position,
        axis,
        abs(float((centroid - position) @ axis)),
        narrowed(geometry, handle.width, config.root_opening_margin),
    )


def narrowed(geometry: GripperGeometry, width: float, margin: float) -> GripperGeometry:
    """``geometry`` with its jaws opened only to ``width + 2 * margin`` (m; never wider than
    its ``max_opening``): the planner checks, and the trial opens, this opening."""
    return replace(geometry, max_opening=min(geometry.max_opening, width + 2 * margin))
