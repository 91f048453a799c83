"""The benchmark end to end on two scenes of handles-mini (generated objects, no data needed):
a method outside simgrasp scored from its files, a repeated run's records, a changed suite
definition refused on resume, and broken answers named in their scenes' records."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from simgrasp.bench.grasp_files import AnswerProblem, answer_grasps
from simgrasp.bench.runner import score_suite
from simgrasp.bench.scene_task import AnswerSource
from simgrasp.bench.suites import SUITES, suite_by_name
from simgrasp.cli import main
from simgrasp.errors import SimgraspError
from simgrasp.runs.engine import RunConfig

METHOD = Path(__file__).parent / "bench_method.py"
PART = ("2", "9")
"""A hammer lying alone in ideal depth, and one standing among five neighbors in Kinect depth:
the two quickest scenes of handles-mini for the oracle."""


def _records(out: Path) -> list[dict]:
    rows = [json.loads(line) for line in (out / "trials.jsonl").read_text().splitlines()]
    for row in rows:
        row.pop("timings_s")
    return sorted(rows, key=lambda row: row["scene"])


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("export")
    assert (
        main(["bench", "export", "handles-mini", str(folder), "--no-progress", "--scenes", *PART])
        == 0
    )
    return folder


def test_suites_are_frozen_and_sized() -> None:
    assert len(SUITES["handles-v1"].scenes()) >= 200
    mini = SUITES["handles-mini"]
    assert len(mini.scenes()) <= 12
    assert not any(scene.needs_ycb for scene in mini.scenes())
    assert mini.digest() == suite_by_name("handles-mini").digest()
    assert replace(mini, protocol="fast").digest() != mini.digest()
    assert len({s.id for s in SUITES["handles-v1"].scenes()}) == len(SUITES["handles-v1"].scenes())


def test_ycb_suite_without_ycb_folder_is_one_line(monkeypatch, capsys) -> None:
    monkeypatch.delenv("SIMGRASP_YCB_DIR", raising=False)
    assert main(["bench", "export", "handles-v1", "/nonexistent/x", "--no-progress"]) == 2
    error = capsys.readouterr().err.strip()
    assert "\n" not in error and "SIMGRASP_YCB_DIR" in error and "96 scenes" in error


def test_export_holds_what_a_method_reads(exported: Path) -> None:
    scenes = json.loads((exported / "suite.json").read_text())["scenes"]
    assert len(scenes) == 2
    for scene in scenes:
        observation = json.loads((exported / scene / "observation.json").read_text())
        cloud = np.load(exported / scene / observation["cloud"])
        assert cloud.ndim == 2 and cloud.shape[1] == 3 and len(cloud) > 100
        assert cloud[:, 2].min() > observation["table_top_z"] - 0.03  # world frame, m (noisy)
        assert len(np.load(exported / scene / observation["scene_cloud"])) > len(cloud)
        view = observation["views"][0]
        depth = np.load(exported / scene / view["depth"])
        assert depth.shape == (view["intrinsics"]["height"], view["intrinsics"]["width"])
        assert np.asarray(view["world_T_camera"]).shape == (4, 4)
        assert 0 < observation["gripper"]["max_opening"] < 0.2


def test_method_outside_simgrasp_is_scored(exported: Path, tmp_path: Path) -> None:
    grasps = tmp_path / "grasps"
    subprocess.run([sys.executable, str(METHOD), str(exported), str(grasps)], check=True)
    out = tmp_path / "scored"
    command = ["bench", "score", "handles-mini", str(grasps), "--out", str(out)]
    assert main([*command, "--no-progress", "--scenes", *PART]) == 0
    records = _records(out)
    assert [r["method"] for r in records] == ["files", "files"]
    assert all(r["attempts"] == 1 and r["grasp"] is not None for r in records)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scenes"] == 2
    assert summary["success"] == sum(r["success"] for r in records) / 2
    for key in ("on_handle", "solvable", "on_handle_of_solvable"):
        assert key in summary
    assert "| placement |" in (out / "report.md").read_text()
    in_process = tmp_path / "in-process"
    command = ["bench", "run", "handles-mini", "--method", "bench_method:propose"]
    assert main([*command, "--out", str(in_process), "--no-progress", "--scenes", PART[0]]) == 0
    same = {**_records(in_process)[0], "method": "files", "grasp_source": "file"}
    assert same == {**records[0], "suite_sha256": same["suite_sha256"]}  # the same outcome


def test_repeated_run_same_records_and_changed_definition_refused(tmp_path: Path) -> None:
    first, second = tmp_path / "first", tmp_path / "second"
    for out in (first, second, first):  # the third resumes a finished run: nothing redone
        command = ["bench", "run", "handles-mini", "--method", "antipodal", "--out", str(out)]
        assert main([*command, "--attempts", "3", "--no-progress", "--scenes", "2"]) == 0
    assert _records(first) == _records(second)
    assert len(_records(first)) == 1
    assert 1 <= _records(first)[0]["attempts"] <= 3
    changed = replace(suite_by_name("handles-mini").part((2,)), protocol="fast")
    with pytest.raises(SimgraspError, match="suite_sha256") as refused:
        score_suite(changed, first, AnswerSource("antipodal"), RunConfig(progress=False), [])
    assert "\n" not in str(refused.value)


def test_missing_and_invalid_answers_are_named_failures(tmp_path: Path) -> None:
    grasps = tmp_path / "grasps"
    grasps.mkdir()
    part = suite_by_name("handles-mini").part((2, 9))
    broken = part.scenes()[0].id
    (grasps / f"{broken}.json").write_text('{"grasps": [{"world_T_tcp": [[1, 0], [0, 1]]}]}')
    source = AnswerSource(grasps_dir=str(grasps))
    records = score_suite(part, tmp_path / "out", source, RunConfig(progress=False), [])
    assert records[0]["failure"] == "invalid_grasp_file"
    assert "grasp 0" in records[0]["failure_detail"] and broken in records[0]["failure_detail"]
    assert records[1]["failure"] == "missing_grasp_file" and not records[1]["success"]


@pytest.mark.parametrize(
    ("payload", "detail"),
    [
        ({"grasp": []}, 'no "grasps"'),
        ({"grasps": 3}, "not a list"),
        ({"grasps": [{"width": 0.05}]}, "world_T_tcp"),
        ({"grasps": [{"world_T_tcp": (2 * np.eye(4)).tolist()}]}, "rotation"),
        ({"grasps": [{"world_T_tcp": np.eye(4).tolist(), "width": 0.5}]}, "width"),
        ({"grasps": [{"world_T_tcp": [["a"] * 4] * 4}]}, "numbers"),
    ],
)
def test_answer_problems_are_named(payload: object, detail: str) -> None:
    problem = answer_grasps(payload, 0.085, "test", "answer.json")
    assert isinstance(problem, AnswerProblem) and problem.failure == "invalid_grasp_file"
    assert detail in problem.detail


def test_valid_answer_reads_best_first() -> None:
    pose = np.eye(4)
    pose[:3, 3] = [0.1, 0.0, 0.2]
    payload = {
        "grasps": [
            {"world_T_tcp": pose.tolist(), "width": None},
            {"world_T_tcp": np.eye(4).tolist(), "width": 0.04},
        ]
    }
    grasps = answer_grasps(payload, 0.085, "test", "answer.json")
    assert not isinstance(grasps, AnswerProblem)
    assert [g.width for g in grasps] == [0.085, 0.04]
    assert np.allclose(grasps[0].world_T_tcp, pose)


def test_scores_read_against_the_oracle() -> None:
    from simgrasp.bench.summary import report_text, summarize

    def row(obj: str, success: bool, on_handle: bool, solvable: bool) -> dict:
        axes = {"object": obj, "placement": "stable", "clutter": 0, "sensor": "ideal"}
        verdict = {"solvable": solvable, "liftable": solvable or success}
        return {**axes, "success": success, "on_handle": on_handle, **verdict, "failure": None}

    rows = [row("a", True, True, True), row("a", False, False, True), row("b", True, True, False)]
    summary = summarize(rows)
    assert summary["scenes"] == 3 and summary["solvable"] == round(2 / 3, 4)
    assert summary["on_handle_of_solvable"] == 0.5
    assert summary["counts"]["beyond_oracle"] == 1
    assert summary["by"]["object"]["b"]["on_handle_of_solvable"] is None
    assert "| b | 1 | 1.00 | 1.00 | 0.00 | - |" in report_text(summary, "t")
