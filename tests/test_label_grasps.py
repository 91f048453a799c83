"""label-grasps on a generated hammer (real MuJoCo): known labels, equality with
``simgrasp trial --grasp``, resume after SIGKILL of a real process, refusal to mix runs."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_trial import handle_grasp, head_point, top_down_grasp

from simgrasp.assets.model import model_for
from simgrasp.cli import main
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.labeling.grasp_sets import GraspSet, read_grasp_set, write_grasp_set
from simgrasp.grasping.labeling.label_run import LABELS_FILE, label_grasp_set, run_identity
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig, label_grasps
from simgrasp.transforms import matrix_to_pose7

OBJECT, SEED = "gen_hammer_s1", 3
"""The hammer and scene of tests/test_trial.py (``load_object("gen_hammer", seed=1)``)."""


@pytest.fixture(scope="module")
def labeler() -> GraspLabeler:
    return GraspLabeler(model_for(OBJECT), LabelConfig(OBJECT, seed=SEED))


def in_object_frame(labeler: GraspLabeler, grasp: Grasp) -> np.ndarray:
    return grasp.object_T_tcp(labeler.scene.world_T_object)


@pytest.fixture(scope="module")
def known_set(labeler: GraspLabeler, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Handle grasp (held, on handle), head grasp (held, off handle), a grasp 12 cm beside the
    hammer (missed) and a NaN row (invalid)."""
    scene = labeler.scene
    point, axis, _ = head_point(scene)
    head = top_down_grasp(scene, point, np.cross([0.0, 0.0, 1.0], axis))
    handle = handle_grasp(scene)
    beside = handle.world_T_tcp.copy()
    mesh_world = scene.object_model.asset.mesh.copy().apply_transform(scene.world_T_object)
    beside[:2, 3] = [mesh_world.bounds[1, 0] + 0.12, 0.0]
    grasps = [handle, head, Grasp(beside, handle.width)]
    matrices = [in_object_frame(labeler, g) for g in grasps] + [np.full((4, 4), np.nan)]
    widths = [g.width for g in grasps] + [0.05]
    return write_grasp_set(tmp_path_factory.mktemp("sets") / "known.npz", matrices, widths)


@pytest.mark.parametrize("protocol", ["full", "fast"])
def test_known_grasps_get_the_expected_labels(known_set: Path, tmp_path: Path, protocol) -> None:
    config = LabelConfig(OBJECT, protocol=protocol, seed=SEED)
    summary, records = label_grasp_set(
        read_grasp_set(known_set), config, tmp_path, grasp_file=known_set, progress=False
    )
    labels = np.load(tmp_path / "labels.npz")
    assert labels["success"].tolist() == [True, True, False, False]
    assert labels["on_handle"].tolist() == [True, False, False, False]
    assert labels["failure"].tolist() == ["", "", "missed", "invalid"]
    assert [r["index"] for r in records] == [0, 1, 2, 3]
    assert "non-finite" in records[3]["problem"]
    assert summary["success_on_handle"] == 1 and summary["success_off_handle"] == 1
    assert summary["invalid"] == 1 and summary["scored"] == 3
    assert summary["handle_source"] == ["shipped"]
    lines = (tmp_path / LABELS_FILE).read_text().splitlines()
    assert sorted(json.loads(line)["index"] for line in lines) == [0, 1, 2, 3]


def test_label_grasps_in_memory_equals_the_on_disk_run(known_set: Path, tmp_path: Path) -> None:
    """label_grasps on the file's arrays (no file, no directory) gives the labels and records
    of the resumable on-disk run of the file, the invalid row reported by its index."""
    config = LabelConfig(OBJECT, protocol="fast", seed=SEED)
    _, on_disk = label_grasp_set(
        read_grasp_set(known_set), config, tmp_path, grasp_file=known_set, progress=False
    )
    with np.load(known_set) as arrays:
        matrices, widths = arrays["object_T_grasp"], arrays["width"]
    result = label_grasps(OBJECT, GraspSet.from_arrays(matrices, widths), config=config)
    labels = np.load(tmp_path / "labels.npz")
    for name in ("success", "on_handle", "failure", "handle_fraction", "lift_height"):
        np.testing.assert_array_equal(getattr(result, name), labels[name], err_msg=name)
    assert result.failure.tolist() == ["", "", "missed", "invalid"]
    in_memory = [json.loads(json.dumps(r)) for r in result.records]
    for record in (*in_memory, *on_disk):
        record.pop("timings_s", None)
    assert in_memory == on_disk
    bare = label_grasps(OBJECT, matrices[:1], config=config)  # an array: fully open jaws
    assert bare.records[0]["index"] == 0 and len(bare.success) == 1
    with pytest.raises(ValueError, match="config labels 'gen_hammer_s1', not 'gen_mug'"):
        label_grasps("gen_mug", matrices, config=config)


@pytest.mark.parametrize(("gripper", "protocol"), [("builtin", None), ("franka_panda", "acronym")])
def test_label_equals_trial_grasp(
    labeler: GraspLabeler, tmp_path: Path, capsys, gripper: str, protocol: str | None
) -> None:
    """A grasp's label is the record of `simgrasp trial --grasp` of the same object, gripper,
    protocol and seed (the full protocol: trial's default; the acronym one: free-floating, the
    object-frame grasp placed at the raised object in both)."""
    pose = matrix_to_pose7(in_object_frame(labeler, handle_grasp(labeler.scene))).tolist()
    width = 0.07
    path = tmp_path / "one.json"
    path.write_text(json.dumps({"poses": [pose], "width": [width]}))
    config = LabelConfig(OBJECT, gripper, protocol or "full", seed=SEED)
    _, (label,) = label_grasp_set(
        read_grasp_set(path), config, tmp_path / "out", grasp_file=path, progress=False
    )
    argv = ["trial", OBJECT, "--seed", str(SEED), "--grasp-frame", "object", "--gripper", gripper]
    argv += ["--protocol", protocol] if protocol else []
    exact = [np.format_float_positional(v) for v in pose]  # round-trips; no exponent for argparse
    argv += ["--width", repr(width), "--json", "--grasp", *exact]
    capsys.readouterr()
    assert main(argv) == 0
    trial = json.loads(capsys.readouterr().out)
    for record in (label, trial):
        for key in ("timings_s", "grasp_source", "index", "protocol"):
            record.pop(key, None)
    assert label == trial
    assert label["success"] is True


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--protocol", "fast"], "--protocol needs --grasp (the full chain runs the --trial.* "
         "settings)"),
        (["--protocol", "fast", "--trial.hold-time", "2", "--grasp", "0", "0", "0.1", "1", "0",
          "0", "0"], "give --protocol or --trial.* settings, not both"),
    ],
)  # fmt: skip
def test_trial_protocol_refusals(capsys, extra: list[str], message: str) -> None:
    assert main(["trial", OBJECT, *extra]) == 2
    assert capsys.readouterr().err.strip() == f"simgrasp trial: error: {message}"


def test_another_run_into_the_same_directory_is_refused(known_set: Path, tmp_path: Path) -> None:
    grasps = read_grasp_set(known_set)
    first = LabelConfig(OBJECT, protocol="fast", seed=SEED)
    label_grasp_set(grasps, first, tmp_path, grasp_file=known_set, progress=False)
    other = LabelConfig(OBJECT, protocol="full", seed=SEED)
    with pytest.raises(ValueError, match="another run.*protocol"):
        label_grasp_set(grasps, other, tmp_path, grasp_file=known_set, progress=False)


def test_a_run_of_an_older_protocol_definition_is_refused(known_set: Path, tmp_path: Path) -> None:
    """run.json holds the protocol's trial settings: labels made before the definition of
    ``fast`` changed are not mixed with new ones."""
    grasps = read_grasp_set(known_set)
    config = LabelConfig(OBJECT, protocol="fast", seed=SEED)
    label_grasp_set(grasps, config, tmp_path, grasp_file=known_set, progress=False)
    run = json.loads((tmp_path / "run.json").read_text())
    assert run["trial"]["quiet_speed"] == config.trial.quiet_speed
    run["trial"]["hold_time"] = 1.0
    (tmp_path / "run.json").write_text(json.dumps(run))
    with pytest.raises(ValueError, match="another run.*trial.hold_time: 1.0 -> "):
        label_grasp_set(grasps, config, tmp_path, grasp_file=known_set, progress=False)


def test_a_run_goes_on_over_more_of_the_same_grasps(known_set: Path, tmp_path: Path) -> None:
    """Labels are per grasp index: labeling the first two grasps, then all four, labels only
    the last two (the first two are kept, not done again); back to two labels nothing."""
    grasps = read_grasp_set(known_set)
    config = LabelConfig(OBJECT, protocol="fast", seed=SEED)
    first_two = GraspSet(grasps.object_T_tcp[:2], grasps.width[:2], {}, grasps.fmt)
    summary, _ = label_grasp_set(first_two, config, tmp_path, grasp_file=known_set, progress=False)
    assert summary["labeled_this_run"] == 2
    summary, records = label_grasp_set(
        grasps, config, tmp_path, grasp_file=known_set, progress=False
    )
    assert summary["labeled_this_run"] == 1  # grasp 3 is the invalid NaN row: not executed
    assert [r["index"] for r in records] == [0, 1, 2, 3]
    assert json.loads((tmp_path / "run.json").read_text())["count"] == 4
    summary, _ = label_grasp_set(first_two, config, tmp_path, grasp_file=known_set, progress=False)
    assert summary["labeled_this_run"] == 0


def test_only_acronym_runs_name_their_soft_friction_and_integrator(known_set: Path) -> None:
    """run.json of an ``acronym`` run holds its ``impratio`` (0.45), finger ``solimp`` width
    (7 mm) and ``integrator`` (discrete), so a directory labeled with other physics is refused;
    the other protocols' values are those every run had before the settings existed, left out
    so their directories still resume."""
    grasps = read_grasp_set(known_set)
    trials = {
        protocol: run_identity(grasps, LabelConfig(OBJECT, protocol=protocol), known_set)["trial"]
        for protocol in ("acronym", "acronym-fast", "fast", "full")
    }
    for protocol in ("acronym", "acronym-fast"):
        physics = (
            trials[protocol]["impratio"],
            trials[protocol]["finger_solimp_width"],
            trials[protocol]["integrator"],
        )
        assert physics == (0.45, 0.007, "discrete")
    for protocol in ("fast", "full"):
        for setting in ("impratio", "integrator", "finger_solimp_width"):
            assert setting not in trials[protocol]


def test_resume_after_sigkill(labeler: GraspLabeler, tmp_path: Path) -> None:
    """Kill -9 a real label-grasps process mid-run; the rerun labels only the missing grasps
    and every grasp ends with exactly one record."""
    handle = handle_grasp(labeler.scene)
    count = 30
    matrices = []
    for offset in np.linspace(-0.03, 0.03, count):
        world_T_tcp = handle.world_T_tcp.copy()
        world_T_tcp[:3, 3] += offset * world_T_tcp[:3, 0]
        matrices.append(in_object_frame(labeler, Grasp(world_T_tcp, handle.width)))
    grasp_file = write_grasp_set(tmp_path / "set.npz", matrices, [handle.width] * count)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "simgrasp", "label-grasps", OBJECT, "--seed", str(SEED)]
    command += ["--grasps", str(grasp_file), "--out", str(out), "--protocol", "fast"]
    command += ["--no-picture"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    log = out / LABELS_FILE
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and process.poll() is None:
        if log.exists() and log.read_bytes().count(b"\n") >= 3:
            break
        time.sleep(0.05)
    assert process.poll() is None, "label-grasps ended before it could be killed"
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    before = log.read_bytes().count(b"\n")
    assert 3 <= before < count
    done = subprocess.run(command, capture_output=True, text=True, check=False, timeout=600)
    assert done.returncode == 0, done.stderr
    indices = [json.loads(line)["index"] for line in log.read_text().splitlines()]
    assert sorted(indices) == list(range(count))
    summary = json.loads((out / "summary.json").read_text())
    assert summary["labeled_this_run"] == count - before
    assert np.load(out / "labels.npz")["success"].shape == (count,)


def test_free_floating_labels(known_set: Path, tmp_path: Path) -> None:
    """In free space (ACRONYM-style) the handle and head grasps hold the hammer against its
    weight and the tugs; the grasp beside it closes on nothing."""
    config = LabelConfig(OBJECT, protocol="fast", seed=SEED, free_floating=True)
    _, records = label_grasp_set(
        read_grasp_set(known_set), config, tmp_path, grasp_file=known_set, progress=False
    )
    assert [r["failure"] for r in records] == [None, None, "missed", "invalid"]
    assert [r["on_handle"] for r in records] == [True, False, False, False]
    assert records[0]["object_pose"][2] > 0.4  # started in the air
    assert records[0]["lift_height"] < 0.0  # sagged a little under its weight, still held


def test_labels_picture_is_the_same_from_run_to_run(tmp_path: Path) -> None:
    """The labels picture's surface points come from a seeded draw: two pictures of the same
    records are the same bytes (the surface was an unseeded trimesh sample)."""
    import trimesh

    from simgrasp.plots.grasp_labels import plot_labels

    mesh = trimesh.creation.box((0.04, 0.06, 0.1))
    grasps = np.tile(np.eye(4), (2, 1, 1))
    records: list[dict[str, Any]] = [
        {"success": True, "failure": None, "on_handle": False},
        {"success": False, "failure": "missed", "on_handle": False},
    ]
    pictures = [
        plot_labels(mesh, grasps, np.full(2, 0.08), records, tmp_path / f"{i}.png", "box")
        for i in range(2)
    ]
    assert pictures[0].read_bytes() == pictures[1].read_bytes()
