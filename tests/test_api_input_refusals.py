"""Bad input to the Python API (``simgrasp.run_trial`` etc.) and the gymnasium env: one line
naming the argument, refused before any scene is built or any trial runs."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium
import numpy as np
import pytest

import simgrasp
from simgrasp.envs.action import grasp_from_action
from simgrasp.errors import SimgraspError

GRASP = np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.3], [0, 0, 0, 1]])
"""A rigid TCP pose 0.3 m above the world origin."""


def refused(call: Callable[[], Any], message: str) -> None:
    """``call`` raises a one-line :class:`SimgraspError` that starts with ``message``."""
    with pytest.raises(SimgraspError) as error:
        call()
    text = str(error.value)
    assert "\n" not in text
    assert text.startswith(message), text


def scaled(factor: float) -> np.ndarray:
    pose = GRASP.copy()
    pose[:3, :3] *= factor
    return pose


def reflected() -> np.ndarray:
    pose = GRASP.copy()
    pose[0, 0] = -1.0
    return pose


def bad_last_row() -> np.ndarray:
    pose = GRASP.copy()
    pose[3] = [1.0, 0.0, 0.0, 1.0]
    return pose


def test_run_trial_refuses_an_unknown_grasp_frame() -> None:
    refused(
        lambda: simgrasp.run_trial("gen_hammer", grasp=GRASP, grasp_frame="camera"),  # type: ignore[arg-type]
        "grasp_frame: 'camera' is not one of world, object",
    )


@pytest.mark.parametrize(
    ("grasp", "message"),
    [
        (scaled(2.0), "grasp: rotation is not orthonormal"),
        (reflected(), "grasp: rotation is a reflection"),
        (bad_last_row(), "grasp: last row [1.0, 0.0, 0.0, 1.0] is not [0 0 0 1]"),
        ([0, 0, 0.3, 2, 0, 0, 0], "grasp: quaternion norm 2 is not 1"),
        ("identity", "grasp must be a (4, 4) transform or a 7-vector"),
    ],
)
def test_run_trial_refuses_a_grasp_that_is_no_rigid_pose(grasp: Any, message: str) -> None:
    refused(lambda: simgrasp.run_trial("gen_hammer", grasp=grasp), message)


def test_run_trial_refuses_a_width_that_is_no_number() -> None:
    refused(
        lambda: simgrasp.run_trial("gen_hammer", grasp=GRASP, width="wide"),  # type: ignore[arg-type]
        "width must be a number (m), got str",
    )


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: simgrasp.run_trial("gen_hammer", grasp=GRASP, config=simgrasp.TrialConfig()),  # type: ignore[arg-type]
            "config must be a ChainConfig, got TrialConfig",
        ),
        (
            lambda: simgrasp.label_grasps("gen_hammer", GRASP[None], config=simgrasp.ChainConfig()),  # type: ignore[arg-type]
            "config must be a LabelConfig, got ChainConfig",
        ),
        (
            lambda: simgrasp.detect_handles(np.zeros((10, 3)), config=simgrasp.ChainConfig()),  # type: ignore[arg-type]
            "config must be a DetectorConfig, QuadricDetectorConfig or TenPasConfig, "
            "got ChainConfig",
        ),
        (
            lambda: simgrasp.detect_handles(np.zeros((10, 3)), config="quadric"),  # type: ignore[arg-type]
            "config must be a DetectorConfig, QuadricDetectorConfig or TenPasConfig, got str",
        ),
        (
            lambda: simgrasp.segment_scene(np.zeros((10, 3)), {"max_range": 2}),  # type: ignore[arg-type]
            "config must be a SegmentConfig, got dict",
        ),
        (
            lambda: simgrasp.segment_scene("scene.png", depth={"intrinsics": (60, 60, 32, 24)}),  # type: ignore[arg-type]
            "depth must be a DepthImageConfig, got dict",
        ),
    ],
)
def test_a_config_of_the_wrong_type_is_named(call: Callable[[], Any], message: str) -> None:
    refused(call, message)


def test_label_grasps_refuses_an_object_that_is_no_name() -> None:
    refused(
        lambda: simgrasp.label_grasps(5, GRASP[None]),  # type: ignore[arg-type]
        "obj must be an object name (str), got int",
    )


@pytest.mark.parametrize("count", [2.5, float("nan"), "3", None, 0, True])
def test_sample_grasps_refuses_a_count_that_is_no_positive_integer(count: Any) -> None:
    refused(
        lambda: simgrasp.sample_grasps("gen_hammer", count),
        f"count must be a positive integer, got {count!r}",
    )


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: simgrasp.segment_scene("scene.npy", viewpoint=[0, 0, 5]),
            "viewpoint is for an array scene; a file's viewpoint is its own",
        ),
        (
            lambda: simgrasp.segment_scene(np.zeros((10, 3)), viewpoint=[0, 0]),
            "viewpoint must be 3 finite coordinates (m), got [0.0, 0.0]",
        ),
        (
            lambda: simgrasp.segment_scene(np.zeros((10, 3)), viewpoint=[np.nan, 0, 0]),
            "viewpoint must be 3 finite coordinates (m), got [nan, 0.0, 0.0]",
        ),
        (
            lambda: simgrasp.segment_scene([["a", "b", "c"]]),
            "scene must be a scene file path or an (N, 3) or (H, W, 3) array, got list",
        ),
        (
            lambda: simgrasp.segment_scene(
                np.zeros((10, 3)), depth=simgrasp.DepthImageConfig(intrinsics=(1, 1, 1, 1))
            ),
            "depth is for a depth image file, not an array scene",
        ),
    ],
)
def test_segment_scene_refuses_arguments_that_do_not_fit_the_scene(
    call: Callable[[], Any], message: str
) -> None:
    refused(call, message)


def test_detect_handles_reads_a_file_name_and_refuses_a_missing_one() -> None:
    refused(lambda: simgrasp.detect_handles("cloud.npy"), "cloud.npy: no such point-cloud file")
    refused(
        lambda: simgrasp.detect_handles("cloud.npy", np.zeros((3, 3))),
        "normals come from the file when points is a file",
    )


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("nope_obj", "objects: unknown YCB object 'nope_obj'"),
        ("gen_hamer", "objects: unknown generated object 'gen_hamer'"),
        ("/nonexistent/mug.obj?units=mm", "objects: object mesh /nonexistent/mug.obj does not"),
    ],
)
def test_env_refuses_an_unknown_object_when_made(name: str, message: str) -> None:
    refused(
        lambda: gymnasium.make("simgrasp:simgrasp/HandleGrasp-v0", objects=("gen_hammer", name)),
        message,
    )


def test_env_names_an_action_that_is_no_numbers() -> None:
    refused(
        lambda: grasp_from_action("grasp", 0.08),
        "invalid action 'grasp': expected 8 finite numbers [x, y, z, qw, qx, qy, qz, width]",
    )
