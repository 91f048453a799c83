"""Segmented, fused object clouds from rendered depth frames."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree
from test_render import BOX_HALF_SIZE, BOX_POS, BOX_QUAT, N_VIEWS, build_scene

from simgrasp.assets.ycb import ycb_mesh_path
from simgrasp.perception.noise import DepthNoiseConfig
from simgrasp.scenes.camera import add_camera, default_viewpoints
from simgrasp.scenes.observe import object_cloud
from simgrasp.scenes.render import DepthFrame, SceneRenderer
from simgrasp.seeding import rng_for

pytestmark = pytest.mark.filterwarnings("ignore:no working headless GL:RuntimeWarning")


@pytest.fixture(scope="module")
def scene_frames() -> tuple[mujoco.MjModel, list[DepthFrame]]:
    model, data = build_scene()
    with SceneRenderer(model) as renderer:
        return model, [renderer.depth(data, f"view{k}") for k in range(N_VIEWS)]


def _visible_box_surface(spacing: float = 0.004) -> np.ndarray:
    """World points on the five box faces not resting on the table."""
    samples = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            if axis == 2 and sign < 0:
                continue
            others = [a for a in range(3) if a != axis]
            grids = [np.arange(-BOX_HALF_SIZE[a], BOX_HALF_SIZE[a], spacing) for a in others]
            uu, vv = np.meshgrid(*grids)
            face = np.zeros((uu.size, 3))
            face[:, others[0]], face[:, others[1]] = uu.ravel(), vv.ravel()
            face[:, axis] = sign * BOX_HALF_SIZE[axis]
            samples.append(face)
    world_R_box = np.zeros(9)
    mujoco.mju_quat2Mat(world_R_box, BOX_QUAT)
    return np.concatenate(samples) @ world_R_box.reshape(3, 3).T + BOX_POS


def _coverage(points_world: np.ndarray) -> float:
    distance, _ = cKDTree(points_world).query(_visible_box_surface())
    return float(np.mean(distance < 0.003))


def test_fusing_views_covers_more_of_the_object(scene_frames) -> None:
    model, frames = scene_frames
    object_body = model.body("object").id
    single = [object_cloud([frame], [object_body]) for frame in frames]
    fused = object_cloud(frames, [object_body])
    assert fused.view_counts == tuple(len(c) for c in single)
    assert max(_coverage(c.points_world) for c in single) < 0.7
    assert _coverage(fused.points_world) > 0.95
    # Each point remembers the camera it was seen from.
    for k, frame in enumerate(frames):
        rows = slice(sum(fused.view_counts[:k]), sum(fused.view_counts[: k + 1]))
        np.testing.assert_array_equal(
            fused.viewpoints_world[rows],
            np.broadcast_to(frame.world_T_cam[:3, 3], (fused.view_counts[k], 3)),
        )
    assert fused.camera_names == tuple(f"view{k}" for k in range(N_VIEWS))


def test_voxel_downsampling_keeps_viewpoints_consistent(scene_frames) -> None:
    model, frames = scene_frames
    object_body = model.body("object").id
    fused = object_cloud(frames, [object_body])
    down = object_cloud(frames, [object_body], voxel_size=0.005)
    assert 0 < len(down) < len(fused) / 4
    assert sum(down.view_counts) == len(down) and all(c > 0 for c in down.view_counts)
    assert _coverage(down.points_world) > 0.9
    # A point's viewpoint sees it: the point lies in front of that camera's image plane.
    to_point = down.points_world - down.viewpoints_world
    camera_axes = {tuple(f.world_T_cam[:3, 3]): f.world_T_cam[:3, 2] for f in frames}
    axis = np.array([camera_axes[tuple(v)] for v in down.viewpoints_world])
    assert np.all(np.einsum("ij,ij->i", to_point, axis) > 0.3)


def test_segmentation_selects_bodies(scene_frames) -> None:
    model, frames = scene_frames
    gripper = model.body("gripper").id
    gripper_cloud = object_cloud(frames, [gripper])
    both = object_cloud(frames, [gripper, model.body("object").id])
    assert len(gripper_cloud) > 0
    assert len(both) == len(gripper_cloud) + len(object_cloud(frames, [model.body("object").id]))
    palm_center = model.body("gripper").pos
    assert np.all(np.abs(gripper_cloud.points_world - palm_center) < [0.011, 0.041, 0.021])


def test_depth_noise_is_seeded_and_applied_in_the_camera_frame(scene_frames) -> None:
    from test_render import box_surface_distance

    model, frames = scene_frames
    object_body = model.body("object").id
    config = DepthNoiseConfig(dropout=0.2)
    clean = object_cloud(frames, [object_body])
    noisy = object_cloud(frames, [object_body], noise=config, rng=rng_for(1, "noise"))
    again = object_cloud(frames, [object_body], noise=config, rng=rng_for(1, "noise"))
    np.testing.assert_array_equal(noisy.points_world, again.points_world)
    for clean_count, noisy_count in zip(clean.view_counts, noisy.view_counts, strict=True):
        assert noisy_count == round(0.8 * clean_count)
    distance = box_surface_distance(noisy.points_world)
    # ~0.6 m away the axial sigma is ~1.3 mm: clearly off the surface, but not far off.
    assert 3e-4 < np.median(distance) < 3e-3
    assert np.median(box_surface_distance(clean.points_world)) < 1e-4


def test_object_cloud_errors(scene_frames) -> None:
    model, frames = scene_frames
    with pytest.raises(ValueError, match="at least one depth frame"):
        object_cloud([], [1])
    with pytest.raises(ValueError, match="object_body_ids is empty"):
        object_cloud(frames, [])
    with pytest.raises(ValueError, match="needs an rng"):
        object_cloud(frames, [1], noise=DepthNoiseConfig())
    with pytest.raises(ValueError, match="voxel_size"):
        object_cloud(frames, [1], voxel_size=0.0)
    absent = object_cloud(frames, [model.nbody + 5])
    assert len(absent) == 0 and absent.view_counts == (0,) * N_VIEWS


def _world_mesh(model: mujoco.MjModel, data: mujoco.MjData, geom: str) -> trimesh.Trimesh:
    """The compiled mesh of ``geom`` at its current world pose (MuJoCo re-centers meshes)."""
    geom_id = model.geom(geom).id
    mesh_id = model.geom_dataid[geom_id]
    first_vert, n_vert = model.mesh_vertadr[mesh_id], model.mesh_vertnum[mesh_id]
    first_face, n_face = model.mesh_faceadr[mesh_id], model.mesh_facenum[mesh_id]
    vertices_geom = model.mesh_vert[first_vert : first_vert + n_vert]
    world_R_geom = data.geom_xmat[geom_id].reshape(3, 3)
    vertices_world = vertices_geom @ world_R_geom.T + data.geom_xpos[geom_id]
    return trimesh.Trimesh(vertices_world, model.mesh_face[first_face : first_face + n_face])


def test_ycb_mug_cloud_lies_on_the_mesh(ycb_dir: str) -> None:
    mesh_path, _ = ycb_mesh_path(ycb_dir, "025_mug")
    mug = trimesh.load(mesh_path, force="mesh")
    assert isinstance(mug, trimesh.Trimesh)
    spec = mujoco.MjSpec()
    spec.add_mesh(name="mug", uservert=mug.vertices.ravel(), userface=mug.faces.ravel())
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.5, 0.5, 0.02], pos=[0, 0, -0.02]
    )
    body = spec.worldbody.add_body(name="mug", pos=[0.01, 0.02, 0.0], quat=[0.9, 0.0, 0.0, 0.436])
    body.add_geom(name="mug", type=mujoco.mjtGeom.mjGEOM_MESH, meshname="mug")
    for view in default_viewpoints((0.0, 0.0, 0.04), distance=0.5, n=2):
        add_camera(spec, view)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with SceneRenderer(model) as renderer:
        frames = [renderer.depth(data, name) for name in ("view0", "view1")]
    cloud = object_cloud(frames, [model.body("mug").id])
    assert len(cloud) > 5000 and all(count > 1000 for count in cloud.view_counts)
    sample = rng_for(0, "test_observe", "mug").choice(len(cloud), 1500, replace=False)
    _, distance, _ = trimesh.proximity.closest_point(
        _world_mesh(model, data, "mug"), cloud.points_world[sample]
    )
    assert np.median(distance) < 2e-4 and np.percentile(distance, 99) < 1e-3
