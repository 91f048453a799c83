"""A Ray instance for a run's tasks: a new local one with ``workers`` CPUs, or the cluster at
``address`` (``auto``: ``$RAY_ADDRESS`` or the one ``ray start`` made)."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from typing import Any

from simgrasp.errors import SimgraspError


@contextlib.contextmanager
def ray_session(workers: int, address: str | None) -> Iterator[Any]:
    """Yield the ``ray`` module with a session up: without ``address`` a new local instance
    with ``workers`` CPUs (shut down afterwards), even if ``RAY_ADDRESS`` is set; the tasks
    see this process's ``SIMGRASP_*`` and ``MUJOCO_*`` variables."""
    try:
        import ray
    except ImportError:
        raise SimgraspError(
            "--backend ray needs Ray: install the extra with `pip install 'simgrasp[ray]'` "
            "(or `pip install 'ray[default]'`)"
        ) from None
    started = not ray.is_initialized()
    if started:
        env = {k: v for k, v in os.environ.items() if k.startswith(("SIMGRASP_", "MUJOCO_"))}
        try:
            ray.init(
                address=address or "local",
                num_cpus=None if address else workers,
                include_dashboard=False,
                log_to_driver=False,
                runtime_env={"env_vars": env},
            )
        except ConnectionError as exc:  # no cluster at --address (or none started for auto)
            raise SimgraspError(f"--address {address}: cannot join a Ray cluster ({exc})") from None
    try:
        yield ray
    finally:
        if started:
            ray.shutdown()
