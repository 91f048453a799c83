"""Grasp-set readers: our npz/json, ACRONYM .h5 (made here with h5py), graspnetAPI rows; every
bad row reported by index and kept out of the valid set."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import h5py
import numpy as np
import pytest
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

from simgrasp.grasping.labeling.grasp_sets import (
    ACRONYM_TCP_OFFSET,
    GraspSet,
    read_grasp_set,
    write_grasp_set,
)
from simgrasp.transforms import matrix_to_pose7


def rigid(rotvec: ArrayLike, translation: ArrayLike) -> np.ndarray:
    transform = np.eye(4)
    transform[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    transform[:3, 3] = translation
    return transform


GOOD = rigid([0.3, -0.2, 1.1], [0.01, 0.02, 0.03])


def test_npz_matrices_with_bad_rows_reported_by_index(tmp_path: Path) -> None:
    matrices = np.stack([GOOD, GOOD, GOOD, GOOD, np.zeros((4, 4)), GOOD])
    matrices[1, 0, 0] = np.nan
    matrices[2, :3, :3] *= 1.5  # scaled: not orthonormal
    matrices[3, :3, 0] *= -1.0  # a reflection
    widths = np.array([0.04, 0.04, 0.04, 0.04, 0.04, -0.01])
    path = write_grasp_set(tmp_path / "set.npz", matrices, widths)
    grasps = read_grasp_set(path)
    assert len(grasps) == 6 and grasps.fmt == "npz"
    assert sorted(grasps.problems) == [1, 2, 3, 4, 5]
    assert "non-finite" in grasps.problems[1]
    assert "orthonormal" in grasps.problems[2] and "orthonormal" in grasps.problems[4]
    assert "reflection" in grasps.problems[3]
    assert "width" in grasps.problems[5]
    assert grasps.valid.tolist() == [True, False, False, False, False, False]
    np.testing.assert_allclose(grasps.object_T_tcp[0], GOOD)
    np.testing.assert_array_equal(grasps.object_T_tcp[1], np.eye(4))


def test_from_arrays_checks_rows_as_the_file_reader(tmp_path: Path) -> None:
    """GraspSet.from_arrays: the same rows, reasons and replaced poses as reading them from
    our .npz; a wrong shape or width count raises naming it."""
    matrices = np.stack([GOOD, GOOD, np.zeros((4, 4)), GOOD, GOOD])
    matrices[1, 2, 3] = np.inf
    matrices[3, 3] = [0.0, 0.0, 0.1, 1.0]  # not a rigid transform's last row
    widths = np.array([0.04, 0.04, 0.04, 0.04, 0.0])
    grasps = GraspSet.from_arrays(matrices, widths)
    assert grasps.fmt == "arrays" and len(grasps) == 5
    assert list(grasps.problems) == [1, 2, 3, 4]
    assert grasps.problems[1] == "non-finite values"
    assert "not orthonormal" in grasps.problems[2]
    assert "last row" in grasps.problems[3]
    assert grasps.problems[4].endswith("is not a positive length")
    assert grasps.valid.tolist() == [True, False, False, False, False]
    read = read_grasp_set(write_grasp_set(tmp_path / "set.npz", matrices, widths))
    assert read.problems == grasps.problems
    np.testing.assert_array_equal(read.object_T_tcp, grasps.object_T_tcp)
    np.testing.assert_array_equal(grasps.object_T_tcp[1], np.eye(4))
    assert np.isnan(GraspSet.from_arrays(matrices[:1]).width).all()  # no width: fully open
    with pytest.raises(ValueError, match=r"object_T_grasp must be N x 4 x 4, got shape \(4, 4\)"):
        GraspSet.from_arrays(GOOD)
    with pytest.raises(ValueError, match="width has 2 entries for 5 grasps"):
        GraspSet.from_arrays(matrices, widths[:2])


def test_json_poses_without_width(tmp_path: Path) -> None:
    pose = matrix_to_pose7(GOOD).tolist()
    unnormalized = pose[:3] + [2 * q for q in pose[3:]]
    path = tmp_path / "set.json"
    path.write_text(json.dumps({"poses": [pose, unnormalized, [0.0] * 7]}))
    grasps = read_grasp_set(path)
    np.testing.assert_allclose(grasps.object_T_tcp[0], GOOD, atol=1e-12)
    assert np.isnan(grasps.width).all()
    assert sorted(grasps.problems) == [1, 2]
    assert "quaternion norm 2" in grasps.problems[1]
    assert "quaternion norm 0" in grasps.problems[2]


def test_acronym_h5_maps_the_franka_frame_to_our_tcp(tmp_path: Path) -> None:
    """ACRONYM's hand frame: approach +z, closing along x, pads ~0.1034 m along +z."""
    bad = np.eye(4)
    bad[:3, :3] = 0.0
    franka = np.stack([np.eye(4), GOOD, bad])
    path = tmp_path / "Mug_0.h5"
    with h5py.File(path, "w") as handle:
        handle["grasps/transforms"] = franka
        handle["grasps/qualities/flex/object_in_gripper"] = np.array([1, 0, 1])
    grasps = read_grasp_set(path)
    assert grasps.fmt == "acronym" and list(grasps.problems) == [2]
    tcp = grasps.object_T_tcp[0]
    np.testing.assert_allclose(tcp[:3, 3], [0.0, 0.0, ACRONYM_TCP_OFFSET])
    np.testing.assert_allclose(tcp[:3, 2], [0.0, 0.0, 1.0])  # approach = Franka +z
    np.testing.assert_allclose(tcp[:3, 1], [1.0, 0.0, 0.0])  # closing = Franka x
    assert np.linalg.det(tcp[:3, :3]) == pytest.approx(1.0)
    moved = grasps.object_T_tcp[1]
    np.testing.assert_allclose(moved[:3, 3], GOOD[:3, 3] + ACRONYM_TCP_OFFSET * GOOD[:3, 2])
    np.testing.assert_allclose(moved[:3, 1], GOOD[:3, 0], atol=1e-12)


def test_acronym_file_without_grasps_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "empty.h5"
    with h5py.File(path, "w") as handle:
        handle["object/scale"] = 1.0
    with pytest.raises(ValueError, match="grasps/transforms"):
        read_grasp_set(path)


def test_files_that_are_no_hdf5_or_hold_odd_content_are_one_line_each(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """label-grasps and compare-labels on a file that is not HDF5, on an ACRONYM file whose
    object scale is text, and on GraspGen files whose scale is text, whose object has no mesh
    or whose grasps are no table: one line naming the file, no traceback."""
    from simgrasp.cli import main

    not_hdf5 = tmp_path / "Mug_x.h5"
    not_hdf5.write_text("not an HDF5 file")
    odd = tmp_path / "grasps" / "Mug_y.h5"
    odd.parent.mkdir()
    with h5py.File(odd, "w") as handle:
        handle["object/file"] = "meshes/mug.obj"
        handle["object/scale"] = "large"
        handle["grasps/transforms"] = GOOD[None]
    scale_text = tmp_path / "gg_scale.json"
    scale_text.write_text(json.dumps({"object": {"file": "m.obj", "scale": "x"}, "grasps": {}}))
    not_table = tmp_path / "gg_grasps.json"
    not_table.write_text(json.dumps({"object": {"file": "m.obj"}, "grasps": "all of them"}))
    no_file = tmp_path / "gg_object.json"
    no_file.write_text(json.dumps({"object": "mug", "grasps": {"transforms": []}}))
    label = ["label-grasps", "--gripper", "franka_panda", "--out", str(tmp_path / "out")]
    runs = [
        *(([*label, "--grasps", str(f)], f) for f in (scale_text, no_file, not_table, not_hdf5)),
        ([*label, "--grasps", str(odd)], odd),
        (["compare-labels", str(tmp_path), "--reference", str(not_hdf5)], not_hdf5),
    ]
    for args, name in runs:
        assert main(args) == 2
        err = capsys.readouterr().err.strip()
        assert str(name) in err and len(err.splitlines()) == 1, err


def test_graspnet_rows_approach_is_the_rotation_x_axis(tmp_path: Path) -> None:
    rotation = GOOD[:3, :3]
    row = np.concatenate([[0.9, 0.05, 0.02, 0.03], rotation.reshape(-1), [0.1, 0.2, 0.3], [7]])
    skewed = row.copy()
    skewed[4] += 0.5
    path = tmp_path / "grasps.npy"
    np.save(path, np.stack([row, skewed]))
    grasps = read_grasp_set(path)
    assert grasps.fmt == "graspnet" and list(grasps.problems) == [1]
    tcp = grasps.object_T_tcp[0]
    np.testing.assert_allclose(tcp[:3, 2], rotation[:, 0])
    np.testing.assert_allclose(tcp[:3, 1], rotation[:, 1])
    np.testing.assert_allclose(tcp[:3, 3], [0.1, 0.2, 0.3])
    assert grasps.width[0] == pytest.approx(0.05)


def test_unknown_suffix_and_missing_file(tmp_path: Path) -> None:
    (tmp_path / "set.csv").write_text("1,2,3\n")
    with pytest.raises(ValueError, match="unknown grasp file type"):
        read_grasp_set(tmp_path / "set.csv")
    with pytest.raises(FileNotFoundError):
        read_grasp_set(tmp_path / "none.npz")


def test_sampler_table_margins_match_the_planner() -> None:
    """The sampler's vectorized table check is the planner's table_margin, grasp by grasp."""
    from dataclasses import replace

    from simgrasp.grasping.planning.antipodal import Table
    from simgrasp.grasping.planning.planner import table_margin
    from simgrasp.grasping.planning.planner_config import PlannerConfig
    from simgrasp.grippers.geometry import GripperGeometry

    rng = np.random.default_rng(0)
    geometry = GripperGeometry(max_opening=0.085, closed_pad_reach=0.02)
    table = Table(rigid([0.2, 0.1, 0.5], [0.0, 0.0, 0.03]), top_z=0.0)
    poses = np.stack(
        [rigid(rng.normal(size=3), rng.normal(0, 0.05, 3) + [0, 0, 0.1]) for _ in range(50)]
    )
    openings = rng.uniform(0.01, 0.085, 50)
    margins = table.margins(poses, openings, geometry)
    expected = [
        table_margin(table.world_T_object @ p, replace(geometry, max_opening=w), 0.0,
                     PlannerConfig())
        for p, w in zip(poses, openings, strict=True)
    ]  # fmt: skip
    np.testing.assert_allclose(margins, expected, atol=1e-12)
    assert (margins < 0).any() and (margins > 0).any()


def test_compare_labels_confusion_leaves_out_unscored(tmp_path: Path) -> None:
    from simgrasp.grasping.labeling.label_compare import compare_labels
    from simgrasp.grasping.labeling.label_run import write_label_arrays

    def records(outcomes: Sequence[tuple[bool | None, str | None]]) -> list[dict]:
        return [
            {"success": s, "on_handle": s, "failure": f, "handle_fraction": 0.0,
             "lift_height": 0.0}
            for s, f in outcomes
        ]  # fmt: skip

    full = [(True, None), (True, None), (False, "missed"), (False, "invalid"), (None, None)]
    fast = [(True, None), (False, "dropped_in_perturbation"), (False, "missed"),
            (False, "invalid"), (True, None)]  # fmt: skip
    full[4] = (None, "sim_unstable")
    for name, outcomes in (("full", full), ("fast", fast)):
        (tmp_path / name).mkdir()
        write_label_arrays(tmp_path / name / "labels.npz", records(outcomes))
    result = compare_labels(tmp_path / "full", tmp_path / "fast")
    assert result["scored"] == 3
    assert (result["held_held"], result["held_failed"]) == (1, 1)
    assert (result["failed_held"], result["failed_failed"]) == (0, 1)
    assert result["agreement"] == pytest.approx(2 / 3)
    assert result["on_handle_agreement"] == 1.0
