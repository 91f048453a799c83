"""Worker pools for parallel runs: spawned processes that exit when their parent does.

A run spawns its own pool, unless it runs inside :func:`shared_pool` (a data set's files
labeled one after another): then its workers stay up from one object to the next, each run
warming them up for its own object.

Workers are started with ``spawn`` (a GL context made before a ``fork`` hangs the child). A
pool's workers watch their parent: if it dies without shutting the pool down (``SIGKILL``, a
job scheduler's ``SIGTERM``, a crash), each worker exits within ``PARENT_CHECK_S`` seconds
instead of lingering with its simulator and renderer memory.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor

PARENT_CHECK_S = 1.0
"""How often (s) a worker checks that its parent process is still alive."""

_SHARED: list[tuple[int, ProcessPoolExecutor]] = []
"""The pools of the :func:`shared_pool` blocks this process is in, innermost last."""


def spawn_pool(workers: int) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``workers`` spawned processes that exit with this one and
    render with this process's backend (:func:`simgrasp.scenes.render.worker_environment`)."""
    from simgrasp.scenes.render import worker_environment  # here: a worker never imports it

    return ProcessPoolExecutor(
        workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_start_worker,
        initargs=(os.getpid(), worker_environment()),
    )


def _start_worker(parent_pid: int, environment: dict[str, str]) -> None:
    """Worker initializer: set ``environment`` (before anything renders), and a daemon thread
    ends the worker once ``parent_pid`` is gone (the worker is then re-parented, so its
    parent id changes)."""
    os.environ.update(environment)

    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(PARENT_CHECK_S)
        os._exit(1)

    threading.Thread(target=watch, name="exit-with-parent", daemon=True).start()


@contextlib.contextmanager
def shared_pool(workers: int) -> Iterator[None]:
    """Within the block, runs of ``workers`` local workers (:func:`pool_for`) use one pool
    of spawned processes instead of each spawning its own; it is shut down at the end."""
    if workers <= 1:
        yield
        return
    pool = spawn_pool(workers)
    _SHARED.append((workers, pool))
    try:
        yield
    finally:
        _SHARED.pop()
        pool.shutdown(cancel_futures=True)


def pool_for(workers: int) -> tuple[ProcessPoolExecutor, bool]:
    """A pool of ``workers`` processes for one run and whether the run owns it (shuts it down
    when done): the innermost :func:`shared_pool` of that size, else a new one."""
    if _SHARED and _SHARED[-1][0] == workers:
        return _SHARED[-1][1], False
    return spawn_pool(workers), True
