"""The control loop of one grasp trial: stepping, mocap interpolation, contact tests and the
divergence and release checks that end a phase (:class:`Runner`; see
:mod:`simgrasp.grasping.trials.trial` for the phases)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.trials.scoring import FingerContacts
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene


class Diverged(Exception):
    """The simulation left its stability limits."""


_OBJECT, _LEFT_FINGER, _RIGHT_FINGER, _GRIPPER = 1, 2, 4, 8
"""Bit codes of geoms (others 0): the object's, each finger's, the rest of the gripper's. The
two codes of a contact OR-ed say what it joins (geoms of one body never touch each other)."""
_ANY_GRIPPER = _LEFT_FINGER | _RIGHT_FINGER | _GRIPPER


class Released(Exception):
    """The object has left the jaws (see ``TrialConfig.release_gap``)."""


@dataclass
class Runner:
    """The control loop of one trial: precomputed ids, mocap interpolation, divergence checks."""

    scene: Scene
    config: TrialConfig
    steps: int = 0
    watch_release: bool = False
    """Set once the jaws hold the object: from then on :meth:`check` raises ``Released`` when
    the object has left them."""

    def __post_init__(self) -> None:
        model = self.scene.model
        self.model, self.data = model, self.scene.data
        self.nstep = self.config.control_steps
        self.control_dt = self.config.control_dt
        """Simulated time (s) of one control period: ``nstep`` steps of the model's time step."""
        warning = mujoco.mjtWarning
        self.unstable = [
            int(w) for w in (warning.mjWARN_BADQPOS, warning.mjWARN_BADQVEL, warning.mjWARN_BADQACC)
        ]
        """MuJoCo's divergence warnings (it resets a non-finite state and counts one of these)."""
        self.mocap = self.scene.gripper.mocap_id
        self.gripper_geoms = np.asarray(self.scene.gripper.geom_ids)
        self.object_geoms = np.flatnonzero(model.geom_bodyid == self.scene.object_body)
        codes = np.zeros(model.ngeom, dtype=int)
        (left, right), codes[self.gripper_geoms] = self.scene.gripper.finger_geoms, _GRIPPER
        codes[list(left)], codes[list(right)] = _LEFT_FINGER, _RIGHT_FINGER
        codes[self.object_geoms] = _OBJECT
        self.geom_codes: list[int] = codes.tolist()
        """Each geom's bit code (``_OBJECT`` ...), read by the contact tests."""
        colliding = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
        self.gripper_colliders = [int(g) for g in self.gripper_geoms if colliding[g]]
        self.object_colliders = [int(g) for g in self.object_geoms if colliding[g]]
        self.object_body, self.gripper_root = self.scene.object_body, self.scene.gripper.root_body
        self.object_radius = max(
            float(np.linalg.norm(model.geom_pos[g] - model.body_ipos[self.object_body]))
            + float(model.geom_rbound[g])
            for g in self.object_colliders
        )
        free = self.scene.gripper.free_dof
        gripper_dofs = np.flatnonzero(np.isin(model.dof_bodyid, self.scene.gripper.body_ids))
        finger_dofs = gripper_dofs[(gripper_dofs < free) | (gripper_dofs >= free + 6)]
        self.finger_dofs: list[int] = finger_dofs.tolist()
        # Live views of the data the checks read after every control step (read as Python
        # floats: for a handful of numbers that is several times faster than numpy calls).
        data = self.data
        self.warning_counts = data.warning.number
        self.qvel = data.qvel
        self.object_cvel = data.cvel[self.object_body]
        self.gripper_cvel = data.cvel[self.gripper_root]
        self.object_com = data.subtree_com[self.object_body]
        self.gripper_com = data.subtree_com[self.gripper_root]

    def advance(
        self, duration: float, mocap_from: NDArray | None = None, to: NDArray | None = None
    ):
        """Step ``duration`` seconds; with ``mocap_from``/``to``, move the target linearly."""
        chunks = self.chunks(duration)
        for k in range(1, chunks + 1):
            if mocap_from is not None:
                self.data.mocap_pos[self.mocap] = mocap_from + (to - mocap_from) * (k / chunks)
            self.step()

    def chunks(self, duration: float) -> int:
        """Control periods in ``duration`` seconds (at least one)."""
        return max(1, int(round(duration / self.control_dt)))

    def step(self) -> None:
        """One control period: ``nstep`` physics steps, then :meth:`check`."""
        mujoco.mj_step(self.model, self.data, self.nstep)
        self.steps += self.nstep
        self.check()

    def wait(self, duration: float, min_time: float = 0.0) -> None:
        """Step up to ``duration`` seconds with the target still; with
        ``config.quiet_speed``, end early once :meth:`relative_speed` has stayed below it for
        ``config.quiet_time`` and ``min_time`` has passed."""
        config = self.config
        if config.quiet_speed is None:
            self.advance(duration)
            return
        quiet_needed = self.chunks(config.quiet_time)
        min_chunks = int(round(min_time / self.control_dt))
        quiet = 0
        for k in range(1, self.chunks(duration) + 1):
            self.step()
            quiet = quiet + 1 if self.relative_speed() < config.quiet_speed else 0
            if quiet >= quiet_needed and k >= min_chunks:
                return

    def wait_for_touch(self, limit: float) -> float:
        """Step until both fingers touch the object, at most ``limit`` seconds; returns the
        time stepped (s)."""
        chunks = self.chunks(limit)
        for k in range(1, chunks + 1):
            self.step()
            if self.fingers_touch():
                return k * self.control_dt
        return chunks * self.control_dt

    def fingers_touch(self) -> bool:
        """Whether both fingers touch the object now."""
        return self._finger_rows()[1] == _OBJECT | _LEFT_FINGER | _RIGHT_FINGER

    def finger_contacts(self) -> FingerContacts:
        """The finger-object contacts now (points in the world frame, m)."""
        rows, touched = self._finger_rows()
        points_world = self.data.contact.pos[rows]  # (N, 3), a copy
        return FingerContacts(
            points_world, bool(touched & _LEFT_FINGER), bool(touched & _RIGHT_FINGER)
        )

    def _finger_rows(self) -> tuple[list[int], int]:
        """Rows of ``data.contact`` that join a finger and the object, and their pair codes
        OR-ed."""
        codes, rows, touched = self.geom_codes, [], 0
        for row, (first, second) in enumerate(self.data.contact.geom.tolist()):
            pair = codes[first] | codes[second]
            if pair in (_OBJECT | _LEFT_FINGER, _OBJECT | _RIGHT_FINGER):
                rows.append(row)
                touched |= pair
        return rows, touched

    def use_hold_timestep(self) -> None:
        """From now on step with ``config.hold_timestep``, capped at the gripper's
        ``max_timestep``, keeping the control period (no change when that is no coarser)."""
        config = self.config
        if config.hold_timestep is None:
            return
        timestep = min(config.hold_timestep, self.scene.gripper.gripper.max_timestep)
        if timestep <= config.timestep:
            return
        self.nstep = max(1, round(config.control_dt / timestep))
        self.model.opt.timestep, self.control_dt = timestep, timestep * self.nstep

    def relative_speed(self) -> float:
        """A bound (m/s) on how fast any point of the object moves relative to the gripper,
        or a finger joint moves (m/s or rad/s): the larger of the two. From ``cvel`` (each
        body's velocity at its tree's center of mass, world axes) of the last step."""
        wo0, wo1, wo2, vo0, vo1, vo2 = self.object_cvel.tolist()
        wg0, wg1, wg2, vg0, vg1, vg2 = self.gripper_cvel.tolist()
        o0, o1, o2 = self.object_com.tolist()
        g0, g1, g2 = self.gripper_com.tolist()
        d0, d1, d2 = o0 - g0, o1 - g1, o2 - g2
        linear = math.hypot(
            vo0 - vg0 - (wg1 * d2 - wg2 * d1),
            vo1 - vg1 - (wg2 * d0 - wg0 * d2),
            vo2 - vg2 - (wg0 * d1 - wg1 * d0),
        )
        angular = math.hypot(wo0 - wg0, wo1 - wg1, wo2 - wg2)
        qvel = self.qvel.tolist()
        fingers = max((abs(qvel[dof]) for dof in self.finger_dofs), default=0.0)
        return max(linear + angular * self.object_radius, fingers)

    def check(self) -> None:
        """Raise ``Diverged`` or ``Released`` when the state calls for it (runs after every
        control step: kept to a few reads of live views)."""
        data, config = self.data, self.config
        counts = self.warning_counts.tolist()
        if any(counts[w] for w in self.unstable):
            raise Diverged
        if max(map(abs, self.qvel.tolist())) > config.max_speed:
            raise Diverged
        if data.ncon:
            contacts = data.contact
            if min(contacts.dist.tolist()) < -config.max_penetration:
                raise Diverged
            if self.watch_release and not self._touching(contacts.geom) and self._object_clear():
                raise Released
        elif self.watch_release and self._object_clear():
            raise Released

    def _object_clear(self) -> bool:
        """Whether every colliding object geom is ``release_gap`` or more from every colliding
        gripper geom (``mj_geomDistance``; only called when they are not in contact)."""
        gap = self.config.release_gap
        return all(
            mujoco.mj_geomDistance(self.model, self.data, g, o, gap, None) >= gap
            for g in self.gripper_colliders
            for o in self.object_colliders
        )

    def _touching(self, contact_geoms: NDArray[np.int32]) -> bool:
        """Whether any contact (rows of geom id pairs) joins an object and a gripper geom."""
        codes = self.geom_codes
        for first, second in contact_geoms.tolist():
            pair = codes[first] | codes[second]
            if pair & _OBJECT and pair & _ANY_GRIPPER:
                return True
        return False
