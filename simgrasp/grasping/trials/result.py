"""The record of one grasp trial (:class:`TrialResult`) and the names of its failures and key
moments (:func:`simgrasp.grasping.trials.trial.run_trial` fills it)."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any, Literal

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


@dataclass(frozen=True)
class TrialResult:
    """The record of one trial (world frame unless named otherwise; m, s).

    ``success`` is None when the simulation diverged (``failure == "sim_unstable"``).
    ``object_pose`` (``world_T_object``, the scene's initial object pose) and ``grasp``
    (``world_T_tcp``, the commanded grasp) are ``[x, y, z, qw, qx, qy, qz]``.
    ``contact_points_object`` are the finger-object contacts at the end of the hold, in the
    object frame. ``slip_*`` is the object's motion relative to the TCP from the end of closing
    to the end of the hold / of the perturbation.
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
    :mod:`simgrasp.grasping.trials.shake`); None, and left out of the record, otherwise."""
    handle_source: str = "shipped"
    """Where the handle label ``on_handle`` was scored against came from
    (:attr:`simgrasp.assets.object.ObjectAsset.handle_source`: ``shipped``, ``file`` or
    ``automatic``)."""

    def to_json(self) -> dict[str, Any]:
        """The record as a dict of JSON types (shallow: its lists are this result's own);
        ``score`` only where the protocol gives one."""
        record = {f.name: getattr(self, f.name) for f in fields(self)}
        if record["score"] is None:
            del record["score"]
        return record
