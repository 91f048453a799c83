"""The target's cloud cut from the whole scene, as a robot would: our segmenter, not the mask.

``segment``: each camera's depth frame (as the sensor returns it) becomes an organized scene
cloud in the world frame (640 x 480, NaN where the sensor returned nothing), which
:func:`simgrasp.perception.segmentation.segment.segment_scene` cuts into the table and the
objects on it, as
``simgrasp segment`` cuts a real Kinect frame (with :meth:`SegmentConfig.simulated`, for the
exactly flat rendered table); in each view every segment (with its side parts) at least
``MAJORITY`` on the target's true pixels is taken, as an object recognizer would hand the
target over (none when no segment is mostly the target: a target barely seen behind a
neighbor is not handed over as that neighbor), and the views' picks are fused
into the target cloud. Every other segment is fused into the
obstacle cloud the planner keeps the open gripper clear of. ``mask``: the renderer's
segmentation cuts the target (today's ground truth) and the distractors' pixels are the
obstacles. ``target_iou`` compares the cut with the target's true pixels over all views
(pixels the sensor returned a depth for): intersection over union, summed over the views.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.perception.camera import depth_to_points_cam, transform_points
from simgrasp.perception.scene_cloud import SceneCloud
from simgrasp.perception.segmentation.segment import segment_scene
from simgrasp.perception.segmentation.segment_config import FIRST_OBJECT, SegmentConfig
from simgrasp.perception.voxel import voxel_downsample
from simgrasp.scenes.observe import CLOUD_VOXEL, ObjectCloud, SceneObservation, noisy_cloud
from simgrasp.scenes.render import DepthFrame
from simgrasp.scenes.scene import Scene

MAJORITY = 0.5
"""A segment at least this share of whose pixels are the target's is one of its pieces (an
over-segmented mug: its inside and outside; a thin tool lying flat, broken in fragments by
the table band); an object recognizer would hand them over together."""


@dataclass(frozen=True, eq=False)
class PerceivedTarget:
    """The target's cloud, the rest of the scene as obstacle points (M, 3; world frame, m),
    and the cut's IoU against the true target pixels."""

    cloud: ObjectCloud
    obstacles_world: NDArray[np.float64]
    target_iou: float


def perceive_target(
    scene: Scene,
    observation: SceneObservation,
    perception: str,
    noise: float,
    seed: int,
    config: SegmentConfig | None = None,
) -> PerceivedTarget:
    """Cut the target from ``observation``'s frames with ``perception`` (``segment`` or
    ``mask``; module docstring), then apply the cloud noise ``noise`` (seeded by ``seed``) as
    :func:`simgrasp.scenes.observe.cloud_from_views` does."""
    frames = observation.frames
    distractors = [scene.model.body(d.body).id for d in scene.distractors]
    targets, others, views, inter, union = [], [], [], 0, 0
    for frame in frames:
        truth = (frame.body_ids == scene.object_body) & (frame.depth > 0)
        if perception == "segment":
            views.append(world_pixels(frame))
            cut, rest = _segmented_cut(frame, views[-1], truth, config or SegmentConfig.simulated())
        else:
            cut, rest = truth, np.isin(frame.body_ids, distractors) & (frame.depth > 0)
            views.append(world_pixels(frame, rest))
        targets.append(cut)
        others.append(rest)
        inter += int((cut & truth).sum())
        union += int((cut | truth).sum())
    if perception == "mask":
        cloud = observation.cloud  # exactly today's ground-truth cut
    else:
        cloud = noisy_cloud(_fused(frames, views, targets), noise, seed)
    obstacles = np.concatenate(_masked_points(views, others), axis=0)
    if len(obstacles):
        obstacles = voxel_downsample(obstacles, CLOUD_VOXEL)[0]  # as _fused's, no viewpoints
    return PerceivedTarget(cloud, obstacles, inter / union if union else 0.0)


def world_pixels(
    frame: DepthFrame, mask: NDArray[np.bool_] | None = None
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """The world-frame points (N, 3; m) of ``frame``'s pixels with a depth (within ``mask``)
    and their flat pixel indices (N,), ascending: computed once per frame, cut by each mask."""
    points_cam, pixels = depth_to_points_cam(frame.depth, frame.intrinsics, mask)
    return transform_points(frame.world_T_cam, points_cam), pixels


def organized_cloud(
    frame: DepthFrame, view: tuple[NDArray[np.float64], NDArray[np.intp]] | None = None
) -> SceneCloud:
    """``frame`` as an organized scene cloud in the world frame (NaN where no depth), seen
    from the camera's optical center; ``view`` is its :func:`world_pixels` when known."""
    points_world, pixels = view or world_pixels(frame)
    grid = np.full((frame.depth.size, 3), np.nan, dtype=np.float32)
    grid[pixels] = points_world
    height, width = frame.depth.shape
    return SceneCloud(grid, width, height, frame.camera_position_world, None, frame.camera_name)


def _segmented_cut(
    frame: DepthFrame,
    view: tuple[NDArray[np.float64], NDArray[np.intp]],
    truth: NDArray[np.bool_],
    config: SegmentConfig,
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(H, W) the target's segments, and every other object segment: the segments (with
    their side parts) of which ``truth`` holds at least ``MAJORITY`` of the pixels."""
    segmentation = segment_scene(organized_cloud(frame, view), config)
    shape = frame.depth.shape
    labels = segmentation.labels
    objects = labels.reshape(shape) >= FIRST_OBJECT
    sizes = np.bincount(labels, minlength=FIRST_OBJECT)
    hits = np.bincount(labels[truth.reshape(-1)], minlength=len(sizes))
    chosen: list[int] = []
    for label in segmentation.whole_objects():
        members = [o.label for o in segmentation.objects if label in (o.label, o.part_of)]
        if int(hits[members].sum()) >= MAJORITY * int(sizes[members].sum()) > 0:
            chosen += members
    cut = np.isin(labels, chosen).reshape(shape)
    return cut, objects & ~cut


def _fused(
    frames: list[DepthFrame],
    views: list[tuple[NDArray[np.float64], NDArray[np.intp]]],
    masks: list[NDArray[np.bool_]],
) -> ObjectCloud:
    """The masked pixels of every frame (their :func:`world_pixels` ``views``) fused into one
    world-frame cloud (``CLOUD_VOXEL`` voxels), each point keeping the viewpoint of its nearest
    input point."""
    per_view = _masked_points(views, masks)
    points_world = np.concatenate(per_view, axis=0)
    view_index = np.repeat(np.arange(len(frames)), [len(p) for p in per_view])
    if len(points_world):
        fused, _ = voxel_downsample(points_world, CLOUD_VOXEL)
        view_index = view_index[cKDTree(points_world).query(fused)[1]]
        points_world = fused
    eyes = np.stack([frame.camera_position_world for frame in frames])
    return ObjectCloud(
        points_world=points_world,
        viewpoints_world=eyes[view_index].reshape(-1, 3),
        view_counts=tuple(int(c) for c in np.bincount(view_index, minlength=len(frames))),
        camera_names=tuple(frame.camera_name for frame in frames),
    )


def _masked_points(
    views: list[tuple[NDArray[np.float64], NDArray[np.intp]]], masks: list[NDArray[np.bool_]]
) -> list[NDArray[np.float64]]:
    """Per view, the world points (N_i, 3) of its masked pixels (``views``: each frame's
    :func:`world_pixels`)."""
    return [
        points[mask.reshape(-1)[pixels]]
        for (points, pixels), mask in zip(views, masks, strict=True)
    ]
