"""The full chain (render -> detect -> plan -> execute) and the grasp planner, with the real
simulator and renderer."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from data_needs import ROBOTIQ

import simgrasp
from simgrasp.assets.model import model_for
from simgrasp.errors import SimgraspError
from simgrasp.grasping.planning.clearance import collides
from simgrasp.grasping.planning.grasp_points import narrowed
from simgrasp.grasping.planning.planner import (
    PlannerConfig,
    grasps_from_handles,
    table_margin,
)
from simgrasp.grasping.trials.chain import run_chain
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.handles.core.detection import Handle
from simgrasp.transforms import pose7_to_matrix

GEOMETRY = GripperGeometry(max_opening=0.085)


def _handle(center, axis) -> Handle:
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return Handle(np.asarray(center, float), axis, 0.03, 1.0, 10, (-0.05, 0.05))


def test_handle_grasps_close_across_the_handle_and_clear_the_table() -> None:
    handle = _handle([0.0, 0.0, 0.05], [1.0, 0.2, 0.0])
    cameras = np.array([[0.5, 0.0, 0.5]])
    grasps = grasps_from_handles(
        [handle], np.zeros((0, 3)), cameras, GEOMETRY, 0.0, np.random.default_rng(0)
    )
    assert grasps
    for grasp in grasps:
        x_axis, y_axis = grasp.world_T_tcp[:3, 0], grasp.world_T_tcp[:3, 1]
        assert abs(x_axis @ handle.axis) == pytest.approx(1.0, abs=1e-9)
        assert abs(y_axis @ handle.axis) < 1e-9
        assert table_margin(grasp.world_T_tcp, GEOMETRY, 0.0, PlannerConfig()) >= -1e-9
    scores = [g.score for g in grasps]
    assert scores == sorted(scores, reverse=True)
    assert grasps[0].approach_world[2] < -0.5, "the best grasp should come from above"


def test_fingertips_that_swing_forward_stay_above_the_table_once_closed() -> None:
    """A handle lying on the table: a top-down grasp of a gripper whose fingertips reach 23 mm
    past the TCP once closed (9.5 mm open) sits high enough for the closed tips to clear the
    table by ``grasp_table_clearance``, higher than the open gripper alone would need."""
    handle = _handle([0.0, 0.0, 0.01], [1.0, 0.0, 0.0])
    open_only = GripperGeometry(max_opening=0.085, pad_reach=0.0095)
    swinging = GripperGeometry(max_opening=0.085, pad_reach=0.0095, closed_pad_reach=0.023)
    config = PlannerConfig()
    heights = []
    for geometry in (open_only, swinging):
        grasps = grasps_from_handles(
            [handle], np.zeros((0, 3)), np.zeros((1, 3)), geometry, 0.0, np.random.default_rng(0)
        )
        top_down = max(grasps, key=lambda g: -g.approach_world[2])
        assert top_down.approach_world[2] == pytest.approx(-1.0)
        heights.append(top_down.world_T_tcp[2, 3])
    assert heights[0] == pytest.approx(0.0095 + config.grasp_table_clearance, abs=2e-4)
    assert heights[1] == pytest.approx(0.023 + config.grasp_table_clearance, abs=2e-4)


def _standing_strap_and_mug_body() -> tuple[Handle, np.ndarray]:
    """A strap standing 4.2 cm above the table at the origin, its axis sloping 5 degrees toward
    +x, and the points of a mug body beside it: a 4.5 cm radius cylinder whose axis is 6.5 cm
    away along -x."""
    handle = _handle([0.0, 0.0, 0.042], [0.09, 0.0, 0.99])
    angles, heights = np.meshgrid(np.linspace(0, 2 * np.pi, 90), np.linspace(0, 0.09, 30))
    body = np.column_stack(
        [-0.065 + 0.045 * np.cos(angles.ravel()), 0.045 * np.sin(angles.ravel()), heights.ravel()]
    )
    return handle, body


def test_the_best_grasp_is_centered_in_the_gap_around_a_handle() -> None:
    """With a camera off to one side, the view bonus alone turns the best approach to the
    strap 24 degrees off the line through the mug's axis, one finger passing close to the body;
    the clearance bonus brings it back to within a few degrees of that line."""
    handle, body = _standing_strap_and_mug_body()
    cameras = np.array([[0.3, 0.4, 0.5]])

    def best_azimuth(config: PlannerConfig) -> float:
        rng = np.random.default_rng(0)
        best = grasps_from_handles([handle], body, cameras, GEOMETRY, 0.0, rng, config)[0]
        approach = best.approach_world
        return float(np.degrees(np.arctan2(approach[1], -approach[0])))

    assert abs(best_azimuth(PlannerConfig(clearance_weight=0.0))) > 15
    assert abs(best_azimuth(PlannerConfig())) < 5


def test_a_standing_handle_is_approached_from_above_its_side() -> None:
    """A mug's strap standing 4.2 cm above the table beside its body (a 4.5 cm radius cylinder
    of points), the strap's axis sloping 5 degrees away from the body as detected. Approaches
    perpendicular to the axis that miss the body come from outside and rise with the slope,
    which puts a Robotiq-sized palm into the table at the pre-grasp: only approaches tilted
    down about the closing direction remain, and they still close across the strap."""
    handle, body = _standing_strap_and_mug_body()
    robotiq_like = GripperGeometry(
        max_opening=0.085,
        pad_reach=0.0095,
        closed_pad_reach=0.023,
        finger_length=0.06,
        finger_width=0.025,
        palm_size=(0.07, 0.14, 0.06),
    )
    cameras = np.array([[0.5, 0.0, 0.5]])

    def plan(config: PlannerConfig) -> list:
        rng = np.random.default_rng(0)
        return grasps_from_handles([handle], body, cameras, robotiq_like, 0.0, rng, config)

    assert plan(PlannerConfig(approach_pitches=(0.0,), fallback_pitches=())) == []
    grasps = plan(PlannerConfig())
    unchanged = plan(PlannerConfig(fallback_pitches=()))  # found at the usual pitches
    assert [g.world_T_tcp.tolist() for g in grasps] == [g.world_T_tcp.tolist() for g in unchanged]
    steep = plan(PlannerConfig(approach_pitches=(0.0,)))  # only the fallback's clear it
    assert steep and all(g.approach_world[2] < -0.5 for g in steep)  # 45-60 deg off a rise
    assert grasps
    for grasp in grasps:
        assert abs(grasp.world_T_tcp[:3, 1] @ handle.axis) < 1e-9, "jaws close across it"
        assert grasp.approach_world[0] < -0.5, "from outside, toward the body"
        assert grasp.approach_world[2] < -0.1, "tilted down"
        assert table_margin(grasp.world_T_tcp, robotiq_like, 0.0, PlannerConfig()) >= -1e-9


def test_the_best_grasp_holds_the_handle_nearest_the_centroid_with_the_pads_on_it() -> None:
    """A handle covered from x = -0.05 to 0.05 with the cloud's centroid far along +x: the best
    grasp moves toward the centroid but stops a finger width inside the covered stretch."""
    handle = Handle(
        np.array([0.0, 0.0, 0.05]), np.array([1.0, 0.0, 0.0]), 0.03, 1.0, 10, (-0.05, 0.05)
    )
    heavy_end = np.array([[0.30, 0.0, 0.05], [0.32, 0.0, 0.05]])  # pulls the centroid to +x
    cameras = np.array([[0.5, 0.0, 0.5]])
    grasps = grasps_from_handles(
        [handle], heavy_end, cameras, GEOMETRY, 0.0, np.random.default_rng(0)
    )
    best_x = grasps[0].world_T_tcp[0, 3]
    assert best_x == pytest.approx(0.05 - GEOMETRY.finger_width, abs=1e-9)
    xs = {round(g.world_T_tcp[0, 3], 9) for g in grasps}
    assert xs == {0.0, round(best_x, 9)}, "the handle's center stays a fallback grasp point"


def _flat_loop_beside_a_lying_body() -> tuple[Handle, np.ndarray]:
    """A mug lying on its side (body axis along y, 3.7 cm radius, centered at x = -0.03) with
    its loop flat on the table: two arms along x at y = +-0.03 from the body's wall to x =
    0.052, joined by a bar along y, a 2.4 cm tube whose axis lies 1.2 cm up. The handle as the
    clustering makes it from the loop's axis points: its center on the bar, its axis the
    dominant direction of its candidates (the two arms', along x)."""
    arm_x = np.linspace(0.012, 0.052, 9)
    bar_y = np.linspace(-0.025, 0.025, 6)
    trace = np.vstack(
        [np.column_stack([arm_x, np.full(9, side), np.full(9, 0.012)]) for side in (-0.03, 0.03)]
        + [np.column_stack([np.full(6, 0.052), bar_y, np.full(6, 0.012)])]
    )
    trace_axes = np.vstack([np.tile([1.0, 0.0, 0.0], (18, 1)), np.tile([0.0, 1.0, 0.0], (6, 1))])
    center = np.array([0.052, 0.0, 0.012])
    along = (trace - center) @ np.array([1.0, 0.0, 0.0])
    handle = Handle(
        center,
        np.array([1.0, 0.0, 0.0]),
        0.024,
        1.0,
        24,
        (float(along.min()), 0.0),
        trace,
        trace_axes,
    )
    angles = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    y = np.linspace(-0.045, 0.045, 10)
    body = np.array(
        [[-0.03 + 0.037 * np.cos(a), yy, 0.037 + 0.037 * np.sin(a)] for a in angles for yy in y]
    )
    tube_top = trace + np.array([0.0, 0.0, 0.012])
    return handle, np.vstack([body, tube_top])


def test_a_loop_lying_flat_is_also_grasped_at_its_root_across_the_arm() -> None:
    """The flat loop's handle axis runs along its arms while its center sits on the bar, so
    every grasp on the axis line closes along the bar. The loop's trace adds its root: the
    arm nearest the body's centroid, a pad width out from the wall, the jaws closing across
    the arm and opened to the handle's width plus the root margin."""
    handle, cloud = _flat_loop_beside_a_lying_body()
    cameras = np.array([[0.5, 0.0, 0.5]])
    config = PlannerConfig()

    def plan(h: Handle) -> list:
        return grasps_from_handles([h], cloud, cameras, GEOMETRY, 0.0, np.random.default_rng(0))

    def at_root(grasp) -> bool:
        return bool(grasp.world_T_tcp[0, 3] < 0.045 and abs(grasp.world_T_tcp[1, 3]) > 0.02)

    untraced = dataclasses.replace(handle, trace=np.zeros((0, 3)), trace_axes=np.zeros((0, 3)))
    assert not any(at_root(g) for g in plan(untraced))
    roots = [g for g in plan(handle) if at_root(g)]
    assert roots
    for grasp in roots:
        assert abs(grasp.world_T_tcp[:3, 1] @ [1.0, 0.0, 0.0]) < 1e-9, "closes across the arm"
        side = np.sign(grasp.world_T_tcp[1, 3])
        root = np.array([0.012 + GEOMETRY.finger_width, 0.03 * side, 0.012])
        backed_off = grasp.world_T_tcp[:3, 3] - root
        assert np.linalg.norm(np.cross(backed_off, grasp.approach_world)) < 1e-9, "at the root"
        assert grasp.width == pytest.approx(handle.width + 2 * config.root_opening_margin)
        jaws = narrowed(GEOMETRY, handle.width, config.root_opening_margin)
        assert not collides(grasp.world_T_tcp, cloud, jaws, 0)


def test_a_handle_whose_trace_and_trace_axes_differ_is_refused() -> None:
    with pytest.raises(SimgraspError, match=r"trace \(2, 3\) and trace_axes \(1, 3\)"):
        dataclasses.replace(
            _handle([0.0, 0.0, 0.05], [1.0, 0.0, 0.0]),
            trace=np.zeros((2, 3)),
            trace_axes=np.zeros((1, 3)),
        )


def test_a_straight_handles_trace_adds_no_grasp() -> None:
    """A straight handle's root lies on its axis line, turned nowhere: the grasps are those of
    the same handle without a trace."""
    handle = _handle([0.0, 0.0, 0.05], [1.0, 0.0, 0.0])
    xs = np.linspace(-0.05, 0.05, 11)
    traced = dataclasses.replace(
        handle,
        trace=np.column_stack([xs, np.zeros(11), np.full(11, 0.05)]),
        trace_axes=np.tile([1.0, 0.0, 0.0], (11, 1)),
    )
    heavy_end = np.array([[0.30, 0.0, 0.05], [0.32, 0.0, 0.05]])
    cameras = np.array([[0.5, 0.0, 0.5]])

    def poses(h: Handle) -> list:
        rng = np.random.default_rng(0)
        return [
            g.world_T_tcp.tolist()
            for g in grasps_from_handles([h], heavy_end, cameras, GEOMETRY, 0.0, rng)
        ]

    assert poses(traced) == poses(handle)


def test_a_cloud_point_inside_a_finger_rejects_the_grasp() -> None:
    handle = _handle([0.0, 0.0, 0.1], [1.0, 0.0, 0.0])
    rng = np.random.default_rng(0)
    grasps = grasps_from_handles([handle], np.zeros((0, 3)), np.zeros((1, 3)), GEOMETRY, 0.0, rng)
    pose = grasps[0].world_T_tcp
    finger_point_tcp = np.array([0.0, GEOMETRY.max_opening / 2 + 0.005, -0.01])
    finger_point_world = pose[:3, :3] @ finger_point_tcp + pose[:3, 3]
    assert collides(pose, finger_point_world[None], GEOMETRY, 0)
    between_pads = pose[:3, 3][None]
    assert not collides(pose, between_pads, GEOMETRY, 0)


def test_an_isolated_point_in_a_finger_is_a_flying_pixel_a_patch_is_an_obstacle() -> None:
    """A depth sensor's flying pixel (a point with no neighbor within ``obstacle_radius``)
    does not block a grasp; three points within a few millimeters of it (a surface) do."""
    handle = _handle([0.0, 0.0, 0.1], [1.0, 0.0, 0.0])
    free = grasps_from_handles(
        [handle], np.zeros((0, 3)), np.zeros((1, 3)), GEOMETRY, 0.0, np.random.default_rng(0)
    )
    pose = free[0].world_T_tcp
    in_finger = (
        pose[:3, :3] @ np.array([0.0, GEOMETRY.max_opening / 2 + 0.005, -0.01]) + pose[:3, 3]
    )

    def poses(cloud: np.ndarray) -> list[np.ndarray]:
        rng = np.random.default_rng(0)
        grasps = grasps_from_handles([handle], cloud, np.zeros((1, 3)), GEOMETRY, 0.0, rng)
        return [g.world_T_tcp for g in grasps]

    assert any(np.allclose(p, pose) for p in poses(in_finger[None]))
    patch = in_finger + np.array([[0.0, 0.0, 0.0], [0.002, 0.0, 0.0], [0.0, 0.0, 0.002]])
    assert not any(np.allclose(p, pose) for p in poses(patch))
    strict = PlannerConfig(obstacle_radius=0.0)
    rng = np.random.default_rng(0)
    grasps = grasps_from_handles(
        [handle], in_finger[None], np.zeros((1, 3)), GEOMETRY, 0.0, rng, strict
    )
    assert not any(np.allclose(g.world_T_tcp, pose) for g in grasps)


@pytest.fixture(scope="module")
def hammer_model():
    return model_for("gen_hammer")


@pytest.fixture(scope="module")
def hammer_chain(hammer_model):
    """The generated hammer's full chain of seed 0, through the front door."""
    return simgrasp.run_trial(hammer_model, seed=0)


def test_full_chain_grasps_the_generated_hammer_by_its_handle(hammer_chain) -> None:
    result = hammer_chain
    assert isinstance(result, simgrasp.ChainResult)
    assert result.cloud_points > 500
    assert result.detection_accuracy is not None
    assert result.candidates > 0 and result.detection_accuracy >= 0.8
    assert result.handle_recall
    assert result.success and result.on_handle, result.failure
    assert result.failure is None and result.to_json()["failure"] is None


def test_a_chain_result_names_its_failure_as_its_record_does(hammer_chain) -> None:
    """``ChainResult.failure``: the trial's failure, ``no_grasp`` without a grasp, a
    neighbor's doing in clutter (which the record's ``failure`` holds too)."""
    result = hammer_chain
    assert result.trial is not None and result.failure is None
    missed = dataclasses.replace(result.trial, success=False, failure="missed")
    variants = {
        "missed": dataclasses.replace(result, trial=missed),
        "no_grasp": dataclasses.replace(result, trial=None),
        "wrong_object": dataclasses.replace(
            result, trial=missed, scene_fields={"failure": "wrong_object"}
        ),
    }
    for failure, variant in variants.items():
        assert variant.failure == failure == variant.to_json()["failure"]
        assert variant.success is False


@pytest.mark.parametrize("gripper", ["builtin", ROBOTIQ])
def test_full_chain_holds_an_upright_mug_by_its_handle(gripper: str) -> None:
    config = ChainConfig.of(gripper=gripper, scene__placement="upright")
    result = run_chain(model_for("gen_mug"), config, seed=0)
    assert result.detection_accuracy is not None
    assert result.detection_accuracy >= 0.9 and result.handle_recall
    assert result.success and result.on_handle, result.to_json()["failure"]


@pytest.mark.parametrize("seed", [3, 5])
def test_full_chain_holds_a_lying_mug_by_the_root_of_its_flat_loop(seed: int) -> None:
    """The generated mug lying on its side, its loop flat on the table, seen by the Kinect
    model: the loop's handle (center on the bar, axis along the arms) is held by its root."""
    result = run_chain(model_for("gen_mug"), ChainConfig.of(sensor__kind="kinect"), seed=seed)
    world_T_object = pose7_to_matrix(result.to_json()["object_pose"])
    assert abs(world_T_object[2, 2]) < 0.2, "lying on its side (the mug's axis, object z)"
    assert result.success and result.on_handle, result.to_json()["failure"]


def test_full_chain_is_reproducible(hammer_model) -> None:
    first = run_chain(hammer_model, ChainConfig(), seed=3).to_json()
    second = run_chain(hammer_model, ChainConfig(), seed=3).to_json()
    for record in (first, second):
        record.pop("timings_s")
    assert first == second


@pytest.mark.parametrize("detector", ["centroid", "random", "tenpas"])
def test_baselines_run_through_the_same_chain(hammer_model, detector: str) -> None:
    result = run_chain(hammer_model, ChainConfig.of(detector__kind=detector), seed=1)
    record = result.to_json()
    assert result.failure == record["failure"]
    assert record["detector"] == detector
    assert record["success"] in (True, False)
    assert record["failure"] in (
        None,
        "no_grasp",
        "approach_collision",
        "missed",
        "slipped_in_lift",
        "dropped_in_perturbation",
        "invalid_start",
    )


def test_a_kinect_trial_reproduces_bit_for_bit_with_its_seed(hammer_model) -> None:
    """The sensor model draws from the trial's seed: the same seed gives the same record, and
    the kinect cloud differs from the ideal one."""
    kinect = ChainConfig.of(sensor__kind="kinect")
    first = run_chain(hammer_model, kinect, seed=2).to_json()
    second = run_chain(hammer_model, kinect, seed=2).to_json()
    ideal = run_chain(hammer_model, ChainConfig(), seed=2).to_json()
    for record in (first, second, ideal):
        del record["timings_s"]
    assert first == second
    assert first["cloud_points"] != ideal["cloud_points"]


def test_the_sensor_is_part_of_a_trials_identity() -> None:
    from simgrasp.evaluation.sweep import plan_trials
    from simgrasp.evaluation.trial_log import trial_key

    specs = plan_trials(["gen_mug"], {"sensor.kind": ["ideal", "kinect"]}, range(1))
    ideal, kinect = specs
    assert ideal.key != kinect.key
    assert kinect.summary_fields()["sensor"] == "kinect"
    # records written before sensors existed were seen by the ideal sensor
    old = {k: v for k, v in ideal.summary_fields().items() if k not in ("sensor", "settings")}
    assert trial_key(old) == ideal.key
