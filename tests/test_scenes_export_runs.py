"""``simgrasp scenes export`` run safety: one run per folder, recorded settings, resume."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

from simgrasp.cli import main
from simgrasp.evaluation.scene_export import export_identity, spans
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.runs.out_dir import claim_out_dir
from simgrasp.scenes.config import SceneConfig

EXPORT = ["scenes", "export", "--object", "gen_hammer", "--views", "1"]


def _export(out: Path, *flags: str) -> int:
    return main([*EXPORT, "--out", str(out), *flags])


def _error(capsys: pytest.CaptureFixture[str]) -> str:
    """The one error line a refused command printed."""
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("simgrasp scenes: error: ")
    return line


def test_a_rerun_skips_finished_seeds_and_redoes_a_torn_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """More --seeds add only the missing seeds; a killed write's temporary file is removed,
    and a seed missing a view is written again."""
    out = tmp_path / "views"
    assert _export(out, "--seeds", "1") == 0
    first = out / "gen_hammer_s0_view0.pcd"
    written = first.stat().st_mtime_ns
    (out / ".gen_hammer_s1_view0.pcd.x1.part").write_bytes(b"torn")
    capsys.readouterr()
    assert _export(out, "--seeds", "2") == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines == [
        f"skipped seeds 0: their views are already in {out}",
        str(out / "gen_hammer_s1_view0.pcd"),
    ]
    assert first.stat().st_mtime_ns == written
    assert sorted(p.name for p in out.glob("*.pcd")) == [
        "gen_hammer_s0_view0.pcd",
        "gen_hammer_s1_view0.pcd",
    ]
    assert not list(out.glob(".*.part"))


def test_changed_settings_are_refused_and_leave_the_folder_alone(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "views"
    assert _export(out, "--seeds", "1") == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    capsys.readouterr()
    assert _export(out, "--seeds", "2", "--sensor", "kinect") == 2
    assert "sensor.kind: 'ideal' -> 'kinect'" in _error(capsys)
    assert _export(out, "--seeds", "1", "--clutter", "1", "--clutter-objects", "gen_mug") == 2
    assert "scene.clutter: 0 -> 1" in _error(capsys)
    assert main([*EXPORT[:3], "gen_mug", "--views", "1", "--out", str(out)]) == 2
    assert "object: 'gen_hammer' -> 'gen_mug'" in _error(capsys)
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.name != ".simgrasp.lock"} == {
        name: data for name, data in before.items() if name != ".simgrasp.lock"
    }


def test_a_held_folder_and_unrecorded_views_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "views"
    with claim_out_dir(out, ["simgrasp", "scenes", "export", "--out", str(out)]):
        assert _export(out, "--seeds", "1") == 2
    assert "is in use by another run" in _error(capsys)
    (out / "old_s0_view0.pcd").write_bytes(b"an earlier version's view")
    assert _export(out, "--seeds", "1") == 2
    assert f"--out {out} holds PCD files with no run.json" in _error(capsys)
    other = tmp_path / "labels"
    with claim_out_dir(other, ["simgrasp", "label-grasps", "gen_hammer"]):
        pass
    assert _export(other, "--seeds", "1") == 2
    assert "holds the output of `simgrasp label-grasps`" in _error(capsys)


def test_the_identity_records_a_mesh_files_digest(tmp_path: Path) -> None:
    mesh = tmp_path / "box.stl"
    trimesh.creation.box((0.05, 0.04, 0.03)).export(mesh)
    scene, sensor = SceneConfig(), SensorSettings()
    before = export_identity(str(mesh), str(mesh), scene, sensor)
    trimesh.creation.box((0.06, 0.04, 0.03)).export(mesh)
    after = export_identity(str(mesh), str(mesh), scene, sensor)
    assert before["mesh_sha256"] != after["mesh_sha256"]
    assert "mesh_sha256" not in export_identity("gen_hammer", "gen_hammer_s0", scene, sensor)


def test_spans_joins_consecutive_seeds() -> None:
    assert spans([0, 1, 2, 5, 7, 8]) == "0-2, 5, 7-8"
    assert spans([4]) == "4"
