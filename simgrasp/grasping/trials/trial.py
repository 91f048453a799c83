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

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.result import Failure, Phase, TrialResult
from simgrasp.grasping.trials.runner import Diverged, Released, Runner
from simgrasp.grasping.trials.scoring import (
    FingerContacts,
    geoms_touching,
    handle_fraction,
    points_in_object_frame,
    relative_pose,
    slip_distance,
)
from simgrasp.grasping.trials.start_states import StartStates
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene

OPEN_TOLERANCE = 0.001
"""A free-floating trial starts once the jaws are this close (m) to the grasp width..."""
OPEN_LIMIT = 1.0
"""... or after this many seconds of opening."""
INTEGRATORS = {
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}
"""MuJoCo's integrator of each ``TrialConfig.integrator`` name."""


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
    """Reset the scene for a trial (``mj_resetData``, no rebuild) with the trial's time step,
    friction impedance ratio, integrator and sleep setting; a free-floating object is raised
    and its gravity compensated."""
    options, sleep = scene.model.opt, int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    options.enableflags = (
        (options.enableflags | sleep) if config.sleep else (options.enableflags & ~sleep)
    )
    scene.reset()
    options.timestep = config.timestep
    options.impratio = config.impratio
    options.integrator = INTEGRATORS[config.integrator]
    _set_finger_solimp(scene, config)
    scene.model.body_gravcomp[scene.object_body] = 1.0 if config.free_floating else 0.0
    if config.free_floating:
        scene.data.qpos[scene.object_qpos + 2] += config.float_height
        mujoco.mj_forward(scene.model, scene.data)


def _set_finger_solimp(scene: Scene, config: TrialConfig) -> None:
    """The fingers' ``solimp`` for this trial: the gripper model's own, with the ramp width
    of ``config.finger_solimp_width`` where it is set (the same scene may run trials of
    several configs)."""
    left, right = scene.gripper.finger_geoms
    solimp = scene.gripper.finger_solimp.copy()
    if config.finger_solimp_width is not None:
        solimp[:, 2] = config.finger_solimp_width
    scene.model.geom_solimp[list(left + right)] = solimp


def run_trial(
    scene: Scene,
    grasp: Grasp,
    config: TrialConfig | None = None,
    on_phase: Callable[[Phase, Scene], None] | None = None,
    starts: StartStates | None = None,
) -> TrialResult:
    """Execute ``grasp`` (world frame) in ``scene`` and score it.

    The scene is reset first (``mj_resetData``, no rebuild), so repeated trials on one scene
    are independent and identical for identical inputs: this is the one trial code path of
    ``trial``, ``evaluate``, the env and ``label-grasps``. ``on_phase`` is called at the key
    moments (pre-grasp, closed, lifted, perturbed), e.g. to render frames; it must not change
    the simulation state. With ``starts``, a free-floating trial restores its start (the scene
    settled, the jaws opened to ``grasp.width``) as recorded by the first trial of the same
    config and the same opening width (m): the same record, ``steps`` included (the physics
    steps the trial stands for), from fewer physics steps.
    """
    config = config or TrialConfig()
    _start(scene, config)
    trial = _Trial(scene, grasp, config, Runner(scene, config), on_phase)
    trial.starts = starts if starts is not None and starts.applies(config) else None
    if config.shake is not None:
        trial.record["score"] = 0.0
    start = trial.clock = time.perf_counter()
    try:
        failure = _execute(trial)
    except Diverged:
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
        handle_source=scene.object_model.asset.handle_source,
        **trial.record,
    )


@dataclass
class _Trial:
    """The state one trial's phases share: inputs, the control loop, timings and the record
    fields they fill (``record`` starts with the values of a trial that ends before lifting)."""

    scene: Scene
    grasp: Grasp
    config: TrialConfig
    runner: Runner
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
    starts: StartStates | None = None
    """Where a free-floating trial's start is kept and restored from (see ``run_trial``)."""
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
    ``config.shake``, the shake (:mod:`simgrasp.grasping.trials.shake`) replaces the lift, hold and
    tugs."""
    from simgrasp.grasping.trials.shake import shake_phase

    tests = (_lift_and_hold, _perturb) if trial.config.shake is None else (shake_phase,)
    for phase in (_settle, _pregrasp, _approach, _close, *tests):
        failure = phase(trial)
        if failure is not None:
            return failure
    return None


def _settle(trial: _Trial) -> None:
    """1. The object settles while the parked gripper opens to the grasp width (restored from
    ``trial.starts`` where it holds this start)."""
    scene, config, starts = trial.scene, trial.config, trial.starts
    width = min(trial.grasp.width, scene.gripper.gripper.max_opening)
    restored = None if starts is None else starts.restore(scene, config, width)
    if restored is not None:
        trial.runner.steps += restored
    else:
        scene.gripper.set_opening(scene.data, width)
        trial.runner.wait(config.settle_time)
        if config.free_floating:  # no approach follows, during which the jaws finish opening
            _open_jaws(trial, width)
        if starts is not None:
            starts.record(scene, config, width, trial.runner.steps)
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
    except Released:
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
    except Released:
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
