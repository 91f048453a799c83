"""Grasp trials on a generated hammer with both grippers (real MuJoCo, real object models).

Grasps are placed by hand from the object's geometry and handle label: the label box's center
and axis for the handle, the head beyond the label's end for the head.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from data_needs import ROBOTIQ

from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.grasping.grasp import Grasp, tcp_pose
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import FAST_TRIAL, TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.labels import Box, Capsule
from simgrasp.scenes.scene import Scene, build_scene

GRIPPERS = ("builtin", ROBOTIQ)
TABLE_CLEARANCE = 0.005  # fingertips above the table top (m)
DOWN = np.array([0.0, 0.0, -1.0])


@pytest.fixture(scope="module", params=GRIPPERS)
def hammer_scene(request: pytest.FixtureRequest) -> Scene:
    model = build_object_model(load_object("gen_hammer", seed=1))
    return build_scene(model, make_gripper(request.param), seed=3)


def handle_center_axis(region: Box | Capsule) -> tuple[np.ndarray, np.ndarray]:
    """Midpoint and axis of a label region (object frame)."""
    if isinstance(region, Capsule):
        return (region.p0 + region.p1) / 2, region.axis
    return region.center, region.axis


def top_down_grasp(scene: Scene, point_object: np.ndarray, axis_object: np.ndarray) -> Grasp:
    """A top-down grasp closing across ``axis_object`` at ``point_object``, with the TCP raised
    so the fingertips clear the table."""
    world_T_object = scene.world_T_object
    point_world = world_T_object[:3, :3] @ point_object + world_T_object[:3, 3]
    axis_world = world_T_object[:3, :3] @ axis_object
    closing_world = np.cross(axis_world, DOWN)
    gripper = scene.gripper.gripper
    point_world[2] = max(
        point_world[2], scene.config.table_top_z + gripper.finger_reach + TABLE_CLEARANCE
    )
    return Grasp(tcp_pose(point_world, closing_world, DOWN), gripper.max_opening)


def handle_grasp(scene: Scene) -> Grasp:
    center, axis = handle_center_axis(scene.object_model.asset.handle.regions[0])
    return top_down_grasp(scene, center, axis)


def head_point(scene: Scene) -> tuple[np.ndarray, np.ndarray, float]:
    """(point, handle axis, head length) of the hammer head, beyond the label's end (object
    frame). The head lies across the handle; the point is in the middle of one of its arms."""
    label = scene.object_model.asset.handle.regions[0]
    assert isinstance(label, Box)
    axis = label.axis
    vertices = scene.object_model.asset.mesh.vertices
    along = (vertices - label.center) @ axis
    label_end = label.half_extents.max()
    head = vertices[along > label_end]
    assert len(head) > 0, "the hammer head should extend beyond the handle label"
    across = np.cross([0.0, 0.0, 1.0], axis)
    head_across = (head - label.center) @ across
    head_center = head.mean(axis=0)
    arm = (label.half_extents[1] + head_across.max()) / 2
    return head_center + arm * across, axis, float(np.ptp(head_across))


@pytest.fixture(scope="module")
def handle_result(hammer_scene: Scene):
    return run_trial(hammer_scene, handle_grasp(hammer_scene))


def test_handle_grasp_lifts_and_is_on_handle(hammer_scene: Scene, handle_result) -> None:
    result = handle_result
    assert result.failure is None, result.failure
    assert result.success is True
    assert result.on_handle
    assert result.handle_fraction >= 0.5
    assert result.lift_height > 0.15
    assert result.slip_lift is not None and result.slip_lift < 0.02
    assert len(result.contact_points_object) >= 2
    # Contacts lie on the labeled handle (object frame).
    points = np.asarray(result.contact_points_object)
    assert hammer_scene.object_model.asset.handle.contains(points).mean() >= 0.5


def test_head_grasp_lifts_but_is_not_on_handle(hammer_scene: Scene) -> None:
    point, axis, _ = head_point(hammer_scene)
    # Close along the handle axis across the head's thickness.
    across = np.cross([0.0, 0.0, 1.0], axis)
    result = run_trial(hammer_scene, top_down_grasp(hammer_scene, point, across))
    assert result.success is True, result.failure
    assert not result.on_handle
    assert result.handle_fraction < 0.5


def test_grasp_far_from_the_object_is_missed(hammer_scene: Scene) -> None:
    mesh_world = hammer_scene.object_model.asset.mesh.copy()
    mesh_world.apply_transform(hammer_scene.world_T_object)
    far = np.array([mesh_world.bounds[1, 0] + 0.10 + 0.02, 0.0, 0.0])
    grasp = top_down_grasp(hammer_scene, np.zeros(3), np.array([1.0, 0.0, 0.0]))
    world_T_tcp = grasp.world_T_tcp.copy()
    world_T_tcp[:2, 3] = far[:2]
    assert mesh_world.nearest.on_surface([world_T_tcp[:3, 3]])[1][0] > 0.10
    for config in (TrialConfig(), FAST_TRIAL):  # the fast close, touching nothing, runs its cap
        result = run_trial(hammer_scene, Grasp(world_T_tcp, grasp.width), config)
        assert result.success is False
        assert result.failure == "missed"
        assert not result.on_handle


def test_too_wide_head_is_not_lifted(hammer_scene: Scene) -> None:
    """Closing along the head's length (wider than the stroke) cannot lift the hammer."""
    point, axis, head_length = head_point(hammer_scene)
    assert head_length > hammer_scene.gripper.gripper.max_opening
    label = hammer_scene.object_model.asset.handle.regions[0]
    assert isinstance(label, Box)
    head_middle = point.copy()
    head_middle -= ((point - label.center) @ np.cross([0.0, 0.0, 1.0], axis)) * np.cross(
        [0.0, 0.0, 1.0], axis
    )
    result = run_trial(hammer_scene, top_down_grasp(hammer_scene, head_middle, axis))
    assert result.success is False
    assert result.failure in ("approach_collision", "missed", "slipped_in_lift")
    assert result.lift_height < 0.05
    assert not result.on_handle


def test_pregrasp_through_the_table_is_invalid_start(hammer_scene: Scene) -> None:
    """A side approach with the jaws opening vertically puts the lower finger in the table."""
    center, axis = handle_center_axis(hammer_scene.object_model.asset.handle.regions[0])
    world_T_object = hammer_scene.world_T_object
    point_world = world_T_object[:3, :3] @ center + world_T_object[:3, 3]
    side = np.cross(world_T_object[:3, :3] @ axis, DOWN)
    grasp = Grasp(tcp_pose(point_world, -DOWN, side), hammer_scene.gripper.gripper.max_opening)
    result = run_trial(hammer_scene, grasp)
    assert result.failure == "invalid_start"
    assert result.success is False
    assert result.steps * TrialConfig().timestep == pytest.approx(TrialConfig().settle_time)


def test_same_seed_gives_identical_record(hammer_scene: Scene, handle_result) -> None:
    again = run_trial(hammer_scene, handle_grasp(hammer_scene))
    assert again == handle_result  # timings are excluded from comparison
    first, second = handle_result.to_json(), again.to_json()
    first.pop("timings_s"), second.pop("timings_s")
    assert first == second


def test_divergence_is_sim_unstable_not_scored(hammer_scene: Scene) -> None:
    config = dataclasses.replace(TrialConfig(), max_speed=1e-9)
    result = run_trial(hammer_scene, handle_grasp(hammer_scene), config)
    assert result.failure == "sim_unstable"
    assert result.success is None


def test_a_state_mujoco_resets_is_sim_unstable(
    hammer_scene: Scene, tmp_path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A non-finite velocity makes MuJoCo reset the state with a warning; the trial must end
    as ``sim_unstable`` instead of going on from the reset state."""
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to ./MUJOCO_LOG.TXT

    def poison(phase: str, scene: Scene) -> None:
        if phase == "closed":
            scene.data.qvel[0] = np.nan

    result = run_trial(hammer_scene, handle_grasp(hammer_scene), on_phase=poison)
    assert result.failure == "sim_unstable"
    assert result.success is None


def test_an_object_torn_from_the_jaws_ends_the_trial_as_dropped(
    hammer_scene: Scene, handle_result
) -> None:
    """Tugs far beyond the grip tear the hammer out; the trial stops once it has left the jaws
    (release_gap), without simulating its fall onto the table."""
    config = dataclasses.replace(TrialConfig(), perturb_force_scale=30.0)
    result = run_trial(hammer_scene, handle_grasp(hammer_scene), config)
    assert result.failure == "dropped_in_perturbation"
    assert result.success is False
    assert result.sim_time < handle_result.sim_time - 1.0  # ended before the last tugs


def test_waiting_phases_end_once_the_grip_is_at_rest(hammer_scene: Scene) -> None:
    """With ``quiet_speed`` the settle, hold, tugs and rests end once the hammer is still in
    the jaws: the same verdict in fewer steps; every tug still lasts ``quiet_min_tug``."""
    waiting = dataclasses.replace(FAST_TRIAL, quiet_speed=None)
    quiet = dataclasses.replace(FAST_TRIAL, quiet_speed=0.01)
    full_time = run_trial(hammer_scene, handle_grasp(hammer_scene), waiting)
    early = run_trial(hammer_scene, handle_grasp(hammer_scene), quiet)
    assert (early.success, early.on_handle) == (full_time.success, full_time.on_handle)
    assert early.success and early.on_handle
    assert early.steps < full_time.steps
    floor = (  # the approach and the lift never end early; every tug lasts its minimum
        quiet.pregrasp_distance / quiet.approach_speed
        + quiet.lift_height / quiet.lift_speed
        + len(quiet.perturb_directions) * (quiet.quiet_min_tug + quiet.quiet_time)
    )
    assert early.sim_time > floor


def test_the_fast_close_squeezes_a_set_time_once_both_fingers_touch(hammer_scene: Scene) -> None:
    """With ``squeeze_time`` the close ends that long after both fingers touch the handle (or
    at rest sooner), however far the fully open jaws had to travel: the fast protocol holds the
    handle as the full one does, and a later ``close_time`` cap changes nothing."""
    moments: dict[str, float] = {}
    fast = run_trial(
        hammer_scene,
        handle_grasp(hammer_scene),
        FAST_TRIAL,
        on_phase=lambda phase, scene: moments.__setitem__(phase, float(scene.data.time)),
    )
    assert fast.success and fast.on_handle
    approach = FAST_TRIAL.pregrasp_distance / FAST_TRIAL.approach_speed
    closing = moments["closed"] - moments["pregrasp"] - approach - 2 * FAST_TRIAL.control_dt
    assert FAST_TRIAL.quiet_time < closing < FAST_TRIAL.close_time
    later_cap = dataclasses.replace(FAST_TRIAL, close_time=2.0)
    assert run_trial(hammer_scene, handle_grasp(hammer_scene), later_cap) == fast


def test_a_sleeping_object_wakes_when_the_gripper_touches_it(hammer_scene: Scene) -> None:
    """With ``sleep`` the hammer lying still is asleep when the gripper arrives and wakes at its
    touch: the record is the one of a hammer kept awake (but for the micrometers an awake
    hammer creeps on the table)."""
    awake: dict[str, bool] = {}
    asleep = run_trial(
        hammer_scene,
        handle_grasp(hammer_scene),
        FAST_TRIAL,
        on_phase=lambda phase, scene: awake.__setitem__(
            phase, bool(scene.data.body_awake[scene.object_body])
        ),
    )
    assert awake == {"pregrasp": False, "closed": True, "lifted": True, "perturbed": True}
    kept_awake = dataclasses.replace(FAST_TRIAL, sleep=False)
    awake_result = run_trial(hammer_scene, handle_grasp(hammer_scene), kept_awake)
    verdict = ("success", "failure", "on_handle", "steps")
    assert [getattr(awake_result, f) for f in verdict] == [getattr(asleep, f) for f in verdict]
    assert awake_result.lift_height == pytest.approx(asleep.lift_height, abs=1e-4)


def test_a_coarser_step_from_the_hold_on_keeps_the_verdict(
    hammer_scene: Scene, handle_result
) -> None:
    """``hold_timestep`` steps the hold and the tugs with 4 ms instead of 2 ms where the
    gripper allows it (``max_timestep``: the built-in one, not the Robotiq): the same verdict in
    fewer steps over the same simulated time; the next trial starts with the scene's own step
    again (the full protocol's record is unchanged)."""
    fine = run_trial(
        hammer_scene,
        handle_grasp(hammer_scene),
        dataclasses.replace(FAST_TRIAL, hold_timestep=None),
    )
    coarse = run_trial(hammer_scene, handle_grasp(hammer_scene), FAST_TRIAL)
    assert (coarse.success, coarse.on_handle) == (fine.success, fine.on_handle) == (True, True)
    if hammer_scene.gripper.gripper.max_timestep > FAST_TRIAL.timestep:
        assert coarse.steps < fine.steps
        assert coarse.sim_time == pytest.approx(fine.sim_time, abs=0.2)
    else:
        assert coarse == fine
    assert run_trial(hammer_scene, handle_grasp(hammer_scene)) == handle_result


def test_a_tug_that_tears_the_object_out_is_not_cut_short(hammer_scene: Scene) -> None:
    """An object moving in the jaws is never at rest: a grip that fails under the full tugs
    fails with the early end as well."""
    config = dataclasses.replace(FAST_TRIAL, quiet_speed=0.01, perturb_force_scale=30.0)
    result = run_trial(hammer_scene, handle_grasp(hammer_scene), config)
    assert result.failure == "dropped_in_perturbation"
