"""Spawned worker pools: workers exit when their parent process dies without shutting down."""

from __future__ import annotations

import multiprocessing
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

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
        assert parent.stdout is not None
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


def _pid(item: int) -> int:
    """The task of the runs below: which worker process ran ``item``."""
    time.sleep(0.05)  # long enough that both workers take items
    return os.getpid()


def _pid_in_pairs(item: int, pairs: Any) -> int:
    """As :func:`_pid`, two items at a time: each waits at the ``pairs`` barrier for the
    other worker's."""
    pairs.wait(timeout=120)
    return os.getpid()


def test_runs_inside_a_shared_pool_use_the_same_workers() -> None:
    """Two runs of the engine inside ``shared_pool`` (a data set's files) are served by the
    same worker processes, which exit at the block's end; runs outside it spawn their own."""
    from simgrasp.runs.engine import RunConfig, Work, run_tasks
    from simgrasp.runs.process_pool import shared_pool

    config = RunConfig(workers=2, progress=False)
    with shared_pool(2), multiprocessing.Manager() as manager:
        pairs = manager.Barrier(2)  # both workers take part in the first run, however slow
        first = set(run_tasks(Work(_pid_in_pairs, (pairs,)), range(8), config))
        second = set(run_tasks(Work(_pid), range(8), config))
    assert second <= first and os.getpid() not in first
    deadline = time.monotonic() + 10 * PARENT_CHECK_S
    while any(_alive(pid) for pid in first) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(_alive(pid) for pid in first)
    alone = set(run_tasks(Work(_pid), range(8), config))
    assert alone.isdisjoint(first)


def _backend_in_worker(_: int) -> tuple[str | None, str]:
    """The task below: the forced backend a worker was given and the one it renders with."""
    from simgrasp.gl_platform import FORCE_ENV
    from simgrasp.scenes.render import select_backend

    return os.environ.get(FORCE_ENV), select_backend()


def test_workers_render_with_the_backend_of_the_process_that_starts_them() -> None:
    """A worker never probes GL on its own (a probe timing out on a loaded machine switched
    one Ray worker to ray casting, and its trials' depth, grasps and lift heights changed)."""
    from simgrasp.runs.process_pool import spawn_pool
    from simgrasp.scenes.render import select_backend

    pool = spawn_pool(1)
    try:
        given, used = pool.submit(_backend_in_worker, 0).result(timeout=120)
    finally:
        pool.shutdown()
    assert given == used == select_backend()
