"""Bad command lines are one line naming the flag, the folder or the object (exit 2), never a
traceback, a silent no-op or a silently wrong answer: demo never deletes another command's run,
an empty --objects, flags that would be ignored, two label runs of different objects, a
--base-url that is no URL, a --dest or a CLOUD that is the wrong kind of path."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from simgrasp.cli import main
from simgrasp.errors import SimgraspError
from simgrasp.runs.identity import file_digest
from simgrasp.runs.out_dir import claim_out_dir


def refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """The one error line ``argv`` is refused with (exit status 2, nothing else on stderr)."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    prefix = f"simgrasp {argv[0]}: error: "
    assert err.startswith(prefix), err
    return err[len(prefix) :].rstrip("\n")


def no_trials(*args: Any, **kwargs: Any) -> list[dict[str, Any]]:
    pytest.fail("the demo ran trials in a folder it must refuse")


def sweep_stopped_after_claim(*args: Any, **kwargs: Any) -> list[dict[str, Any]]:
    raise SimgraspError("stopped at the first trial")


def test_demo_refuses_another_commands_run_and_restarts_only_its_own(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("SIMGRASP_YCB_DIR", raising=False)
    monkeypatch.setattr("simgrasp.evaluation.sweep.run_sweep", no_trials)
    runs = {}
    for command in ("evaluate", "demo"):
        out = runs[command] = tmp_path / command
        with claim_out_dir(out, ["simgrasp", command, "--out", str(out)]):
            (out / "trials.jsonl").write_text('{"object": "gen_hammer_s0"}\n')
            (out / "defaults.json").write_text("{}\n")
    demo = ["demo", "--seeds", "1", "--workers", "1", "--out"]
    for _ in range(2):  # a refusal leaves the folder as it was: the second is refused too
        line = refused([*demo, str(runs["evaluate"])], capsys)
        assert line == f"{runs['evaluate']} holds an evaluate run (trials.jsonl); use another --out"
    assert (runs["evaluate"] / "trials.jsonl").read_text() == '{"object": "gen_hammer_s0"}\n'
    assert (runs["evaluate"] / "defaults.json").exists()
    unknown = tmp_path / "unknown"  # no lock names its writer: a readable record is kept
    unknown.mkdir()
    (unknown / "trials.jsonl").write_text('{"object": "gen_hammer_s0"}\n')
    line = refused([*demo, str(unknown)], capsys)
    assert line == f"{unknown} holds another command's run (trials.jsonl); use another --out"
    monkeypatch.setattr("simgrasp.evaluation.sweep.run_sweep", sweep_stopped_after_claim)
    assert refused([*demo, str(runs["demo"])], capsys) == "stopped at the first trial"
    # its own run, under today's defaults as far as they were recorded: resumed, kept
    assert (runs["demo"] / "trials.jsonl").read_text() == '{"object": "gen_hammer_s0"}\n'


@pytest.mark.parametrize(
    "argv",
    [
        ["evaluate", "--objects", ""],
        ["labels", "--objects", ""],
        ["detect-eval", "--objects", ""],
        ["evaluate", "--detector", ""],  # ran nothing, then: "no trial records to report"
        ["evaluate", "--sensor", " , "],
        ["labels", "--osd", ""],  # drew every object's label instead of a scene's
        ["detect-eval", "--real", "m.toml", "--real-configs", ""],
    ],
)
def test_an_empty_list_is_refused(
    argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A comma list given empty (``--osd "$SCENE"`` with SCENE unset) is refused in one line
    naming the flag, before anything is written; it would run the command's default."""
    line = refused([*argv, "--out", str(tmp_path / "out")], capsys)
    assert line.startswith(f"{argv[-2]} is empty: give at least one value ("), line
    assert not (tmp_path / "out").exists()


IGNORED_FLAGS = [
    (["detect-eval", "--real-configs", "standoff", "--objects", "gen_hammer", "--seeds", "1"],
     "--real-configs needs --real"),
    (["detect-eval", "--real-dir", "/x", "--objects", "gen_hammer", "--seeds", "1"],
     "--real-dir needs --real"),
    (["detect-eval", "--real", "m.toml", "--objects", "gen_hammer", "--seeds", "1"],
     "--objects and --real conflict"),
    (["detect-eval", "--real", "m.toml", "--workers", "2"], "--workers and --real conflict"),
    (["labels", "--osd", "learn33", "--real", "knife1"], "--osd and --real conflict"),
    (["labels", "--osd", "learn33", "--objects", "gen_hammer"], "--objects and --osd conflict"),
    (["labels", "--manifest", "nosuch.toml", "--objects", "gen_hammer"],
     "--manifest needs --real"),
    (["labels", "--real-dir", "/x", "--objects", "gen_hammer"],
     "--real-dir needs --osd or --real"),
    (["compare-labels", "lg1", "lg2", "--plot", "p.png"], "--plot needs --reference"),
    (["compare-labels", "lg1", "lg2", "--interval-draws", "50"],
     "--interval-draws needs --reference"),
    (["compare-labels", "lg1", "lg2", "--seed", "3"], "--seed needs --reference"),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "message"), IGNORED_FLAGS)
def test_a_flag_that_would_be_ignored_is_refused(
    argv: list[str],
    message: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("SIMGRASP_REAL_DIR", str(tmp_path / "no-real-data"))
    out = [] if argv[0] == "compare-labels" else ["--out", "out"]
    assert refused([*argv, *out], capsys).startswith(message)
    assert not (tmp_path / "out").exists() and not (tmp_path / "p.png").exists()


def label_dir(path: Path, object_name: str, digest: str, success: list[bool]) -> Path:
    """A label-grasps output folder: its run.json and labels.npz."""
    path.mkdir()
    run = {"object": object_name, "gripper": "builtin", "grasps_sha256": digest}
    (path / "run.json").write_text(json.dumps(run))
    held = np.array(success)
    failure = np.array(["" if s else "missed" for s in success])
    np.savez(path / "labels.npz", success=held, failure=failure, on_handle=held)
    return path


def test_label_runs_of_different_objects_are_not_compared(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    hammer = label_dir(tmp_path / "lg1", "gen_hammer", "f948", [True])
    mug = label_dir(tmp_path / "lg14", "gen_mug", "f948", [False])
    line = refused(["compare-labels", str(hammer), str(mug)], capsys)
    assert line == f"{hammer} labels gen_hammer_s0 but {mug} labels gen_mug_s0"
    same = label_dir(tmp_path / "lg2", "gen_hammer_s0", "f948", [True])  # the same object
    assert main(["compare-labels", str(hammer), str(same)]) == 0
    assert "agreement 1.000" in capsys.readouterr().out


def acronym_file(root: Path, scale: float) -> Path:
    """An ACRONYM-style grasp file of a mesh in ``root/meshes`` with FleX labels."""
    mesh = root / "meshes" / "Mug" / "cup.obj"
    mesh.parent.mkdir(parents=True)
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    path = root / "grasps" / f"Mug_cup_{scale}.h5"
    path.parent.mkdir()
    with h5py.File(path, "w") as handle:
        handle["object/file"] = "meshes/Mug/cup.obj"
        handle["object/scale"] = scale
        handle["grasps/transforms"] = np.tile(np.eye(4), (2, 1, 1))
        handle["grasps/qualities/flex/object_in_gripper"] = np.array([1, 0])
    return path


def test_labels_of_another_object_are_not_compared_with_a_reference(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    reference = acronym_file(tmp_path, 0.05)
    mesh = tmp_path / "meshes" / "Mug" / "cup.obj"
    ours = label_dir(tmp_path / "lg7", "gen_hammer", file_digest(reference), [True, False])
    line = refused(["compare-labels", str(ours), "--reference", str(reference)], capsys)
    assert (
        line
        == f"{ours} labels gen_hammer_s0 but {reference.name} holds grasps of {mesh}?scale=0.05"
    )
    mug = label_dir(
        tmp_path / "lg6", f"{mesh}?scale=0.05&mass=0.1", file_digest(reference), [True, False]
    )
    assert main(["compare-labels", str(mug), "--reference", str(reference)]) == 0
    assert "[overall]" in capsys.readouterr().out


def test_fetch_ycb_refuses_a_base_url_that_is_no_url(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fetch = ["fetch-ycb", "--objects", "025_mug", "--dest", str(tmp_path), "--base-url"]
    for url in ("notaurl", "ftp://host/ycb", "http:///data"):
        assert (
            refused([*fetch, url], capsys)
            == f"--base-url {url}: not a URL (http://, https://, file://)"
        )
    assert main([*fetch, (tmp_path / "mirror").as_uri()]) == 1  # a URL: no archive there
    assert "cannot reach file://" in capsys.readouterr().err


def test_fetch_ycb_refuses_a_file_as_dest(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    dest = tmp_path / "cloud.txt"
    dest.write_text("x")
    argv = ["fetch-ycb", "--objects", "025_mug", "--dest", str(dest)]
    assert refused(argv, capsys) == f"--dest {dest}: is a file, not a folder"


@pytest.mark.parametrize("name", ["adir", "d.ply", "d.png"])
def test_detect_refuses_a_folder_as_cloud(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / name
    folder.mkdir()
    for extra in ([], ["--segment"]):
        line = refused(["detect", str(folder), *extra], capsys)
        assert line == f"{folder}: is a folder, not a point-cloud file"


@pytest.mark.parametrize("name", ["adir", "d.pcd"])
def test_segment_refuses_a_folder_as_scene(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / name
    folder.mkdir()
    assert (
        refused(["segment", str(folder)], capsys)
        == f"{folder}: is a folder, not a scene-cloud file"
    )


def test_detect_eval_real_holds_its_output_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two ``detect-eval --real`` runs on one --out would score the same clouds twice: the
    second is refused while the first holds the folder."""
    out = tmp_path / "out"
    with claim_out_dir(out, ["detect-eval", "--real", "a.toml"]):
        line = refused(["detect-eval", "--real", "m.toml", "--out", str(out)], capsys)
    assert line.startswith(f"--out {out} is in use by another run"), line
