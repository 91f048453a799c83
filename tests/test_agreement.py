"""Agreement metrics of our labels against a reference's, and their interval over files."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from simgrasp.grasping.labeling.agreement import agreement, file_interval
from simgrasp.grasping.labeling.reference_compare import compare_with_reference, comparison_text
from simgrasp.runs.identity import file_digest


def test_agreement_counts_and_rates() -> None:
    """3 reference successes (2 held by us) and 2 failures (1 held): accuracy 3/5, balanced
    (2/3 + 1/2) / 2, AUROC from the score's ranks."""
    reference = [True, True, True, False, False]
    ours = [True, True, False, True, False]
    result = agreement(reference, ours, score=[0.9, 0.8, 0.1, 0.7, 0.2])
    assert [result[k] for k in ("ref_success_ours_success", "ref_success_ours_failure")] == [2, 1]
    assert [result[k] for k in ("ref_failure_ours_success", "ref_failure_ours_failure")] == [1, 1]
    assert result["accuracy"] == pytest.approx(0.6)
    assert result["balanced_accuracy"] == pytest.approx((2 / 3 + 1 / 2) / 2)
    assert result["auroc"] == pytest.approx(4 / 6)  # pairs (success above failure): 4 of 6


def test_interval_spans_what_the_files_disagree_on() -> None:
    """A file we label perfectly and one we label all wrong, of equal size: draws of both
    copies of one file give 1 and 0, so the 95 % interval is [0, 1]; identical files give a
    point; no draws, or one file with labels, give no interval; a seed repeats its interval."""
    right = (np.array([True, False] * 10), np.array([True, False] * 10))
    wrong = (np.array([True, False] * 10), np.array([False, True] * 10))
    spread = file_interval([right, wrong], draws=400, seed=1)
    assert spread is not None
    assert spread["accuracy"] == [0.0, 1.0] and spread["balanced_accuracy"] == [0.0, 1.0]
    assert spread == file_interval([right, wrong], draws=400, seed=1)
    assert file_interval([wrong, right, wrong], draws=0, seed=1) is None
    point = file_interval([right, right, right], draws=100, seed=1)
    assert point is not None and point["accuracy"] == [1.0, 1.0]
    empty = (np.zeros(0, bool), np.zeros(0, bool))
    assert file_interval([right, empty], draws=100, seed=1) is None


def test_interval_balanced_accuracy_with_one_class_in_a_draw() -> None:
    """A file with only reference successes and one with only failures: a draw of one kind
    has one class, whose rate is its balanced accuracy (no NaN reaches the interval)."""
    successes = (np.ones(10, bool), np.array([True] * 8 + [False] * 2))
    failures = (np.zeros(10, bool), np.zeros(10, bool))
    interval = file_interval([successes, failures], draws=400, seed=0)
    assert interval is not None
    assert interval["balanced_accuracy"] == pytest.approx([0.8, 1.0])
    assert np.isfinite(interval["accuracy"]).all()


def test_compare_with_reference_gives_groups_of_several_files_an_interval(tmp_path: Path) -> None:
    """A data set of two Mug files (our labels under ``ours/<file stem>``): the Mug and
    overall groups get an interval over the two files, each file none, and the text says it."""
    ours = tmp_path / "ours"
    files = []
    for name, flex, held in (
        ("Mug_a_1.0", [1, 0, 1, 1], [1, 0, 1, 1]),
        ("Mug_b_1.0", [1, 0], [0, 1]),
    ):
        path = tmp_path / f"{name}.h5"
        with h5py.File(path, "w") as handle:
            handle["grasps/transforms"] = np.tile(np.eye(4), (len(flex), 1, 1))
            handle["grasps/qualities/flex/object_in_gripper"] = np.array(flex)
        labels = ours / name
        labels.mkdir(parents=True)
        run = {"object": "gen_mug", "grasps_sha256": file_digest(path)}
        (labels / "run.json").write_text(json.dumps(run))
        success = np.array(held, dtype=bool)
        failure = np.array(["" if s else "missed" for s in success])
        np.savez(labels / "labels.npz", success=success, failure=failure, score=success * 1.0)
        files.append(path)
    comparison = compare_with_reference(ours, files, draws=200, seed=0)
    assert all("interval" not in row for row in comparison["files"])
    for group in ("Mug", "overall"):
        interval = comparison["groups"][group]["interval"]
        assert interval["files"] == 2 and interval["accuracy"] == [0.0, 1.0]
    assert "[overall] 95 % interval over its 2 files (200 resamples)" in comparison_text(comparison)
    assert "interval" not in compare_with_reference(ours, files)["groups"]["overall"]
