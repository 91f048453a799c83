"""A Ray instance for a run's tasks: a new local one with ``workers`` CPUs, or the cluster at
``address`` (``auto``: ``$RAY_ADDRESS`` or the one ``ray start`` made)."""

from __future__ import annotations

import contextlib
import os
import socket
from collections.abc import Iterator
from typing import Any

from simgrasp.errors import SimgraspError
from simgrasp.scenes.render import worker_environment

CONNECT_TIMEOUT_S = 5.0
"""How long a HOST:PORT cluster address may take to accept a connection."""


@contextlib.contextmanager
def ray_session(workers: int, address: str | None) -> Iterator[Any]:
    """Yield the ``ray`` module with a session up: without ``address`` a new local instance
    with ``workers`` CPUs (shut down afterwards), even if ``RAY_ADDRESS`` is set; the tasks
    see this process's ``SIMGRASP_*`` and ``MUJOCO_*`` variables and render with its backend
    (:func:`simgrasp.scenes.render.worker_environment`)."""
    try:
        import ray
    except ImportError:
        raise SimgraspError(
            "--backend ray needs Ray: install the extra with `pip install 'simgrasp[ray]'` "
            "(or `pip install 'ray[default]'`)"
        ) from None
    started = not ray.is_initialized()
    if started and address:
        _check_reachable(address)
    if started:
        env = {k: v for k, v in os.environ.items() if k.startswith(("SIMGRASP_", "MUJOCO_"))}
        env.update(worker_environment())  # every task renders with this process's backend
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


def _check_reachable(address: str) -> None:
    """Refuse a ``HOST:PORT`` address where nothing answers within
    :data:`CONNECT_TIMEOUT_S` (Ray itself retries such an address for minutes, or for ever on
    a name that does not resolve); ``auto`` and ``ray://`` addresses are left to Ray."""
    if address == "auto" or "://" in address:
        return
    host, _, port = address.rpartition(":")
    if not (host and port.isdigit()):
        raise SimgraspError(f"--address {address}: expected HOST:PORT, auto or ray://HOST:PORT")
    try:
        socket.create_connection((host, int(port)), timeout=CONNECT_TIMEOUT_S).close()
    except OSError as exc:
        raise SimgraspError(f"--address {address}: no Ray cluster answers there ({exc})") from None
