"""Every threshold of the ten Pas & Platt style handle detector, in one frozen dataclass.

Lengths are meters, angles radians. The detector (:mod:`simgrasp.handles.tenpas_detector`)
fits a Taubin quadric per spherical neighborhood, takes the direction of minimal curvature as
the local axis, fits a circle across it, keeps cylindrical shells that fit the gripper and have
a clear gap around them, and chains aligned shells into handles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from simgrasp.errors import SimgraspError


@dataclass(frozen=True)
class TenPasConfig:
    """Parameters of :func:`simgrasp.handles.tenpas_detector.detect_tenpas_handles`."""

    gripper_max_opening: float = 0.085
    """Maximum jaw opening of the parallel gripper (m); shells wider than it are rejected."""
    voxel_size: float = 0.003
    """Voxel edge for down-sampling the input cloud (m); 0 disables down-sampling."""
    neighborhood_radius: float = 0.02
    """Radius of the spherical neighborhood around each sampled center (m). 2 cm suits long
    handles (tools, cutlery); small handle loops (YCB mug, scissors) are found more often with
    about 1.25 cm, at the cost of noisier axes and radii on long handles."""
    max_points: int = 96
    """Neighborhoods with more points are subsampled (seeded) to this many."""
    min_points: int = 16
    """Neighborhoods with fewer points are not fitted."""
    neighborhoods: int | None = None
    """Number of neighborhood centers; ``None`` scales it with object size (voxel count)."""
    min_radius: float = 0.003
    """Shells thinner than this radius (m) are rejected (noise, edges)."""
    max_circle_residual: float = 0.2
    """Largest RMS distance of the projected points from the fitted circle, as a fraction of
    the fitted radius; worse fits are not cylinders."""
    surface_tolerance: float = 0.5
    """The neighborhood center must lie on the fitted circle: its distance from the axis may
    differ from the radius by at most this fraction of the radius."""
    shell_gap: float = 0.003
    """Inner shell radius = fitted radius + this tolerance (m) for the cylinder's own points."""
    finger_clearance: float = 0.01
    """Shell thickness (m): the room the gripper's fingers need around the handle."""
    shell_half_length: float = 0.01
    """Half length (m) along the axis over which the shell is checked."""
    max_shell_fraction: float = 0.1
    """Reject a shell if more than this fraction of the points inside its outer cylinder lie
    between its inner and outer cylinders."""
    align_angle: float = math.radians(20.0)
    """Shells chain into one handle if their axes differ by less than this angle (rad) ..."""
    align_distance: float = 0.006
    """... each axis point lies within this distance (m) of the other's axis line ..."""
    align_radius_ratio: float = 0.5
    """... their radii differ by at most this fraction of the larger one ..."""
    align_gap: float = 0.04
    """... and their axis points are at most this far apart along the axis (m)."""
    min_shells: int = 3
    """A handle needs at least this many aligned shells (ten Pas & Platt used about 3)."""
    kind_rtol: float = 1e-2
    """Relative tolerance with which the candidates' Taubin quadrics classify their kind
    (reporting and plots only; the tests above do not use the kind)."""

    def __post_init__(self) -> None:
        positive = (
            "gripper_max_opening",
            "neighborhood_radius",
            "min_radius",
            "max_circle_residual",
            "surface_tolerance",
            "finger_clearance",
            "shell_half_length",
            "align_angle",
            "align_distance",
            "align_radius_ratio",
            "align_gap",
            "kind_rtol",
        )
        for name in positive:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise SimgraspError(f"tenpas config: {name} must be a number, got {value!r}")
            if not (math.isfinite(value) and value > 0):
                raise SimgraspError(f"tenpas config: {name} must be positive, got {value!r}")
        for name in ("voxel_size", "shell_gap"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
                raise SimgraspError(f"tenpas config: {name} must be >= 0, got {value!r}")
        if self.min_radius >= self.gripper_max_opening / 2:
            raise SimgraspError(
                f"tenpas config: min_radius {self.min_radius} must be below half the gripper "
                f"opening {self.gripper_max_opening / 2}"
            )
        if not 0 <= self.max_shell_fraction < 1:
            raise SimgraspError(
                f"tenpas config: max_shell_fraction must be in [0, 1), got "
                f"{self.max_shell_fraction!r}"
            )
        if self.align_angle >= math.pi / 2:
            raise SimgraspError(
                f"tenpas config: align_angle must be below pi/2 rad, got {self.align_angle!r}"
            )
        if self.kind_rtol >= 1:
            raise SimgraspError(f"tenpas config: kind_rtol must be below 1, got {self.kind_rtol!r}")
        if self.align_radius_ratio >= 1:
            raise SimgraspError(
                "tenpas config: align_radius_ratio must be below 1, got "
                f"{self.align_radius_ratio!r}"
            )
        if self.min_points < 9 or self.max_points < self.min_points:
            raise SimgraspError(
                "tenpas config: need 9 <= min_points <= max_points, got "
                f"{self.min_points}, {self.max_points}"
            )
        if self.neighborhoods is not None and self.neighborhoods < 1:
            raise SimgraspError(
                f"tenpas config: neighborhoods must be >= 1, got {self.neighborhoods}"
            )
        if self.min_shells < 1:
            raise SimgraspError(f"tenpas config: min_shells must be >= 1, got {self.min_shells}")
