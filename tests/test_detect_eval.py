"""`simgrasp detect-eval` end to end on real YCB meshes: tables, CSV and the accuracy plot; its
resume after a SIGKILL and its lock on a generated tool."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
import warnings
from dataclasses import asdict, replace
from pathlib import Path

import pytest

from simgrasp.assets.registry import load_object
from simgrasp.cli import main
from simgrasp.evaluation.detection_eval import (
    evaluate_detection,
    evaluate_object,
    plot_accuracy_vs_noise,
)
from simgrasp.evaluation.detection_run import DETECTIONS_FILE


@pytest.mark.usefixtures("ycb_dir")
def test_detect_eval_writes_the_tables_csv_and_plot(tmp_path: Path, capsys) -> None:
    argv = ["detect-eval", "--objects", "025_mug,048_hammer", "--noise", "0,0.05"]
    assert main([*argv, "--seeds", "2", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "### quadric: detection accuracy (mean ± std over 2 seeds)" in out
    assert "### tenpas: detection accuracy" in out
    rows = list(csv.DictReader((tmp_path / "detect_eval.csv").open()))
    assert len(rows) == 2 * 2 * 2 * 2  # objects x sigmas x seeds x detectors
    quadric_at_zero = [r for r in rows if r["detector"] == "quadric" and r["sigma"] == "0.0"]
    assert all(r["handle_recall"] == "True" for r in quadric_at_zero)
    assert (tmp_path / "accuracy_vs_noise.png").stat().st_size > 10_000


def test_plot_of_a_noise_level_without_candidates_has_a_gap_not_a_warning(
    ycb_dir: str, tmp_path: Path
) -> None:
    """A sigma where no seed yielded a candidate (accuracy NaN in every seed) is left out of
    its object's line, without numpy's 'Mean of empty slice' warning."""
    records = evaluate_object("014_lemon", "quadric", [0.0], [0], ycb_dir)
    records.append(replace(records[0], sigma=0.1, candidates=0, accuracy=float("nan")))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        path = plot_accuracy_vs_noise(records, tmp_path / "plot.png")
    assert path.stat().st_size > 0


def test_detect_eval_resumes_after_sigkill_and_holds_its_out(tmp_path: Path) -> None:
    """Kill -9 a real detect-eval mid-run: the rerun runs only the missing detections, each
    ends with exactly one record, those of the killed run are whole; a second run on the same
    --out while the first runs, and a run with another gripper width, are refused."""
    out = tmp_path / "out"
    command = [sys.executable, "-m", "simgrasp", "detect-eval", "--objects", "gen_hammer"]
    command += ["--detector", "quadric", "--seeds", "10", "--noise", "0,0.02", "--out", str(out)]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    log = out / DETECTIONS_FILE
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and process.poll() is None:
        if log.exists() and log.read_bytes().count(b"\n") >= 2:
            break
        time.sleep(0.05)
    assert process.poll() is None, "detect-eval ended before it could be killed"
    second = subprocess.run(command, capture_output=True, text=True, check=False, timeout=120)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    assert second.returncode == 2 and "is in use by another run" in second.stderr, second.stderr
    killed = [json.loads(line) for line in log.read_text().splitlines()]
    assert 2 <= len(killed) < 20
    done = subprocess.run(command, capture_output=True, text=True, check=False, timeout=600)
    assert done.returncode == 0, done.stderr
    keys = [(r["seed"], r["sigma"]) for r in map(json.loads, log.read_text().splitlines())]
    assert sorted(keys) == sorted((seed, sigma) for seed in range(10) for sigma in (0.0, 0.02))
    rows = list(csv.DictReader((out / "detect_eval.csv").open()))
    assert [(int(r["seed"]), float(r["sigma"])) for r in rows] == [
        (seed, sigma) for seed in range(10) for sigma in (0.0, 0.02)
    ]
    asset = load_object("gen_hammer")
    record = killed[-1]
    fresh = asdict(evaluate_detection(asset, "quadric", record["sigma"], record["seed"]))
    untimed = [{k: v for k, v in r.items() if not k.startswith("t_")} for r in (record, fresh)]
    assert untimed[0] == untimed[1]
    other = subprocess.run(
        [*command, "--gripper-width", "0.1"], capture_output=True, text=True, timeout=120
    )
    assert other.returncode == 2 and "detections of another run" in other.stderr, other.stderr
