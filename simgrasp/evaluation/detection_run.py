"""``detect-eval``'s resumable run: every object x detector x seed x noise level one detection
(:func:`~simgrasp.evaluation.detection_eval.evaluate_detection`), run by the run engine
(:mod:`simgrasp.runs`) and appended to ``OUT/detections.jsonl`` as it finishes.

A killed run loses no finished detection; the same command again runs only the missing ones.
``OUT/run.json`` holds the cloud size, the gripper opening and every detector's default
settings: a directory recorded with others is refused instead of mixing their records.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from simgrasp.assets.registry import load_object
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.detection_eval import CLOUD_POINTS, EvalRecord, evaluate_detection
from simgrasp.handles import default_config
from simgrasp.handles.detector_config import DETECTORS, DetectorName
from simgrasp.runs.engine import RunConfig, Work, run_resumable, run_tasks
from simgrasp.runs.identity import claim_identity
from simgrasp.runs.record_log import RecordLog

DETECTIONS_FILE = "detections.jsonl"
RUN_FILE = "run.json"
DetectionKey = tuple[str, str, float, int]


@dataclass(frozen=True)
class DetectionItem:
    """One detection of a run: an object (its asset name), a detector, a noise sigma, a seed."""

    object: str
    detector: DetectorName
    sigma: float
    seed: int

    @property
    def key(self) -> DetectionKey:
        return (self.object, self.detector, float(self.sigma), self.seed)


def detection_key(record: Any) -> DetectionKey:
    """The identity (object, detector, sigma, seed) of a whole detection record; a
    ValueError naming the first missing field otherwise."""
    if not isinstance(record, dict):
        raise SimgraspError(f"a detection record is a JSON object, not {type(record).__name__}")
    missing = [f.name for f in fields(EvalRecord) if f.name not in record]
    if missing:
        raise SimgraspError(f"detection record without {', '.join(missing)}: {record!r:.200}")
    return (record["object"], record["detector"], float(record["sigma"]), record["seed"])


def plan_detections(
    objects: Sequence[str],
    detectors: Sequence[DetectorName],
    sigmas: Sequence[float],
    seeds: Sequence[int],
    ycb_dir: str | None,
) -> list[DetectionItem]:
    """Object x detector x seed x sigma, in the CSV's order; the objects are loaded here (an
    unknown name fails before any worker starts) to name them as their records do."""
    names = [load_object(name, ycb_dir=ycb_dir).name for name in objects]
    return [
        DetectionItem(name, detector, float(sigma), int(seed))
        for name in dict.fromkeys(names)
        for detector in detectors
        for seed in seeds
        for sigma in sigmas
    ]


@functools.cache
def _asset(name: str, ycb_dir: str | None):  # -> ObjectAsset, loaded once per process
    return load_object(name, ycb_dir=ycb_dir)


def run_detection(
    item: DetectionItem, ycb_dir: str | None, gripper_max_opening: float | None
) -> dict[str, Any]:
    """The JSON record of one detection (the engine's task; NaN accuracy as null)."""
    record = evaluate_detection(
        _asset(item.object, ycb_dir), item.detector, item.sigma, item.seed, gripper_max_opening
    )
    return {k: None if isinstance(v, float) and math.isnan(v) else v
            for k, v in asdict(record).items()}  # fmt: skip


def from_json(record: dict[str, Any]) -> EvalRecord:
    """The :class:`EvalRecord` of a logged record (null accuracy as NaN)."""
    values: dict[str, Any] = {}
    for field in fields(EvalRecord):
        value = record[field.name]
        values[field.name] = float("nan") if value is None else value
    return EvalRecord(**values)


def run_identity(gripper_max_opening: float | None) -> dict[str, Any]:
    """What ``run.json`` holds: the cloud size, the opening, every detector's defaults."""
    return {
        "cloud_points": CLOUD_POINTS,
        "gripper_max_opening": gripper_max_opening,
        "detectors": {
            name: asdict(default_config(name, gripper_max_opening)) for name in DETECTORS
        },
    }


def run_evaluation(
    items: Sequence[DetectionItem],
    out_dir: Path,
    *,
    run: RunConfig | None = None,
    ycb_dir: str | None = None,
    gripper_max_opening: float | None = None,
) -> list[EvalRecord]:
    """Run the detections of ``items`` not yet in ``out_dir``; every item's record, in
    ``items`` order."""
    run = run or RunConfig()
    out_dir = Path(out_dir)
    claim_identity(
        out_dir / RUN_FILE, run_identity(gripper_max_opening), what="detections of another run"
    )
    objects = tuple((name,) for name in dict.fromkeys(item.object for item in items))
    work = Work(run_detection, (ycb_dir, gripper_max_opening), _warm_up, objects[: run.workers])
    finished = run_resumable(
        items,
        lambda item: item.key,
        RecordLog(out_dir / DETECTIONS_FILE, key=detection_key),
        lambda todo: run_tasks(work, todo, run),
        progress=run.progress,
        desc="detect-eval",
        unit="detection",
    )
    return [from_json(finished[item.key]) for item in items]


def _warm_up(name: str, ycb_dir: str | None, _gripper_max_opening: float | None) -> None:
    """Load an object in a worker (and with it the detectors' imports)."""
    _asset(name, ycb_dir)
