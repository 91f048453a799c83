"""Label a grasp set into a directory, resumably: ``labels.jsonl``, ``labels.npz``, a summary.

Every labeled grasp is appended to ``OUT/labels.jsonl`` as it finishes (one line, flushed and
``fsync``-ed by the run engine, :mod:`simgrasp.runs`), so a killed run (even
``kill -9``; its workers exit with it) loses at most the grasp being written; run the same
command again and only the missing grasps run. ``OUT/run.json`` names what the directory
labels (object, gripper, protocol, seed, placement, the grasp file's SHA-256, a mesh-file
object's mesh SHA-256, every trial setting of the protocol, the gripper's time-step cap where
the protocol coarsens the step): a second run with other settings, another file or an edited
mesh, or after the protocol's definition changed, is refused instead of mixing labels. Rows
that are not grasps get a record with failure ``invalid`` and are never executed.

Outputs in input order: ``labels.npz`` (bool ``success`` and ``on_handle``, str ``failure``:
empty for a success, float ``handle_fraction`` and ``lift_height``), ``summary.json``.
"""

from __future__ import annotations

import json
import time
from collections import Counter
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.grasping.labeling.grasp_sets import GraspSet
from simgrasp.grasping.labeling.labeling import INVALID, LabelConfig, LabelResult, label_records
from simgrasp.grippers import make_gripper
from simgrasp.grippers.mount import MOUNT_IMPRATIO
from simgrasp.runs.engine import Backend, RunConfig, run_resumable
from simgrasp.runs.identity import claim_identity, file_digest, object_file_digests
from simgrasp.runs.record_log import RecordLog

LABELS_FILE = "labels.jsonl"
RUN_FILE = "run.json"
OTHER_RUN = "labels of another run"
"""What a refused directory holds instead (:func:`~simgrasp.runs.identity.claim_identity`)."""


def label_key(record: Any) -> int:
    """The identity of a label record: its grasp index."""
    if not isinstance(record, dict) or not isinstance(record.get("index"), int):
        raise SimgraspError(
            f"a label record is a JSON object with an integer index: {record!r:.200}"
        )
    return record["index"]


def labeled_file_digest(out_dir: Path) -> str | None:
    """The SHA-256 of the grasp file a label directory was made from (its ``run.json``), or
    None when it does not say (no or an unreadable ``run.json``)."""
    try:
        digest = json.loads((Path(out_dir) / RUN_FILE).read_text()).get("grasps_sha256")
    except (OSError, ValueError, AttributeError):
        return None
    return digest if isinstance(digest, str) else None


SETTINGS_ADDED = {
    "shake": None,
    "start_tolerance": None,
    "impratio": MOUNT_IMPRATIO,
    "integrator": "implicitfast",
    "finger_solimp_width": None,
}
"""Trial settings added after label runs existed, with the value every earlier run had:
``run.json`` leaves a setting out while it holds that value, so earlier directories resume
and only runs whose physics changed are refused."""


FILE_DIGESTS = ("mesh_sha256", "handles_sha256")
"""The object's file digests (``run.json``); a directory written before they were recorded
adopts them (:func:`_adopt_file_digests`)."""


def _adopt_file_digests(path: Path, identity: dict[str, Any]) -> None:
    """Record the object's file digests (:data:`FILE_DIGESTS`) in a ``run.json`` written
    before runs recorded them, so such a directory (a long ACRONYM run, say) resumes from here
    on: its files cannot be checked before this, only after."""
    adopted = {key: identity[key] for key in FILE_DIGESTS if key in identity}
    if not adopted or not path.is_file():
        return
    try:
        earlier = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):  # claim_identity names what is wrong with it
        return
    if isinstance(earlier, dict) and set(adopted) - set(earlier):
        earlier.update({key: value for key, value in adopted.items() if key not in earlier})
        path.write_text(json.dumps(earlier, indent=2) + "\n", encoding="utf-8")


def run_identity(grasps: GraspSet, config: LabelConfig, grasp_file: Path) -> dict[str, Any]:
    """What ``run.json`` holds: the label config, the grasp file's SHA-256 and row count, a
    mesh-file object's mesh SHA-256, a handle label file's SHA-256, every trial setting of
    the protocol, the gripper's time-step cap where the protocol coarsens the step."""
    run = {**asdict(config), "grasps_sha256": file_digest(grasp_file), "count": len(grasps)}
    run.update(object_file_digests(config.object))  # YCB, generated: none, as before
    run["trial"] = json.loads(json.dumps(asdict(config.trial)))
    for key, before in SETTINGS_ADDED.items():
        if run["trial"][key] == before:
            del run["trial"][key]
    if config.trial.hold_timestep is not None:  # the step actually used is capped by the gripper
        run["gripper_max_timestep"] = make_gripper(config.gripper).max_timestep
    return run


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
    """Label every grasp of ``grasps`` not yet in ``out_dir`` (the run engine's
    :func:`~simgrasp.runs.engine.run_resumable` over
    :func:`~simgrasp.grasping.labeling.label_records`); write the outputs; return the summary
    (also ``summary.json``) and every record in input order."""
    run = RunConfig(workers, backend, address, progress)
    out_dir = Path(out_dir)
    identity = run_identity(grasps, config, grasp_file)
    _adopt_file_digests(out_dir / RUN_FILE, identity)
    claim_identity(  # labels are per grasp index: a run may go on over more of the same file
        out_dir / RUN_FILE,
        identity,
        what=OTHER_RUN,
        ignore=("count",),
    )
    executed: list[int] = []
    start = time.perf_counter()
    finished = run_resumable(
        range(len(grasps)),
        lambda index: index,
        RecordLog(out_dir / LABELS_FILE, key=label_key),
        lambda todo: label_records(grasps, todo, config, ycb_dir, run),
        progress=progress,
        desc="label",
        on_record=lambda r: executed.append(r["index"]) if r["failure"] != INVALID else None,
    )
    wall = time.perf_counter() - start
    records = [finished[i] for i in range(len(grasps))]
    write_label_arrays(out_dir / "labels.npz", records)
    summary = summarize(records, config, new=len(executed), wall_s=wall, workers=workers)
    (out_dir / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary, records


def check_run_dir(out_dir: Path, identity: dict[str, Any]) -> None:
    """Refuse, as :func:`label_grasp_set` would but writing nothing (file digests an older
    ``run.json`` lacks aside: :func:`_adopt_file_digests`), a label directory whose
    ``run.json`` records settings other than ``identity`` (:func:`run_identity`; its grasp
    count aside); a directory without one passes."""
    path = Path(out_dir) / RUN_FILE
    if not path.is_file():
        return
    _adopt_file_digests(path, identity)
    try:
        earlier = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):  # claim_identity names what is wrong with it
        earlier = None
    count = earlier.get("count") if isinstance(earlier, dict) else None
    # with nothing ignored, claim_identity only compares an existing file: it never writes it
    claim_identity(path, {**identity, "count": count}, what=OTHER_RUN)


def write_label_arrays(path: Path, records: list[dict[str, Any]]) -> None:
    """``labels.npz`` of records in input order (``sim_unstable`` counts as not a success)."""
    labels = LabelResult.from_records(records)
    arrays = {
        "success": labels.success,
        "on_handle": labels.on_handle,
        "failure": labels.failure,
        "handle_fraction": labels.handle_fraction,
        "lift_height": labels.lift_height,
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
        "handle_source": sorted({r["handle_source"] for r in executed if "handle_source" in r}),
        "failures": dict(Counter(r["failure"] for r in records if r["failure"])),
        "labeled_this_run": new,
        "wall_s_this_run": wall_s,
        "workers": workers,
        "grasps_per_s": new / wall_s if new and wall_s > 0 else None,
        "trial_wall_s": trial_wall,
        "grasps_per_core_s": len(executed) / trial_wall if trial_wall > 0 else None,
    }
