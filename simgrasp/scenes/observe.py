"""Observing a scene: render its cameras, then segment, back-project, add noise and fuse the
object's pixels into one world-frame cloud with normals turned toward the cameras."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property, partial

import numpy as np
from scipy.spatial import cKDTree

from simgrasp.errors import SimgraspError
from simgrasp.perception.camera import depth_to_points_cam, transform_points
from simgrasp.perception.noise import DepthNoiseConfig, depth_camera_noise, multiplicative_noise
from simgrasp.perception.normals import estimate_normals
from simgrasp.perception.sensors import apply_sensor
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.perception.voxel import voxel_downsample
from simgrasp.scenes.render import DepthFrame, SceneRenderer
from simgrasp.scenes.scene import Scene
from simgrasp.seeding import rng_for

CLOUD_VOXEL = 0.003
"""Voxel edge (m) of the fused object cloud the chain plans on."""


@dataclass(frozen=True, eq=False)
class ObjectCloud:
    """A segmented object cloud fused from one or more views (world frame, meters).

    Attributes:
        points_world: (N, 3) surface points.
        viewpoints_world: (N, 3) optical center of the camera each point was seen from, for
            orienting normals toward the sensor.
        view_counts: number of points contributed by each frame, in frame order (after noise
            and down-sampling; sums to N).
        camera_names: the camera of each frame, in frame order.
    """

    points_world: np.ndarray
    viewpoints_world: np.ndarray
    view_counts: tuple[int, ...]
    camera_names: tuple[str, ...]

    def __len__(self) -> int:
        return int(self.points_world.shape[0])


def object_cloud(
    frames: Sequence[DepthFrame],
    object_body_ids: Iterable[int],
    *,
    noise: DepthNoiseConfig | None = None,
    rng: np.random.Generator | None = None,
    voxel_size: float | None = None,
) -> ObjectCloud:
    """Fuse the object's pixels of ``frames`` into one world-frame cloud.

    Per frame: keep pixels whose body id is in ``object_body_ids`` (the table, grippers and
    every other body are dropped), back-project them to the OpenCV camera frame, optionally
    apply the depth-camera noise model ``noise`` (``perception.noise.depth_camera_noise``,
    drawing from ``rng`` frame by frame, in order), and map them to the world frame. The views
    are concatenated and, with ``voxel_size`` (meters), voxel down-sampled; each down-sampled
    point keeps the viewpoint of its nearest input point.
    """
    frames = list(frames)
    if not frames:
        raise SimgraspError("object_cloud needs at least one depth frame")
    body_ids = np.unique(np.asarray(list(object_body_ids), dtype=np.int64))
    if body_ids.size == 0:
        raise SimgraspError("object_body_ids is empty: no body to keep")
    if np.any(body_ids < 0):
        raise SimgraspError(f"object_body_ids must be body ids >= 0, got {body_ids.tolist()}")
    if noise is not None and rng is None:
        raise SimgraspError("a noise model needs an rng (derive it with simgrasp.seeding.rng_for)")
    if voxel_size is not None and not voxel_size > 0:
        raise SimgraspError(f"voxel_size must be positive meters, got {voxel_size}")

    points_per_view = [_view_points_world(frame, body_ids, noise, rng) for frame in frames]
    points_world = np.concatenate(points_per_view, axis=0)
    view_index = np.repeat(np.arange(len(frames)), [len(p) for p in points_per_view])
    if voxel_size is not None and len(points_world) > 0:
        points_world, _ = voxel_downsample(points_world, voxel_size)
        _, nearest = cKDTree(np.concatenate(points_per_view, axis=0)).query(points_world)
        view_index = view_index[nearest]
    camera_positions = np.stack([frame.camera_position_world for frame in frames])
    return ObjectCloud(
        points_world=points_world,
        viewpoints_world=camera_positions[view_index].reshape(-1, 3),
        view_counts=tuple(int(c) for c in np.bincount(view_index, minlength=len(frames))),
        camera_names=tuple(frame.camera_name for frame in frames),
    )


def _view_points_world(
    frame: DepthFrame,
    body_ids: np.ndarray,
    noise: DepthNoiseConfig | None,
    rng: np.random.Generator | None,
) -> np.ndarray:
    mask = np.isin(frame.body_ids, body_ids)
    points_cam, _ = depth_to_points_cam(frame.depth, frame.intrinsics, mask)
    if noise is not None and rng is not None and len(points_cam) > 0:
        points_cam, _ = depth_camera_noise(points_cam, rng, noise)
    return transform_points(frame.world_T_cam, points_cam)


def render_views(scene: Scene, renderer: SceneRenderer) -> list[DepthFrame]:
    """Depth and segmentation from every scene camera, the scene reset to its initial state."""
    scene.reset()
    return [renderer.depth(scene.data, camera) for camera in scene.cameras]


def sensed_views(frames: list[DepthFrame], sensor: SensorSettings, seed: int) -> list[DepthFrame]:
    """``frames`` as the ``sensor`` returns them: each view's depth image through the sensor
    model (seeded by ``seed`` and the view's index), pixels it returns nothing for at 0 depth
    (they give no points); the segmentation stays the rendered one. An ideal sensor returns
    ``frames`` themselves."""
    if sensor.kind == "ideal":
        return frames
    model = sensor.model()
    return [
        replace(
            frame,
            depth=apply_sensor(
                frame.depth, frame.intrinsics.matrix, model, rng_for(seed, "sensor", index)
            ),
        )
        for index, frame in enumerate(frames)
    ]


def cloud_from_views(
    scene: Scene, frames: list[DepthFrame], noise: float, seed: int
) -> ObjectCloud:
    """Fuse the object's pixels of ``frames`` into a world-frame cloud (``CLOUD_VOXEL``
    voxels) and apply the multiplicative noise ``noise`` about its centroid (seeded by
    ``seed``)."""
    return noisy_cloud(
        object_cloud(frames, [scene.object_body], voxel_size=CLOUD_VOXEL), noise, seed
    )


def noisy_cloud(cloud: ObjectCloud, noise: float, seed: int) -> ObjectCloud:
    """``cloud`` with the multiplicative noise ``noise`` about its centroid (seeded by
    ``seed``; ``cloud`` itself when ``noise`` is 0)."""
    if noise == 0 or len(cloud) == 0:
        return cloud
    centroid = cloud.points_world.mean(axis=0)
    rng = rng_for(seed, "chain", "noise")
    noisy = centroid + multiplicative_noise(cloud.points_world - centroid, noise, rng)
    return ObjectCloud(noisy, cloud.viewpoints_world, cloud.view_counts, cloud.camera_names)


@dataclass(frozen=True, eq=False)
class SceneObservation:
    """What the scene's cameras saw: every frame, and the object's fused cloud (fused from the
    frames by ``fuse`` on first use, once: a cut by our segmenter never needs it)."""

    frames: list[DepthFrame]
    fuse: Callable[[], ObjectCloud] = field(repr=False)

    @cached_property
    def cloud(self) -> ObjectCloud:
        """The object's fused cloud (:func:`cloud_from_views`)."""
        return self.fuse()


def observe(
    scene: Scene,
    renderer: SceneRenderer,
    noise: float,
    seed: int,
    sensor: SensorSettings | None = None,
) -> SceneObservation:
    """Render every scene camera with ``renderer`` (reset to the scene's initial state), pass
    each view through ``sensor`` (default ideal; :func:`sensed_views`) and fuse the object's
    pixels into a world-frame cloud (see :func:`cloud_from_views`)."""
    frames = sensed_views(render_views(scene, renderer), sensor or SensorSettings(), seed)
    return SceneObservation(frames, partial(cloud_from_views, scene, frames, noise, seed))


def viewpoint_normals(cloud: ObjectCloud) -> np.ndarray:
    """(N, 3) unit normals of a fused camera cloud, each turned toward the camera that saw its
    point (world frame)."""
    normals = estimate_normals(cloud.points_world, orient="none")
    toward = np.einsum("ij,ij->i", normals, cloud.viewpoints_world - cloud.points_world)
    normals[toward < 0] *= -1
    return normals
