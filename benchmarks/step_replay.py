"""Compare a harness with the physics alone on the same steps: record every ``mj_step`` call a
harness makes on one model and replay the calls as raw stepping, or time the calls in place."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator

import numpy as np

from simgrasp._mujoco import mujoco

STATE = mujoco.mjtState.mjSTATE_INTEGRATION
Calls = list[tuple[np.ndarray, int]]


@contextlib.contextmanager
def _wrapped_steps(model: mujoco.MjModel, around: Callable[..., None]) -> Iterator[None]:
    """Within the block, ``mujoco.mj_step(m, d, nstep)`` of ``model`` runs as
    ``around(original_mj_step, m, d, nstep)``; other models' steps (e.g. the Robotiq's one-off
    calibration model) run untouched."""
    original = mujoco.mj_step

    def step(m, d, nstep=1):
        if m is model:
            around(original, m, d, nstep)
        else:
            original(m, d, nstep)

    mujoco.mj_step = step
    try:
        yield
    finally:
        mujoco.mj_step = original


@contextlib.contextmanager
def recorded_steps(model: mujoco.MjModel) -> Iterator[Calls]:
    """Within the block, record (integration state, nstep) before each ``mj_step`` of
    ``model``."""
    size = mujoco.mj_stateSize(model, STATE)
    calls: Calls = []

    def record(step, m, d, nstep):
        state = np.empty(size)
        mujoco.mj_getState(m, d, state, STATE)
        calls.append((state, nstep))
        step(m, d, nstep)

    with _wrapped_steps(model, record):
        yield calls


def replay_seconds(model: mujoco.MjModel, data: mujoco.MjData, calls: Calls) -> float:
    """Seconds spent in ``mj_step`` replaying ``calls``, each from its recorded state (only
    the ``mj_step`` calls are timed)."""
    total = 0.0
    for state, nstep in calls:
        mujoco.mj_setState(model, data, state, STATE)
        start = time.perf_counter()
        mujoco.mj_step(model, data, nstep)
        total += time.perf_counter() - start
    return total


@contextlib.contextmanager
def timed_steps(model: mujoco.MjModel) -> Iterator[list[float]]:
    """Within the block, add up the seconds spent inside each ``mj_step`` of ``model`` (one
    list item). Unlike a replay this needs no state restore: MuJoCo's sleep state (which bodies
    sleep) is not part of ``mj_getState`` and could not be replayed."""
    seconds = [0.0]

    def time_it(step, m, d, nstep):
        start = time.perf_counter()
        step(m, d, nstep)
        seconds[0] += time.perf_counter() - start

    with _wrapped_steps(model, time_it):
        yield seconds
