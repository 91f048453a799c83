"""Simulated single views with exact handle labels, posed like a real capture: an object on a
table seen by one camera through a sensor model (:mod:`simgrasp.perception.sensors`).

The scene is ray cast with Open3D (the object's mesh on a 1 m table slab, exact depth along
the optical axis, the object's pixels by hit geometry), the depth image passes through the
sensor model, and the object's pixels are back-projected to the camera frame (OpenCV axes,
sensor at the origin), as the real captures of ``detect-eval --real`` are given. Candidates
are scored in the object's mesh frame against its shipped label.

Poses: ``upright`` stands the mug on its base with its handle (mesh +x) to the camera's side;
``lying`` lays it on its side, its axis horizontal and its handle flat beside it, the handle
loop facing up (the AffordanceGrasp capture's pose). The camera looks at the object's center
from ``distance`` (m) at ``elevation_deg`` above the table, from the -y side.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.handles.single_view.detector import SingleViewConfig
from simgrasp.labels import HandleLabel
from simgrasp.perception.camera import CameraIntrinsics, depth_to_points_cam
from simgrasp.seeding import rng_for

Pose = Literal["upright", "lying"]


@dataclass(frozen=True)
class SimView:
    """One simulated capture: object, its pose, the camera and the sensor model."""

    object: str = "025_mug"
    pose: Pose = "upright"
    distance: float = 0.78
    """Camera to object center (m)."""
    elevation_deg: float = 32.0
    """Camera above the table plane (degrees; 90 looks straight down)."""
    sensor: str = "kinect"
    """Sensor model name (ideal, kinect, stereo)."""
    azimuth_deg: float = 0.0
    """The camera's place around the object (degrees about the vertical, counterclockwise
    seen from above; 0: from the -y side, the handle to the camera's right)."""
    width: int = 640
    height: int = 480
    fovy_deg: float = 58.0

    @property
    def name(self) -> str:
        turned = f" azimuth {self.azimuth_deg:g}" if self.azimuth_deg else ""
        return f"{self.object} {self.pose} {self.sensor} {self.distance:g} m{turned}"


REAL_CAPTURE_VIEWS = {
    "gpd_table_mug": (
        SimView(pose="upright", distance=0.78, elevation_deg=32.0, sensor="kinect"),
        SimView(pose="upright", distance=0.78, elevation_deg=32.0, sensor="stereo"),
    ),
    "affordancegrasp_mug1": (
        SimView(pose="lying", distance=0.30, elevation_deg=90.0, sensor="stereo"),
        # the kinect model returns nothing nearer than its minimum range: seen from 0.6 m
        SimView(pose="lying", distance=0.60, elevation_deg=90.0, sensor="kinect"),
    ),
}
"""The YCB mug's simulated views posed like each real mug capture of the real-data manifest:
the GPD table mug (upright, 0.78 m, 32 degrees above the table) and the AffordanceGrasp mug
(lying, handle flat beside it, 0.30 m straight above)."""


@dataclass(frozen=True)
class SimCapture:
    """A rendered view: points in the camera frame (m), and ``object_T_cam`` to the mesh frame."""

    points_cam: NDArray[np.float64]
    object_T_cam: NDArray[np.float64]
    label: HandleLabel


def _world_T_object(mesh_bounds: NDArray[np.float64], pose: Pose) -> NDArray[np.float64]:
    """The object's pose on the table (world z up, table top at z = 0)."""
    rotation = np.eye(3)
    if pose == "lying":  # mesh +z (the mug's axis) to world -y; the handle (+x) stays +x
        rotation = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    elif pose != "upright":
        raise SimgraspError(f"unknown pose {pose!r}; use upright or lying")
    corners = np.array(np.meshgrid(*mesh_bounds.T)).reshape(3, -1).T
    turned = corners @ rotation.T
    center = (turned.min(axis=0) + turned.max(axis=0)) / 2
    world_T_object = np.eye(4)
    world_T_object[:3, :3] = rotation
    world_T_object[:3, 3] = [-center[0], -center[1], -turned[:, 2].min()]
    return world_T_object


def _world_T_cam(target: NDArray[np.float64], view: SimView) -> NDArray[np.float64]:
    """OpenCV camera pose (x right, y down, z forward) looking at ``target``."""
    elevation, azimuth = np.radians(view.elevation_deg), np.radians(view.azimuth_deg)
    side = np.array([np.sin(azimuth), -np.cos(azimuth), 0.0])  # the camera's side, from above
    offset = np.cos(elevation) * side + np.array([0.0, 0.0, np.sin(elevation)])
    if view.elevation_deg > 89.0:  # straight down: keep the image's up along the side's
        offset = 1e-3 * side + np.array([0.0, 0.0, 1.0])
        offset /= np.linalg.norm(offset)
    position = target + view.distance * offset
    forward = (target - position) / np.linalg.norm(target - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    world_T_cam = np.eye(4)
    world_T_cam[:3, :3] = np.column_stack([right, down, forward])
    world_T_cam[:3, 3] = position
    return world_T_cam


def _o3d_mesh(mesh):  # noqa: ANN001, ANN202
    """A trimesh mesh as an Open3D tensor mesh for ray casting."""
    import open3d as o3d

    legacy = o3d.geometry.TriangleMesh(
        o3d.utility.Vector3dVector(mesh.vertices), o3d.utility.Vector3iVector(mesh.faces)
    )
    return o3d.t.geometry.TriangleMesh.from_legacy(legacy)


def _ray_cast(mesh, world_T_object, world_T_cam, intrinsics):  # noqa: ANN001, ANN202
    """Exact depth (m along the optical axis) and the object's pixel mask."""
    import open3d as o3d
    import trimesh

    scene = o3d.t.geometry.RaycastingScene()
    object_id = scene.add_triangles(_o3d_mesh(mesh.copy().apply_transform(world_T_object)))
    table = trimesh.creation.box([1.0, 1.0, 0.05])
    table.apply_translation([0.0, 0.0, -0.025])
    scene.add_triangles(_o3d_mesh(table))
    rays = o3d.t.geometry.RaycastingScene.create_rays_pinhole(
        intrinsic_matrix=o3d.core.Tensor.from_numpy(np.ascontiguousarray(intrinsics.matrix)),
        extrinsic_matrix=o3d.core.Tensor.from_numpy(np.linalg.inv(world_T_cam)),
        width_px=intrinsics.width,
        height_px=intrinsics.height,
    )
    hits = scene.cast_rays(rays)
    distance = hits["t_hit"].numpy()
    directions = rays.numpy()[..., 3:]
    depth = distance * (directions @ world_T_cam[:3, 2])
    depth[~np.isfinite(depth)] = 0.0
    return depth, hits["geometry_ids"].numpy() == object_id


def capture(view: SimView, seed: int, ycb_dir: str | None = None) -> SimCapture:
    """Render ``view`` through its sensor model (seeded by ``seed``)."""
    from simgrasp.assets.registry import load_object
    from simgrasp.perception.sensors import apply_sensor, sensor_config

    asset = load_object(view.object, ycb_dir)
    world_T_object = _world_T_object(np.asarray(asset.mesh.bounds), view.pose)
    target = world_T_object[:3, :3] @ asset.mesh.bounds.mean(axis=0) + world_T_object[:3, 3]
    world_T_cam = _world_T_cam(target, view)
    intrinsics = CameraIntrinsics.from_fovy(view.width, view.height, view.fovy_deg)
    depth, on_object = _ray_cast(asset.mesh, world_T_object, world_T_cam, intrinsics)
    sensed = apply_sensor(
        depth.astype(np.float32),
        intrinsics.matrix,
        sensor_config(view.sensor),
        rng_for(seed, "sim_view", view.name),
    )
    points_cam, _ = depth_to_points_cam(sensed, intrinsics, on_object)
    object_T_cam = np.linalg.inv(world_T_object) @ world_T_cam
    return SimCapture(points_cam, object_T_cam, asset.handle)


def score_view(  # noqa: ANN201
    view: SimView,
    config_name: str,
    seed: int,
    ycb_dir: str | None = None,
    single_view: SingleViewConfig | None = None,
    degradation: str = "as captured",
):
    """Detect with the named setting (``single_view`` as
    :func:`~simgrasp.evaluation.real_detect.detect_named` takes it) on the view rendered with
    ``seed`` (normals toward the camera) and made worse by ``degradation``
    (:func:`~simgrasp.evaluation.capture_degradations.degraded`, drawn from ``seed``), scored
    in the mesh frame: a :class:`~simgrasp.evaluation.real_detect.RealDetectRow` with the
    view's name as its cloud and ``"sim"`` as its data set."""
    import time

    from simgrasp.evaluation.capture_degradations import degraded
    from simgrasp.evaluation.real_detect import RealDetectRow, detect_named

    shot = capture(view, seed, ycb_dir)
    rng = rng_for(seed, "degraded", degradation, view.name)
    points, eye = degraded(np.asarray(shot.points_cam, np.float64), np.zeros(3), degradation, rng)
    start = time.perf_counter()
    detection = detect_named(points, config_name, seed, eye, single_view)
    elapsed = time.perf_counter() - start
    moved = detection.moved(shot.object_T_cam)
    centers = moved.candidate_centers
    top = moved.handles[0].center[None] if moved.handles else np.zeros((0, 3))
    return RealDetectRow(
        cloud=view.name,
        dataset="sim",
        split="sim",
        config=config_name,
        seed=seed,
        points=len(points),
        candidates=len(centers),
        on_handle=int(shot.label.contains(centers).sum()) if len(centers) else 0,
        handles=len(moved.handles),
        top_on_handle=bool(shot.label.contains(top).any()),
        detect_s=elapsed,
    )
