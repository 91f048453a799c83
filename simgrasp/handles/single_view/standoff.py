"""The standoff test for single-view clouds: a handle stands off the rest of the object, with
free space on both sides of it where the fingers go, as the sensor sees it.

For a candidate with handle point ``h`` (on its fitted axis), axis ``a`` and width ``w``, seen
from ``eye``: the fingers close across the part along ``t``, perpendicular to the axis and to
the ray from the eye. In the strip of the cloud within ``half_length`` of ``h`` along the axis,
a finger's slot on each side (``w / 2 + gap`` to ``w / 2 + gap + finger`` across the axis,
from the eye down to ``depth_margin`` past the part's far side) must be nearly empty: at
most ``max_blocked`` of the strip's points in either slot. A patch of a mug's body, its rim,
or a fit smaller than the part it sits on has the body in a slot; a strap or a knife's
handle has air there. The jaws must also open across the part with the gap on both sides
(``w + 2 gap`` at most the gripper's opening), which a mug's body seen whole does not allow.

Lengths are meters, in the cloud's frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.config.checks import Checked, Fraction, NonNegative, Positive
from simgrasp.handles.core.detection import Candidate


@dataclass(frozen=True)
class StandoffConfig(Checked):
    """Parameters of :func:`standoff_mask` (meters)."""

    gap: NonNegative = 0.002
    """Clearance between the part's fitted surface and a finger."""
    finger: Positive = 0.008
    """Width of the slot a finger needs beside the part."""
    half_length: Positive = 0.008
    """Half the finger pad's extent along the handle axis."""
    depth_margin: NonNegative = 0.005
    """How far past the part's far side (along the ray) a finger reaches."""
    max_blocked: Fraction = 0.1
    """Largest share of the strip's points allowed in either finger slot."""
    min_width: NonNegative = 0.0
    """Candidates fitted narrower than this are rejected (0: no limit)."""
    max_axis_cosine: Fraction = 0.9
    """Candidates whose axis is this close to the ray (|cos|) are seen end-on: not tested."""


def slot_shares(
    near: NDArray[np.float64],
    candidate: Candidate,
    eye: NDArray[np.float64],
    config: StandoffConfig,
) -> tuple[float, float]:
    """The shares of the strip's ``near`` points in the finger slot on each side of
    ``candidate`` (0, 0 when the axis is seen end-on or the strip is empty)."""
    center = candidate.handle_point
    ray = center - eye
    ray /= np.linalg.norm(ray)
    axis = candidate.axis / np.linalg.norm(candidate.axis)
    if abs(axis @ ray) > config.max_axis_cosine:
        return 0.0, 0.0
    across = np.cross(ray, axis)
    across /= np.linalg.norm(across)
    offset = near - center
    strip = np.abs(offset @ axis) <= config.half_length
    if not strip.any():
        return 0.0, 0.0
    side = offset[strip] @ across
    depth = offset[strip] @ ray
    inner = candidate.width / 2 + config.gap
    in_reach = depth <= candidate.width / 2 + config.depth_margin
    count = int(strip.sum())
    low, high = (
        float((in_reach & (sign * side >= inner) & (sign * side <= inner + config.finger)).sum())
        / count
        for sign in (-1.0, 1.0)
    )
    return low, high


def _blocked(
    near: NDArray[np.float64],
    candidate: Candidate,
    eye: NDArray[np.float64],
    config: StandoffConfig,
) -> bool:
    """Whether a finger slot beside ``candidate`` holds too many of the ``near`` points."""
    return max(slot_shares(near, candidate, eye, config)) > config.max_blocked


def standoff_mask(
    candidates: tuple[Candidate, ...],
    points: NDArray[np.float64],
    eye: NDArray[np.float64],
    max_opening: float,
    config: StandoffConfig | None = None,
) -> NDArray[np.bool_]:
    """(M,) which candidates pass the standoff test against the cloud ``points`` (N, 3) seen
    from ``eye`` (3,), for a gripper opening ``max_opening``."""
    config = config or StandoffConfig()
    if not candidates:
        return np.zeros(0, dtype=bool)
    tree = cKDTree(points)
    keep = np.zeros(len(candidates), dtype=bool)
    for i, candidate in enumerate(candidates):
        if not config.min_width <= candidate.width <= max_opening - 2 * config.gap:
            continue
        reach = candidate.width / 2 + config.gap + config.finger + config.half_length
        near = points[tree.query_ball_point(candidate.handle_point, reach)]
        keep[i] = not _blocked(near, candidate, eye, config)
    return keep
