"""One grasp trial in MuJoCo: the scene reset, the phases of a protocol run in turn, the record.

A trial runs a sequence of phases (:mod:`simgrasp.grasping.trials.phases`; world frame, meters,
seconds; the gripper follows a mocap target through a soft weld) named by its protocol
(:mod:`simgrasp.grasping.trials.protocol`), or by its settings when no protocol names them:

1. settle: the object rests on the table while the parked gripper opens to the grasp width.
2. pregrasp: the open gripper is placed ``pregrasp_distance`` back along the approach (-z of
   the TCP); touching anything there is ``invalid_start``.
3. approach: the target moves to the grasp pose at ``approach_speed``; if the TCP is held back
   or the object is shoved, ``approach_collision``.
4. close: the jaws close and squeeze (force limited) for ``close_time`` (or, with
   ``squeeze_time``, that long after both fingers touch); unless both fingers touch the object,
   ``missed``.
5. lift by ``lift_height`` at ``lift_speed``, then hold ``hold_time``; unless the object rose
   with the gripper and both fingers still touch it, ``slipped_in_lift``. Contacts at the end of
   the hold give ``on_handle``.
6. tugs: a force of ``perturb_force_scale`` x the object's weight pulls at its center of
   mass along each of ``perturb_directions`` in turn (as GraspDataGen does); unless it is still
   held afterwards, ``dropped_in_perturbation``.

With ``TrialConfig.shake`` (the ``acronym`` protocols), ACRONYM's shake replaces 5 and 6.
From the close on, an object that is ``release_gap`` or more from every part of the gripper
has been let go: the phase ends there with its failure (its fall onto the table, where a thin
hull can tunnel deep enough to look like a divergence, is not simulated).
``TrialConfig.free_floating`` runs the trial in free space as ACRONYM does: the object floats
with its gravity compensated, the gripper appears at the grasp itself and closes (phases 2-4
without the pre-grasp offset and the approach), then the object's gravity comes on instead of
the lift (phase 5), then the tugs.

Divergence (a non-finite state MuJoCo had to reset, its bad-qacc warning, penetration or speed
beyond the limits) ends the trial as ``sim_unstable`` with ``success = None``: neither success
nor failure. The simulation is deterministic: the same scene, grasp, config and phases give an
identical record.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.phases import TrialPhase, phase_sequence
from simgrasp.grasping.trials.protocol import default_phases
from simgrasp.grasping.trials.result import Failure, Phase, TrialResult
from simgrasp.grasping.trials.runner import Diverged, Runner
from simgrasp.grasping.trials.start_states import StartStates
from simgrasp.grasping.trials.state import TrialState
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene

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
    phases: Sequence[str] | None = None,
) -> TrialResult:
    """Execute ``grasp`` (world frame) in ``scene`` and score it.

    The scene is reset first (``mj_resetData``, no rebuild), so repeated trials on one scene
    are independent and identical for identical inputs: this is the one trial code path of
    ``trial``, ``evaluate``, the env and ``label-grasps``. ``phases`` names the phases run in
    turn (a protocol's, :class:`~simgrasp.grasping.trials.protocol.TrialProtocol`); by default
    those of ``config`` (:func:`~simgrasp.grasping.trials.protocol.default_phases`). The first
    failure ends the trial. ``on_phase`` is called at the key moments (pre-grasp, closed,
    lifted, perturbed), e.g. to render frames; it must not change the simulation state. With
    ``starts``, a free-floating trial restores its start (the scene settled, the jaws opened
    to ``grasp.width``) as recorded by the first trial of the same config and the same opening
    width (m): the same record, ``steps`` included (the physics steps the trial stands for),
    from fewer physics steps.
    """
    config = config or TrialConfig()
    sequence = phase_sequence(default_phases(config) if phases is None else phases)
    _start(scene, config)
    state = TrialState(scene, grasp, config, Runner(scene, config), on_phase)
    state.starts = starts if starts is not None and starts.applies(config) else None
    if config.shake is not None:
        state.record["score"] = 0.0
    start = state.clock = time.perf_counter()
    try:
        failure = _execute(state, sequence)
    except Diverged:
        failure = "sim_unstable"
    state.timings["total"] = time.perf_counter() - start
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
        steps=state.runner.steps,
        timings_s=state.timings,
        handle_source=scene.object_model.asset.handle_source,
        **state.record,
    )


def _execute(state: TrialState, phases: Sequence[TrialPhase]) -> Failure | None:
    """Run ``phases`` in turn, each one's wall time recorded under its name; the first
    failure ends the trial (None: success)."""
    for phase in phases:
        try:
            failure = phase.run(state)
        finally:
            state.lap(phase.name)
        if failure is not None:
            return failure
    return None
