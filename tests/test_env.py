"""The gymnasium environment ``simgrasp/HandleGrasp-v0`` and the scripted DetectorPolicy, with
the real simulator and renderer."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from typing import TypedDict

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.vector import AsyncVectorEnv

import simgrasp  # noqa: F401  (registers the env)
from simgrasp.assets.model import model_for
from simgrasp.envs.handle_grasp import HandleGraspConfig, HandleGraspEnv, trial_reward
from simgrasp.envs.policy import FALLBACK_SOURCE, DetectorPolicy
from simgrasp.grasping.trials.chain import run_chain
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.result import TrialResult
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.camera import CameraSpec
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import observe, viewpoint_normals
from simgrasp.scenes.scene import build_scene

ENV_ID = "simgrasp/HandleGrasp-v0"
# One small camera and a short trial keep the API checks fast; the chain comparison below uses
# the default (the chain's) configuration.
SMALL_CAMERA = CameraSpec(
    "view0", pos=(0.3, -0.35, 0.4), lookat=(0.0, 0.0, 0.03), width=160, height=120
)


class SmallEnv(TypedDict):
    """The :class:`HandleGraspConfig` fields the API checks override."""

    objects: tuple[str, ...]
    max_points: int
    scene: SceneConfig
    trial: TrialConfig


SMALL = SmallEnv(
    objects=("gen_hammer", "gen_can"),
    max_points=1024,
    scene=SceneConfig(cameras=(SMALL_CAMERA,)),
    trial=TrialConfig(hold_time=0.2, perturb_directions=((0.0, 0.0, -1.0),)),
)
AIR_GRASP = np.array([0.4, 0.4, 0.3, 0.0, 1.0, 0.0, 0.0, 0.08])
"""Top-down (TCP +z along world -z), far from the object: closes on nothing."""


@pytest.fixture
def small_env():
    env = HandleGraspEnv(**SMALL)
    yield env
    env.close()


def _trial_record(**changes) -> TrialResult:
    record = {
        "object": "gen_hammer_s0",
        "gripper": "builtin",
        "seed": 0,
        "object_pose": [0.0] * 7,
        "grasp": [0.0] * 7,
        "grasp_width": 0.08,
        "grasp_source": "action",
        "success": True,
        "failure": None,
        "on_handle": True,
        "handle_fraction": 1.0,
        "lift_height": 0.2,
        "slip_lift": 0.0,
        "slip_perturb": 0.0,
        "contact_points_object": [],
        "sim_time": 1.0,
        "steps": 500,
        "timings_s": {},
    }
    return TrialResult(**{**record, **changes})


def test_import_simgrasp_registers_the_env_without_importing_mujoco() -> None:
    code = (
        "import sys, gymnasium, simgrasp\n"
        f"assert {ENV_ID!r} in gymnasium.registry\n"
        "assert 'mujoco' not in sys.modules, 'import simgrasp imported mujoco'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_gymnasium_env_checker_passes() -> None:
    env = gymnasium.make(f"simgrasp:{ENV_ID}", render_mode="rgb_array", **SMALL)
    try:
        check_env(env.unwrapped)
    finally:
        env.close()


def test_observation_is_the_chains_cloud_and_images(
    renderers: RendererKeeper, small_env: HandleGraspEnv
) -> None:
    obs, info = small_env.reset(seed=11)
    assert obs in small_env.observation_space
    assert obs["depth"].shape == (1, 120, 160) and obs["depth"].dtype == np.float32
    assert obs["mask"].any() and np.all(obs["depth"][obs["mask"] == 1] > 0)
    np.testing.assert_allclose(obs["intrinsics"][0], SMALL_CAMERA.intrinsics.matrix)
    np.testing.assert_allclose(obs["world_T_cam"][0][:3, 3], SMALL_CAMERA.pos, atol=1e-9)

    config = small_env.config
    scene = build_scene(
        model_for(info["object"]),
        make_gripper(config.gripper),
        config.scene_config,
        info["episode_seed"],
    )
    cloud = observe(scene, renderers.renderer_for(scene), config.noise, info["episode_seed"]).cloud
    count = len(cloud)
    assert info["cloud_points"] == count and 10 < count <= config.max_points
    assert obs["valid"].sum() == count and not obs["valid"][count:].any()
    np.testing.assert_array_equal(obs["points_world"][:count], cloud.points_world)
    np.testing.assert_array_equal(obs["normals_world"][:count], viewpoint_normals(cloud))
    assert not obs["points_world"][count:].any()


def test_large_clouds_are_subsampled_with_the_episode_seed() -> None:
    env = HandleGraspEnv(**(SMALL | {"max_points": 100}))
    try:
        options = {"object": "gen_hammer", "episode_seed": 5}
        first, info = env.reset(seed=0, options=options)
        second, _ = env.reset(seed=1, options=options)
    finally:
        env.close()
    assert info["cloud_points"] > 100 and first["valid"].all()
    for key in first:
        np.testing.assert_array_equal(first[key], second[key], err_msg=key)


def test_seeded_resets_are_deterministic(small_env: HandleGraspEnv) -> None:
    first, first_info = small_env.reset(seed=7)
    again, again_info = small_env.reset(seed=7)
    other_env = HandleGraspEnv(**SMALL)
    try:
        other, other_info = other_env.reset(seed=7)
    finally:
        other_env.close()
    assert first_info == again_info == other_info
    for key in first:
        np.testing.assert_array_equal(first[key], again[key], err_msg=key)
        np.testing.assert_array_equal(first[key], other[key], err_msg=key)
    _, next_info = small_env.reset(seed=8)
    assert next_info["episode_seed"] != first_info["episode_seed"]


def test_an_episode_after_another_of_its_object_looks_as_in_a_fresh_env(
    small_env: HandleGraspEnv,
) -> None:
    """The env keeps its renderer across episodes of one object: the second episode's images
    and cloud (the hammer elsewhere on the table) equal those of a fresh env."""
    first, _ = small_env.reset(options={"object": "gen_hammer", "episode_seed": 0})
    after, _ = small_env.reset(options={"object": "gen_hammer", "episode_seed": 1})
    fresh_env = HandleGraspEnv(**SMALL)
    try:
        fresh, _ = fresh_env.reset(options={"object": "gen_hammer", "episode_seed": 1})
    finally:
        fresh_env.close()
    assert not np.array_equal(first["depth"], after["depth"])
    for key in fresh:
        np.testing.assert_array_equal(after[key], fresh[key], err_msg=key)


def test_one_grasp_per_episode(small_env: HandleGraspEnv) -> None:
    with pytest.raises(RuntimeError, match="before reset"):
        small_env.step(AIR_GRASP)
    obs, info = small_env.reset(seed=2)
    after, reward, terminated, truncated, step_info = small_env.step(AIR_GRASP)
    assert (reward, terminated, truncated) == (0.0, True, False)
    assert step_info["failure"] == "missed" and step_info["success"] is False
    assert step_info["episode_seed"] == info["episode_seed"] == step_info["seed"]
    assert step_info["object"] == info["object"] and "timings_s" not in step_info
    assert after in small_env.observation_space
    np.testing.assert_array_equal(after["points_world"], obs["points_world"])
    with pytest.raises(RuntimeError, match="terminated"):
        small_env.step(AIR_GRASP)


@pytest.mark.parametrize(
    ("action", "message"),
    [
        (np.r_[AIR_GRASP[:3], 0.0, 0.0, 0.0, 0.0, 0.08], "quaternion"),
        (np.r_[np.nan, AIR_GRASP[1:]], "finite"),
        (AIR_GRASP[:7], "8 finite numbers"),
    ],
)
def test_bad_actions_are_rejected_naming_the_action(
    small_env: HandleGraspEnv, action: np.ndarray, message: str
) -> None:
    small_env.reset(seed=3)
    with pytest.raises(ValueError, match=message) as error:
        small_env.step(action)
    assert "invalid action [" in str(error.value)
    small_env.step(AIR_GRASP)  # a rejected action does not end the episode


def test_bad_configuration_and_options_are_rejected(small_env: HandleGraspEnv) -> None:
    with pytest.raises(TypeError, match="unknown HandleGraspEnv option"):
        HandleGraspEnv(num_view=2)
    with pytest.raises(ValueError, match="reward"):
        HandleGraspConfig(reward="lifted")  # type: ignore[arg-type]  # refused on purpose
    mixed = SceneConfig(cameras=(SMALL_CAMERA, replace(SMALL_CAMERA, name="view1", width=320)))
    with pytest.raises(ValueError, match="one image size"):
        HandleGraspEnv(scene=mixed)
    with pytest.raises(ValueError, match="unknown reset option"):
        small_env.reset(options={"seed": 1})
    with pytest.raises(ValueError, match="episode_seed"):
        small_env.reset(options={"episode_seed": -1})


def test_a_step_after_a_failed_reset_names_the_failed_reset(small_env: HandleGraspEnv) -> None:
    """A failed reset ends the previous episode: the next step must not grasp in it, and says
    why there is no episode."""
    small_env.reset(seed=0)
    with pytest.raises(ValueError, match="no_such_thing"):
        small_env.reset(options={"object": "no_such_thing"})
    with pytest.raises(RuntimeError, match=r"the last reset\(\) failed .*no_such_thing"):
        small_env.step(AIR_GRASP)
    small_env.reset(seed=0, options={"object": "gen_can"})
    assert small_env.step(AIR_GRASP)[2] is True


def test_reward_kinds() -> None:
    held_elsewhere = _trial_record(on_handle=False, handle_fraction=0.0)
    dropped = _trial_record(success=False, failure="dropped_in_perturbation")
    diverged = _trial_record(success=None, failure="sim_unstable")
    assert trial_reward(_trial_record(), "on_handle") == 1.0
    assert trial_reward(held_elsewhere, "on_handle") == 0.0
    assert trial_reward(held_elsewhere, "lift") == 1.0
    assert trial_reward(dropped, "lift") == trial_reward(diverged, "lift") == 0.0


@pytest.mark.parametrize("seed", [1, 0])
def test_env_and_detector_policy_reproduce_the_chain(seed: int) -> None:
    chain = run_chain(model_for("gen_hammer"), ChainConfig.of(detector__kind="quadric"), seed=seed)
    assert chain.trial is not None
    env = gymnasium.make(f"simgrasp:{ENV_ID}")
    try:
        obs, info = env.reset(seed=99, options={"object": "gen_hammer", "episode_seed": seed})
        policy = DetectorPolicy.for_env(env, detector="quadric")
        action = policy.act(obs, seed=info["episode_seed"])
        _, reward, terminated, _, step_info = env.step(action)
    finally:
        env.close()
    assert info["cloud_points"] == chain.cloud_points
    np.testing.assert_allclose(step_info["grasp"], chain.trial.grasp, atol=1e-12)
    assert step_info["grasp_width"] == chain.trial.grasp_width
    assert step_info["success"] == chain.success
    assert step_info["failure"] == chain.trial.failure
    assert step_info["on_handle"] == chain.trial.on_handle
    assert terminated and reward == float(chain.on_handle)
    if seed == 0:  # the chain holds the hammer by its handle with this seed (test_chain.py)
        assert reward == 1.0


def test_policy_falls_back_to_a_top_down_grasp_without_a_cloud(small_env: HandleGraspEnv) -> None:
    obs, info = small_env.reset(seed=4)
    for detector in ("centroid", "random", "tenpas"):
        action = DetectorPolicy.for_env(small_env, detector).act(obs, info["episode_seed"])
        assert action in small_env.action_space, detector
    policy = DetectorPolicy.for_env(small_env)
    obs["valid"][:] = 0
    grasp = policy.plan(obs, seed=0)
    assert grasp.source == FALLBACK_SOURCE
    np.testing.assert_allclose(grasp.approach_world, [0.0, 0.0, -1.0])
    np.testing.assert_allclose(grasp.world_T_tcp[:2, 3], [0.0, 0.0])
    assert grasp.world_T_tcp[2, 3] > policy.geometry.pad_reach


def test_rgb_array_render(small_env: HandleGraspEnv) -> None:
    assert small_env.render() is None
    env = HandleGraspEnv(render_mode="rgb_array", **SMALL)
    try:
        with pytest.raises(RuntimeError, match="before reset"):
            env.render()
        env.reset(seed=5)
        image = env.render()
    finally:
        env.close()
        env.close()
    assert image is not None
    assert image.shape == (480, 640, 3) and image.dtype == np.uint8
    assert image.std() > 10, "the picture should show the scene, not a blank image"


def test_async_vector_env_matches_sequential_envs() -> None:
    seeds: list[int | None] = [21, 22]
    expected = []
    actions = []
    for seed in seeds:
        env = gymnasium.make(ENV_ID, **SMALL)
        try:
            obs, info = env.reset(seed=seed)
            actions.append(DetectorPolicy.for_env(env).act(obs, info["episode_seed"]))
            _, reward, _, _, step_info = env.step(actions[-1])
        finally:
            env.close()
        expected.append((obs, info, reward, step_info))

    vector_env = gymnasium.make_vec(
        ENV_ID,
        num_envs=2,
        vectorization_mode="async",
        vector_kwargs={"context": "spawn"},
        **SMALL,
    )
    assert isinstance(vector_env, AsyncVectorEnv)
    try:
        obs, infos = vector_env.reset(seed=seeds)
        _, rewards, terminated, truncated, step_infos = vector_env.step(np.stack(actions))
    finally:
        vector_env.close()
    for i, (single_obs, info, reward, step_info) in enumerate(expected):
        assert infos["episode_seed"][i] == info["episode_seed"]
        np.testing.assert_array_equal(obs["points_world"][i], single_obs["points_world"])
        assert rewards[i] == reward and terminated[i] and not truncated[i]
        assert list(step_infos["grasp"][i]) == step_info["grasp"]
        assert step_infos["success"][i] == step_info["success"]
        assert step_infos["failure"][i] == step_info["failure"]


def test_the_sensor_field_gives_seeded_sensed_depth() -> None:
    """With ``sensor`` kinect the observed depth is the sensor's (it differs from the ideal
    render, in whole millimetres) and the same episode seed gives the same observation."""
    from simgrasp.perception.sensors.settings import SensorSettings

    options = {"object": "gen_hammer", "episode_seed": 5}
    observations = []
    for sensor in ("kinect", "kinect", "ideal"):
        env = HandleGraspEnv(sensor=SensorSettings(kind=sensor), **SMALL)
        try:
            observations.append(env.reset(seed=0, options=options)[0])
        finally:
            env.close()
    first, again, ideal = observations
    for key in first:
        np.testing.assert_array_equal(first[key], again[key])
    seen = first["depth"][first["depth"] > 0]
    assert not np.array_equal(first["depth"], ideal["depth"])
    np.testing.assert_allclose(seen * 1000, np.round(seen * 1000), atol=1e-3)
