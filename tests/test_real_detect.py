"""``detect-eval --real``: the real-data manifest, its bad inputs (each one line, exit code 2)
and a run on real clouds (needs ``$SIMGRASP_REAL_DIR`` or ``../shared/real``; skipped cleanly
without it)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from simgrasp.cli import main
from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest
from simgrasp.resources import model_path

from shapes import mug_like

needs_real = pytest.mark.real  # skipped without the real clouds (tests/data_needs.py)
HANDLE_BOX = {"type": "box", "center": [0.06, 0.0, 0.045], "half_extents": [0.03, 0.012, 0.04]}


def _manifest(tmp_path: Path, entry: str, handle: dict = HANDLE_BOX, scale: float = 1.0) -> Path:
    """A one-cloud manifest beside a synthetic mug (``mug.xyz``, coordinates x ``scale``)."""
    np.savetxt(tmp_path / "mug.xyz", mug_like(seed=0, density=1e6).points * scale)
    labels = {"objects": {"mug": {"whole_object": False, "regions": [handle]}}}
    (tmp_path / "labels.json").write_text(json.dumps(labels))
    path = tmp_path / "manifest.toml"
    path.write_text(
        '[[cloud]]\nname = "mug"\ndataset = "synthetic"\nlabels = "labels.json"\n'
        "viewpoint = [0.3, 0.0, 0.05]\n" + entry
    )
    return path


def _fails(argv: list[str], capsys) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    return err


def _eval(manifest: Path, out: Path) -> list[str]:
    return ["detect-eval", "--real", str(manifest), "--seeds", "1", "--out", str(out)]


def test_a_missing_cloud_file_is_one_line(tmp_path: Path, capsys) -> None:
    manifest = _manifest(tmp_path, 'path = "nowhere.xyz"\nsplit = "tune"\n')
    err = _fails([*_eval(manifest, tmp_path / "o"), "--real-dir", str(tmp_path)], capsys)
    assert "cloud mug: no file" in err and "nowhere.xyz" in err


def test_a_label_outside_the_cloud_is_one_line(tmp_path: Path, capsys) -> None:
    far = {**HANDLE_BOX, "center": [1.5, 0.0, 0.0]}
    manifest = _manifest(tmp_path, f'path = "{tmp_path}/mug.xyz"\nsplit = "tune"\n', far)
    err = _fails(_eval(manifest, tmp_path / "o"), capsys)
    assert "cloud mug: its handle label holds 0" in err and "outside the cloud" in err


def test_a_cloud_in_millimetres_read_as_meters_is_one_line(tmp_path: Path, capsys) -> None:
    manifest = _manifest(tmp_path, f'path = "{tmp_path}/mug.xyz"\nsplit = "tune"\n', scale=1000)
    err = _fails(_eval(manifest, tmp_path / "o"), capsys)
    assert "cloud mug" in err and "millimetres" in err


@pytest.mark.parametrize(
    ("entry", "problem"),
    [
        ('path = "m.xyz"\nsplit = "test"\n', "split must be tune or holdout"),
        ('path = "m.xyz"\nsplit = "tune"\nunits = "km"\n', "units must be one of m, mm, cm"),
        ('split = "tune"\n', "missing 'path'"),
        ('path = "m.xyz"\nsplit = "tune"\ncolour = 1\n', "unknown key(s) colour"),
        ('path = "m.xyz"\nsplit = "tune"\nlabel_key = "cup"\n', "has no entry 'cup'"),
    ],
)
def test_bad_manifest_entries_are_one_line(tmp_path: Path, capsys, entry: str, problem: str):
    err = _fails(_eval(_manifest(tmp_path, entry), tmp_path / "o"), capsys)
    assert "cloud mug" in err and problem in err


def test_millimetre_units_scale_the_cloud_and_viewpoint(tmp_path: Path) -> None:
    entry = f'path = "{tmp_path}/mug.xyz"\nsplit = "tune"\nunits = "mm"\n'
    manifest = _manifest(tmp_path, entry, scale=1000)
    manifest.write_text(manifest.read_text().replace("[0.3, 0.0, 0.05]", "[300.0, 0.0, 50.0]"))
    (cloud,) = read_manifest(manifest)
    assert np.allclose(cloud.viewpoint, [0.3, 0.0, 0.05])
    points = load_real_cloud(cloud)
    assert np.ptp(points[:, 2]) == pytest.approx(0.09, abs=0.005)


def test_the_shipped_manifest_names_tune_and_holdout_clouds(tmp_path: Path) -> None:
    clouds = read_manifest(model_path("handles", "real_detect.toml"), tmp_path)
    splits = {c.name: c.split for c in clouds}
    assert splits["gpd_table_mug"] == splits["affordancegrasp_mug1"] == "holdout"
    assert {splits[f"knife{k}"] for k in range(1, 6)} == {"tune"}


def test_the_readmes_manifest_path_finds_the_shipped_file_from_any_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``models/handles/real_detect.toml`` as the README writes it, run where no ``models/``
    folder is (an installed wheel), is the shipped manifest; another missing path stays one
    line naming it."""
    monkeypatch.chdir(tmp_path)
    shipped = read_manifest(model_path("handles", "real_detect.toml"), tmp_path)
    relative = read_manifest(Path("models/handles/real_detect.toml"), tmp_path)
    assert [c.name for c in relative] == [c.name for c in shipped]
    with pytest.raises(ValueError, match="models/handles/nothing.toml: no such manifest file"):
        read_manifest(Path("models/handles/nothing.toml"), tmp_path)


@needs_real
def test_detect_eval_real_on_a_tiny_manifest_resumes_without_duplicates(
    real_dir: Path, tmp_path: Path, capsys
) -> None:
    shipped = model_path("handles", "real_detect.toml").read_text()
    knife3 = "[[cloud]]" + next(t for t in shipped.split("[[cloud]]") if '"knife3"' in t)
    labels = model_path("handles", "real_handles.json")
    manifest = tmp_path / "tiny.toml"
    manifest.write_text(knife3.replace('"real_handles.json"', json.dumps(str(labels))))
    argv = [*_eval(manifest, tmp_path), "--real-dir", str(real_dir)]
    assert main([*argv, "--real-configs", "default,tenpas"]) == 0
    assert "| knife3 (tune) |" in capsys.readouterr().out
    assert main([*argv, "--real-configs", "default,tenpas"]) == 0  # all done: nothing redone
    rows = list(csv.DictReader((tmp_path / "real_detect.csv").open()))
    assert [(r["config"], r["seed"]) for r in rows] == [("default", "0"), ("tenpas", "0")]
    default = rows[0]
    assert default["top_on_handle"] == "True"  # knife3's handle is found by the default
    assert int(default["on_handle"]) >= 0.9 * int(default["candidates"]) > 0
