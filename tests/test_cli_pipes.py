"""The command line as a pipeline stage: a reader that stops early (``| head -1``) ends the
command quietly, as it does any Unix tool."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from shapes import mug_like


def test_a_closed_stdout_ends_detect_without_a_traceback(tmp_path: Path) -> None:
    cloud = mug_like(seed=0)
    path = tmp_path / "mug.npy"
    np.save(path, np.hstack([cloud.points, cloud.normals]))
    process = subprocess.Popen(
        [sys.executable, "-m", "simgrasp", "detect", str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert process.stdout is not None
    process.stdout.close()  # the reader is gone before the first line is written
    _, err = process.communicate(timeout=120)
    assert "Traceback" not in err.decode() and "BrokenPipeError" not in err.decode(), err
    assert process.returncode != 0  # nothing reached the reader: not a success
