"""One scene of a bench run, from its id to its record: build the scene, get the answer (the
method's in process, or the answer file), execute it.

The record holds the scene's id and axes, the suite's name and digest, where the grasps came
from and the execution's fields (:mod:`simgrasp.bench.execution`); ``timings_s`` (wall-clock
seconds of the build, the observation, the method and the trials, and ``cpu``: the process's
CPU seconds for the scene, all its threads) is the only field that differs between two runs
of the same scenes. A method that raises is the scene's
``method_error`` failure, named in the record, not the run's end.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from simgrasp.bench.execution import execute_answer
from simgrasp.bench.grasp_files import AnswerProblem, answer_grasps, grasp_file, read_answer
from simgrasp.bench.methods import Method, load_method
from simgrasp.bench.scene_build import build_bench_scene, chain_config, observe_bench_scene
from simgrasp.bench.suites import SuiteDefinition
from simgrasp.errors import SimgraspError
from simgrasp.grasping.grasp import Grasp


@dataclass(frozen=True)
class AnswerSource:
    """Where a run's grasps come from: ``method`` (a proposer's name or ``MODULE:FUNCTION``,
    run in process) or ``grasps_dir`` (a folder of ``SCENE.json`` answers); ``attempts``:
    how many of each answer's grasps may be executed, best first, until one holds."""

    method: str | None = None
    grasps_dir: str | None = None
    attempts: int = 1

    def __post_init__(self) -> None:
        if (self.method is None) == (self.grasps_dir is None):
            raise SimgraspError("give a method or a folder of grasp files, not both")
        if self.attempts < 1:
            raise SimgraspError(f"attempts must be >= 1, got {self.attempts}")

    def identity(self) -> dict[str, Any]:
        """What a record folder of this source holds, for ``run.json``."""
        if self.method is not None:
            return {"method": self.method, "attempts": self.attempts}
        return {"grasps": str(Path(self.grasps_dir or "").resolve()), "attempts": self.attempts}


@lru_cache(maxsize=8)
def _method(name: str) -> Method:
    return load_method(name)


def scene_record(scene_id: str, suite: SuiteDefinition, source: AnswerSource) -> dict[str, Any]:
    """The record of scene ``scene_id`` of ``suite`` with the grasps of ``source``."""
    scene = suite.scene(scene_id)
    timings: dict[str, float] = {}
    clock, cpu = time.perf_counter(), time.process_time()

    def lap(name: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        timings[name], clock = now - clock, now

    built = build_bench_scene(suite, scene)
    lap("build")
    max_opening = float(built.gripper.gripper.max_opening)
    if source.method is not None:
        observation = observe_bench_scene(suite, scene, built)
        lap("observe")
        answer = _answer_of(source.method, observation, max_opening)
        lap("method")
    else:
        path = grasp_file(Path(source.grasps_dir or "."), scene.id)
        answer = read_answer(path, max_opening, "file")
    fields = execute_answer(built, answer, chain_config(suite, scene).trial, source.attempts)
    fields.pop("timings_s", None)
    lap("trials")
    timings["cpu"] = time.process_time() - cpu
    return {
        "scene": scene.id,
        "world": scene.world,
        "suite": suite.name,
        "suite_sha256": suite.digest(),
        **scene.axes(),
        "seed": scene.seed,
        "method": source.method or "files",
        **fields,
        "timings_s": timings,
    }


def _answer_of(name: str, observation: Any, max_opening: float) -> list[Grasp] | AnswerProblem:
    """The method's answer for ``observation``, checked as a file's would be."""
    try:
        payload = _method(name)(observation)
    except Exception as error:  # the method's own failure: this scene's, named in its record
        detail = f"{name}: {type(error).__name__}: {error}".splitlines()[0]
        return AnswerProblem("method_error", detail)
    return answer_grasps(payload, max_opening, name, f"the answer of {name}")
