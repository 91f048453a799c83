"""The object flags (--scale/--units/--mass/--density/--friction/--handles) on every command
that takes an OBJECT, and the one-line refusals of flags that contradict each other."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from simgrasp.cli import main

BOX_M = (0.04, 0.06, 0.10)
GRASP = ["--grasp", "0", "0", "0.3", "0", "1", "0", "0"]


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A working directory holding ``box_mm.stl`` (a box in millimetres), ``box_m.stl`` (in
    meters), ``g.npz`` (one grasp) and garbage-byte mesh files; its own object cache."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("SIMGRASP_CACHE_DIR", str(tmp_path / "cache"))
    trimesh.creation.box(np.array(BOX_M) * 1000).export(tmp_path / "box_mm.stl")
    trimesh.creation.box(BOX_M).export(tmp_path / "box_m.stl")
    np.savez(tmp_path / "g.npz", object_T_grasp=np.eye(4)[None])
    garbage = np.random.default_rng(0).bytes(4096)
    for suffix in (".glb", ".ply", ".off"):
        (tmp_path / f"garbage{suffix}").write_bytes(garbage)
    return tmp_path


def _error_line(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """The one stderr line of a refused command (exit status 2)."""
    code = main(args)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"simgrasp {args[0]}: error: ")
    return err[0].removeprefix(f"simgrasp {args[0]}: error: ")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["trial", "box_mm.stl", "--units", "mm", "--mass", "0.3", "--density", "500", *GRASP],
            "give --mass or --density, not both",
        ),
        (
            ["label-grasps", "box_mm.stl", "--units", "mm", "--mass", "0.3", "--density", "500",
             "--grasps", "g.npz", "--out", "labels"],
            "give --mass or --density, not both",
        ),
        (
            ["trial", "box_m.stl", "--scale", "0.5", "--units", "m", *GRASP],
            "give --scale or --units, not both",
        ),
        (
            ["trial", "box_mm.stl", "--units", "mm", "--scale", "0.001", *GRASP],
            "give --scale or --units, not both",
        ),
        (
            ["trial", "gen_hammer", "--handles", "garbage.ply", *GRASP],
            "--handles garbage.ply: a mesh file, not a JSON handle label file",
        ),
        (["trial", "gen_hammer", "--grasp-frame", "object"], "--grasp-frame needs --grasp"),
        (
            ["trial", "gen_hammer", "--grasp", "0", "0", "0.3", "2", "0", "0", "0"],
            "--grasp: quaternion norm 2 is not 1",
        ),
        (
            ["trial", "gen_hammer", "--scale", "2"],
            "--scale only applies to a mesh file object, not 'gen_hammer'",
        ),
        (
            ["trial", "garbage.glb", *GRASP],
            "object mesh garbage.glb: cannot read it (incorrect header on GLB file)",
        ),
        (["trial", "garbage.ply", *GRASP], "object mesh garbage.ply: cannot read it (Not a ply"),
        (["trial", "garbage.off", *GRASP], "object mesh garbage.off: cannot read it (not enough"),
    ],
    ids=["mass-density", "label-mass-density", "scale-units", "units-scale", "handles-mesh",
         "frame-no-grasp", "quaternion", "scale-named", "glb", "ply", "off"],
)  # fmt: skip
def test_bad_object_flags_are_one_line(
    workdir: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    """Contradicting flags, a mesh as handle file, a lone --grasp-frame, a non-unit
    quaternion and an unreadable mesh: one line naming the flag or file, nothing written."""
    assert _error_line(args, capsys).startswith(message)
    assert not (workdir / "labels").exists()


def test_object_and_sample_grasps_take_the_object_flags(
    workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The millimetre box's advice (--units mm) works on ``sample-grasps`` and ``object``,
    whose export stays inside --out."""
    refused = _error_line(["sample-grasps", "box_mm.stl", "--n", "3", "--out", "g3.npz"], capsys)
    assert "box_mm.stl" in refused and "pass --units mm" in refused
    assert (
        main(["sample-grasps", "box_mm.stl", "--units", "mm", "--n", "3", "--out", "g3.npz"]) == 0
    )
    with np.load(workdir / "g3.npz") as grasps:
        assert grasps["width"].shape == (3,)
        made_by = json.loads(str(grasps["made_by"]))  # what drew them, seed included
    assert made_by["object"] == "box_mm.stl?units=mm" and made_by["seed"] == 0
    assert made_by["n"] == 3 and made_by["gripper"] == "builtin"
    assert main(["object", "export", "box_mm.stl", "--units", "mm", "--out", "ex"]) == 0
    assert (workdir / "ex" / "box_mm.xml").is_file()
    assert "box_mm.stl?units=mm: wrote ex/box_mm.xml" in capsys.readouterr().out


def test_files_of_a_mesh_object_are_named_by_its_stem(
    workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A mesh spec (``/abs/box_mm.stl?units=mm``) names no file: label-grasps' default output
    folder and scenes' views take the mesh's stem, inside their output folders, and scenes
    takes the object flags."""
    mesh = str(workdir / "box_mm.stl")
    assert main(["label-grasps", mesh, "--units", "mm", "--grasps", "g.npz", "--no-picture"]) == 0
    assert (workdir / "out" / "labels" / "box_mm" / "labels.jsonl").is_file()
    assert not list(workdir.glob("box_mm.stl?*"))
    scenes = ["scenes", "export", "--object", mesh, "--units", "mm", "--seeds", "1"]
    assert main([*scenes, "--scene.num-views", "1", "--out", "s"]) == 0
    assert [p.name for p in (workdir / "s").glob("*.pcd")] == ["box_mm_s0_view0.pcd"]


def test_evaluate_refuses_to_resume_on_an_edited_mesh(
    workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A mesh file edited under its name after a sweep ran on it: resuming into the same
    folder would pool trials of two meshes as one object, so it is refused in one line; the
    unchanged file resumes (no trial rerun)."""
    sweep = ["evaluate", "--objects", "box_m.stl", "--detector", "random", "--noise", "0"]
    sweep += ["--out", "e", "--no-progress", "--seeds"]
    assert main([*sweep, "1"]) == 0
    log = (workdir / "e" / "trials.jsonl").read_bytes()
    assert main([*sweep, "1"]) == 0 and (workdir / "e" / "trials.jsonl").read_bytes() == log
    capsys.readouterr()
    trimesh.creation.box(np.array(BOX_M) * 1.3).export(workdir / "box_m.stl")
    assert main([*sweep, "2"]) == 2  # after a note that the new mesh's handle is being found
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert (
        "holds trials of these objects run on other mesh or handle label file contents (box_m.stl:"
        in line
    )
    assert (workdir / "e" / "trials.jsonl").read_bytes() == log


def test_evaluate_refuses_to_resume_on_an_edited_handle_label_file(
    workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The handle label file given for an object sets what ``on_handle`` means: edited under
    its name after a sweep, resuming into the same folder is refused in one line."""
    handles = workdir / "handles.json"
    label = {"whole_object": False, "regions": [_top_box(0.01)]}
    handles.write_text(json.dumps({"description": "test", "objects": {"box_m": label}}))
    sweep = ["evaluate", "--objects", "box_m.stl?handles=handles.json", "--detector", "random"]
    sweep += ["--noise", "0", "--out", "e", "--no-progress", "--seeds"]
    assert main([*sweep, "1"]) == 0
    log = (workdir / "e" / "trials.jsonl").read_bytes()
    label["regions"] = [_top_box(0.04)]
    handles.write_text(json.dumps({"description": "test", "objects": {"box_m": label}}))
    capsys.readouterr()
    assert main([*sweep, "2"]) == 2
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert "handle label file contents (handles of box_m.stl?handles=handles.json:" in line
    assert (workdir / "e" / "trials.jsonl").read_bytes() == log


def _top_box(half_height: float) -> dict[str, object]:
    """A handle region: the top of the box ``BOX_M``, ``half_height`` (m) deep each way."""
    center = [0.0, 0.0, BOX_M[2] / 2]
    half = [BOX_M[0] / 2, BOX_M[1] / 2, half_height]
    return {"type": "box", "center": center, "rotation": np.eye(3).tolist(), "half_extents": half}
