"""``label-grasps`` on bad grasp files: one line naming the file, no traceback, and in a data
set run the bad file found before any file is labeled. The ACRONYM test needs
``SIMGRASP_ACRONYM_DIR``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from data_needs import require_data

from simgrasp.cli import main
from simgrasp.grasping.labeling.grasp_sets import read_grasp_set, write_grasp_set

OBJECT = "gen_hammer"
EXAMPLE = "examples/grasps/Mug_10f6e09036350e92b3f21f1137c3c347_0.0002682457830986903.h5"
FAR = np.array([[1.0, 0, 0, 5.0], [0, 1, 0, 5.0], [0, 0, 1, 5.0], [0, 0, 0, 1]])
"""A valid grasp far from the object (a quick miss)."""
PREFIX = "simgrasp label-grasps: error: "


def error_line(capsys: pytest.CaptureFixture[str], args: list[str]) -> str:
    """The error ``label-grasps`` ends with: exit code 2 and one stderr line, its message."""
    assert main(["label-grasps", *args]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(PREFIX), lines
    return lines[0].removeprefix(PREFIX)


def _garbage(path: Path) -> None:
    path.write_bytes(np.random.default_rng(0).bytes(2000))


def _width_count(path: Path) -> None:
    np.savez(path, object_T_grasp=np.stack([FAR] * 3), width=[0.05, 0.05])


def _graspnet_shape(path: Path) -> None:
    np.save(path, np.zeros((4, 3)))


def _no_rows(path: Path) -> None:
    np.savez(path, object_T_grasp=np.zeros((0, 4, 4)))


def _text_poses(path: Path) -> None:
    path.write_text(json.dumps({"poses": [[0, 0, 0, 1, 0, 0], [0, 0, 0, 1, 0, 0, 0]]}))


@pytest.mark.parametrize(
    ("name", "write", "message"),
    [
        ("garbage.npz", _garbage, "not a readable .npz grasp file ("),
        ("garbage.npy", _garbage, "not a readable .npy grasp file ("),
        ("empty.npz", lambda path: path.write_bytes(b""), "empty file"),
        ("count.npz", _width_count, "width has 2 entries for 3 grasps"),
        ("rows.npy", _graspnet_shape, "graspnet rows must be N x 17, got shape (4, 3)"),
        ("none.npz", _no_rows, "no row of the grasp file is a valid grasp (it has no rows)"),
        ("ragged.json", _text_poses, "poses must be numbers, got list"),
    ],
)
def test_a_bad_grasp_file_is_one_line_naming_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, write, message: str
) -> None:
    path = tmp_path / name
    write(path)
    args = [OBJECT, "--grasps", str(path), "--out", str(tmp_path / "out")]
    assert error_line(capsys, args).startswith(f"{path}: {message}")


def test_a_bad_file_of_a_data_set_stops_the_run_before_any_is_labeled(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "grasps"
    write_grasp_set(folder / "a.npz", FAR[None], np.array([0.05]))
    (folder / "b.npz").write_bytes(b"")
    out = tmp_path / "out"
    message = error_line(capsys, [OBJECT, "--grasps", str(folder), "--out", str(out)])
    assert message == f"{folder / 'b.npz'}: empty file"
    assert not (out / "a").exists()


def test_export_of_another_format_is_refused_before_labeling(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = write_grasp_set(tmp_path / "g.npz", FAR[None], np.array([0.05]))
    out = tmp_path / "out"
    args = [OBJECT, "--grasps", str(path), "--export", "acronym", "--out", str(out)]
    assert error_line(capsys, args) == f"--export acronym needs acronym grasp files, not {path}"
    assert not (out / "labels.jsonl").exists()


def test_a_file_without_an_object_needs_object(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = write_grasp_set(tmp_path / "g.npz", FAR[None], np.array([0.05]))
    message = error_line(capsys, ["--grasps", str(path), "--out", str(tmp_path / "out")])
    assert message == f"{path} names no object: give OBJECT"


def test_row_problems_print_plain_numbers(tmp_path: Path) -> None:
    path = tmp_path / "w.npz"
    np.savez(path, object_T_grasp=np.stack([FAR] * 3), width=[-1.0, 0.05, np.nan])
    problems = read_grasp_set(path).problems
    assert problems == {
        0: "width -1 is not a positive length",
        2: "width nan is not a positive length",
    }


def test_acronym_file_labels_without_label_flags(tmp_path: Path) -> None:
    """The README's usage with no OBJECT and no label flag: the file names its object."""
    grasp_file = require_data("acronym") / EXAMPLE
    out = tmp_path / "out"
    args = ["--grasps", str(grasp_file), "--max-grasps", "1", "--no-picture", "--out", str(out)]
    assert main(["label-grasps", *args]) == 0
    assert len((out / "labels.jsonl").read_text().splitlines()) == 1
