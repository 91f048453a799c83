"""Handle detection on a single-view cloud with the standoff test
(:mod:`simgrasp.handles.standoff`): the quadric detector's candidates, those without free
space for the fingers on both sides (as the sensor sees them) dropped, the rest clustered and
ranked as the detector does (support, centrality, jaw clearance)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike

from simgrasp.handles.cluster import cluster_handles
from simgrasp.handles.config import QuadricDetectorConfig
from simgrasp.handles.detection import Detection
from simgrasp.handles.quadric_detector import detect_quadric_handles
from simgrasp.handles.standoff import StandoffConfig, standoff_mask


def _single_view_quadric() -> QuadricDetectorConfig:
    """:meth:`QuadricDetectorConfig.noisy_camera_cloud` (Taubin fits of 12 mm neighborhoods,
    own 6 mm normals, 6 mm shell) plus a fine pass of 12 mm (one center per 3 voxels)."""
    return QuadricDetectorConfig.noisy_camera_cloud(fine_half_size=0.012)


@dataclass(frozen=True)
class SingleViewConfig:
    """The quadric detector's settings and the standoff test's."""

    quadric: QuadricDetectorConfig = field(default_factory=_single_view_quadric)
    standoff: StandoffConfig = field(default_factory=StandoffConfig)
    surface_anchor: bool = True
    """Take handle centers from the candidates' seen surface points, not their fitted axes:
    a one-sided view leaves a thin part's fitted axis up to centimeters off the part (a
    knife's handle seen from above)."""


def detect_single_view(
    points: ArrayLike, config: SingleViewConfig, seed: int, viewpoint: ArrayLike
) -> Detection:
    """Handles in one object's single-view ``points`` (N, 3, m) seen from ``viewpoint``."""
    quadric = config.quadric
    eye = np.asarray(viewpoint, dtype=float)
    raw = detect_quadric_handles(
        points, None, replace(quadric, min_relative_score=0.0), seed, viewpoint=eye
    )
    if not raw.candidates:
        return raw
    cloud = raw.points if raw.points is not None else np.asarray(points, dtype=float)
    keep = standoff_mask(raw.candidates, cloud, eye, quadric.gripper_max_opening, config.standoff)
    kept = tuple(c for c, k in zip(raw.candidates, keep, strict=True) if k)
    if not kept:
        return replace(raw, candidates=(), handles=())
    centroid = cloud.mean(axis=0)
    rms = float(np.sqrt(((cloud - centroid) ** 2).sum(axis=1).mean()))
    handles, members = cluster_handles(
        np.stack([c.handle_point for c in kept]),
        np.stack([c.axis for c in kept]),
        np.array([c.width for c in kept]),
        distance=quadric.cluster_distance,
        min_support=quadric.min_support,
        object_center=centroid if quadric.prefer_central else None,
        centrality_length=max(quadric.centrality_min_length, quadric.centrality_scale * rms),
        max_opening=quadric.gripper_max_opening if quadric.prefer_clearance else None,
        min_relative_score=quadric.min_relative_score,
        anchors=np.stack([c.center for c in kept]) if config.surface_anchor else None,
    )
    supporting = sorted({int(i) for m in members for i in m})
    return replace(raw, candidates=tuple(kept[i] for i in supporting), handles=handles)
