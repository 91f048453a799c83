"""Scenes with a real generated object: table, seeded rest pose, cameras, parked gripper, XML."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.grasping.grasp import Grasp, tcp_pose
from simgrasp.grasping.trials.scoring import geoms_touching
from simgrasp.grippers import make_gripper
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.scene import build_scene
from simgrasp.transforms import pose7_to_matrix


@pytest.fixture(scope="module")
def mug_model():
    return build_object_model(load_object("gen_mug", seed=2))


def test_object_rests_on_the_table_and_the_gripper_is_parked(mug_model) -> None:
    config = SceneConfig(table_top_z=0.1)
    scene = build_scene(mug_model, make_gripper("builtin"), config, seed=4)
    mujoco.mj_step(scene.model, scene.data, 250)  # 0.5 s
    mesh_world = mug_model.asset.mesh.copy()
    mesh_world.apply_transform(scene.object_pose())
    assert mesh_world.bounds[0, 2] == pytest.approx(0.1, abs=0.005)
    # The table top is at the configured height and the object barely moved while settling.
    table_top = (
        scene.data.geom_xpos[scene.table_geom][2] + scene.model.geom_size[scene.table_geom][2]
    )
    assert table_top == pytest.approx(0.1)
    assert np.linalg.norm(scene.object_pose()[:3, 3] - scene.world_T_object[:3, 3]) < 0.01
    tcp_world = scene.gripper.world_T_tcp(scene.data)
    assert tcp_world[2, 3] == pytest.approx(0.1 + config.park_height, abs=0.01)
    assert not geoms_touching(scene.data, np.asarray(scene.gripper.geom_ids))


def test_default_camera_is_a_640x480_58_degree_depth_camera(mug_model) -> None:
    scene = build_scene(mug_model, make_gripper("builtin"), seed=0)
    assert scene.cameras == ("view0",)
    camera = scene.model.camera("view0").id
    assert tuple(scene.model.cam_resolution[camera]) == (640, 480)
    assert scene.model.cam_fovy[camera] == pytest.approx(58.0)


def test_rest_pose_is_seeded(mug_model) -> None:
    gripper = make_gripper("builtin")
    first = build_scene(mug_model, gripper, seed=5).world_T_object
    again = build_scene(mug_model, gripper, seed=5).world_T_object
    other = build_scene(mug_model, gripper, seed=6).world_T_object
    np.testing.assert_array_equal(first, again)
    assert not np.allclose(first[:3, :3], other[:3, :3])


def test_upright_placement_stands_the_mug_on_its_base(mug_model) -> None:
    gripper = make_gripper("builtin")
    upright = SceneConfig(placement="upright")
    stable_ups, upright_ups = [], []
    for seed in range(6):
        stable_ups.append(build_scene(mug_model, gripper, seed=seed).world_T_object[2, 2])
        scene = build_scene(mug_model, gripper, upright, seed=seed)
        upright_ups.append(scene.world_T_object[2, 2])
        mujoco.mj_step(scene.model, scene.data, 250)  # 0.5 s: it stays standing
        assert scene.object_pose()[2, 2] > 0.99
    # Drop probabilities lay this mug on its side in most seeds; upright never does.
    assert min(stable_ups) < 0.5
    assert min(upright_ups) > 0.99


def test_unknown_placement_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match="SceneConfig.placement: .sideways. is not one of"):
        SceneConfig(placement="sideways")  # type: ignore[arg-type]  # the refused value


@pytest.mark.parametrize("views", [0, 5, 2.0])
def test_bad_number_of_views_is_a_clear_error(views) -> None:
    with pytest.raises(
        ValueError, match="SceneConfig.num_views: .* is not (one of 1, 2, 3, 4|an int)"
    ):
        SceneConfig(num_views=views)


def test_scene_exports_to_loadable_xml(mug_model, tmp_path) -> None:
    scene = build_scene(mug_model, make_gripper("builtin"), seed=0)
    path = scene.export_xml(tmp_path / "scene.xml")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nbody == scene.model.nbody
    assert model.ngeom == scene.model.ngeom
    assert model.neq == scene.model.neq


def test_grasp_pose7_and_object_frame_round_trip() -> None:
    world_T_object = tcp_pose([0.1, 0.2, 0.0], [0.0, 1.0, 0.0], [0.3, 0.0, 1.0])
    grasp = Grasp(tcp_pose([0.0, 0.1, 0.05], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]), 0.04, 0.7, "x")
    pose7 = grasp.to_pose7()
    assert pose7[3] >= 0 and np.linalg.norm(pose7[3:]) == pytest.approx(1.0)
    np.testing.assert_allclose(
        Grasp.from_pose7(pose7, 0.04).world_T_tcp, grasp.world_T_tcp, atol=1e-12
    )
    object_T_tcp = grasp.object_T_tcp(world_T_object)
    back = Grasp.from_object_frame(object_T_tcp, world_T_object, 0.04)
    np.testing.assert_allclose(back.world_T_tcp, grasp.world_T_tcp, atol=1e-12)


@pytest.mark.parametrize(
    "bad", [[0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, float("nan"), 1, 0, 0, 0]]
)
def test_bad_pose7_is_a_clear_error(bad) -> None:
    with pytest.raises(ValueError, match="grasp pose"):
        pose7_to_matrix(bad, "grasp pose")


def test_bad_grasp_width_and_frame_are_clear_errors() -> None:
    with pytest.raises(ValueError, match="width"):
        Grasp(np.eye(4), 0.0)
    skewed = np.eye(4)
    skewed[0, 1] = 0.5
    with pytest.raises(ValueError, match="rotation"):
        Grasp(skewed, 0.05)


@pytest.mark.parametrize("path", sorted((Path(__file__).parents[1] / "scenes").glob("*.xml")))
def test_example_scenes_open_and_step(path: Path) -> None:
    """The committed example scenes (scripts/export_example_scenes.py) load in plain MuJoCo
    with the table, the object and the four chain cameras, and simulate."""
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, 50)
    assert model.ncam == 4 and np.isfinite(data.qpos).all()
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "object") >= 0
