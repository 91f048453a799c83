"""``trial --record`` adds the replay's states and changes nothing else in the record."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path


def _trial(*extra: str) -> dict:
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    done = subprocess.run(
        [sys.executable, "-m", "simgrasp", "trial", "gen_hammer", "--json", *extra],
        env=env, check=True, capture_output=True, text=True,
    )  # fmt: skip
    record = json.loads(done.stdout)
    record.pop("timings_s")
    return record


def test_record_adds_replay_only():
    plain, recorded = _trial(), _trial("--record")
    replay = recorded.pop("replay")
    assert recorded == plain
    assert len(replay["t"]) > 100 and replay["t"] == sorted(replay["t"])
    assert [p["name"] for p in replay["phases"]][:2] == ["approach and close", "lift and hold"]
    assert replay["tcp_pose"][-1][2] > replay["tcp_pose"][0][2] - 0.2  # lifted at the end
