"""Every script in ``examples/`` runs as a newcomer would run it (a fresh process, small
arguments) and prints what it promises."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

CASES = {
    "detect_npy.py": ([], "handles"),
    "run_chain.py": (["gen_hammer", "0"], "lifted: True"),
    "label_sampled_grasps.py": (["12"], "grasps lift the hammer"),
    "sweep_two_detectors.py": (["sweep", "1"], "centroid"),
    "env_policy.py": (["1"], "episode 0:"),
    "label_your_mesh.py": (["12"], "grasps hold the object"),
}


def test_every_example_is_run_here() -> None:
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted(CASES)


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted(CASES))
def test_example_runs(script: str, tmp_path: Path) -> None:
    args, expected = CASES[script]
    env = {**os.environ, "PYTHONPATH": str(EXAMPLES.parent)}
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / script), *args],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert expected in done.stdout
