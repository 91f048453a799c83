"""One grasp trial in MuJoCo: settle, pre-grasp, approach, close, lift, hold, perturb; scored.

Phases (world frame, meters, seconds; the gripper follows a mocap target through a soft weld):

1. settle: the object rests on the table while the parked gripper opens to the grasp width.
2. pre-grasp: the open gripper is placed ``pregrasp_distance`` back along the approach (-z of
   the TCP); touching anything there is ``invalid_start``.
3. approach: the target moves to the grasp pose at ``approach_speed``; if the TCP is held back
   or the object is shoved, ``approach_collision``.
4. close: the jaws close and squeeze (force limited) for ``close_time`` (or, with
   ``squeeze_time``, that long after both fingers touch); unless both fingers touch the object,
   ``missed``.
5. lift by ``lift_height`` at ``lift_speed``, then hold ``hold_time``; unless the object rose
   with the gripper and both fingers still touch it, ``slipped_in_lift``. Contacts at the end of
   the hold give ``on_handle``.
6. perturb: a force of ``perturb_force_scale`` x the object's weight pulls at its center of
   mass along each of ``perturb_directions`` in turn (as GraspDataGen does); unless it is still
   held afterwards, ``dropped_in_perturbation``.

From the close on, an object that is ``release_gap`` or more from every part of the gripper
has been let go: the phase ends there with its failure (its fall onto the table, where a thin
hull can tunnel deep enough to look like a divergence, is not simulated).

Protocols: ``full`` (:class:`TrialConfig`'s defaults: ``trial``, ``evaluate``, the env) and
``fast`` (:data:`FAST_TRIAL`, for labeling grasp sets: waits that end once the grip is at rest,
a squeeze of set length once both fingers touch, a coarser step from the hold on where the
gripper allows it, the resting object asleep until touched). ``TrialConfig.free_floating``
runs the trial in free space as ACRONYM does: the object floats with its gravity compensated,
the gripper appears at the grasp itself and closes (phases 2-4 without the pre-grasp offset
and the approach), then the object's gravity comes on instead of the lift (phase 5), then the
tugs.

Divergence (a non-finite state MuJoCo had to reset, its bad-qacc warning, penetration or speed
beyond the limits) ends the trial as ``sim_unstable`` with ``success = None``: neither success
nor failure. The simulation is deterministic: the same scene, grasp and config give an identical
record.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.scoring import (
    FingerContacts,
    geoms_touching,
    handle_fraction,
    points_in_object_frame,
    relative_pose,
    slip_distance,
)
from simgrasp.grasping.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene

Failure = Literal[
    "approach_collision",
    "missed",
    "slipped_in_lift",
    "dropped_in_perturbation",
    "sim_unstable",
    "invalid_start",
    "dropped_in_shaking",
]
Phase = Literal["pregrasp", "closed", "lifted", "perturbed"]

OPEN_TOLERANCE = 0.001
"""A free-floating trial starts once the jaws are this close (m) to the grasp width..."""
OPEN_LIMIT = 1.0
"""... or after this many seconds of opening."""


@dataclass(frozen=True)
class TrialResult:
    """The record of one trial (world frame unless named otherwise; m, s).

    ``success`` is None when the simulation diverged (``failure == "sim_unstable"``).
    ``object_pose`` and ``grasp`` are ``[x, y, z, qw, qx, qy, qz]``; ``object_pose`` is the
    scene's initial object pose. ``contact_points_object`` are the finger-object contacts at
    the end of the hold, in the object frame. ``slip_*`` is the object's motion relative to the
    TCP from the end of closing to the end of the hold / of the perturbation.
    """

    object: str
    gripper: str
    seed: int
    object_pose: list[float]
    grasp: list[float]
    grasp_width: float
    grasp_source: str
    success: bool | None
    failure: Failure | None
    on_handle: bool
    handle_fraction: float
    lift_height: float
    slip_lift: float | None
    slip_perturb: float | None
    contact_points_object: list[list[float]]
    sim_time: float
    steps: int
    timings_s: dict[str, float] = field(compare=False)
    score: float | None = None
    """How firmly the object was held, in [0, 1] (protocols with a shake,
    :mod:`simgrasp.grasping.shake`); None, and left out of the record, otherwise."""

    def to_json(self) -> dict[str, Any]:
        """The record as a dict of JSON types (shallow: its lists are this result's own);
        ``score`` only where the protocol gives one."""
        record = {f.name: getattr(self, f.name) for f in fields(self)}
        if record["score"] is None:
            del record["score"]
        return record


class _Diverged(Exception):
    """The simulation left its stability limits."""


_OBJECT, _LEFT_FINGER, _RIGHT_FINGER, _GRIPPER = 1, 2, 4, 8
"""Bit codes of geoms (others 0): the object's, each finger's, the rest of the gripper's. The
two codes of a contact OR-ed say what it joins (geoms of one body never touch each other)."""
_ANY_GRIPPER = _LEFT_FINGER | _RIGHT_FINGER | _GRIPPER


class _Released(Exception):
    """The object has left the jaws (see ``TrialConfig.release_gap``)."""


@dataclass
class _Runner:
    """The control loop of one trial: precomputed ids, mocap interpolation, divergence checks."""

    scene: Scene
    config: TrialConfig
    steps: int = 0
    watch_release: bool = False
    """Set once the jaws hold the object: from then on :meth:`check` raises ``_Released`` when
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
        """Raise ``_Diverged`` or ``_Released`` when the state calls for it (runs after every
        control step: kept to a few reads of live views)."""
        data, config = self.data, self.config
        counts = self.warning_counts.tolist()
        if any(counts[w] for w in self.unstable):
            raise _Diverged
        if max(map(abs, self.qvel.tolist())) > config.max_speed:
            raise _Diverged
        if data.ncon:
            contacts = data.contact
            if min(contacts.dist.tolist()) < -config.max_penetration:
                raise _Diverged
            if self.watch_release and not self._touching(contacts.geom) and self._object_clear():
                raise _Released
        elif self.watch_release and self._object_clear():
            raise _Released

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


def initial_object_pose(scene: Scene, config: TrialConfig) -> NDArray[np.float64]:
    """``world_T_object`` at the start of a trial: the scene's rest pose, raised by
    ``float_height`` when free-floating."""
    world_T_object = scene.world_T_object.copy()
    if config.free_floating:
        world_T_object[2, 3] += config.float_height
    return world_T_object


def _initial_pose7(scene: Scene, config: TrialConfig) -> list[float]:
    """:func:`initial_object_pose` as ``[x, y, z, qw, qx, qy, qz]``: its position, and the
    rest pose's orientation (the start never turns the object), converted once per scene."""
    pose7 = scene.rest_pose7.copy()
    pose7[:3] = initial_object_pose(scene, config)[:3, 3]
    return pose7.tolist()


def _start(scene: Scene, config: TrialConfig) -> None:
    """Reset the scene for a trial (``mj_resetData``, no rebuild) with the trial's time step and
    sleep setting; a free-floating object is raised and its gravity compensated."""
    options, sleep = scene.model.opt, int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    options.enableflags = (
        (options.enableflags | sleep) if config.sleep else (options.enableflags & ~sleep)
    )
    scene.reset()
    options.timestep = config.timestep
    scene.model.body_gravcomp[scene.object_body] = 1.0 if config.free_floating else 0.0
    if config.free_floating:
        scene.data.qpos[scene.object_qpos + 2] += config.float_height
        mujoco.mj_forward(scene.model, scene.data)


def run_trial(
    scene: Scene,
    grasp: Grasp,
    config: TrialConfig | None = None,
    on_phase: Callable[[Phase, Scene], None] | None = None,
) -> TrialResult:
    """Execute ``grasp`` (world frame) in ``scene`` and score it.

    The scene is reset first (``mj_resetData``, no rebuild), so repeated trials on one scene
    are independent and identical for identical inputs: this is the one trial code path of
    ``trial``, ``evaluate``, the env and ``label-grasps``. ``on_phase`` is called at the key
    moments (pre-grasp, closed, lifted, perturbed), e.g. to render frames; it must not change
    the simulation state.
    """
    config = config or TrialConfig()
    _start(scene, config)
    trial = _Trial(scene, grasp, config, _Runner(scene, config), on_phase)
    if config.shake is not None:
        trial.record["score"] = 0.0
    start = trial.clock = time.perf_counter()
    try:
        failure = _execute(trial)
    except _Diverged:
        failure = "sim_unstable"
    trial.timings["total"] = time.perf_counter() - start
    success = None if failure == "sim_unstable" else failure is None
    return TrialResult(
        object=scene.object_name,
        gripper=scene.gripper.gripper.name,
        seed=scene.seed,
        object_pose=_initial_pose7(scene, config),
        grasp=grasp.to_pose7().tolist(),
        grasp_width=float(grasp.width),
        grasp_source=grasp.source,
        success=success,
        failure=failure,
        sim_time=float(scene.data.time),
        steps=trial.runner.steps,
        timings_s=trial.timings,
        **trial.record,
    )


@dataclass
class _Trial:
    """The state one trial's phases share: inputs, the control loop, timings and the record
    fields they fill (``record`` starts with the values of a trial that ends before lifting)."""

    scene: Scene
    grasp: Grasp
    config: TrialConfig
    runner: _Runner
    on_phase: Callable[[Phase, Scene], None] | None
    timings: dict[str, float] = field(default_factory=dict)
    record: dict[str, Any] = field(
        default_factory=lambda: {
            "on_handle": False,
            "handle_fraction": 0.0,
            "lift_height": 0.0,
            "slip_lift": None,
            "slip_perturb": None,
            "contact_points_object": [],
        }
    )
    clock: float = 0.0
    world_T_object_settled: NDArray[np.float64] | None = None
    tcp_T_object_closed: NDArray[np.float64] | None = None
    object_z_closed: float = 0.0

    def lap(self, name: str) -> None:
        """Record the wall time since the previous lap as phase ``name``."""
        now = time.perf_counter()
        self.timings[name] = now - self.clock
        self.clock = now

    def moment(self, phase: Phase) -> None:
        if self.on_phase:
            self.on_phase(phase, self.scene)

    def held(self) -> FingerContacts:
        """Finger-object contacts now."""
        return self.runner.finger_contacts()

    def slip(self, world_T_object: NDArray[np.float64]) -> float:
        """The object's motion relative to the TCP since the end of the close (m)."""
        world_T_tcp = self.scene.gripper.world_T_tcp(self.scene.data)
        assert self.tcp_T_object_closed is not None, "slip is measured after the close"
        return slip_distance(self.tcp_T_object_closed, relative_pose(world_T_tcp, world_T_object))

    def still_lifted(self, world_T_object: NDArray[np.float64]) -> bool:
        rise = world_T_object[2, 3] - self.object_z_closed
        limit = self.config.lifted_fraction * self.config.lift_height
        return bool(rise >= -limit if self.config.free_floating else rise >= limit)


def _execute(trial: _Trial) -> Failure | None:
    """Run the phases in turn; the first failure ends the trial (None: success). With
    ``config.shake``, the shake (:mod:`simgrasp.grasping.shake`) replaces the lift, hold and
    tugs."""
    from simgrasp.grasping.shake import shake_phase

    tests = (_lift_and_hold, _perturb) if trial.config.shake is None else (shake_phase,)
    for phase in (_settle, _pregrasp, _approach, _close, *tests):
        failure = phase(trial)
        if failure is not None:
            return failure
    return None


def _settle(trial: _Trial) -> None:
    """1. The object settles while the parked gripper opens to the grasp width."""
    gripper, grasp = trial.scene.gripper, trial.grasp
    width = min(grasp.width, gripper.gripper.max_opening)
    gripper.set_opening(trial.scene.data, width)
    trial.runner.wait(trial.config.settle_time)
    if trial.config.free_floating:  # no approach follows, during which the jaws finish opening
        _open_jaws(trial, width)
    trial.world_T_object_settled = trial.scene.object_pose()
    trial.lap("settle")


def _open_jaws(trial: _Trial, width: float) -> None:
    """Step until the jaws are within ``OPEN_TOLERANCE`` of ``width`` (at most ``OPEN_LIMIT``
    seconds: a linkage may stop short of its full stroke)."""
    data, gripper = trial.scene.data, trial.scene.gripper
    elapsed = 0.0
    while abs(gripper.opening(data) - width) > OPEN_TOLERANCE and elapsed < OPEN_LIMIT:
        trial.runner.advance(trial.runner.control_dt)
        elapsed += trial.runner.control_dt


def _pregrasp(trial: _Trial) -> Failure | None:
    """2. The open gripper appears ``pregrasp_distance`` back along the approach."""
    scene, grasp = trial.scene, trial.grasp
    world_T_pregrasp = grasp.world_T_tcp.copy()
    if not trial.config.free_floating:
        world_T_pregrasp[:3, 3] -= trial.config.pregrasp_distance * grasp.approach_world
    scene.gripper.teleport(scene.data, world_T_pregrasp)
    mujoco.mj_forward(scene.model, scene.data)
    trial.moment("pregrasp")
    touching = geoms_touching(scene.data, trial.runner.gripper_geoms, trial.config.start_tolerance)
    trial.lap("pregrasp")
    return "invalid_start" if touching else None


def _approach(trial: _Trial) -> Failure | None:
    """3. The target moves to the grasp pose; a held-back TCP or a shoved object fails."""
    scene, grasp, config = trial.scene, trial.grasp, trial.config
    if config.free_floating:  # the gripper already is at the grasp
        return None
    data, gripper = scene.data, scene.gripper
    mocap_start = data.mocap_pos[gripper.mocap_id].copy()
    gripper.command_tcp(data, grasp.world_T_tcp)
    mocap_goal = data.mocap_pos[gripper.mocap_id].copy()
    trial.runner.advance(config.pregrasp_distance / config.approach_speed, mocap_start, mocap_goal)
    trial.runner.advance(2 * trial.runner.control_dt)  # let the weld catch up
    lag = np.linalg.norm(gripper.world_T_tcp(data)[:3, 3] - grasp.world_T_tcp[:3, 3])
    settled = trial.world_T_object_settled
    assert settled is not None, "the approach follows the settle"
    pushed = np.linalg.norm(scene.object_pose()[:3, 3] - settled[:3, 3])
    trial.lap("approach")
    if lag > config.approach_lag_limit or pushed > config.approach_push_limit:
        return "approach_collision"
    return None


def _close(trial: _Trial) -> Failure | None:
    """4. The jaws close and squeeze (``close_time``, or ``squeeze_time`` once both fingers
    touch); unless both fingers touch the object then, ``missed``."""
    scene, config, runner = trial.scene, trial.config, trial.runner
    scene.gripper.close(scene.data)
    if config.squeeze_time is None:
        runner.wait(config.close_time)
    else:
        closing = runner.wait_for_touch(config.close_time)
        if closing < config.close_time:
            runner.wait(min(config.squeeze_time, config.close_time - closing))
    trial.moment("closed")
    trial.lap("close")
    if not trial.held().both:
        return "missed"
    trial.tcp_T_object_closed = relative_pose(
        scene.gripper.world_T_tcp(scene.data), scene.object_pose()
    )
    trial.object_z_closed = scene.object_pose()[2, 3]
    return None


def _lift_and_hold(trial: _Trial) -> Failure | None:
    """5. Lift (free-floating: switch the object's gravity on instead) and hold; score the
    contacts (``on_handle``) at the end of the hold."""
    scene, config, record = trial.scene, trial.config, trial.record
    trial.runner.watch_release = True
    lift_start = scene.data.mocap_pos[scene.gripper.mocap_id].copy()
    lift_goal = lift_start + np.array([0.0, 0.0, config.lift_height])
    try:
        if config.free_floating:
            scene.model.body_gravcomp[scene.object_body] = 0.0
        else:
            trial.runner.advance(config.lift_height / config.lift_speed, lift_start, lift_goal)
        trial.runner.use_hold_timestep()
        trial.runner.wait(config.hold_time)
    except _Released:
        trial.lap("lift_hold")
        record["lift_height"] = float(scene.object_pose()[2, 3] - trial.object_z_closed)
        return "slipped_in_lift"
    trial.lap("lift_hold")
    trial.moment("lifted")
    world_T_object = scene.object_pose()
    record["lift_height"] = float(world_T_object[2, 3] - trial.object_z_closed)
    record["slip_lift"] = trial.slip(world_T_object)
    contacts = score_contacts(trial)
    if not (contacts.both and trial.still_lifted(world_T_object)):
        return "slipped_in_lift"
    return None


def score_contacts(trial: _Trial) -> FingerContacts:
    """The finger-object contacts now, recorded in the object frame with the share on the
    handle label (``contact_points_object``, ``handle_fraction``, ``on_handle``)."""
    scene, config, record = trial.scene, trial.config, trial.record
    contacts = trial.held()
    points_object = points_in_object_frame(contacts.points_world, scene.object_pose())
    fraction = handle_fraction(points_object, scene.object_model.asset.handle, config.handle_margin)
    record["contact_points_object"] = points_object.tolist()
    record["handle_fraction"] = fraction
    record["on_handle"] = bool(len(points_object)) and fraction >= config.on_handle_threshold
    return contacts


def _perturb(trial: _Trial) -> Failure | None:
    """6. Weight-sized tugs along each direction, each followed by a rest."""
    scene, config = trial.scene, trial.config
    data, body = scene.data, scene.object_body
    weight = scene.model.body_subtreemass[body] * np.linalg.norm(scene.model.opt.gravity)
    try:
        for direction in np.asarray(config.perturb_directions, dtype=float).reshape(-1, 3):
            force = config.perturb_force_scale * weight * direction / np.linalg.norm(direction)
            data.xfrc_applied[body, :3] = force
            trial.runner.wait(config.perturb_time, min_time=config.quiet_min_tug)
            data.xfrc_applied[body, :3] = 0.0
            trial.runner.wait(config.rest_time)
    except _Released:
        data.xfrc_applied[body, :3] = 0.0
        trial.lap("perturb")
        return "dropped_in_perturbation"
    trial.lap("perturb")
    trial.moment("perturbed")
    world_T_object = scene.object_pose()
    trial.record["slip_perturb"] = trial.slip(world_T_object)
    if not (trial.held().both and trial.still_lifted(world_T_object)):
        return "dropped_in_perturbation"
    return None
