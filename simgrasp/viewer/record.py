"""``trial --record``: the states a replay needs, sampled while the trial runs.

The trial's phase callback marks the key moments and, at the first (the pre-grasp, once the
object has settled), installs a MuJoCo control callback (``mujoco.set_mjcb_control``; not
earlier: model compilation runs its own ``mj_forward`` that a Python callback cannot serve),
removed when the recorded block ends. It copies ``qpos`` at every step into the slot of its
sim time at ``rate_hz``, keeping the last state of each slot. It only reads the state, so the
trial's record is the same with and without ``--record``. After the trial the scene's model
turns each sampled ``qpos`` into the object's pose, the TCP's pose and the jaw opening
(``mj_kinematics`` on a scratch ``MjData``). The settle before the pre-grasp is not replayed.

The replay (``record["replay"]``; world frame, meters, seconds, poses ``[x y z qw qx qy qz]``):
``t``, ``object_pose``, ``tcp_pose``, ``opening`` per sample, ``phases`` (name and start
time), ``table`` (top height and half size), ``gripper`` (its planning geometry).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from dataclasses import asdict
from typing import Any

import numpy as np

from simgrasp._mujoco import mujoco
from simgrasp.transforms import make_transform, matrix_to_pose7

RATE_HZ = 30.0
"""Samples per second of sim time."""
PHASE_AFTER = {
    "pregrasp": "approach and close",
    "closed": "lift and hold",
    "lifted": "perturb",
    "perturbed": "done",
}
"""The phase a replay shows after each key moment of the trial."""


class StateRecorder:
    """Samples a trial's states (module docstring); pass it as the trial's phase callback
    (``next_phase`` is called after it, e.g. the key-frame renderer) inside :meth:`installed`."""

    def __init__(self, next_phase: Callable[[str, Any], None] | None = None) -> None:
        self.next_phase = next_phase
        self.samples: dict[int, tuple[float, np.ndarray]] = {}
        self.moments: list[tuple[str, float]] = []
        self.scene: Any = None

    def __call__(self, phase: str, scene: Any) -> None:
        if self.scene is None:
            mujoco.set_mjcb_control(self._on_step)
            self._on_step(scene.model, scene.data)
        self.scene = scene
        self.moments.append((phase, float(scene.data.time)))
        if self.next_phase is not None:
            self.next_phase(phase, scene)

    def _on_step(self, _model: Any, data: Any) -> None:
        time = float(data.time)
        self.samples[int(time * RATE_HZ)] = (time, np.array(data.qpos))

    @contextlib.contextmanager
    def installed(self) -> Iterator[StateRecorder]:
        """Record every step from the first phase on inside the block (the callback is
        removed on the way out)."""
        try:
            yield self
        finally:
            mujoco.set_mjcb_control(None)

    def replay(self) -> dict[str, Any] | None:
        """The replay of the recorded trial (module docstring); None when no trial ran."""
        if self.scene is None or not self.samples:
            return None
        scene = self.scene
        scratch = mujoco.MjData(scene.model)
        rows: dict[str, list[Any]] = {"t": [], "object_pose": [], "tcp_pose": [], "opening": []}
        for slot in sorted(self.samples):
            time, qpos = self.samples[slot]
            scratch.qpos[:] = qpos
            mujoco.mj_kinematics(scene.model, scratch)
            rows["t"].append(round(time, 4))
            body = scene.object_body
            world_T_object = make_transform(scratch.xmat[body].reshape(3, 3), scratch.xpos[body])
            rows["object_pose"].append(_pose(world_T_object))
            rows["tcp_pose"].append(_pose(scene.gripper.world_T_tcp(scratch)))
            rows["opening"].append(round(scene.gripper.opening(scratch), 5))
        return {
            "rate_hz": RATE_HZ,
            **rows,
            "phases": self._phases(),
            "table": _table(scene),
            "gripper": asdict(scene.gripper.gripper.planning_geometry()),
        }

    def _phases(self) -> list[dict[str, Any]]:
        phases = []
        for phase, time in self.moments:
            phases.append({"name": PHASE_AFTER.get(phase, phase), "t": round(time, 4)})
        return phases


def _pose(world_T_frame: np.ndarray) -> list[float]:
    return [round(v, 6) for v in matrix_to_pose7(world_T_frame).tolist()]


def _table(scene: Any) -> dict[str, Any]:
    """The table box (world frame): its top height and half size."""
    geom = scene.table_geom
    center, half = scene.model.geom_pos[geom], scene.model.geom_size[geom]
    return {"center": center.tolist(), "half_size": half.tolist()}
