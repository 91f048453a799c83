"""One grasp trial in MuJoCo: settle, pre-grasp, approach, close, lift, hold, perturb; scored.

Phases (world frame, meters, seconds; the gripper follows a mocap target through a soft weld):

1. settle: the object rests on the table while the parked gripper opens to the grasp width.
2. pre-grasp: the open gripper is placed ``pregrasp_distance`` back along the approach (-z of
   the TCP); touching anything there is ``invalid_start``.
3. approach: the target moves to the grasp pose at ``approach_speed``; if the TCP is held back
   or the object is shoved, ``approach_collision``.
4. close: the jaws squeeze (force limited) for ``close_time``; unless both fingers touch the
   object, ``missed``.
5. lift by ``lift_height`` at ``lift_speed``, then hold ``hold_time``; unless the object rose
   with the gripper and both fingers still touch it, ``slipped_in_lift``. Contacts at the end of
   the hold give ``on_handle``.
6. perturb: a force of ``perturb_force_scale`` x the object's weight pulls at its center of
   mass along each of ``perturb_directions`` in turn (as GraspDataGen does); unless it is still
   held afterwards, ``dropped_in_perturbation``.

From the close on, an object that is ``release_gap`` or more from every part of the gripper
has been let go: the phase ends there with its failure (its fall onto the table, where a thin
hull can tunnel deep enough to look like a divergence, is not simulated).

Divergence (non-finite state, MuJoCo's bad-qacc warning, penetration or speed beyond the
limits) ends the trial as ``sim_unstable`` with ``success = None``: neither success nor failure.
The simulation is deterministic: the same scene, grasp and config give an identical record.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.scoring import (
    finger_contacts,
    geoms_touching,
    handle_fraction,
    points_in_object_frame,
    relative_pose,
    slip_distance,
)
from simgrasp.grasping.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene
from simgrasp.transforms import matrix_to_pose7

Failure = Literal[
    "approach_collision",
    "missed",
    "slipped_in_lift",
    "dropped_in_perturbation",
    "sim_unstable",
    "invalid_start",
]
Phase = Literal["pregrasp", "closed", "lifted", "perturbed"]


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

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


class _Diverged(Exception):
    """The simulation left its stability limits."""


_GRIPPER, _OBJECT = 2, 3
"""Codes of :attr:`_Runner.geom_part` (others 0): a contact joins the object and the gripper
exactly when the product of its two geoms' codes is 6."""


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
        self.bad_qacc = int(mujoco.mjtWarning.mjWARN_BADQACC)
        self.mocap = self.scene.gripper.mocap_id
        self.gripper_geoms = np.asarray(self.scene.gripper.geom_ids)
        self.object_geoms = np.flatnonzero(model.geom_bodyid == self.scene.object_body)
        self.geom_part = np.zeros(model.ngeom, dtype=np.int8)
        self.geom_part[self.gripper_geoms] = _GRIPPER
        self.geom_part[self.object_geoms] = _OBJECT
        colliding = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
        self.gripper_colliders = [int(g) for g in self.gripper_geoms if colliding[g]]
        self.object_colliders = [int(g) for g in self.object_geoms if colliding[g]]

    def advance(
        self, duration: float, mocap_from: NDArray | None = None, to: NDArray | None = None
    ):
        """Step ``duration`` seconds; with ``mocap_from``/``to``, move the target linearly."""
        chunks = max(1, int(round(duration / self.config.control_dt)))
        data, model, nstep = self.data, self.model, self.nstep
        for k in range(1, chunks + 1):
            if mocap_from is not None:
                data.mocap_pos[self.mocap] = mocap_from + (to - mocap_from) * (k / chunks)
            mujoco.mj_step(model, data, nstep)
            self.steps += nstep
            self.check()

    def check(self) -> None:
        data = self.data
        if data.warning[self.bad_qacc].number > 0 or not np.isfinite(data.qpos).all():
            raise _Diverged
        if np.abs(data.qvel).max() > self.config.max_speed:
            raise _Diverged
        if data.ncon and data.contact.dist.min() < -self.config.max_penetration:
            raise _Diverged
        if self.watch_release and not self._object_in_gripper() and self._object_clear():
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

    def _object_in_gripper(self) -> bool:
        """Whether any object geom touches any gripper geom (a lookup by geom id per contact:
        this runs at every control step)."""
        if self.data.ncon == 0:
            return False
        contacts = self.data.contact
        first, second = self.geom_part[contacts.geom1], self.geom_part[contacts.geom2]
        return bool(np.any(first * second == _GRIPPER * _OBJECT))


def run_trial(
    scene: Scene,
    grasp: Grasp,
    config: TrialConfig | None = None,
    on_phase: Callable[[Phase, Scene], None] | None = None,
) -> TrialResult:
    """Execute ``grasp`` (world frame) in ``scene`` and score it.

    The scene is reset first, so repeated trials on one scene are independent and identical
    for identical inputs. ``on_phase`` is called at the key moments (pre-grasp, closed, lifted,
    perturbed), e.g. to render frames; it must not change the simulation state.
    """
    config = config or TrialConfig()
    scene.reset()
    scene.model.opt.timestep = config.timestep
    runner = _Runner(scene, config)
    timings: dict[str, float] = {}
    record: dict[str, Any] = {
        "on_handle": False,
        "handle_fraction": 0.0,
        "lift_height": 0.0,
        "slip_lift": None,
        "slip_perturb": None,
        "contact_points_object": [],
    }
    start = time.perf_counter()
    try:
        failure = _execute(scene, grasp, config, runner, timings, record, on_phase)
    except _Diverged:
        failure = "sim_unstable"
    timings["total"] = time.perf_counter() - start
    success = None if failure == "sim_unstable" else failure is None
    return TrialResult(
        object=scene.object_name,
        gripper=scene.gripper.gripper.name,
        seed=scene.seed,
        object_pose=matrix_to_pose7(scene.world_T_object).tolist(),
        grasp=grasp.to_pose7().tolist(),
        grasp_width=float(grasp.width),
        grasp_source=grasp.source,
        success=success,
        failure=failure,
        sim_time=runner.steps * config.timestep,
        steps=runner.steps,
        timings_s=timings,
        **record,
    )


def _execute(
    scene: Scene,
    grasp: Grasp,
    config: TrialConfig,
    runner: _Runner,
    timings: dict[str, float],
    record: dict[str, Any],
    on_phase: Callable[[Phase, Scene], None] | None,
) -> Failure | None:
    """Run the phases; fill ``timings`` and ``record``; return the failure mode or None."""
    data, gripper = scene.data, scene.gripper
    left, right = (np.asarray(g) for g in gripper.finger_geoms)
    gripper_geoms, object_geoms = runner.gripper_geoms, runner.object_geoms

    def held() -> tuple[bool, Any]:
        contacts = finger_contacts(data, left, right, object_geoms)
        return contacts.both, contacts

    clock = time.perf_counter()

    def lap(name: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        timings[name] = now - clock
        clock = now

    # 1. settle, opening the parked gripper
    gripper.set_opening(data, min(grasp.width, gripper.gripper.max_opening))
    runner.advance(config.settle_time)
    world_T_object_settled = scene.object_pose()
    lap("settle")

    # 2. pre-grasp
    world_T_pregrasp = grasp.world_T_tcp.copy()
    world_T_pregrasp[:3, 3] -= config.pregrasp_distance * grasp.approach_world
    gripper.teleport(data, world_T_pregrasp)
    mujoco.mj_forward(scene.model, data)
    if on_phase:
        on_phase("pregrasp", scene)
    if geoms_touching(data, gripper_geoms):
        lap("pregrasp")
        return "invalid_start"
    lap("pregrasp")

    # 3. approach
    mocap_start = data.mocap_pos[gripper.mocap_id].copy()
    gripper.command_tcp(data, grasp.world_T_tcp)
    mocap_goal = data.mocap_pos[gripper.mocap_id].copy()
    runner.advance(config.pregrasp_distance / config.approach_speed, mocap_start, mocap_goal)
    runner.advance(2 * config.control_dt)  # let the weld catch up
    lag = np.linalg.norm(gripper.world_T_tcp(data)[:3, 3] - grasp.world_T_tcp[:3, 3])
    pushed = np.linalg.norm(scene.object_pose()[:3, 3] - world_T_object_settled[:3, 3])
    lap("approach")
    if lag > config.approach_lag_limit or pushed > config.approach_push_limit:
        return "approach_collision"

    # 4. close
    gripper.close(data)
    runner.advance(config.close_time)
    if on_phase:
        on_phase("closed", scene)
    lap("close")
    if not held()[0]:
        return "missed"
    tcp_T_object_closed = relative_pose(gripper.world_T_tcp(data), scene.object_pose())
    object_z_closed = scene.object_pose()[2, 3]

    # 5. lift and hold
    runner.watch_release = True
    lift_start = data.mocap_pos[gripper.mocap_id].copy()
    lift_goal = lift_start + np.array([0.0, 0.0, config.lift_height])
    try:
        runner.advance(config.lift_height / config.lift_speed, lift_start, lift_goal)
        runner.advance(config.hold_time)
    except _Released:
        lap("lift_hold")
        record["lift_height"] = float(scene.object_pose()[2, 3] - object_z_closed)
        return "slipped_in_lift"
    lap("lift_hold")
    if on_phase:
        on_phase("lifted", scene)
    world_T_object = scene.object_pose()
    both, contacts = held()
    record["lift_height"] = float(world_T_object[2, 3] - object_z_closed)
    record["slip_lift"] = slip_distance(
        tcp_T_object_closed, relative_pose(gripper.world_T_tcp(data), world_T_object)
    )
    points_object = points_in_object_frame(contacts.points_world, world_T_object)
    fraction = handle_fraction(points_object, scene.object_model.asset.handle, config.handle_margin)
    record["contact_points_object"] = points_object.tolist()
    record["handle_fraction"] = fraction
    record["on_handle"] = bool(len(points_object)) and fraction >= config.on_handle_threshold
    lifted = record["lift_height"] >= config.lifted_fraction * config.lift_height
    if not (both and lifted):
        return "slipped_in_lift"

    # 6. perturb
    weight = scene.model.body_subtreemass[scene.object_body] * np.linalg.norm(
        scene.model.opt.gravity
    )
    try:
        for direction in np.asarray(config.perturb_directions, dtype=float).reshape(-1, 3):
            force = config.perturb_force_scale * weight * direction / np.linalg.norm(direction)
            data.xfrc_applied[scene.object_body, :3] = force
            runner.advance(config.perturb_time)
            data.xfrc_applied[scene.object_body, :3] = 0.0
            runner.advance(config.perturb_time)
    except _Released:
        data.xfrc_applied[scene.object_body, :3] = 0.0
        lap("perturb")
        return "dropped_in_perturbation"
    lap("perturb")
    if on_phase:
        on_phase("perturbed", scene)
    world_T_object = scene.object_pose()
    record["slip_perturb"] = slip_distance(
        tcp_T_object_closed, relative_pose(gripper.world_T_tcp(data), world_T_object)
    )
    still_lifted = (
        world_T_object[2, 3] - object_z_closed >= config.lifted_fraction * config.lift_height
    )
    if not (held()[0] and still_lifted):
        return "dropped_in_perturbation"
    return None
