"""Checked settings: a typo or an out-of-range value is refused however a config is built
(flags, --set, a TOML file, Python), in one line naming its dotted key; --help shows what each
setting allows; the proposer and sensor registries resolve without MuJoCo and take entries at
run time."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_parsers import command_parser

from simgrasp.cli import main
from simgrasp.config.checks import SettingError
from simgrasp.errors import SimgraspError
from simgrasp.grasping.cloud_view import CloudView
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.planner import GripperGeometry, top_down_above_table
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grasping.planning.proposal import Proposal, plan_grasps
from simgrasp.grasping.proposers import PROPOSERS, ProposerEntry
from simgrasp.grasping.trials.chain_config import ChainConfig, ChainDetectorConfig
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.scenes.config import SceneConfig

BAD = [
    # (dotted key, value as typed, what the message says about it)
    ("sensor.kind", "kinnect", "'kinnect' is not one of ideal, kinect, stereo"),
    ("detector.kind", "quadratic", "'quadratic' is not one of quadric, tenpas, centroid, random"),
    ("scene.placement", "sideways", "'sideways' is not one of stable, upright"),
    ("noise", "1.5", "1.5 is not in [0, 1)"),
    ("detector.quadric.voxel_size", "-0.001", "-0.001 is not >= 0"),
    ("planner.max_handles", "0", "0 is not >= 1"),
    ("trial.timestep", "0", "0.0 is not > 0"),
    ("sensor.kinect.edge_dropout", "2", "2.0 is not in [0, 1]"),
    ("scene.num_views", "9", "9 is not one of 1, 2, 3, 4"),
]
IDS = [key for key, _, _ in BAD]


def _refused(argv: list[str], key: str, detail: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == f"simgrasp {argv[0]}: error: {key}: {detail}\n", err


@pytest.mark.parametrize(("key", "value", "detail"), BAD, ids=IDS)
def test_a_bad_flag_is_refused_naming_its_key(key, value, detail, capsys) -> None:
    flag = "--" + key.replace("_", "-")
    _refused(["trial", "gen_mug", flag, value, "--print-config"], key, detail, capsys)


@pytest.mark.parametrize(("key", "value", "detail"), BAD, ids=IDS)
def test_a_bad_set_item_is_refused_naming_its_key(key, value, detail, capsys) -> None:
    _refused(["trial", "gen_mug", "--set", f"{key}={value}", "--print-config"], key, detail, capsys)


@pytest.mark.parametrize(("key", "value", "detail"), BAD, ids=IDS)
def test_a_bad_toml_value_is_refused_naming_its_key(
    key, value, detail, tmp_path: Path, capsys
) -> None:
    *table, name = key.split(".")
    text = value if re.fullmatch(r"-?[\d.]+", value) else f"'{value}'"
    header = f"[{'.'.join(table)}]\n" if table else ""
    path = tmp_path / "run.toml"
    path.write_text(f"{header}{name} = {text}\n")
    _refused(["trial", "gen_mug", "--config", str(path), "--print-config"], key, detail, capsys)


@pytest.mark.parametrize(("key", "value", "detail"), BAD, ids=IDS)
def test_a_bad_python_value_is_refused_naming_its_key(key, value, detail) -> None:
    typed: object = value
    if re.fullmatch(r"-?[\d.]+", value):
        integer = key in ("planner.max_handles", "scene.num_views")
        typed = int(value) if integer else float(value)
    with pytest.raises(SettingError) as caught:
        ChainConfig.of(**{key.replace(".", "__"): typed})
    assert str(caught.value) == f"{key}: {detail}"


def test_a_config_made_directly_names_its_class_and_field() -> None:
    with pytest.raises(SettingError, match=r"^SensorSettings.kind: 'kinnect' is not one of"):
        SensorSettings(kind="kinnect")
    with pytest.raises(SettingError, match=r"^SegmentConfig.plane_distance: -1 is not > 0$"):
        SegmentConfig(plane_distance=-1)
    with pytest.raises(SettingError, match=r"^SegmentConfig.plane_samples: 2.5 is not an integer"):
        SegmentConfig(plane_samples=2.5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: TrialConfig(free_floating="no"), "TrialConfig.free_floating: 'no' is not true"),  # type: ignore[arg-type]
        (
            lambda: SceneConfig(table_half_size=(1.0,)),  # type: ignore[arg-type]
            "table_half_size: (1.0,) has 1 values, not 3",
        ),
        (lambda: SceneConfig(table_half_size="big"), "table_half_size: 'big' is not a sequence"),  # type: ignore[arg-type]
        (lambda: SceneConfig(table_top_z=float("nan")), "SceneConfig.table_top_z: nan is not a"),
        (lambda: TrialConfig(hold_time="2"), "TrialConfig.hold_time: '2' is not a number"),  # type: ignore[arg-type]
        (lambda: ChainConfig(sensor="kinect"), "ChainConfig.sensor: 'kinect' is not a SensorSet"),  # type: ignore[arg-type]
        (lambda: SensorSettings(kind=None), "SensorSettings.kind: None is not"),  # type: ignore[arg-type]
    ],
    ids=["bool", "length", "text-tuple", "nan", "text-number", "nested", "none"],
)
def test_a_field_of_the_wrong_type_is_refused_when_made_directly(make, message) -> None:  # noqa: ANN001
    """Plain Python skips the flags' parsing: a truthy string for a bool, a short tuple, text
    for a number or a nested config would otherwise be kept and fail deep in a trial."""
    with pytest.raises(SettingError) as caught:
        make()
    assert message in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["segment", "s.pcd", "--set", "segment.plane_distance=-1"], "segment.plane_distance:"),
        (["evaluate", "--out", "o", "--workers", "0"], "workers: 0 is not >= 1"),
        (["evaluate", "--out", "o", "--sensor", "ideal,lidar"], "sensor: 'lidar' is not one of"),
        (["evaluate", "--out", "o", "--noise", "0,1.5"], "noise: 1.5 is not in [0, 1)"),
        (["detect-eval", "--seeds", "0"], "seeds: 0 is not >= 1"),
        (["label-grasps", "gen_mug", "--grasps", "g.npz", "--seed", "-1"], "seed: -1 is not >= 0"),
        (["detect", "c.npy", "--detector.tenpas.min-shells", "0"], "detector.tenpas.min_shells:"),
    ],
    ids=["segment", "workers", "sensors", "noises", "detect-eval", "label", "detect"],
)
def test_every_command_checks_its_tree(argv, message, capsys) -> None:
    assert main([*argv, "--print-config"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_the_env_config_is_checked() -> None:
    from simgrasp.envs.handle_grasp import HandleGraspConfig

    with pytest.raises(SettingError, match=r"^HandleGraspConfig.noise: 2 is not in \[0, 1\)$"):
        HandleGraspConfig(noise=2)
    with pytest.raises(SettingError, match="HandleGraspConfig.gripper: 'parallel' is not one of"):
        HandleGraspConfig(gripper="parallel")


def test_the_command_line_refuses_in_one_line_without_a_traceback() -> None:
    argv = ["-m", "simgrasp", "trial", "gen_hammer", "--set", "sensor.kind=kinnect"]
    done = subprocess.run([sys.executable, *argv], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == (
        "simgrasp trial: error: sensor.kind: 'kinnect' is not one of ideal, kinect, stereo\n"
    )


def test_help_shows_what_each_setting_allows() -> None:
    sub = command_parser("trial")
    text = re.sub(r"\s+", " ", sub.format_help())
    assert "--sensor.kind {ideal,kinect,stereo}, --sensor {ideal,kinect,stereo}" in text
    assert "(str: one of ideal, kinect, stereo; default: ideal)" in text
    assert "(float: in [0, 1); default: 0.0)" in text  # noise
    assert "(float: > 0; default: 0.002)" in text  # trial.timestep
    assert "(int: >= 1; default: 3)" in text  # planner.max_handles
    assert "one of quadric, tenpas, centroid, random" in text


def test_registries_resolve_every_entry_without_importing_mujoco() -> None:
    code = (
        "import sys\n"
        "from simgrasp.grasping.proposers import PROPOSERS\n"
        "from simgrasp.perception.sensors.registry import SENSOR_MODELS\n"
        "from simgrasp.grippers.registry import GRIPPERS\n"
        "assert 'mujoco' not in sys.modules\n"
        "functions = [e.load() for e in PROPOSERS.values()]\n"
        "classes = [e.config_class() for e in SENSOR_MODELS.values()]\n"
        "models = [e.model_function() for e in SENSOR_MODELS.values()]\n"
        "assert all(map(callable, functions + classes + models))\n"
        "assert [c.name for c in classes] == list(SENSOR_MODELS)\n"
        "print(len(functions), len(classes), 'mujoco' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["4", "3", "False"]


def propose_topmost(
    view: CloudView,
    geometry: GripperGeometry,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> Proposal:
    """A toy proposer: a top-down grasp at the cloud's highest point."""
    top = view.points_world[view.points_world[:, 2].argmax()]
    pose = top_down_above_table(top, (0.0, 1.0, 0.0), geometry, view.table_top_z, planner)
    return [Grasp(pose, geometry.max_opening, score=1.0, source="topmost")], None


def test_a_proposer_registered_at_run_time_is_a_choice_and_plans(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    entry = ProposerEntry("topmost", f"{__name__}:propose_topmost", "toy: the topmost point")
    with pytest.raises(SettingError, match="'topmost' is not one of"):
        ChainConfig.of(detector__kind="topmost")
    monkeypatch.setitem(PROPOSERS, "topmost", entry)
    config = ChainConfig.of(detector__kind="topmost")
    rng = np.random.default_rng(0)
    points = rng.uniform(-0.03, 0.03, (200, 3)) + [0.0, 0.0, 0.05]
    view = CloudView(points, np.tile([0.0, 0.0, 1.0], (200, 1)), np.array([[0, 0, 1.0]]), 0.0)
    geometry = make_gripper("builtin").planning_geometry()
    grasps, detection = plan_grasps(view, geometry, config.detector, config.planner, 0)
    assert detection is None and [g.source for g in grasps] == ["topmost"]
    top = points[points[:, 2].argmax()]
    assert np.allclose(grasps[0].world_T_tcp[:2, 3], top[:2])
    assert grasps[0].world_T_tcp[2, 3] >= top[2] - 1e-9


def test_an_unknown_proposer_or_sensor_is_no_silent_fallback() -> None:
    from simgrasp.perception.sensors import sensor_config

    with pytest.raises(SimgraspError, match="unknown sensor 'lidar'"):
        sensor_config("lidar")
    assert type(SensorSettings(kind="stereo").model()).__name__ == "StereoConfig"


def test_detect_and_trial_detector_defaults_differ_by_the_stated_fine_pass_only() -> None:
    """``detect`` keeps the plain defaults and ``trial`` adds a fine pass; both say so."""
    from dataclasses import replace

    from simgrasp.handles.detector_config import DetectorConfig

    chain, plain = ChainConfig().detector.quadric, DetectorConfig().quadric
    assert chain != plain and replace(chain, fine_half_size=0.0) == plain
    for command in ("detect", "trial"):
        sub = command_parser(command)
        text = re.sub(r"\s+", " ", sub.format_help())
        assert "--detector.quadric.fine-half-size" in text and "0.012" in text
        assert "Detector defaults" in text or "chain default" in text
