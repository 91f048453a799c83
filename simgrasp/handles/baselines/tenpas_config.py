"""Every threshold of the ten Pas & Platt style handle detector, in one frozen dataclass.

Lengths are meters, angles radians. The detector (:mod:`simgrasp.handles.baselines.tenpas_detector`)
fits a Taubin quadric per spherical neighborhood, takes the direction of minimal curvature as
the local axis, fits a circle across it, keeps cylindrical shells that fit the gripper and have
a clear gap around them, and chains aligned shells into handles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

from simgrasp.config.checks import Checked, NonNegative, Positive, PositiveInt, Range

BelowOne = Annotated[float, Range(gt=0, lt=1)]
"""A float in (0, 1)."""


@dataclass(frozen=True)
class TenPasConfig(Checked):
    """Parameters of :func:`simgrasp.handles.baselines.tenpas_detector.detect_tenpas_handles`."""

    gripper_max_opening: Positive = 0.085
    """Maximum jaw opening of the parallel gripper (m); shells wider than it are rejected."""
    voxel_size: NonNegative = 0.003
    """Voxel edge for down-sampling the input cloud (m); 0 disables down-sampling."""
    neighborhood_radius: Positive = 0.02
    """Radius of the spherical neighborhood around each sampled center (m). 2 cm suits long
    handles (tools, cutlery); small handle loops (YCB mug, scissors) are found more often with
    about 1.25 cm, at the cost of noisier axes and radii on long handles."""
    max_points: Annotated[int, Range(ge=9)] = 96
    """Neighborhoods with more points are subsampled (seeded) to this many."""
    min_points: Annotated[int, Range(ge=9)] = 16
    """Neighborhoods with fewer points are not fitted."""
    neighborhoods: PositiveInt | None = None
    """Number of neighborhood centers; ``None`` scales it with object size (voxel count)."""
    min_radius: Positive = 0.003
    """Shells thinner than this radius (m) are rejected (noise, edges)."""
    max_circle_residual: Positive = 0.2
    """Largest RMS distance of the projected points from the fitted circle, as a fraction of
    the fitted radius; worse fits are not cylinders."""
    surface_tolerance: Positive = 0.5
    """The neighborhood center must lie on the fitted circle: its distance from the axis may
    differ from the radius by at most this fraction of the radius."""
    shell_gap: NonNegative = 0.003
    """Inner shell radius = fitted radius + this tolerance (m) for the cylinder's own points."""
    finger_clearance: Positive = 0.01
    """Shell thickness (m): the room the gripper's fingers need around the handle."""
    shell_half_length: Positive = 0.01
    """Half length (m) along the axis over which the shell is checked."""
    max_shell_fraction: Annotated[float, Range(ge=0, lt=1)] = 0.1
    """Reject a shell if more than this fraction of the points inside its outer cylinder lie
    between its inner and outer cylinders."""
    align_angle: Annotated[float, Range(gt=0, lt=math.pi / 2)] = math.radians(20.0)
    """Shells chain into one handle if their axes differ by less than this angle (rad) ..."""
    align_distance: Positive = 0.006
    """... each axis point lies within this distance (m) of the other's axis line ..."""
    align_radius_ratio: BelowOne = 0.5
    """... their radii differ by at most this fraction of the larger one ..."""
    align_gap: Positive = 0.04
    """... and their axis points are at most this far apart along the axis (m)."""
    min_shells: PositiveInt = 3
    """A handle needs at least this many aligned shells (ten Pas & Platt used about 3)."""
    kind_rtol: BelowOne = 1e-2
    """Relative tolerance with which the candidates' Taubin quadrics classify their kind
    (reporting and plots only; the tests above do not use the kind)."""

    def _check(self) -> None:
        self.require_below("min_points", "max_points", strict=False)
        if self.min_radius >= self.gripper_max_opening / 2:
            self.refuse(
                "min_radius",
                f"is not below half the gripper opening ({self.gripper_max_opening / 2})",
            )
