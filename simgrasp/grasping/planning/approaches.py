"""Approach directions around a handle's axis for the planner (world frame, unit vectors).

An approach is perpendicular to the handle's axis at an angle around it (0: the steepest
downward one), optionally tilted down about the jaws' closing direction toward the axis's
lower end (a pitch), so the pads still close across the handle.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.transforms import orthonormal


def downward_basis(axis: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unit vectors ``u, v`` perpendicular to ``axis`` with ``u`` the steepest downward
    direction (world -z projected off the axis); any perpendicular pair for a vertical axis."""
    down = np.array([0.0, 0.0, -1.0]) - axis * -axis[2]
    if np.linalg.norm(down) < 1e-6:
        return orthonormal(axis)
    u = down / np.linalg.norm(down)
    return u, np.cross(axis, u)


def is_sloping(axis: NDArray[np.float64], config: PlannerConfig) -> bool:
    """Whether the unit ``axis`` slopes at least ``config.pitch_min_slope`` from level: only
    approaches around such an axis are tilted."""
    return bool(abs(axis[2]) >= np.sin(config.pitch_min_slope))


def pitched(
    approach: NDArray[np.float64], axis: NDArray[np.float64], pitches: Sequence[float]
) -> list[NDArray[np.float64]]:
    """``approach`` (perpendicular to the sloping handle ``axis``) turned about the closing
    direction by each of ``pitches`` (rad) so that it descends: toward the axis's lower end."""
    down_axis = -np.sign(axis[2]) * axis
    return [np.cos(pitch) * approach + np.sin(pitch) * down_axis for pitch in pitches]


def approach_angles(rng: np.random.Generator, config: PlannerConfig) -> NDArray[np.floating]:
    """``config.approaches_per_handle`` approach angles around a handle's axis (rad): 0 (the
    steepest downward approach) and evenly spaced ones turned by one seeded jitter."""
    step = 2 * np.pi / config.approaches_per_handle
    angles = np.arange(config.approaches_per_handle) * step
    angles[1:] += rng.uniform(-step / 2, step / 2)
    return angles


def handle_approaches(
    axis: NDArray[np.float64],
    angles: NDArray[np.floating],
    pitches: Sequence[float],
    config: PlannerConfig,
    level: bool = True,
) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """``(around, approach)`` pairs about a handle's unit ``axis``: ``around`` perpendicular
    to the axis at each of ``angles`` (rad, :func:`approach_angles`), ``approach`` it tilted
    by each of ``pitches`` (:func:`pitched`) around a sloping axis (:func:`is_sloping`), or
    ``around`` itself around a flatter one, where a tilt turns the approach sideways more than
    down (none there when ``level`` is False: a second pass of steeper pitches adds nothing)."""
    sloping = is_sloping(axis, config)
    if not sloping and not level:
        return []
    u, v = downward_basis(axis)
    pairs = []
    for angle in angles:
        around = np.cos(angle) * u + np.sin(angle) * v
        approaches = pitched(around, axis, pitches) if sloping else [around]
        pairs += [(around, approach) for approach in approaches]
    return pairs
