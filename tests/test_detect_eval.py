"""`simgrasp detect-eval` end to end on real YCB meshes: tables, CSV and the accuracy plot."""

from __future__ import annotations

import csv
import warnings
from dataclasses import replace
from pathlib import Path

import pytest

from simgrasp.cli import main
from simgrasp.evaluation.detection_eval import evaluate_object, plot_accuracy_vs_noise


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
