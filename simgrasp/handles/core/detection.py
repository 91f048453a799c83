"""What a handle detector returns: accepted neighborhoods (candidates) and handle hypotheses.

All positions and directions are in the input cloud's own frame, in its units (meters).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception.camera import transform_points
from simgrasp.quadric import Quadric

TIMING_STEPS = ("voxelize", "normals", "sample", "fit", "test", "cluster")


@dataclass(frozen=True)
class Candidate:
    """One neighborhood accepted as handle-like.

    Attributes:
        center: the neighborhood center, a cloud point (m).
        quadric: the quadric fitted to the neighborhood (cloud frame).
        kind: the quadric's kind as a string (``QuadricKind`` value), or the detector's own
            primitive name (``"cylinder_shell"`` for the ten Pas detector).
        axis: unit direction along the handle.
        width: grasp width across the handle (m): twice the smaller transverse semi-axis.
        handle_point: a point on the handle's axis near ``center`` (m), where grasps aim.
    """

    center: NDArray[np.float64]
    quadric: Quadric
    kind: str
    axis: NDArray[np.float64]
    width: float
    handle_point: NDArray[np.float64]

    def to_json(self) -> dict[str, Any]:
        return {
            "center": self.center.tolist(),
            "kind": self.kind,
            "coefficients": self.quadric.coefficients.tolist(),
            "axis": self.axis.tolist(),
            "width": self.width,
        }

    def moved(self, a_T_b: NDArray[np.float64]) -> Candidate:
        """This candidate (frame b) in frame a: its points, axis and quadric moved by the rigid
        4x4 ``a_T_b``."""
        rotation, translation = a_T_b[:3, :3], a_T_b[:3, 3]
        return replace(
            self,
            center=rotation @ self.center + translation,
            handle_point=rotation @ self.handle_point + translation,
            axis=rotation @ self.axis,
            quadric=self.quadric.transformed(a_T_b),
        )


@dataclass(frozen=True)
class Handle:
    """A handle hypothesis: candidates clustered along one graspable part.

    Attributes:
        center: grasp point on the handle axis (m).
        axis: unit direction along the handle.
        width: grasp width across the handle (m, median of its candidates).
        score: in [0, 1]; support share of all candidates weighted by axis agreement.
        support: number of candidates in the cluster.
        span: ``(low, high)``, the stretch of the axis its candidates cover, as offsets (m)
            along ``axis`` from ``center`` (``low <= 0 <= high``).
        trace: (K, 3) the points its candidates give it (m; those ``center`` is taken from:
            on their fitted axes, or their seen surface points where the detector anchors
            handles there): the handle's own course, which on a curved handle (a mug's loop)
            leaves the line through ``center`` along ``axis``; empty when the detector did
            not record it. The planner grasps a curved handle at its root from it.
        trace_axes: (K, 3) unit directions of those candidates' axes (sign arbitrary).
    """

    center: NDArray[np.float64]
    axis: NDArray[np.float64]
    width: float
    score: float
    support: int
    span: tuple[float, float]
    trace: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))
    trace_axes: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))

    def __post_init__(self) -> None:
        if np.shape(self.trace) != np.shape(self.trace_axes) or np.shape(self.trace)[1:] != (3,):
            raise SimgraspError(
                f"Handle: trace {np.shape(self.trace)} and trace_axes "
                f"{np.shape(self.trace_axes)} must both be (K, 3)"
            )

    def moved(self, a_T_b: NDArray[np.float64]) -> Handle:
        """This handle (frame b) in frame a: its center, axis and trace moved by the rigid 4x4
        ``a_T_b``."""
        rotation, translation = a_T_b[:3, :3], a_T_b[:3, 3]
        return replace(
            self,
            center=rotation @ self.center + translation,
            axis=rotation @ self.axis,
            trace=transform_points(a_T_b, self.trace),
            trace_axes=self.trace_axes @ rotation.T,
        )

    @property
    def extent(self) -> float:
        """Half length (m) of the longest stretch from ``center`` covered by candidates."""
        return max(-self.span[0], self.span[1])

    def to_json(self) -> dict[str, Any]:
        return {
            "center": self.center.tolist(),
            "axis": self.axis.tolist(),
            "width": self.width,
            "score": self.score,
            "support": self.support,
            "span": list(self.span),
        }


@dataclass(frozen=True)
class Detection:
    """The result of one detector run on one cloud.

    ``neighborhood_centers`` holds every sampled neighborhood center (accepted or not), so
    accuracy and recall can be computed against labels; ``timings_s`` has the paper's steps.
    """

    candidates: tuple[Candidate, ...]
    handles: tuple[Handle, ...]
    neighborhood_centers: NDArray[np.float64]
    detector: str
    timings_s: dict[str, float] = field(default_factory=dict)
    points: NDArray[np.float64] | None = None
    """The (down-sampled) cloud the detector worked on, for plots."""

    def moved(self, a_T_b: NDArray[np.float64]) -> Detection:
        """This detection (frame b) in frame a: its candidates, handles, neighborhood centers and
        worked cloud moved by the rigid 4x4 ``a_T_b``; timings and detector name kept."""
        points = None if self.points is None else transform_points(a_T_b, self.points)
        return replace(
            self,
            candidates=tuple(c.moved(a_T_b) for c in self.candidates),
            handles=tuple(h.moved(a_T_b) for h in self.handles),
            neighborhood_centers=transform_points(a_T_b, self.neighborhood_centers.reshape(-1, 3)),
            points=points,
        )

    @property
    def neighborhoods(self) -> int:
        return len(self.neighborhood_centers)

    @property
    def candidate_centers(self) -> NDArray[np.float64]:
        if not self.candidates:
            return np.zeros((0, 3))
        return np.stack([c.center for c in self.candidates])

    def to_json(self) -> dict[str, Any]:
        return {
            "detector": self.detector,
            "handles": [h.to_json() for h in self.handles],
            "candidates": [c.to_json() for c in self.candidates],
            "neighborhoods": self.neighborhoods,
            "timings_s": {step: float(self.timings_s.get(step, 0.0)) for step in TIMING_STEPS},
        }
