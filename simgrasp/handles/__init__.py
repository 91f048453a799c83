"""Handle detection: from one object's point cloud to handle hypotheses.

``detect`` runs either the quadric detector (the paper's method, default; :mod:`.core`), on
one camera's view the single-view detector (:mod:`.single_view`), or the ten Pas & Platt 2013
style detector (:mod:`.baselines`) behind the same interface, so the harness can compare them.
:mod:`.presets` names whole settings of each; :mod:`.scene_detect` detects on every object of
a segmented scene; :mod:`.accuracy` scores a detection against labeled handles.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from simgrasp.errors import SimgraspError
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.baselines.tenpas_detector import detect_tenpas_handles
from simgrasp.handles.core.cloud_input import validate_cloud
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import Candidate, Detection, Handle
from simgrasp.handles.core.quadric_detector import detect_quadric_handles
from simgrasp.handles.detector_config import DETECTORS, DetectorName
from simgrasp.handles.single_view.detector import (
    FALLBACK_DETECTOR,
    SingleViewConfig,
    detect_single_view,
)
from simgrasp.handles.single_view.view_kind import is_single_view


def default_config(
    detector: DetectorName, gripper_max_opening: float | None = None
) -> QuadricDetectorConfig | TenPasConfig:
    """The default configuration of ``detector``, optionally for another gripper opening (m)."""
    _check_known(detector)
    config_type = QuadricDetectorConfig if detector == "quadric" else TenPasConfig
    if gripper_max_opening is None:
        return config_type()
    return config_type(gripper_max_opening=gripper_max_opening)


def detect(
    points: ArrayLike,
    normals: ArrayLike | None = None,
    config: QuadricDetectorConfig | TenPasConfig | None = None,
    seed: int = 0,
    *,
    detector: DetectorName = "quadric",
    viewpoint: ArrayLike | None = None,
    table: ArrayLike | None = None,
    scene: ArrayLike | None = None,
    single_view: SingleViewConfig | None = None,
) -> Detection:
    """Detect handles in one object's cloud (N x 3, meters) with the chosen detector.

    ``normals`` (N x 3, pointing out of the object) are estimated when omitted: toward
    ``viewpoint`` for a single camera view, outward for a full object cloud. Results are in
    the cloud's own frame. ``table``, the supporting plane ``[a, b, c, d]`` (unit normal up,
    ``a x + b y + c z + d`` the height above it, cloud frame), lets the quadric detector's
    plate test (``QuadricDetectorConfig.plate_test``) run; ``scene``, the whole cloud the
    object was cut from, is what it checks a plate's free edge is seen against.

    With ``single_view`` given, a cloud measured to be one view from ``viewpoint`` (or, with
    none and ``single_view.sensor_origin``, from the origin; see
    :mod:`simgrasp.handles.single_view.view_kind`) goes to the single-view detector
    (:mod:`simgrasp.handles.single_view.detector`) with those settings and ``config``'s gripper
    opening, ``normals`` unused (and where it finds no handle, to the quadric detector with
    the settings' ``fallback``, ``table`` and ``scene``); any other cloud to the quadric
    detector with ``config``.
    """
    _check_known(detector)
    config = config if config is not None else default_config(detector)
    points, normals = validate_cloud(points, normals)  # before the view test reads them
    if viewpoint is not None and np.shape(viewpoint) != (3,):
        raise SimgraspError(f"viewpoint must be 3 coordinates (m), got shape {np.shape(viewpoint)}")
    if detector == "quadric":
        if not isinstance(config, QuadricDetectorConfig):
            raise SimgraspError("the quadric detector needs a QuadricDetectorConfig")
        eye = _camera(viewpoint, single_view)
        if single_view is not None and is_single_view(points, eye, single_view.view_test):
            assert eye is not None  # is_single_view is False without a viewpoint
            return _detect_view(points, config, seed, eye, table, scene, single_view)
        return detect_quadric_handles(points, normals, config, seed, viewpoint, table, scene)
    if not isinstance(config, TenPasConfig):
        raise SimgraspError("the tenpas detector needs a TenPasConfig")
    return detect_tenpas_handles(points, normals, config, seed, viewpoint)


def _check_known(detector: str) -> None:
    """Refuse, in one line, a detector name that is not one of :data:`DETECTORS`."""
    if detector not in DETECTORS:
        raise SimgraspError(f"unknown detector {detector!r}; choose one of {', '.join(DETECTORS)}")


def _camera(viewpoint: ArrayLike | None, single_view: SingleViewConfig | None) -> ArrayLike | None:
    """Where a single view would have been seen from: ``viewpoint``, else with
    ``single_view.sensor_origin`` the cloud frame's origin."""
    if viewpoint is not None or single_view is None or not single_view.sensor_origin:
        return viewpoint
    return np.zeros(3)


def _detect_view(
    points: ArrayLike,
    config: QuadricDetectorConfig,
    seed: int,
    viewpoint: ArrayLike,
    table: ArrayLike | None,
    scene: ArrayLike | None,
    single_view: SingleViewConfig,
) -> Detection:
    """One camera's view: the single-view detector, else its fallback (``config``'s gripper
    opening for both)."""
    opening = config.gripper_max_opening
    quadric = replace(single_view.quadric, gripper_max_opening=opening)
    detection = detect_single_view(points, replace(single_view, quadric=quadric), seed, viewpoint)
    if detection.handles or single_view.fallback is None:
        return detection
    fallback = replace(single_view.fallback, gripper_max_opening=opening)
    found = detect_quadric_handles(points, None, fallback, seed, viewpoint, table, scene)
    return replace(found, detector=FALLBACK_DETECTOR)


__all__ = [
    "DETECTORS",
    "Candidate",
    "Detection",
    "Handle",
    "QuadricDetectorConfig",
    "SingleViewConfig",
    "TenPasConfig",
    "default_config",
    "detect",
]
