"""Grasp files that carry their object (ACRONYM, GraspGen), the Franka hand and the ACRONYM
protocol. Real MuJoCo trials; the ACRONYM file tests need ``SIMGRASP_ACRONYM_DIR``."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest
import trimesh
from data_needs import require_data
from PIL import Image

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import model_for
from simgrasp.cli import main
from simgrasp.grasping.labeling.grasp_files import carried_object
from simgrasp.grasping.labeling.grasp_sets import FRANKA_T_TCP, read_grasp_set
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig
from simgrasp.grasping.trials.protocol import PROTOCOLS
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers.mount import MOUNT_IMPRATIO

EXAMPLE = "examples/grasps/Mug_10f6e09036350e92b3f21f1137c3c347_0.0002682457830986903.h5"
ROOT = Path(__file__).parents[1]
OBJECT_T_TCP = np.array([[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, -1, 0.03], [0, 0, 0, 1.0]])
"""A top grasp of the box below: closing along its 4 cm side, the TCP 2 cm under its top."""


def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "simgrasp", *args]
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd)


def _graspgen_file(folder: Path, name: str, count: int, held: list[int] | None = None) -> Path:
    """A GraspGen file on a box mesh (``meshes/box.stl``), ``count`` copies of one grasp
    labeled ``held`` (default: all held)."""
    (folder / "meshes").mkdir(parents=True, exist_ok=True)
    trimesh.creation.box((0.04, 0.06, 0.10)).export(folder / "meshes" / "box.stl")
    hand = OBJECT_T_TCP @ np.linalg.inv(FRANKA_T_TCP)
    entries = {
        "object": {"file": "meshes/box.stl", "scale": 1.0},
        "grasps": {"transforms": [hand.tolist()] * count, "object_in_gripper": held or [1] * count},
    }
    (folder / "grasps").mkdir(exist_ok=True)
    path = folder / "grasps" / name
    path.write_text(json.dumps(entries))
    return path


def _box_labeler(folder: Path, protocol: str = "full") -> GraspLabeler:
    """The Franka hand's labeler of a 4 x 6 x 10 cm, 0.2 kg box (``folder/box.stl``) under
    ``protocol``."""
    box = folder / "box.stl"
    if not box.is_file():
        trimesh.creation.box((0.04, 0.06, 0.10)).export(box)
    name = f"{box}?mass=0.2"
    config = LabelConfig(object=name, gripper="franka_panda", protocol=protocol)
    return GraspLabeler(model_for(name), config)


def test_franka_hand_holds_a_box_on_the_table(tmp_path: Path) -> None:
    labeler = _box_labeler(tmp_path)
    world_T_object = labeler.world_T_object
    axis = world_T_object[:3, 0]  # the box's 4 cm side, horizontal in its rest pose
    down = np.array([0.0, 0.0, -1.0])
    y = axis - (axis @ down) * down
    y /= np.linalg.norm(y)
    world_T_tcp = np.eye(4)
    world_T_tcp[:3, :3] = np.stack([np.cross(y, down), y, down], axis=1)
    top = world_T_object[2, 3] + np.abs(world_T_object[:3, :3].T @ [0, 0, 1]) @ [0.02, 0.03, 0.05]
    world_T_tcp[:3, 3] = [world_T_object[0, 3], world_T_object[1, 3], top - 0.02]
    record = labeler.label(0, np.linalg.inv(world_T_object) @ world_T_tcp, np.nan)
    assert record["success"] is True
    assert record["lift_height"] > 0.15


def _trial_physics(labeler: GraspLabeler) -> tuple[float, int, float]:
    """(impratio, integrator, the fingers' solimp width) the last trial ran with."""
    model = labeler.scene.model
    left, right = labeler.scene.gripper.finger_geoms
    widths = set(model.geom_solimp[list(left + right), 2].tolist())
    assert len(widths) == 1, widths
    return (model.opt.impratio, model.opt.integrator, widths.pop())


def test_each_protocol_runs_its_trials_with_its_friction_and_integrator(tmp_path: Path) -> None:
    """``acronym`` trials run with soft friction (``impratio`` 0.45), soft finger contacts (a
    7 mm ``solimp`` ramp) and the ``discrete`` integrator (FleX agreement on the held-out
    ACRONYM files in docs/results/acronym); the other protocols keep the mounted gripper's 10,
    the fingers' own 1 mm ramp and ``implicitfast``, in the same scene after an ``acronym``
    one."""
    seen = {}
    for protocol in ("acronym", "full"):
        labeler = _box_labeler(tmp_path, protocol)
        labeler.label(0, OBJECT_T_TCP, np.nan)
        seen[protocol] = _trial_physics(labeler)
        labeler.trial_config, labeler.phases = PROTOCOLS["full"].config, PROTOCOLS["full"].phases
        labeler.label(1, OBJECT_T_TCP, np.nan)
        seen[f"{protocol} then full"] = _trial_physics(labeler)
    soft = (0.45, mujoco.mjtIntegrator.mjINT_DISCRETE, 0.007)
    mounted = (10.0, mujoco.mjtIntegrator.mjINT_IMPLICITFAST, 0.001)
    expected = {"acronym": soft, "acronym then full": mounted, "full": mounted}
    assert seen == expected | {"full then full": mounted}
    assert TrialConfig().impratio == MOUNT_IMPRATIO == 10.0


def test_a_finger_touching_a_light_object_pushes_it_and_does_not_throw_it(tmp_path: Path) -> None:
    """A 15 g box grasped 2 cm off its middle, so one pad touches it when the jaws are told to
    close. Solving the contact before the fingers' damping (``implicitfast``), the finger's
    full force throws the box out of reach (``missed``); ``acronym``'s ``discrete`` integrator
    pushes it into the other finger, which holds it."""
    box = tmp_path / "box.stl"
    trimesh.creation.box((0.04, 0.06, 0.10)).export(box)
    name = f"{box}?mass=0.015"
    object_T_tcp = np.eye(4)
    object_T_tcp[:3, :3] = np.stack([[0, 1, 0], [1, 0, 0], [0, 0, -1]], axis=1)
    object_T_tcp[:3, 3] = [0.02, 0.0, 0.03]  # TCP y across the 4 cm side, one pad on a face
    outcomes = {}
    for integrator in ("discrete", "implicitfast"):
        config = LabelConfig(object=name, gripper="franka_panda", protocol="acronym")
        labeler = GraspLabeler(model_for(name), config)
        labeler.trial_config = replace(labeler.trial_config, integrator=integrator)
        record = labeler.label(0, object_T_tcp, np.nan)
        outcomes[integrator] = (record["success"], record["failure"])
    assert outcomes == {"discrete": (True, None), "implicitfast": (False, "missed")}


def test_graspgen_file_labels_without_object_and_exports(tmp_path: Path) -> None:
    grasp_file = _graspgen_file(tmp_path, "box.json", 2)
    assert read_grasp_set(grasp_file).fmt == "graspgen"
    carried = carried_object(grasp_file)
    assert carried is not None and carried.endswith("box.stl?scale=1.0")
    out = tmp_path / "out"
    done = _cli(
        "label-grasps",
        "--grasps",
        str(grasp_file),
        "--gripper",
        "franka_panda",
        "--protocol",
        "acronym",
        "--density",
        "500",
        "--no-picture",
        "--out",
        str(out),
        "--export",
        "graspgen",
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    exported = json.loads((out / "export" / "box.json").read_text())
    ours = exported["grasps"]["qualities"]["simgrasp"]
    assert ours["object_in_gripper"] == [1.0, 1.0]
    assert all(0 < s <= 1 for s in ours["score"])
    assert ours["on_handle"] == [0.0, 0.0]  # a box: its automatic label is empty
    with np.load(out / "labels.npz") as labels:
        assert labels["score"].tolist() == ours["score"]


def test_disagreements_are_replayed_with_pictures(tmp_path: Path) -> None:
    grasp_file = _graspgen_file(tmp_path, "box.json", 3, held=[0, 1, 0])  # we hold all three
    out, examples = tmp_path / "out", tmp_path / "examples"
    labeled = _cli(
        "label-grasps", "--grasps", str(grasp_file), "--gripper", "franka_panda", "--protocol",
        "acronym", "--mass", "0.1", "--no-picture", "--out", str(out), cwd=tmp_path,
    )  # fmt: skip
    assert labeled.returncode == 0, labeled.stderr
    args = ("compare-labels", str(out), "--reference", str(grasp_file), "--examples")
    done = _cli(*args, str(examples), "--examples-per-kind", "1", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    (entry,) = json.loads((examples / "examples.json").read_text())
    assert entry["kind"] == "ours_held" and entry["index"] in (0, 2)
    assert entry["replay"] == "held" and entry["replay_matches"] is True
    picture = Image.open(examples / entry["picture"])
    assert picture.width > 2.5 * picture.height  # three key moments side by side
    wrong = _cli("compare-labels", str(out), str(out), "--examples", str(examples), cwd=tmp_path)
    assert wrong.returncode == 2 and "--examples needs --reference" in wrong.stderr


def test_labels_are_compared_only_with_their_own_grasp_file(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """compare-labels matches a label folder to a grasp file by the file's digest (run.json):
    labels of ``a.json`` are never scored against ``b.json``'s reference labels, nor against
    a run of ``b.json``; a run of a file's first grasp against one of both: that grasp."""
    a = _graspgen_file(tmp_path, "a.json", 2, held=[1, 0])
    b = _graspgen_file(tmp_path, "b.json", 2, held=[0, 0])
    label = ["label-grasps", "--gripper", "franka_panda", "--protocol", "acronym", "--mass", "0.1"]
    for grasp_file, count in ((a, "2"), (b, "2"), (a, "1")):
        out = tmp_path / f"{grasp_file.stem}{count}"
        args = [*label, "--grasps", str(grasp_file), "--max-grasps", count, "--out", str(out)]
        assert main([*args, "--no-picture"]) == 0
    capsys.readouterr()
    assert main(["compare-labels", str(tmp_path / "a2"), "--reference", str(b)]) == 2
    assert "no labels of b.json" in capsys.readouterr().err
    assert main(["compare-labels", str(tmp_path / "a2"), str(tmp_path / "b2")]) == 2
    assert "different grasp files" in capsys.readouterr().err
    assert main(["compare-labels", str(tmp_path / "a2"), "--reference", str(a)]) == 0
    assert main(["compare-labels", str(tmp_path / "a1"), str(tmp_path / "a2")]) == 0
    assert "over 1 scored grasps" in capsys.readouterr().out


def test_an_object_given_with_a_file_that_names_its_own_is_said(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """OBJECT overrides the object a GraspGen file names, and the run says so on stderr."""
    grasp_file = _graspgen_file(tmp_path, "box.json", 1)
    args = ["label-grasps", "gen_hammer", "--grasps", str(grasp_file), "--gripper", "franka_panda"]
    assert main([*args, "--no-picture", "--out", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert "box.json names its own object; labeling gen_hammer instead" in err
    run = json.loads((tmp_path / "out" / "run.json").read_text())
    assert run["object"] == "gen_hammer"


def test_glob_of_one_file_labels_it_as_a_data_set(tmp_path: Path) -> None:
    _graspgen_file(tmp_path, "a.json", 2)
    out = tmp_path / "out"
    pattern = str(tmp_path / "grasps" / "*.json")
    done = _cli(
        "label-grasps", "--grasps", pattern, "--gripper", "franka_panda", "--protocol", "acronym",
        "--mass", "0.1", "--no-picture", "--out", str(out), cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    rows = [json.loads(line) for line in (out / "a" / "labels.jsonl").open()]
    assert sorted(r["index"] for r in rows) == [0, 1]
    assert {r["handle_source"] for r in rows} == {"automatic"}
    summary = json.loads((out / "summary.json").read_text())
    assert [row["file"] for row in summary["files"]] == ["a.json"]


def test_glob_of_files_resumes_after_sigkill(tmp_path: Path) -> None:
    for name in ("a.json", "b.json"):
        _graspgen_file(tmp_path, name, 12)
    out = tmp_path / "out"
    args = (
        "label-grasps",
        "--grasps",
        str(tmp_path / "grasps" / "*.json"),
        "--gripper",
        "franka_panda",
        "--protocol",
        "acronym",
        "--mass",
        "0.1",
        "--out",
        str(out),
    )
    _killed_after_two_labels(args, tmp_path, out / "a" / "labels.jsonl")
    assert not (out / "summary.json").exists()
    done = _cli(*args, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    for stem in ("a", "b"):
        indices = [json.loads(line)["index"] for line in (out / stem / "labels.jsonl").open()]
        assert sorted(indices) == list(range(12))
    summary = json.loads((out / "summary.json").read_text())
    assert [row["file"] for row in summary["files"]] == ["a.json", "b.json"]
    _graspgen_file(tmp_path, "c.json", 12)  # a file more, killed again: no summary of a and b
    _killed_after_two_labels(args, tmp_path, out / "c" / "labels.jsonl")
    assert not (out / "summary.json").exists()


def _killed_after_two_labels(args: tuple[str, ...], cwd: Path, log: Path) -> None:
    """Run ``simgrasp *args`` and SIGKILL it once ``log`` holds two labels."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.Popen(
        [sys.executable, "-m", "simgrasp", *args],
        env=env,
        cwd=cwd,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (log.exists() and log.read_text().count("\n") >= 2):
        time.sleep(0.05)
    run.send_signal(signal.SIGKILL)
    run.wait()


@pytest.fixture(scope="module")
def acronym_dir() -> Path:
    return require_data("acronym")


def test_acronym_file_mapped_success_and_failure(acronym_dir: Path) -> None:
    """FleX's grasps 3 (success) and 0 (failure) of the official example mug: ours agree, and
    the held grasp closes on the mug with both pads."""
    grasp_file = acronym_dir / EXAMPLE
    name = carried_object(grasp_file)
    assert name is not None
    assert "scale=0.0002682458" in name and "mass=0.0130879738" in name
    grasps = read_grasp_set(grasp_file)
    with h5py.File(grasp_file) as handle:
        flex = handle["grasps/qualities/flex/object_in_gripper"][()]
        hand = handle["grasps/transforms"][3]
    assert (flex[3], flex[0]) == (1, 0)
    assert np.allclose(grasps.object_T_tcp[3] @ np.linalg.inv(FRANKA_T_TCP), hand)
    labeler = GraspLabeler(
        model_for(name), LabelConfig(object=name, gripper="franka_panda", protocol="acronym")
    )
    held = labeler.label(3, grasps.object_T_tcp[3], np.nan)
    assert held["success"] is True and held["score"] > 0
    points = np.asarray(held["contact_points_object"])
    tcp_T_object = np.linalg.inv(grasps.object_T_tcp[3])
    sides = (points @ tcp_T_object[:3, :3].T + tcp_T_object[:3, 3])[:, 1]
    assert sides.min() < 0 < sides.max()  # contacts on both pads (TCP -y and +y)
    failed = labeler.label(0, grasps.object_T_tcp[0], np.nan)
    assert failed["success"] is False and failed["score"] == 0.0


def test_export_acronym_read_back(acronym_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    done = _cli(
        "label-grasps",
        "--grasps",
        str(acronym_dir / EXAMPLE),
        "--gripper",
        "franka_panda",
        "--protocol",
        "acronym",
        "--max-grasps",
        "4",
        "--no-picture",
        "--out",
        str(out),
        "--export",
        "acronym",
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    with h5py.File(out / "export" / Path(EXAMPLE).name) as handle:
        ours = handle["grasps/qualities/simgrasp/object_in_gripper"][()]
        on_handle = handle["grasps/qualities/simgrasp/on_handle"][()]
        assert "grasps/qualities/flex/object_in_gripper" in handle
    with np.load(out / "labels.npz") as labels:
        assert ours[:4].tolist() == labels["success"].astype(float).tolist()
        assert on_handle[:4].tolist() == labels["on_handle"].astype(float).tolist()
    assert (ours[4:] == -1).all() and len(ours) == 2000 and (on_handle[4:] == -1).all()
    compared = _cli(
        "compare-labels",
        str(out),
        "--reference",
        str(acronym_dir / EXAMPLE),
        "--json",
        cwd=tmp_path,
    )
    assert json.loads(compared.stdout)["groups"]["overall"]["grasps"] <= 4


def test_restored_start_gives_the_same_records_in_fewer_steps(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The labeler restores a free-floating trial's start (settle and jaw opening) after its
    first trial: records bit for bit those of trials that step it (``steps`` counts the
    restored start's), from fewer calls of the physics step."""
    labeler = _box_labeler(tmp_path, "acronym")
    stepped_physics = [0]
    real_step = mujoco.mj_step

    def counted_step(model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
        stepped_physics[0] += nstep
        real_step(model, data, nstep)

    monkeypatch.setattr(mujoco, "mj_step", counted_step)
    turned = OBJECT_T_TCP @ np.diag([-1.0, -1.0, 1.0, 1.0])  # the same grasp, jaws swapped
    aside = OBJECT_T_TCP.copy()
    aside[0, 3] = 0.1  # beside the box: closes on nothing
    grasps = [OBJECT_T_TCP, turned, aside, OBJECT_T_TCP]
    cached, physics_cached = [], []
    for i, g in enumerate(grasps):
        stepped_physics[0] = 0
        cached.append(labeler.label(i, g, np.nan))
        physics_cached.append(stepped_physics[0])
    stepped = []
    for i, g in enumerate(grasps):
        labeler.starts.states.clear()  # nothing to restore: every trial steps its start
        stepped.append(labeler.label(i, g, np.nan))
    assert [r["failure"] for r in cached] == [None, None, "missed", None]
    assert len(labeler.starts.states) == 1  # one width (the full opening)
    assert physics_cached[0] == cached[0]["steps"]  # the first trial steps its start
    saved = [r["steps"] - n for r, n in zip(cached, physics_cached, strict=True)]
    assert saved[1] > 100 and saved == [0] + [saved[1]] * 3
    for first, second in zip(cached, stepped, strict=True):
        first.pop("timings_s")
        second.pop("timings_s")
        assert first == second


def test_acronym_fast_shakes_one_cycle_of_each_motion(tmp_path: Path) -> None:
    """``acronym-fast`` is ``acronym`` with the shake's second cycles cut: the same firm grip of
    the box is held by both, the fast one stepping exactly the 1 s it leaves out fewer."""
    records = {}
    for protocol in ("acronym", "acronym-fast"):
        labeler = _box_labeler(tmp_path, protocol)
        records[protocol] = labeler.label(0, OBJECT_T_TCP, np.nan)
        timestep = labeler.trial_config.timestep  # the acronym protocols keep it throughout
    full, fast = records["acronym"], records["acronym-fast"]
    assert full["success"] is True and fast["success"] is True
    assert full["steps"] - fast["steps"] == round(1.0 / timestep)
    assert 0.0 < full["score"] <= 1.0 and 0.0 < fast["score"] <= 1.0
