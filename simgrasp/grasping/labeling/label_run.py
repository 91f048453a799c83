"""Label a grasp set into a directory, resumably: ``labels.jsonl``, ``labels.npz``, a summary.

Every labeled grasp is appended to ``OUT/labels.jsonl`` as it finishes (one line, flushed and
``fsync``-ed: :class:`~simgrasp.evaluation.trial_log.TrialLog`), so a killed run (even
``kill -9``; its workers exit with it) loses at most the grasp being written; run the same
command again and only the missing grasps run. ``OUT/run.json`` names what the directory
labels (object, gripper, protocol, seed, placement, the grasp file's SHA-256, every trial
setting of the protocol, the gripper's time-step cap where the protocol coarsens the step): a
second run with other settings or another file, or after the protocol's definition changed,
is refused instead of mixing labels. Rows that are not grasps get a record with failure
``invalid`` and are never executed.

Outputs in input order: ``labels.npz`` (bool ``success`` and ``on_handle``, str ``failure``:
empty for a success, float ``handle_fraction`` and ``lift_height``), ``summary.json``.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import time
from collections import Counter
from collections.abc import Iterator
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import asdict
from pathlib import Path
from typing import Any, Literal

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.evaluation.trial_log import TrialLog
from simgrasp.grasping.labeling.grasp_sets import GraspSet
from simgrasp.grasping.labeling.labeling import (
    INVALID,
    LabelConfig,
    invalid_record,
    label_one,
    prepare,
)
from simgrasp.grippers import make_gripper
from simgrasp.ray_session import ray_session

Backend = Literal["local", "ray"]
LABELS_FILE = "labels.jsonl"
RUN_FILE = "run.json"
Job = tuple[int, np.ndarray, float]
"""(index, object_T_tcp, width) of one grasp to label."""


def label_key(record: Any) -> int:
    """The identity of a label record: its grasp index."""
    if not isinstance(record, dict) or not isinstance(record.get("index"), int):
        raise SimgraspError(
            f"a label record is a JSON object with an integer index: {record!r:.200}"
        )
    return record["index"]


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes (hex)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def check_run(out_dir: Path, run: dict[str, Any]) -> None:
    """Write ``run.json``, or refuse a directory that labels something else."""
    path = Path(out_dir) / RUN_FILE
    if path.exists():
        earlier = json.loads(path.read_text())
        if earlier != run:
            changed = sorted(k for k in set(run) | set(earlier) if run.get(k) != earlier.get(k))
            raise SimgraspError(
                f"{out_dir} holds labels of another run (different {', '.join(changed)}); "
                "use another --out"
            )
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(run, indent=2) + "\n")


def run_local(
    config: LabelConfig, ycb_dir: str | None, jobs: list[Job], workers: int
) -> Iterator[dict[str, Any]]:
    """Label records in completion order, from ``workers`` spawned processes (``<= 1``: here)."""
    from simgrasp.process_pool import spawn_pool

    if workers <= 1:
        yield from (label_one(config, ycb_dir, *job) for job in jobs)
        return
    pool = spawn_pool(workers)
    try:
        list(pool.map(prepare, itertools.repeat(config, workers), itertools.repeat(ycb_dir)))
        pending = {pool.submit(label_one, config, ycb_dir, *job) for job in jobs}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            yield from (future.result() for future in done)
    finally:
        pool.shutdown(cancel_futures=True)


def run_ray(
    config: LabelConfig, ycb_dir: str | None, jobs: list[Job], workers: int, address: str | None
) -> Iterator[dict[str, Any]]:
    """Label records as Ray tasks finish (a new local instance with ``workers`` CPUs, or the
    cluster at ``address``), as ``evaluate --backend ray`` runs its trials."""
    with ray_session(workers, address) as ray:
        remote = ray.remote(label_one)
        pending = [remote.remote(config, ycb_dir, *job) for job in jobs]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield from ray.get(done)


def label_grasp_set(
    grasps: GraspSet,
    config: LabelConfig,
    out_dir: Path,
    *,
    grasp_file: Path,
    ycb_dir: str | None = None,
    workers: int = 1,
    backend: Backend = "local",
    address: str | None = None,
    progress: bool = True,
) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """Label every grasp of ``grasps`` not yet in ``out_dir``; write the outputs; return the
    summary (also ``summary.json``) and every record in input order."""
    from tqdm import tqdm

    if backend not in ("local", "ray"):
        raise SimgraspError(f"unknown backend {backend!r}; use 'local' or 'ray'")
    out_dir = Path(out_dir)
    run = {**asdict(config), "grasps": str(grasp_file), "grasps_sha256": file_digest(grasp_file)}
    run["count"] = len(grasps)
    run["trial"] = json.loads(json.dumps(asdict(config.trial)))
    for key in ("shake", "start_tolerance"):  # None: run.json as before these settings
        if run["trial"][key] is None:
            del run["trial"][key]
    if config.trial.hold_timestep is not None:  # the step actually used is capped by the gripper
        run["gripper_max_timestep"] = make_gripper(config.gripper).max_timestep
    check_run(out_dir, {k: v for k, v in run.items() if k != "grasps"})
    log = TrialLog(out_dir / LABELS_FILE, key=label_key)
    finished = {label_key(r): r for r in log.load() if 0 <= label_key(r) < len(grasps)}
    for index, problem in grasps.problems.items():
        if index not in finished:
            finished[index] = invalid_record(index, problem, config)
            log.append(finished[index])
    jobs = [
        (i, grasps.object_T_tcp[i], float(grasps.width[i]))
        for i in range(len(grasps))
        if i not in finished
    ]
    bar = tqdm(total=len(grasps), initial=len(finished), desc="label", disable=not progress)
    start = time.perf_counter()
    runner = (
        run_ray(config, ycb_dir, jobs, workers, address)
        if backend == "ray"
        else run_local(config, ycb_dir, jobs, workers)
    )
    for record in runner if jobs else ():
        if label_key(record) not in finished:
            log.append(record)
            finished[label_key(record)] = record
            bar.update()
    bar.close()
    wall = time.perf_counter() - start
    records = [finished[i] for i in range(len(grasps))]
    write_label_arrays(out_dir / "labels.npz", records)
    summary = summarize(records, config, new=len(jobs), wall_s=wall, workers=workers)
    (out_dir / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary, records


def write_label_arrays(path: Path, records: list[dict[str, Any]]) -> None:
    """``labels.npz`` of records in input order (``sim_unstable`` counts as not a success)."""
    arrays = {
        "success": np.array([r["success"] is True for r in records], dtype=bool),
        "on_handle": np.array([bool(r["on_handle"]) for r in records], dtype=bool),
        "failure": np.array([r["failure"] or "" for r in records], dtype=str),
        "handle_fraction": np.array([r["handle_fraction"] for r in records], dtype=float),
        "lift_height": np.array([r["lift_height"] for r in records], dtype=float),
    }
    if _scored(records):
        arrays["score"] = np.array([r.get("score", 0.0) for r in records], dtype=float)
    np.savez(path, **arrays)  # type: ignore[arg-type]


def _scored(records: list[dict[str, Any]]) -> bool:
    """Whether the protocol gave the records a ``score`` (an ``invalid`` row has none)."""
    return any("score" in r for r in records)


def summarize(
    records: list[dict[str, Any]], config: LabelConfig, new: int, wall_s: float, workers: int
) -> dict[str, Any]:
    """Counts and shares over the scored grasps (not invalid, not ``sim_unstable``); the
    speed of this run (``grasps_per_s``: labeled this run over its wall time, worker start-up
    included) and per core over all labels (``grasps_per_core_s``: executed grasps over the sum
    of their trials' wall times)."""
    executed = [r for r in records if r["failure"] != INVALID]
    trial_wall = sum(r["timings_s"]["total"] for r in executed)
    valid = [r for r in records if r["failure"] not in (INVALID, "sim_unstable")]
    held = [r for r in valid if r["success"]]
    on_handle = [r for r in held if r["on_handle"]]
    return {
        **asdict(config),
        "grasps": len(records),
        "invalid": sum(r["failure"] == INVALID for r in records),
        "sim_unstable": sum(r["failure"] == "sim_unstable" for r in records),
        "scored": len(valid),
        "success": len(held),
        "success_rate": len(held) / len(valid) if valid else 0.0,
        "success_on_handle": len(on_handle),
        "success_off_handle": len(held) - len(on_handle),
        "on_handle_share_of_successes": len(on_handle) / len(held) if held else 0.0,
        "failures": dict(Counter(r["failure"] for r in records if r["failure"])),
        "labeled_this_run": new,
        "wall_s_this_run": wall_s,
        "workers": workers,
        "grasps_per_s": new / wall_s if new and wall_s > 0 else None,
        "trial_wall_s": trial_wall,
        "grasps_per_core_s": len(executed) / trial_wall if trial_wall > 0 else None,
    }
