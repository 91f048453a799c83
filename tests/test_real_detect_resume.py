"""``detect-eval --real`` resumes only its own run: ``real_run.json`` records the manifest, real
data folder and each cloud's inputs (a change is refused in one line), and a torn last row of
``real_detect.csv`` is cut and redone. Runs on a synthetic mug written by each test."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from simgrasp.cli import main

from shapes import mug_like

HANDLE_BOX = {"type": "box", "center": [0.06, 0.0, 0.045], "half_extents": [0.03, 0.012, 0.04]}
HEADER = "cloud,dataset,split,config,seed,points,candidates,on_handle,handles,top_on_handle,"
HEADER += "detect_s"
ROW = "mug,synthetic,tune,multi_view,{seed},100,10,5,1,True,0.5\r\n"
"""A finished row of the quick ``multi_view`` setting (values made up: kept, not redone)."""


def _write_inputs(folder: Path, handle: dict = HANDLE_BOX) -> Path:
    """A one-cloud manifest in ``folder`` beside a synthetic mug and its label file."""
    np.savetxt(folder / "mug.xyz", mug_like(seed=0, density=1e6).points)
    labels = {"objects": {"mug": {"whole_object": False, "regions": [handle]}}}
    (folder / "labels.json").write_text(json.dumps(labels))
    manifest = folder / "manifest.toml"
    manifest.write_text(
        '[[cloud]]\nname = "mug"\ndataset = "synthetic"\nlabels = "labels.json"\n'
        'path = "mug.xyz"\nsplit = "tune"\nviewpoint = [0.3, 0.0, 0.05]\n'
    )
    return manifest


def _argv(manifest: Path, out: Path, seeds: int = 1) -> list[str]:
    return [
        "detect-eval",
        "--real",
        str(manifest),
        "--real-dir",
        str(manifest.parent),
        "--real-configs",
        "multi_view",
        "--seeds",
        str(seeds),
        "--out",
        str(out),
    ]


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    return err


def _seeds(out: Path) -> list[str]:
    return [r["seed"] for r in csv.DictReader((out / "real_detect.csv").open())]


def test_a_rerun_with_changed_inputs_is_refused_naming_the_change(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    inputs = tmp_path / "in"
    inputs.mkdir()
    manifest, out = _write_inputs(inputs), tmp_path / "out"
    assert main(_argv(manifest, out)) == 0
    before = (out / "real_detect.csv").read_bytes()
    text = manifest.read_text()
    manifest.write_text(text.replace("[0.3, 0.0, 0.05]", "[0.0, 0.3, 0.05]"))  # another view
    assert "manifest:" in _refused(_argv(manifest, out), capsys)
    manifest.write_text(text)
    other_dir = tmp_path / "copy"
    other_dir.mkdir()
    for name in ("mug.xyz", "labels.json"):
        (other_dir / name).write_bytes((inputs / name).read_bytes())
    err = _refused([*_argv(manifest, out), "--real-dir", str(other_dir)], capsys)
    assert "real_dir:" in err and "manifest:" not in err and "clouds" not in err
    cloud = (inputs / "mug.xyz").read_bytes()
    (inputs / "mug.xyz").write_bytes(cloud + b"0 0 0\n")  # one more point
    assert "clouds.mug.file:" in _refused(_argv(manifest, out), capsys)
    (inputs / "mug.xyz").write_bytes(cloud)
    _write_inputs(inputs, {**HANDLE_BOX, "center": [0.061, 0.0, 0.045]})
    assert "clouds.mug.label:" in _refused(_argv(manifest, out), capsys)
    assert (out / "real_detect.csv").read_bytes() == before  # nothing mixed in


def test_a_rerun_with_the_same_inputs_adds_seeds_without_duplicates(tmp_path: Path) -> None:
    """... beside a run on object meshes in the same folder, whose ``run.json`` is its own."""
    manifest, out = _write_inputs(tmp_path), tmp_path / "out"
    out.mkdir()
    (out / "run.json").write_text('{"cloud_points": 1}\n')
    assert main(_argv(manifest, out)) == 0
    recorded = json.loads((out / "real_run.json").read_text())
    assert set(recorded) == {"manifest", "real_dir", "clouds"}
    assert set(recorded["clouds"]["mug"]) == {"file", "label"}
    assert main(_argv(manifest, out, seeds=2)) == 0
    assert _seeds(out) == ["0", "1"]
    assert (out / "run.json").read_text() == '{"cloud_points": 1}\n'


def test_a_folder_without_rows_takes_the_fixed_inputs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A run stopped by a bad label before any row may be rerun with the label fixed."""
    far = {**HANDLE_BOX, "center": [1.5, 0.0, 0.0]}
    manifest, out = _write_inputs(tmp_path, far), tmp_path / "out"
    assert "outside the cloud" in _refused(_argv(manifest, out), capsys)
    _write_inputs(tmp_path)
    assert main(_argv(manifest, out)) == 0
    assert _seeds(out) == ["0"]
    assert (out / "real_run.json").is_file()


@pytest.mark.parametrize(
    "torn",
    [
        "mug,synthetic,tune,multi_v",  # killed mid-row: fields missing
        ROW.format(seed=1)[:-5],  # only the last digits of detect_s and the newline lost
        "mug,synthetic,tune,multi_view,1,100,x,5,1,True,0.5\r\n",  # a last row that is no row
    ],
)
def test_a_torn_last_row_is_cut_with_a_note_and_redone(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], torn: str
) -> None:
    manifest, out = _write_inputs(tmp_path), tmp_path / "out"
    out.mkdir()
    (out / "real_detect.csv").write_text(HEADER + "\r\n" + ROW.format(seed=0) + torn, newline="")
    assert main(_argv(manifest, out, seeds=2)) == 0
    err = capsys.readouterr().err
    assert "cut a torn last row" in err and "it runs again" in err
    rows = list(csv.DictReader((out / "real_detect.csv").open()))
    assert [r["seed"] for r in rows] == ["0", "1"]
    assert rows[0]["candidates"] == "10"  # the finished row is kept, not redone
    assert (out / "real_detect.csv").read_bytes().endswith(b"\r\n")
    assert main(_argv(manifest, out, seeds=2)) == 0  # a clean file: nothing cut or redone
    assert "cut" not in capsys.readouterr().err and _seeds(out) == ["0", "1"]


def test_a_bad_row_before_the_last_is_one_line_naming_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    manifest, out = _write_inputs(tmp_path), tmp_path / "out"
    out.mkdir()
    bad = ROW.format(seed=0).replace("True", "Tru")
    text = HEADER + "\r\n" + bad + ROW.format(seed=1)
    (out / "real_detect.csv").write_text(text, newline="")
    err = _refused(_argv(manifest, out, seeds=2), capsys)
    assert f"{out / 'real_detect.csv'}:2:" in err and "top_on_handle" in err
    assert (out / "real_detect.csv").read_bytes() == text.encode()  # left as it was


def test_rows_of_a_setting_whose_values_changed_are_refused_until_removed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``real_settings.json`` records each setting's values beside its rows: a rerun after a
    setting changed (here: the record as an older default would have left it) is refused
    naming the setting and the value, not resumed under the same name; with that setting's
    rows removed it runs again and records today's values. Another setting joins the folder."""
    manifest, out = _write_inputs(tmp_path), tmp_path / "out"
    assert main(_argv(manifest, out)) == 0
    record_file = out / "real_settings.json"
    record = json.loads(record_file.read_text())
    today = record["multi_view"]["detector"]["neighborhood_half_size"]
    record["multi_view"]["detector"]["neighborhood_half_size"] = today * 2
    record_file.write_text(json.dumps(record))
    err = _refused(_argv(manifest, out), capsys)
    assert "'multi_view'" in err and "neighborhood_half_size" in err and "delete" in err
    rows = (out / "real_detect.csv").read_text().splitlines()
    (out / "real_detect.csv").write_text(rows[0] + "\n")  # the setting's rows removed
    assert main(_argv(manifest, out)) == 0
    record = json.loads(record_file.read_text())
    assert record["multi_view"]["detector"]["neighborhood_half_size"] == today
    argv = _argv(manifest, out)
    argv[argv.index("multi_view")] = "multi_view,learned"
    assert main(argv) == 0
    assert set(json.loads(record_file.read_text())) == {"multi_view", "learned"}
    assert "classifier_sha256" in json.loads(record_file.read_text())["learned"]
