"""label-grasps run safety (real MuJoCo labels of a generated hammer and a box mesh): a folder
run refuses a changed setting before it labels any file, holds each file's folder while it
labels it, and an edited mesh file is a changed setting."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

from simgrasp.cli import main
from simgrasp.grasping.labeling.grasp_sets import read_grasp_set, write_grasp_set
from simgrasp.grasping.labeling.label_run import LABELS_FILE, run_identity
from simgrasp.grasping.labeling.labeling import LabelConfig
from simgrasp.runs.identity import file_digest
from simgrasp.runs.out_dir import claim_out_dir

ROOT = Path(__file__).parents[1]
ERROR = "simgrasp label-grasps: error: "


def _sample(target: Path, count: int, name: str = "gen_hammer") -> Path:
    """``count`` grasps of object ``name`` sampled into ``target``."""
    target.parent.mkdir(parents=True, exist_ok=True)
    assert main(["sample-grasps", name, "--n", str(count), "--out", str(target)]) == 0
    return target


def _label(grasps: Path | str, out: Path, *extra: str) -> int:
    """``label-grasps gen_hammer`` (fast protocol) of ``grasps`` into ``out``; the exit code."""
    args = ["label-grasps", "gen_hammer", "--grasps", str(grasps), "--protocol", "fast"]
    return main([*args, "--no-picture", "--out", str(out), *extra])


def _indices(out: Path) -> list[int]:
    """The grasp indices of a label directory's ``labels.jsonl``, in file order."""
    return [json.loads(line)["index"] for line in (out / LABELS_FILE).open()]


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder of two grasp files of the hammer: ``g1.npz`` (3 grasps), ``g3.npz`` (2)."""
    folder = tmp_path_factory.mktemp("grasps")
    _sample(folder / "g1.npz", 3)
    _sample(folder / "g3.npz", 2)
    return folder


def test_a_folder_run_refuses_a_changed_setting_before_labeling_any_file(
    folder: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """g3 labeled with seed 0, then the folder with seed 1: refused in one line naming g3's
    folder and the seed, before g1 (a new file, first in order) gets any label."""
    out = tmp_path / "out"
    assert _label(folder / "g3*", out) == 0
    kept = {p: p.read_bytes() for p in [out / "summary.json", *(out / "g3").iterdir()]}
    capsys.readouterr()
    assert _label(folder / "*.npz", out, "--seed", "1") == 2
    message = f"{out / 'g3'} holds labels of another run (seed: 0 -> 1); use another --out"
    assert capsys.readouterr().err.strip().splitlines() == [ERROR + message]
    assert not (out / "g1" / LABELS_FILE).exists()
    assert {p: p.read_bytes() for p in kept} == kept


def test_a_folder_run_is_refused_on_a_file_folder_another_run_holds(
    folder: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """While another run holds OUT/g1 (its lock, the one a single-file run takes), the folder
    run is refused in one line naming the folder and the holder; once it is free, it labels."""
    out = tmp_path / "out"
    holder = ["label-grasps", "gen_hammer", "--grasps", "elsewhere.npz"]
    with claim_out_dir(out / "g1", holder):
        assert _label(folder, out) == 2
        (line,) = capsys.readouterr().err.strip().splitlines()
        assert line.startswith(f"{ERROR}--out {out / 'g1'} is in use by another run (pid ")
        assert "simgrasp label-grasps gen_hammer --grasps elsewhere.npz" in line
        assert not (out / "g1" / LABELS_FILE).exists()
    assert _label(folder, out) == 0
    assert sorted(_indices(out / "g1")) == [0, 1, 2]


def test_a_single_file_run_is_refused_on_the_folder_a_folder_run_labels(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """While a folder run (another process) labels OUT/g1, ``--grasps g1.npz --out OUT/g1`` is
    refused in one line naming the folder run, and labels nothing twice."""
    grasp_file = _sample(tmp_path / "grasps" / "g1.npz", 60)
    out = tmp_path / "out"
    args = ["label-grasps", "gen_hammer", "--grasps", str(grasp_file.parent), "--out", str(out)]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    folder_run = subprocess.Popen(
        [sys.executable, "-m", "simgrasp", *args],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        log = out / "g1" / LABELS_FILE
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not (log.exists() and log.read_text().count("\n")):
            time.sleep(0.05)
        assert folder_run.poll() is None, "the folder run ended before the test could race it"
        capsys.readouterr()
        single = ["label-grasps", "gen_hammer", "--grasps", str(grasp_file), "--no-picture"]
        assert main([*single, "--out", str(out / "g1")]) == 2
        (line,) = capsys.readouterr().err.strip().splitlines()
        assert line.startswith(f"{ERROR}--out {out / 'g1'} is in use by another run (pid ")
        assert f"--out {out}" in line
    finally:
        os.killpg(folder_run.pid, signal.SIGKILL)
        folder_run.wait()
    indices = _indices(out / "g1")
    assert len(indices) == len(set(indices))


def _box(path: Path, factor: float = 1.0) -> Path:
    """A 4 x 6 x 10 cm box (times ``factor``) written as a mesh file."""
    box = trimesh.creation.box((0.04, 0.06, 0.10))
    box.apply_scale(factor)
    box.export(path)
    return path


def _box_labeled_twice(tmp_path: Path) -> tuple[Path, Path, list[str]]:
    """A box mesh, 4 grasps sampled on it and the first 2 labeled into ``out``: (the mesh,
    ``out``, the label-grasps arguments for all 4)."""
    mesh = _box(tmp_path / "box.stl")
    grasps = _sample(tmp_path / "g.npz", 4, str(mesh))
    out = tmp_path / "out"
    args = ["label-grasps", str(mesh), "--grasps", str(grasps), "--protocol", "fast"]
    args += ["--no-picture", "--out", str(out)]
    assert main([*args, "--max-grasps", "2"]) == 0
    return mesh, out, args


def test_an_edited_mesh_file_is_refused_as_a_changed_setting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two labels of a box mesh, then the file scaled by 1.3 and the run extended to all its
    grasps: refused in one line naming ``mesh_sha256``; the old labels stay alone."""
    mesh, out, args = _box_labeled_twice(tmp_path)
    assert json.loads((out / "run.json").read_text())["mesh_sha256"] == file_digest(mesh)
    _box(mesh, 1.3)
    capsys.readouterr()
    assert main(args) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"{ERROR}{out} holds labels of another run (mesh_sha256: ")
    assert sorted(_indices(out)) == [0, 1]


def test_a_folder_labeled_before_mesh_digests_resumes_and_records_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A mesh object's folder whose ``run.json`` predates the mesh digest (a long ACRONYM run,
    say) resumes over more grasps, labeling only the new ones, and records the digest from
    then on."""
    mesh, out, args = _box_labeled_twice(tmp_path)
    run = json.loads((out / "run.json").read_text())
    del run["mesh_sha256"]  # as written before this version
    (out / "run.json").write_text(json.dumps(run))
    assert main(args) == 0
    assert sorted(_indices(out)) == [0, 1, 2, 3]
    assert len((out / "labels.jsonl").read_text().splitlines()) == 4  # none labeled twice
    assert json.loads((out / "run.json").read_text())["mesh_sha256"] == file_digest(mesh)


def test_a_catalog_object_records_its_mesh_and_a_generated_one_none(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A catalog name resolves to its mesh file, whose SHA-256 ``run.json`` records; a
    generated (or YCB) object records none, so its earlier folders resume."""
    mesh = _box(tmp_path / "box.stl")
    (tmp_path / "objects.toml").write_text('[my_box]\nmesh = "box.stl"\n')
    monkeypatch.setenv("SIMGRASP_OBJECTS", str(tmp_path / "objects.toml"))
    grasp_file = write_grasp_set(tmp_path / "g.npz", [np.eye(4)], [0.05])
    grasps = read_grasp_set(grasp_file)
    run = run_identity(grasps, LabelConfig("my_box"), grasp_file)
    assert run["mesh_sha256"] == file_digest(mesh)
    assert "mesh_sha256" not in run_identity(grasps, LabelConfig("gen_hammer"), grasp_file)


def _box_handles(path: Path, half_height: float) -> Path:
    """A handle label file of ``box``: the box's top ``half_height`` (m) as one region."""
    region = {"type": "box", "center": [0.0, 0.0, 0.05], "rotation": np.eye(3).tolist()}
    region["half_extents"] = [0.02, 0.03, half_height]
    label = {"whole_object": False, "regions": [region]}
    path.write_text(json.dumps({"description": "test", "objects": {"box": label}}))
    return path


def test_an_edited_handle_label_file_is_refused_and_an_older_folder_adopts_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--handles FILE`` sets what ``on_handle`` means: its SHA-256 is in ``run.json``, so
    the file edited under its name is refused in one line naming ``handles_sha256`` (a
    resume would score half the grasps on each label); a folder written before the digest
    resumes and records it."""
    mesh = _box(tmp_path / "box.stl")
    handles = _box_handles(tmp_path / "handles.json", 0.01)
    grasps = _sample(tmp_path / "g.npz", 4, str(mesh))
    out = tmp_path / "out"
    args = ["label-grasps", str(mesh), "--handles", str(handles), "--grasps", str(grasps)]
    args += ["--protocol", "fast", "--no-picture", "--out", str(out)]
    assert main([*args, "--max-grasps", "2"]) == 0
    run = json.loads((out / "run.json").read_text())
    assert run["handles_sha256"] == file_digest(handles)
    del run["handles_sha256"]  # as written before this version
    (out / "run.json").write_text(json.dumps(run))
    assert main([*args, "--max-grasps", "3"]) == 0
    assert json.loads((out / "run.json").read_text())["handles_sha256"] == file_digest(handles)
    _box_handles(handles, 0.05)
    capsys.readouterr()
    assert main(args) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"{ERROR}{out} holds labels of another run (handles_sha256: ")
    assert sorted(_indices(out)) == [0, 1, 2]
