"""Benchmarks on a machine without the optional data: they run what they can and say what they
skipped, without a traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

BENCHMARKS = Path(__file__).parents[1] / "benchmarks"
WITHOUT_DATA = {
    k: v for k, v in os.environ.items() if k not in ("MENAGERIE_ROOT", "SIMGRASP_YCB_DIR")
}


def run_benchmark(name: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(BENCHMARKS / name), *args],
        capture_output=True,
        text=True,
        timeout=600,
        env=WITHOUT_DATA,
        check=False,
    )


def test_bench_trial_runs_the_builtin_gripper_and_says_it_skipped_the_robotiq() -> None:
    done = run_benchmark("bench_trial.py", "--repeats", "1")
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr
    rows = [line.split()[0] for line in done.stdout.splitlines() if line.strip()]
    assert "builtin" in rows
    assert "skipped robotiq_2f85" in done.stdout and "MENAGERIE_ROOT" in done.stdout


def test_a_benchmark_that_needs_ycb_says_so_in_one_line() -> None:
    done = run_benchmark("bench_detect.py", "--runs", "1")
    assert done.returncode != 0
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().count("\n") == 0 and "SIMGRASP_YCB_DIR" in done.stderr


def test_bench_single_view_times_the_rendered_views_and_says_it_skipped_the_real_ones(
    tmp_path: Path,
) -> None:
    done = subprocess.run(
        [sys.executable, str(BENCHMARKS / "bench_single_view.py"), "--runs", "1"],
        capture_output=True,
        text=True,
        timeout=600,
        env={**WITHOUT_DATA, "SIMGRASP_REAL_DIR": str(tmp_path / "absent")},
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    rows = [line for line in done.stdout.splitlines() if line.startswith("| sim ")]
    assert len(rows) == 4
    assert all(float(row.split("|")[5]) > 0 for row in rows)  # the with / without ratio
    assert "real clouds skipped" in done.stdout and "absent" in done.stdout
