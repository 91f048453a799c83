"""The ceiling and the floor beside an agreement: the reference's own consistency (its label of
the nearest other grasp within 8 mm and 15 degrees) and the majority-class baseline."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from simgrasp.grasping.labeling.grasp_sets import FRANKA_T_TCP, GraspSet
from simgrasp.grasping.labeling.reference_compare import compare_with_reference, comparison_text
from simgrasp.grasping.labeling.reference_consistency import (
    ceiling_and_floor,
    nearest_neighbours,
    neighbour_agreement,
)
from simgrasp.runs.identity import file_digest


def _pose(x_mm: float, turn_deg: float = 0.0, axis: str = "x") -> np.ndarray:
    """A TCP pose ``x_mm`` along x, turned ``turn_deg`` about ``axis``."""
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_euler(axis, turn_deg, degrees=True).as_matrix()
    pose[0, 3] = x_mm / 1000
    return pose


POSES = np.array(
    [
        _pose(0.0),  # 0: its nearest is 1 (2 mm, 5 deg), not 2 (5 mm)
        _pose(2.0, 5.0),  # 1
        _pose(5.0, 180.0, "z"),  # 2: a half turn about the approach is the same grasp
        _pose(100.0),  # 3: alone
        _pose(100.0, 20.0),  # 4: beside 3 but turned 20 degrees: no neighbour of 3's
        _pose(200.0),  # 5: a refused row (never anyone's neighbour)
        _pose(201.0),  # 6: only 5 near, which is refused
    ]
)


def test_nearest_neighbours_within_8_mm_and_15_degrees() -> None:
    """Nearest by position and angle together; a half turn about the approach is no turn;
    beyond 15 degrees, or only near a refused row, there is none."""
    valid = np.ones(len(POSES), bool)
    valid[5] = False
    found = nearest_neighbours(POSES, np.array([0, 1, 2, 3, 4, 6]), valid)
    assert found.tolist() == [1, 0, 0, -1, -1, -1]
    assert nearest_neighbours(POSES, np.array([2]), valid, mm=2.5).tolist() == [-1]


def test_neighbour_agreement_and_the_figures_beside_an_accuracy() -> None:
    """Of the grasps with a neighbour (0, 1, 2), the reference's neighbour label agrees on 0
    and 1 (both held), not on 2 (dropped, its neighbour 1 held); ours is scored on the same
    three; the majority baseline counts every scored grasp."""
    grasps = GraspSet(POSES, np.full(7, np.nan), {5: "refused"}, "arrays")
    reference = np.array([True, True, False, True, True, True, False])
    ours = np.array([True, False, False, True, True])
    rows = np.array([0, 1, 2, 3, 4])
    reference_right, ours_right = neighbour_agreement(grasps, reference, rows, ours)
    assert reference_right.tolist() == [True, True, False]
    assert ours_right.tolist() == [True, False, True]
    beside = ceiling_and_floor(reference[rows], reference_right, ours_right)
    assert beside["majority"] == pytest.approx(0.8)
    assert beside["consistency"] == pytest.approx(2 / 3)
    assert beside["consistency_grasps"] == 3
    assert beside["ours_on_consistency_grasps"] == pytest.approx(2 / 3)
    none = ceiling_and_floor(np.zeros(0, bool), np.zeros(0, bool), np.zeros(0, bool))
    assert none["consistency"] is None and none["majority"] is None


def test_compare_labels_prints_the_ceiling_and_the_floor_per_file_and_category(
    tmp_path: Path,
) -> None:
    """Two ACRONYM-style files (hand poses in ``grasps/transforms``): each file's row and the
    category's carry the majority baseline and the reference's consistency, pooled over the
    files for the category, and the text prints them beside our accuracy."""
    ours_dir = tmp_path / "ours"
    hand = POSES[:5] @ np.linalg.inv(FRANKA_T_TCP)
    files = []
    for name, flex, held in (
        ("Knife_a_1.0", [1, 1, 0, 1, 1], [1, 0, 0, 1, 1]),
        ("Knife_b_1.0", [1, 1, 1, 0, 0], [1, 1, 1, 1, 1]),
    ):
        path = tmp_path / f"{name}.h5"
        with h5py.File(path, "w") as handle:
            handle["grasps/transforms"] = hand
            handle["grasps/qualities/flex/object_in_gripper"] = np.array(flex)
        labels = ours_dir / name
        labels.mkdir(parents=True)
        run = {"object": "gen_knife", "grasps_sha256": file_digest(path)}
        (labels / "run.json").write_text(json.dumps(run))
        success = np.array(held, dtype=bool)
        failure = np.array(["" if s else "dropped_in_shaking" for s in success])
        np.savez(labels / "labels.npz", success=success, failure=failure, score=success * 1.0)
        files.append(path)
    comparison = compare_with_reference(ours_dir, files)
    first, second = comparison["files"]
    assert first["consistency"] == pytest.approx(2 / 3) and first["majority"] == 0.8
    assert first["ours_on_consistency_grasps"] == pytest.approx(2 / 3)
    assert second["consistency"] == pytest.approx(1.0) and second["majority"] == 0.6
    knives = comparison["groups"]["Knife"]
    assert knives["consistency"] == pytest.approx(5 / 6) and knives["consistency_grasps"] == 6
    assert knives["majority"] == pytest.approx(0.7)
    text = comparison_text(comparison)
    assert "major  self    on  ours" in text.splitlines()[0]
    (knife_line,) = [line for line in text.splitlines() if line.startswith("[Knife]")]
    assert knife_line.split()[1:3] == ["10", "0.700"]
    assert knife_line.split()[5:9] == ["0.700", "0.833", "6", "0.833"]
