"""Spawned worker pools: workers exit when their parent process dies without shutting down."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from simgrasp.runs.process_pool import PARENT_CHECK_S

PARENT = """
import os, time
from simgrasp.runs.process_pool import spawn_pool
pool = spawn_pool(1)
print(pool.submit(os.getpid).result(), flush=True)
time.sleep(120)
"""


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie left for an absent reaper counts as exited)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def test_workers_exit_when_the_parent_is_killed() -> None:
    parent = subprocess.Popen([sys.executable, "-c", PARENT], stdout=subprocess.PIPE, text=True)
    try:
        worker = int(parent.stdout.readline())
        assert _alive(worker)
    finally:
        parent.send_signal(signal.SIGKILL)  # the parent alone: no pool shutdown runs
        parent.wait()
    deadline = time.monotonic() + 10 * PARENT_CHECK_S
    while _alive(worker) and time.monotonic() < deadline:
        time.sleep(0.1)
    if _alive(worker):
        os.kill(worker, signal.SIGKILL)
        raise AssertionError(f"worker {worker} outlived its killed parent")
