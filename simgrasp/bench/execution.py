"""Executing a method's grasps in a bench scene: the scene's record.

The first ``attempts`` grasps of the answer (best first) are tried in turn, each as one trial
of the suite's protocol on the same scene (:func:`~simgrasp.grasping.trials.trial.run_trial`
resets it), until one lifts and holds the object; the record is that trial's, or the last
one's. In clutter the neighbors are watched as the chain watches them
(:mod:`simgrasp.grasping.trials.clutter_scoring`). ``on_handle`` counts only for a success.
Trials are deterministic, so the same scene and grasps give the same record (``timings_s``
apart: wall-clock seconds).
"""

from __future__ import annotations

from typing import Any

from simgrasp.bench.grasp_files import AnswerProblem
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.clutter_scoring import NeighborWatch, score_in_clutter
from simgrasp.grasping.trials.result import TrialResult
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene

DROPPED_FIELDS = ("contact_points_object", "timings_s", "object", "seed")
"""Trial fields a bench record leaves out (bulky, or the scene's own fields)."""


def no_trial(failure: str, detail: str | None = None) -> dict[str, Any]:
    """The record fields of a scene where nothing was executed: ``failure`` names why
    (``no_grasp``, or an :class:`AnswerProblem`'s) and ``detail`` says more."""
    fields: dict[str, Any] = {
        "success": False,
        "on_handle": False,
        "failure": failure,
        "attempts": 0,
        "grasp": None,
    }
    if detail is not None:
        fields["failure_detail"] = detail
    return fields


def execute_answer(
    scene: Scene, answer: list[Grasp] | AnswerProblem, config: TrialConfig, attempts: int
) -> dict[str, Any]:
    """The record fields of executing ``answer`` in ``scene`` (module docstring)."""
    if isinstance(answer, AnswerProblem):
        return {**no_trial(answer.failure, answer.detail), "grasps": 0}
    if not answer:
        return {**no_trial("no_grasp"), "grasps": 0}
    fields: dict[str, Any] = {}
    for attempt, grasp in enumerate(answer[:attempts], start=1):
        trial, fields = _attempt(scene, grasp, config)
        fields = {**fields, "attempts": attempt}
        if trial.success:
            break
    return {**fields, "grasps": len(answer)}


def _attempt(scene: Scene, grasp: Grasp, config: TrialConfig) -> tuple[TrialResult, dict]:
    """One trial of ``grasp`` and its record fields (the clutter fields in clutter)."""
    watch = NeighborWatch.of(scene) if scene.distractors else None
    trial = run_trial(scene, grasp, config, watch)
    fields = trial.to_json()
    timings = {"trial": float(fields["timings_s"].get("total", 0.0))}
    fields = {k: v for k, v in fields.items() if k not in DROPPED_FIELDS}
    if watch is not None:
        fields.update(score_in_clutter(scene, trial, watch, config))
    fields["on_handle"] = bool(trial.on_handle and trial.success)
    fields["timings_s"] = timings
    return trial, fields
