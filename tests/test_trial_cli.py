"""`simgrasp trial` end to end (real object model, MuJoCo and EGL rendering)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image
from test_trial import handle_grasp

from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.cli import main
from simgrasp.cli.trial import _print_summary
from simgrasp.evaluation.sweep import TrialSpec, run_spec
from simgrasp.grasping.trials.chain import ChainResult
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.key_frames import write_frames
from simgrasp.scenes.render import select_backend
from simgrasp.scenes.scene import build_scene
from simgrasp.transforms import matrix_to_pose7


def handle_grasp_object_frame(seed: int) -> list[str]:
    """The top-down handle grasp of test_trial for gen_hammer, expressed in the object frame
    (the CLI builds the same seeded scene, so it maps it back to the same world pose)."""
    model = build_object_model(load_object("gen_hammer"))
    scene = build_scene(model, make_gripper("builtin"), seed=seed)
    object_T_tcp = handle_grasp(scene).object_T_tcp(scene.world_T_object)
    return [f"{v:.12f}" for v in matrix_to_pose7(object_T_tcp)]


def test_trial_json_in_object_frame(tmp_path) -> None:
    """Run as a fresh process: the CLI picks the GL platform before mujoco is imported."""
    pose = handle_grasp_object_frame(seed=1)
    out_png = tmp_path / "trial.png"
    argv = ["trial", "gen_hammer", "--seed", "1", "--grasp", *pose, "--grasp-frame", "object"]
    done = subprocess.run(
        [sys.executable, "-m", "simgrasp", *argv, "--json", "--render", str(out_png)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    record = json.loads(done.stdout)
    for key in ("object", "object_pose", "grasp", "success", "on_handle", "failure"):
        assert key in record
    assert len(record["object_pose"]) == 7 and len(record["grasp"]) == 7
    assert record["success"] is True and record["on_handle"] is True
    assert record["lift_height"] > 0.1
    assert record["timings_s"]["total"] > 0
    image = np.asarray(Image.open(out_png))
    assert image.shape == (960, 1280, 3)  # 2 x 2 grid of 640 x 480 key frames
    assert image.std() > 10  # not a blank picture


def test_unknown_object_and_bad_width_are_clear_errors(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["trial", "no_such_thing"]) == 2
    assert "unknown YCB object 'no_such_thing'" in capsys.readouterr().err
    assert (
        main(
            [
                "trial",
                "gen_hammer",
                "--width",
                "0.5",
                "--grasp",
                "0",
                "0",
                "0.1",
                "1",
                "0",
                "0",
                "0",
            ]
        )
        == 2
    )
    assert "--width must be in (0, 0.085]" in capsys.readouterr().err


def test_trial_rejects_a_fifth_camera(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["trial", "gen_mug", "--views", "5"]) == 2
    assert "scene.num_views: 5 is not one of 1, 2, 3, 4" in capsys.readouterr().err


def test_trial_rejects_bad_render_suffix(capsys: pytest.CaptureFixture[str]) -> None:
    pose = ["0", "0", "0.02", "0", "1", "0", "0"]
    assert main(["trial", "gen_hammer", "--grasp", *pose, "--render", "x.gif"]) == 2
    assert ".png or .mp4" in capsys.readouterr().err


@pytest.mark.parametrize("placement", ["stable", "upright"])
def test_placement_sets_how_the_mug_rests(placement: str, capsys) -> None:
    """Seed 0's generated mug lies on its side when dropped; upright it stands on its base."""
    away = ["0.3", "0.3", "0.2", "0", "1", "0", "0"]  # a top-down grasp far from the mug
    argv = ["trial", "gen_mug", "--seed", "0", "--placement", placement, "--grasp", *away]
    assert main([*argv, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["failure"] == "missed"
    qw, qx, qy, qz = record["object_pose"][3:]
    object_z_up = 1 - 2 * (qx**2 + qy**2)  # world z component of the object's +z axis
    if placement == "upright":
        assert object_z_up > 0.99
    else:
        assert abs(object_z_up) < 0.5


def test_a_chain_without_a_grasp_is_reported_not_a_crash(tmp_path, capsys) -> None:
    """The chain's record when it finds no collision-free grasp (no trial ran): the summary
    shows the detection instead of trial fields, and --render writes nothing."""
    result = ChainResult(
        object="gen_mug",
        detector="quadric",
        gripper="builtin",
        noise=0.0,
        seed=3,
        cloud_points=4632,
        candidates=36,
        handles=1,
        detection_accuracy=1.0,
        handle_recall=True,
        grasp_candidates=0,
        trial=None,
        timings_s={},
    )
    record = result.to_json()
    record["render"] = write_frames([], tmp_path / "frames.png")
    assert record["render"] is None and not (tmp_path / "frames.png").exists()
    _print_summary(record)
    out = capsys.readouterr().out
    assert "failed (no_grasp)" in out
    assert "1 handle(s) from 36 candidates on 4632 cloud points; 0 collision-free" in out
    assert "none: no grasp was executed" in out
    assert "lift height" not in out


def test_trial_reruns_the_evaluate_record_of_the_same_object_and_seed(capsys) -> None:
    """A sweep record (object, seed) is rerun by `simgrasp trial OBJECT --seed SEED`: a
    generated tool keeps its seed-0 sizes in both, only the scene and the chain take the seed."""
    spec = TrialSpec("gen_mug", 3, ChainConfig())
    swept = run_spec(spec, None)
    assert main(["trial", "gen_mug", "--seed", "3", "--json"]) == 0
    rerun = json.loads(capsys.readouterr().out)
    assert rerun["object"] == swept["object_asset"] == "gen_mug_s0"
    for key in ("failure", "success", "on_handle", "candidates", "handles", "object_pose"):
        assert rerun[key] == swept[key], key
    assert rerun["render_backend"] == select_backend()  # as evaluate's defaults.json has it


@pytest.mark.parametrize("blocker", ["file", "dir"])
def test_an_unwritable_render_target_is_refused_before_the_trial(
    tmp_path, capsys, blocker: str
) -> None:
    """Its directory is a file, or the target is a directory: refused before the scene is built,
    so a --json run prints an error line, not a record after a traceback."""
    pose = ["0.3", "0.3", "0.2", "0", "1", "0", "0"]
    if blocker == "file":
        (tmp_path / "a_file").write_text("x")
        target = tmp_path / "a_file" / "frames.png"
    else:
        target = tmp_path / "frames.png"
        target.mkdir()
    argv = ["trial", "gen_hammer", "--grasp", *pose, "--json", "--render", str(target)]
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"--render {target}" in captured.err
    assert ("is a file, not a directory" if blocker == "file" else "not writable") in captured.err


def test_width_without_grasp_is_an_error(capsys) -> None:
    assert main(["trial", "gen_hammer", "--width", "0.05"]) == 2
    assert "--width needs --grasp" in capsys.readouterr().err
