"""Worker pools for parallel runs: spawned processes that exit when their parent does.

Workers are started with ``spawn`` (a GL context made before a ``fork`` hangs the child). A
pool's workers watch their parent: if it dies without shutting the pool down (``SIGKILL``, a
job scheduler's ``SIGTERM``, a crash), each worker exits within ``PARENT_CHECK_S`` seconds
instead of lingering with its simulator and renderer memory.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from concurrent.futures import ProcessPoolExecutor

PARENT_CHECK_S = 1.0
"""How often (s) a worker checks that its parent process is still alive."""


def spawn_pool(workers: int) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``workers`` spawned processes that exit with this one."""
    return ProcessPoolExecutor(
        workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_exit_with_parent,
        initargs=(os.getpid(),),
    )


def _exit_with_parent(parent_pid: int) -> None:
    """Worker initializer: a daemon thread ends the worker once ``parent_pid`` is gone (the
    worker is then re-parented, so its parent id changes)."""

    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(PARENT_CHECK_S)
        os._exit(1)

    threading.Thread(target=watch, name="exit-with-parent", daemon=True).start()
