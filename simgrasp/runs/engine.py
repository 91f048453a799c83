"""Run a list of items through a task function, resumably: here, in spawned worker processes
or as Ray tasks, each worker warmed up first, each finished record appended to the run's log.

:func:`run_tasks` yields the task's records in completion order; :func:`run_resumable` runs
only the items whose record is not yet in the log, appends each new record as it finishes (a
killed run loses nothing finished; run it again and only the missing items run) and shows a
progress bar. The task, its warm-up and their arguments must be picklable (module-level
functions) for worker processes and Ray.
"""

from __future__ import annotations

import contextlib
import itertools
from collections.abc import Callable, Hashable, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass
from typing import Any, Literal

from simgrasp.errors import SimgraspError
from simgrasp.runs.record_log import RecordLog

Backend = Literal["local", "ray"]
BACKENDS: tuple[Backend, ...] = ("local", "ray")
Record = dict[str, Any]


@dataclass(frozen=True)
class RunConfig:
    """Where a run's tasks execute.

    Attributes:
        workers: worker processes (or Ray CPUs); ``1`` with the local backend runs every task
            in this process.
        backend: ``"local"`` (spawned worker processes) or ``"ray"`` (Ray tasks).
        address: the Ray cluster to join (``"auto"``: ``$RAY_ADDRESS`` or the one ``ray start``
            made); ``None`` starts a new local instance with ``workers`` CPUs.
        progress: show a progress bar (tqdm, on stderr).
    """

    workers: int = 1
    backend: Backend = "local"
    address: str | None = None
    progress: bool = True

    def __post_init__(self) -> None:
        if self.backend not in BACKENDS:
            raise SimgraspError(f"unknown backend {self.backend!r}; use 'local' or 'ray'")
        if isinstance(self.workers, bool) or not isinstance(self.workers, int) or self.workers < 1:
            raise SimgraspError(f"workers must be an integer >= 1, got {self.workers!r}")
        if self.address and self.backend != "ray":
            raise SimgraspError(f"--address {self.address} needs --backend ray")


@dataclass(frozen=True)
class Work:
    """What a run executes: ``task(item, *args)`` per item, after ``warm_up(*call, *args)``
    for each ``call`` of ``warm_calls`` (e.g. each object's model built once, or one labeler
    per worker), spread over the workers."""

    task: Callable[..., Any]
    args: tuple[Any, ...] = ()
    warm_up: Callable[..., Any] | None = None
    warm_calls: tuple[tuple[Any, ...], ...] = ()


def run_tasks(work: Work, items: Sequence[Any], config: RunConfig) -> Iterator[Any]:
    """The task's results for ``items``, in completion order; starts no worker (nor Ray) when
    there is nothing to run."""
    if not items:
        return iter(())
    if config.backend == "ray":
        return _run_ray(work, items, config)
    return _run_local(work, items, config.workers)


def workers_kept_up(config: RunConfig) -> contextlib.AbstractContextManager[Any]:
    """The workers of ``config`` held up for a block of runs (a data set's files): local
    worker processes (:func:`~simgrasp.runs.process_pool.shared_pool`) or the Ray session,
    which each :func:`run_tasks` inside uses instead of starting its own (each run still warms
    them up for its own work)."""
    if config.backend == "ray":
        from simgrasp.runs.ray_session import ray_session

        return ray_session(config.workers, config.address)
    from simgrasp.runs.process_pool import shared_pool

    return shared_pool(config.workers)


def _run_local(work: Work, items: Sequence[Any], workers: int) -> Iterator[Any]:
    """Results from ``workers`` spawned processes (``<= 1``: this process)."""
    from simgrasp.runs.process_pool import pool_for

    if workers <= 1:
        if work.warm_up:
            for call in work.warm_calls:
                work.warm_up(*call, *work.args)
        yield from (work.task(item, *work.args) for item in items)
        return
    pool, owned = pool_for(workers)
    pending: set[Future[Any]] = set()
    try:
        if work.warm_up:
            calls = [(*call, *work.args) for call in work.warm_calls]
            list(pool.map(_call, itertools.repeat(work.warm_up), calls))
        pending = {pool.submit(work.task, item, *work.args) for item in items}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield future.result()
    finally:  # on an error, drop the queued tasks instead of running them all first
        for future in pending:
            future.cancel()
        if owned:
            pool.shutdown(cancel_futures=True)


def _call(function: Callable[..., Any], args: tuple[Any, ...]) -> Any:
    return function(*args)


def _run_ray(work: Work, items: Sequence[Any], config: RunConfig) -> Iterator[Any]:
    """Results as Ray tasks finish (:func:`~simgrasp.runs.ray_session.ray_session`)."""
    from simgrasp.runs.ray_session import ray_session

    with ray_session(config.workers, config.address) as ray:
        if work.warm_up:
            warm = ray.remote(work.warm_up)
            ray.get([warm.remote(*call, *work.args) for call in work.warm_calls])
        remote = ray.remote(work.task)
        pending = [remote.remote(item, *work.args) for item in items]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield from ray.get(done)


def run_resumable(
    items: Sequence[Any],
    item_key: Callable[[Any], Hashable],
    log: RecordLog,
    execute: Callable[[Sequence[Any]], Iterable[Record]],
    *,
    progress: bool = True,
    desc: str = "run",
    unit: str = "it",
    on_record: Callable[[Record], None] | None = None,
) -> dict[Hashable, Record]:
    """Every item's record by its key: the log's records of ``items``, then
    ``execute(missing items)``'s records, each appended to the log as it arrives (a record
    whose key is already recorded is dropped: nothing is recorded twice)."""
    from tqdm import tqdm

    keys = [item_key(item) for item in items]
    if len(set(keys)) != len(keys):
        raise SimgraspError("the run's plan lists an item twice")
    wanted = set(keys)
    finished: dict[Hashable, Record] = {}
    for record in log.load():
        key = log.key(record)
        if key in wanted:
            finished[key] = record
    todo = [item for item, key in zip(items, keys, strict=True) if key not in finished]
    bar = tqdm(total=len(items), initial=len(finished), desc=desc, unit=unit, disable=not progress)
    records = iter(execute(todo))
    try:
        for record in records:
            key = log.key(record)
            if key in finished:
                continue
            log.append(record)
            finished[key] = record
            bar.update()
            if on_record:
                on_record(record)
    finally:  # stop the workers (a generator's pool or Ray session), sync the log
        getattr(records, "close", lambda: None)()
        bar.close()
        log.close()
    return finished
