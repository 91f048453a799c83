"""Wall-clock time per detector step (the paper's Table III), for ``Detection.timings_s``."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

from simgrasp.perception import import_open3d


def new_timings() -> dict[str, float]:
    """An empty table of step times (s). Open3D is imported first, so its one-time import
    (about a second) is not charged to a process's first voxelize step."""
    import_open3d()
    return {}


@contextmanager
def timed(timings: dict[str, float], step: str) -> Iterator[None]:
    """Add the wall-clock seconds the block takes to ``timings[step]``."""
    start = time.perf_counter()
    yield
    timings[step] = timings.get(step, 0.0) + time.perf_counter() - start
