"""Handle detection on a single-view cloud with the standoff test
(:mod:`simgrasp.handles.single_view.standoff`): the quadric detector's candidates, those without
free space for the fingers on both sides (as the sensor sees them) dropped, the rest clustered and
ranked as the detector does (support, centrality, jaw clearance).

What differs between captures is measured from the cloud, not chosen: the point spacing
(median nearest-neighbor distance after down-sampling) sets the narrowest fit the data
resolve (``min_width_spacings``), and each candidate's own geometry says whether its fitted
axis can be trusted as the handle's center (``anchor="consistent"``)."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.config.checks import Checked, Fraction, NonNegative, Positive, PositiveInt
from simgrasp.handles.core.cluster import cluster_handles
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import Candidate, Detection
from simgrasp.handles.core.quadric_detector import detect_quadric_handles
from simgrasp.handles.single_view.body_wall import BodyWall, BodyWallConfig, fit_body_wall
from simgrasp.handles.single_view.candidate_features import (
    FEATURES,
    MaxEnsemble,
    TreeClassifier,
    candidate_features,
    read_classifier,
)
from simgrasp.handles.single_view.grid_rolls import pooled_over_rolls
from simgrasp.handles.single_view.standoff import StandoffConfig, standoff_mask
from simgrasp.handles.single_view.view_kind import ViewKindConfig
from simgrasp.resources import model_path

SINGLE_VIEW_DETECTOR = "quadric-single-view"
"""The ``detector`` name of a :func:`detect_single_view` result."""
FALLBACK_DETECTOR = "quadric-single-view-fallback"
"""The ``detector`` name of a single view's detection by :attr:`SingleViewConfig.fallback`."""
CLASSIFIER = "candidate_classifier.json"
"""The shipped classifier (``models/handles/``), written by
``scripts/train_candidate_classifier.py``."""


def _single_view_quadric() -> QuadricDetectorConfig:
    """The quadric detector on one view: Taubin fits (no normals) of 12 mm neighborhoods, one
    center per voxel, own normals over 6 mm, a 6 mm shell, and a fine pass of 12 mm (one
    center per 3 voxels): the ``noisy_camera_cloud`` preset plus a fine pass."""
    return QuadricDetectorConfig(
        own_normals=True,
        normal_radius=0.006,
        neighborhood_half_size=0.012,
        voxels_per_neighborhood=1.0,
        fit_method="taubin",
        shell_thickness=0.006,
        fine_half_size=0.012,
    )


@dataclass(frozen=True)
class SingleViewConfig(Checked):
    """The single-view detector's settings: the quadric detector's, the standoff test's or the
    classifier's, and the view test that routes a cloud here (lengths in meters).
    ``simgrasp detect`` takes each as a flag (``--single-view-detector.classifier-threshold``),
    its default the preset ``learned`` (:mod:`simgrasp.handles.presets`)."""

    quadric: QuadricDetectorConfig = field(default_factory=_single_view_quadric)
    standoff: StandoffConfig = field(default_factory=StandoffConfig)
    anchor: Literal["surface", "axis", "consistent"] = "surface"
    """Where handle centers are taken: ``"surface"``, the candidates' seen surface points (a
    one-sided view leaves a thin part's fitted axis up to centimeters off the part, a
    knife's handle seen from above); ``"axis"``, their fitted axes; ``"consistent"``, the
    axis where it lies within ``axis_slack`` of half the fitted width (plus one point
    spacing) from the seen surface point, else the surface point."""
    axis_slack: Positive = 1.5
    """With ``anchor="consistent"``: allowed ratio of the surface-to-axis distance to half the
    fitted width."""
    min_width_spacings: NonNegative = 0.0
    """Candidates fitted narrower than this many measured point spacings are dropped: a fit
    narrower than the sampling resolves (a rim's 2-5 mm edge in 3 mm voxels) is not a part a
    finger pair can be placed across. 0: no limit."""
    narrow_width_spacings: NonNegative = 0.0
    """With ``classifier``: fits from this many up to ``min_width_spacings`` measured point
    spacings wide are kept too when their fitted axis lies within ``narrow_axis_offset``
    half widths of their seen surface point. Half the fits of a thin flat strap seen from
    0.3 - 0.8 m are under 2 spacings wide, their axes mostly 1 - 4 half widths behind their
    surface (median 2.2); a pot rim's unresolved fit has its axis 6 - 8 half widths off.
    0: none."""
    narrow_axis_offset: Positive = 4.0
    """With ``narrow_width_spacings``: the largest distance (half fitted widths) of a narrow
    fit's axis from its seen surface point."""
    grid_rolls: PositiveInt = 1
    """Candidates are pooled from this many voxel grids, the view turned evenly about the line
    from the viewpoint through its centroid (:mod:`~simgrasp.handles.single_view.grid_rolls`):
    the verdict on a part only a few voxels resolve then depends less on how the camera was
    rolled. 1: the view's own grid only."""
    classifier: bool = False
    """Replace the standoff test by the shipped classifier over candidate features
    (:mod:`simgrasp.handles.single_view.candidate_features`,
    ``models/handles/candidate_classifier.json``, trained on simulated views by
    ``scripts/train_candidate_classifier.py``)."""
    classifier_threshold: Fraction = 0.5
    """With ``classifier``: the least probability of being on a handle a candidate needs."""
    classifier_file: str = ""
    """With ``classifier``: a model written by ``scripts/train_candidate_classifier.py`` to
    use instead of the shipped one (a path; empty: the shipped one)."""
    body_wall: BodyWallConfig = field(default_factory=BodyWallConfig)
    """With ``body_wall.enabled``: kept candidates on the view's body wall are dropped
    (:mod:`simgrasp.handles.single_view.body_wall`; on in the preset ``learned``)."""
    view_test: ViewKindConfig = field(default_factory=ViewKindConfig)
    """When :func:`simgrasp.handles.detect` is given these settings, it runs this detector
    only on clouds this test measures to be one view from the viewpoint."""
    sensor_origin: bool = True
    """When :func:`simgrasp.handles.detect` is given these settings and no viewpoint: test
    whether the cloud is one view from its frame's origin (a depth camera writes its clouds
    in its own frame, the sensor at the origin)."""
    fallback: QuadricDetectorConfig | None = None
    """When :func:`simgrasp.handles.detect` runs this detector and it finds no handle: the
    quadric detector with these settings on the same view (None: no handle)."""

    def with_body_wall(self, enabled: bool) -> SingleViewConfig:
        """These settings with their body-wall test on or off, its other values kept (the
        scripts' ``--body-wall`` and ``--also-body-wall``)."""
        return replace(self, body_wall=replace(self.body_wall, enabled=enabled))

    def classifier_path(self) -> Path:
        """The classifier file these settings read with ``classifier``: ``classifier_file``,
        else the shipped model."""
        return (
            Path(self.classifier_file)
            if self.classifier_file
            else model_path("handles", CLASSIFIER)
        )


def point_spacing(points: NDArray[np.float64]) -> float:
    """The cloud's median nearest-neighbor distance (m)."""
    if len(points) < 2:
        return 0.0
    distances, _ = cKDTree(points).query(points, k=2)
    return float(np.median(distances[:, 1]))


def _anchors(
    kept: tuple[Candidate, ...], config: SingleViewConfig, spacing: float
) -> NDArray[np.float64] | None:
    """(M, 3) handle-center anchors per :attr:`SingleViewConfig.anchor` (None: the axes)."""
    if config.anchor == "axis":
        return None
    surface = np.stack([c.center for c in kept])
    if config.anchor == "surface":
        return surface
    axis = np.stack([c.handle_point for c in kept])
    reach = config.axis_slack * np.array([c.width / 2 for c in kept]) + spacing
    consistent = np.linalg.norm(axis - surface, axis=1) <= reach
    return np.where(consistent[:, None], axis, surface)


def single_view_candidates(
    points: ArrayLike, config: SingleViewConfig, seed: int, eye: NDArray[np.float64]
) -> tuple[Detection, NDArray[np.float64], float]:
    """The quadric detector's candidates before any standoff or classifier test (pooled over
    ``config.grid_rolls`` grids), the view's own down-sampled cloud and its measured point
    spacing (m)."""
    quadric = replace(config.quadric, min_relative_score=0.0)
    raw = pooled_over_rolls(
        lambda view: detect_quadric_handles(view, None, quadric, seed, viewpoint=eye),
        np.asarray(points, dtype=float),
        eye,
        config.grid_rolls,
    )
    cloud = raw.points if raw.points is not None else np.asarray(points, dtype=float)
    return raw, cloud, point_spacing(cloud)


@functools.cache
def _classifier(path: str) -> TreeClassifier | MaxEnsemble:
    """The classifier file at ``path``, read once per process (a scene's objects each run
    the single-view detector)."""
    return read_classifier(Path(path))


def _keep(
    candidates: tuple[Candidate, ...],
    cloud: NDArray[np.float64],
    eye: NDArray[np.float64],
    spacing: float,
    config: SingleViewConfig,
) -> NDArray[np.bool_]:
    """Which candidates pass: the standoff test, or with ``classifier`` the shipped model at
    ``classifier_threshold`` on the fits :func:`_scored` lets through."""
    fits, probability = _scored(candidates, cloud, eye, spacing, config)
    return _passing(fits, probability, config.classifier_threshold)


def _scored(
    candidates: tuple[Candidate, ...],
    cloud: NDArray[np.float64],
    eye: NDArray[np.float64],
    spacing: float,
    config: SingleViewConfig,
) -> tuple[NDArray[np.bool_], NDArray[np.float64] | None]:
    """Without ``classifier``: the standoff test's verdicts and None. With it: which fits
    are at least ``min_width_spacings`` wide, or ``narrow_width_spacings`` wide with their
    axes near their surface (and fit the gripper), and each candidate's probability of being
    on a handle by the shipped model, so that several thresholds need one model pass."""
    floor = _floor(config, config.min_width_spacings, spacing)
    standoff = replace(config.standoff, min_width=floor)
    opening = config.quadric.gripper_max_opening
    if not config.classifier:
        return standoff_mask(candidates, cloud, eye, opening, standoff), None
    model = _classifier(str(config.classifier_path()))
    features = candidate_features(candidates, cloud, eye, spacing, standoff)
    widths = np.array([c.width for c in candidates])
    wide = widths >= floor
    if config.narrow_width_spacings > 0:
        offsets = features[:, FEATURES.index("axis_offset")]
        narrow = widths >= _floor(config, config.narrow_width_spacings, spacing)
        wide |= narrow & (offsets <= config.narrow_axis_offset)
    fits = wide & (widths <= opening - 2 * standoff.gap)
    return fits, model.probability(features)


def _passing(
    fits: NDArray[np.bool_], probability: NDArray[np.float64] | None, threshold: float
) -> NDArray[np.bool_]:
    """``fits`` where ``probability`` (None: no classifier) reaches ``threshold``."""
    return fits if probability is None else fits & (probability >= threshold)


def _floor(config: SingleViewConfig, spacings: float, spacing: float) -> float:
    """The narrowest fit width kept (m): the standoff test's, or ``spacings`` measured point
    spacings (``spacing``, m) when wider."""
    return max(config.standoff.min_width, spacings * spacing)


def detect_single_view(
    points: ArrayLike, config: SingleViewConfig, seed: int, viewpoint: ArrayLike
) -> Detection:
    """Handles in one object's single-view ``points`` (N, 3, m) seen from ``viewpoint``."""
    eye = np.asarray(viewpoint, dtype=float)
    raw, cloud, spacing = single_view_candidates(points, config, seed, eye)
    raw = replace(raw, detector=SINGLE_VIEW_DETECTOR)
    if not raw.candidates:
        return raw
    fits, probability = _scored(raw.candidates, cloud, eye, spacing, config)
    keep = _passing(fits, probability, config.classifier_threshold)
    walls = config.body_wall
    retry = walls.retry_threshold if probability is not None else None
    wall = (
        fit_body_wall(cloud, walls, seed)
        if walls.enabled and (keep.any() or retry is not None)
        else None
    )
    off_wall = _off_wall(raw.candidates, wall, walls)
    detection = _clustered(raw, keep & off_wall, cloud, spacing, config)
    if detection.handles or wall is None or retry is None or wall.radius > walls.retry_max_radius:
        return detection
    return _clustered(raw, _passing(fits, probability, retry) & off_wall, cloud, spacing, config)


def _off_wall(
    candidates: tuple[Candidate, ...], wall: BodyWall | None, config: BodyWallConfig
) -> NDArray[np.bool_]:
    """(M,) True for the candidates whose seen surface points lie off ``wall`` by at least
    ``config.drop_distance``; all True without a wall."""
    if wall is None:
        return np.ones(len(candidates), dtype=bool)
    return wall.distance(np.stack([c.center for c in candidates])) >= config.drop_distance


def _clustered(
    raw: Detection,
    keep: NDArray[np.bool_],
    cloud: NDArray[np.float64],
    spacing: float,
    config: SingleViewConfig,
) -> Detection:
    """``raw`` with its candidates where ``keep`` clustered into ranked handles; only the
    candidates that support a handle are kept."""
    quadric = config.quadric
    kept = tuple(c for c, k in zip(raw.candidates, keep, strict=True) if k)
    if not kept:
        return replace(raw, candidates=(), handles=())
    centroid = cloud.mean(axis=0)
    rms = float(np.sqrt(((cloud - centroid) ** 2).sum(axis=1).mean()))
    ranked = cluster_handles(
        np.stack([c.handle_point for c in kept]),
        np.stack([c.axis for c in kept]),
        np.array([c.width for c in kept]),
        distance=quadric.cluster_distance,
        min_support=quadric.min_support,
        object_center=centroid if quadric.prefer_central else None,
        centrality_length=max(quadric.centrality_min_length, quadric.centrality_scale * rms),
        centrality_measure=quadric.centrality_measure,
        max_opening=quadric.gripper_max_opening if quadric.prefer_clearance else None,
        min_relative_score=quadric.min_relative_score,
        anchors=_anchors(kept, config, spacing),
    )
    supporting = sorted({int(i) for r in ranked for i in r.members})
    handles = tuple(r.handle for r in ranked)
    return replace(raw, candidates=tuple(kept[i] for i in supporting), handles=handles)
