"""Running a suite on the run engine: a method's records, and the oracle's (cached).

:func:`score_suite` gives every scene of a suite one record in ``OUT/trials.jsonl``: its
scene, the suite's name and digest, the method or answer folder, and the execution's fields
(:mod:`simgrasp.bench.execution`). The records are appended as scenes finish, so a killed run
loses no finished scene and a rerun does only the rest (:mod:`simgrasp.runs.engine`);
``OUT/run.json`` records what the folder holds, and a rerun with another suite definition,
method or answer folder is refused in one line (:mod:`simgrasp.runs.identity`).
:func:`oracle_records` runs the oracle (:mod:`simgrasp.bench.oracle`) the same way, once per
suite, into the cache.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import replace
from pathlib import Path
from typing import Any

from simgrasp.bench.scene_task import AnswerSource, scene_record
from simgrasp.bench.suites import BenchScene, SuiteDefinition, check_suite_data
from simgrasp.grasping.session import close_worker_sessions
from simgrasp.runs.engine import RunConfig, Work, run_resumable, run_tasks
from simgrasp.runs.identity import claim_identity
from simgrasp.runs.out_dir import LOG_FILE, claim_out_dir
from simgrasp.runs.record_log import RecordLog

ORACLE_LOG = "oracle.jsonl"


def _scene_key(record: Any) -> Hashable:
    if not isinstance(record, dict) or not isinstance(record.get("scene"), str):
        raise ValueError("not a bench record (no scene)")
    return record["scene"]


def _world_key(record: Any) -> Hashable:
    if not isinstance(record, dict) or not isinstance(record.get("world"), str):
        raise ValueError("not an oracle record (no world)")
    return record["world"]


def score_suite(
    suite: SuiteDefinition,
    out: Path,
    source: AnswerSource,
    run: RunConfig,
    command: list[str],
) -> list[dict[str, Any]]:
    """Every scene's record, in suite order (module docstring)."""
    check_suite_data(suite)
    if source.method is not None:
        from simgrasp.bench.methods import load_method

        load_method(source.method)  # a bad name fails now, not in every scene
    scenes = suite.scenes()
    with claim_out_dir(out, command):
        identity = {"suite": suite.name, "suite_sha256": suite.digest(), **source.identity()}
        claim_identity(out / "run.json", identity, what="records of another run")
        work = Work(scene_record, (suite, source))
        try:
            finished = run_resumable(
                [s.id for s in scenes],
                lambda item: item,
                RecordLog(out / LOG_FILE, _scene_key),
                lambda todo: run_tasks(work, todo, run),
                progress=run.progress,
                desc=f"bench {suite.name}",
                unit="scene",
            )
        finally:  # the scenes run here (one local worker) used this process's session
            close_worker_sessions()
    return [finished[s.id] for s in scenes]


def oracle_folder(suite: SuiteDefinition) -> Path:
    """Where the oracle of ``suite`` is kept: ``$SIMGRASP_CACHE_DIR/bench/NAME-DIGEST``, the
    digest of the whole suite (a part of it shares the whole's oracle)."""
    from simgrasp.assets.cache import cache_dir

    whole = replace(suite, only=())
    return cache_dir("bench") / f"{whole.name}-{whole.digest()[:16]}"


def oracle_records(suite: SuiteDefinition, run: RunConfig) -> dict[str, dict[str, Any]]:
    """The oracle's record of every world of ``suite`` (:attr:`BenchScene.world`), computed
    where the cache of the whole suite lacks it."""
    from simgrasp.bench.oracle import oracle_task

    check_suite_data(suite)
    whole = replace(suite, only=())
    worlds: dict[str, BenchScene] = {}
    for scene in suite.scenes():
        worlds.setdefault(scene.world, scene)
    folder = oracle_folder(suite)
    with claim_out_dir(folder, ["simgrasp", "bench", "oracle", suite.name], wait=True):
        claim_identity(
            folder / "suite.json",
            {"suite": whole.name, "suite_sha256": whole.digest()},
            what="the oracle of another suite",
        )
        work = Work(oracle_task, (whole,))
        try:
            finished = run_resumable(
                list(worlds.values()),
                lambda scene: scene.world,
                RecordLog(folder / ORACLE_LOG, _world_key),
                lambda todo: run_tasks(work, todo, run),
                progress=run.progress,
                desc=f"oracle {suite.name}",
                unit="scene",
            )
        finally:
            close_worker_sessions()
    return {str(world): record for world, record in finished.items()}
