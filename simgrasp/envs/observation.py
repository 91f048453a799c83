"""The observation of :class:`~simgrasp.envs.handle_grasp.HandleGraspEnv`.

A ``gymnasium.spaces.Dict`` for V scene cameras of H x W pixels and a cloud of at most N points
(``max_points``); frames are named as in the README (world frame, meters, OpenCV cameras):

- ``depth`` (V, H, W) float32: meters along each camera's optical axis, 0 where nothing was hit.
  Noise-free renders: the configured noise applies to the cloud only (as in the chain).
- ``mask`` (V, H, W) uint8: 1 where the pixel sees the object, else 0.
- ``points_world`` (N, 3) float64: the chain's segmented object cloud
  (:func:`simgrasp.scenes.observe.cloud_from_views`: fused views, 3 mm voxels, noise), zero-padded.
- ``normals_world`` (N, 3) float64: unit normals turned toward the camera that saw each point
  (:func:`simgrasp.scenes.observe.viewpoint_normals`, on the whole cloud), zero-padded; all
  zero when the cloud is too small to plan on (fewer than ``MIN_CLOUD_POINTS`` points).
- ``valid`` (N,) uint8: 1 for the cloud's points, 0 for padding.
- ``view_index`` (N,) int64: the camera (0..V-1) each point was seen from (0 for padding).
- ``intrinsics`` (V, 3, 3) float64: the pinhole matrices K (pixels).
- ``world_T_cam`` (V, 4, 4) float64: the camera poses (OpenCV frame: x right, y down, z
  forward).

A cloud with more than N points is subsampled to N points without replacement (kept in cloud
order) by a generator seeded with the episode seed, so an episode seed always gives the same
observation; normals are estimated on the whole cloud first.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS
from simgrasp.scenes.camera import default_viewpoints
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.observe import ObjectCloud, viewpoint_normals
from simgrasp.scenes.render import DepthFrame

Observation = dict[str, NDArray]


@dataclass(frozen=True)
class CameraLayout:
    """Number of scene cameras and their common image size (pixels)."""

    num_views: int
    height: int
    width: int


def camera_layout(scene: SceneConfig) -> CameraLayout:
    """The cameras ``build_scene`` adds for ``scene``: its explicit ``cameras``, else
    ``num_views`` default viewpoints. All cameras must share one image size."""
    cameras = scene.cameras or tuple(default_viewpoints(np.zeros(3), n=scene.num_views))
    sizes = sorted({(camera.height, camera.width) for camera in cameras})
    if len(sizes) != 1:
        raise SimgraspError(
            f"all scene cameras must have one image size to stack their images, got (H, W) {sizes}"
        )
    height, width = sizes[0]
    return CameraLayout(num_views=len(cameras), height=height, width=width)


def observation_space(layout: CameraLayout, max_points: int) -> spaces.Dict:
    """The ``Dict`` space of the observation (see the module docstring)."""
    images = (layout.num_views, layout.height, layout.width)
    views = layout.num_views
    return spaces.Dict(
        {
            "depth": spaces.Box(0.0, np.inf, images, np.float32),
            "mask": spaces.Box(0, 1, images, np.uint8),
            "points_world": spaces.Box(-np.inf, np.inf, (max_points, 3), np.float64),
            "normals_world": spaces.Box(-1.0, 1.0, (max_points, 3), np.float64),
            "valid": spaces.Box(0, 1, (max_points,), np.uint8),
            "view_index": spaces.MultiDiscrete(np.full(max_points, views), dtype=np.int64),
            "intrinsics": spaces.Box(0.0, np.inf, (views, 3, 3), np.float64),
            "world_T_cam": spaces.Box(-np.inf, np.inf, (views, 4, 4), np.float64),
        }
    )


def make_observation(
    frames: Sequence[DepthFrame],
    object_body: int,
    cloud: ObjectCloud,
    max_points: int,
    rng: np.random.Generator,
) -> Observation:
    """The observation of ``frames`` (one per scene camera, in scene order) and the chain's
    ``cloud`` of the same scene; ``rng`` draws the subsample of a cloud above ``max_points``."""
    names = tuple(frame.camera_name for frame in frames)
    if names != cloud.camera_names:
        raise SimgraspError(
            f"frames of cameras {names} do not match the cloud's {cloud.camera_names}"
        )
    world_T_cam = np.stack([frame.world_T_cam for frame in frames])
    normals_world = _cloud_normals(cloud)
    view_index = _view_index(cloud.viewpoints_world, world_T_cam[:, :3, 3])
    keep = np.arange(len(cloud))
    if len(cloud) > max_points:
        keep = np.sort(rng.choice(len(cloud), size=max_points, replace=False))
    return {
        "depth": np.stack([frame.depth for frame in frames]).astype(np.float32),
        "mask": np.stack([frame.body_ids == object_body for frame in frames]).astype(np.uint8),
        "points_world": _padded(cloud.points_world[keep], max_points),
        "normals_world": _padded(np.clip(normals_world[keep], -1.0, 1.0), max_points),
        "valid": _padded(np.ones(len(keep), dtype=np.uint8), max_points),
        "view_index": _padded(view_index[keep], max_points),
        "intrinsics": np.stack([frame.intrinsics.matrix for frame in frames]),
        "world_T_cam": world_T_cam,
    }


def _cloud_normals(cloud: ObjectCloud) -> NDArray[np.float64]:
    if len(cloud) < MIN_CLOUD_POINTS:
        return np.zeros((len(cloud), 3))
    return viewpoint_normals(cloud)


def _view_index(
    viewpoints_world: NDArray[np.float64], cameras_world: NDArray[np.float64]
) -> NDArray[np.int64]:
    """Index of the camera at each point's viewpoint (they coincide exactly)."""
    offsets = viewpoints_world[:, None, :] - cameras_world[None, :, :]
    return np.linalg.norm(offsets, axis=2).argmin(axis=1).astype(np.int64)


def _padded(values: NDArray, size: int) -> NDArray:
    """``values`` (n, ...) followed by zero rows up to ``size`` rows."""
    padded = np.zeros((size, *values.shape[1:]), dtype=values.dtype)
    padded[: len(values)] = values
    return padded
