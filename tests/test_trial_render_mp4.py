"""``trial --render out.mp4`` writes a real mp4 (ffmpeg from the imageio-ffmpeg wheel): it
decodes back, at the key frames' size, and its frames show different moments."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from simgrasp.scenes.key_frames import RENDER_SIZE


def test_trial_render_mp4_decodes(tmp_path):
    import imageio_ffmpeg

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    movie = tmp_path / "out.mp4"
    subprocess.run(
        [sys.executable, "-m", "simgrasp", "trial", "gen_hammer", "--render", str(movie)],
        env=env, check=True, capture_output=True, text=True,
    )  # fmt: skip
    assert movie.read_bytes()[4:8] == b"ftyp"  # an ISO media file
    reader = imageio_ffmpeg.read_frames(str(movie))
    meta = next(reader)
    assert tuple(meta["size"]) == RENDER_SIZE
    width, height = RENDER_SIZE
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    assert len(frames) > 0
    assert frames[0].std() > 5  # a picture, not a flat frame
    assert np.abs(frames[-1].astype(int) - frames[0]).mean() > 1.0  # not all the same moment
