"""Scene segmentation against per-point ground truth (the OSD convention).

Ground-truth labels: 0 invalid, 1 - 9 table parts, >= 20 object parts (disjoint parts of one
occluded object carry different labels). As the dataset intends for model-free methods, each
part (label >= 20) is scored by its best IoU with any predicted object (label >= 2).
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception.scene_cloud import read_scene
from simgrasp.perception.segmentation.segment import FIRST_OBJECT, segment_scene
from simgrasp.perception.segmentation.segment_config import SegmentConfig

FIRST_PART = 20
GOOD_IOU = 0.8


@dataclass(frozen=True)
class SceneScore:
    """One scene segmented by one method.

    Attributes:
        scene: the scene's file stem (``learn0``).
        method: ``grid`` (ours) or ``dbscan`` (the plain baseline).
        part_ious: best IoU of each ground-truth part, by increasing part label.
        objects: number of predicted objects.
        seconds: CPU time of the segmentation (s; reading excluded), the least of the
            repeats: on a shared machine CPU time is what one core spends, wall time is not.
        wall_seconds: wall time of the same segmentation (s), the least of the repeats.
        side_parts: objects found to be a side part of another (``part_of``).
        side_parts_right: of those, how many lie mostly on the ground-truth object that their
            whole lies mostly on.
    """

    scene: str
    method: str
    part_ious: tuple[float, ...]
    objects: int
    seconds: float
    wall_seconds: float
    side_parts: int = 0
    side_parts_right: int = 0


def part_ious(truth: NDArray[np.integer], predicted: NDArray[np.integer]) -> NDArray[np.float64]:
    """Best IoU of each ground-truth part (label >= 20, by increasing label) with any
    predicted object (label >= 2); both are per-point label arrays of equal length."""
    truth = np.asarray(truth).reshape(-1)
    predicted = np.asarray(predicted).reshape(-1)
    if truth.shape != predicted.shape:
        raise SimgraspError(f"label arrays differ in length: {truth.size} vs {predicted.size}")
    parts = np.unique(truth[truth >= FIRST_PART])
    if len(parts) == 0:
        return np.zeros(0)
    part_of = np.searchsorted(parts, truth)
    in_part = truth >= FIRST_PART
    objects = np.where(predicted >= FIRST_OBJECT, predicted - FIRST_OBJECT + 1, 0)
    width = int(objects.max()) + 1
    both = np.bincount(
        part_of[in_part] * width + objects[in_part], minlength=len(parts) * width
    ).reshape(len(parts), width)
    part_size = both.sum(axis=1)
    object_size = np.bincount(objects, minlength=width)
    union = part_size[:, None] + object_size[None, :] - both
    iou = both[:, 1:] / np.maximum(union[:, 1:], 1)
    return iou.max(axis=1) if iou.shape[1] else np.zeros(len(parts))


def score_scene(
    path: Path,
    method: Literal["grid", "dbscan"],
    config: SegmentConfig | None = None,
    repeats: int = 1,
) -> SceneScore:
    """Segment the scene at ``path`` with ``method`` and score it against its ``label``
    field; ``seconds`` is the fastest of ``repeats`` runs."""
    scene = read_scene(path)
    if scene.labels is None:
        raise SimgraspError(f"{path}: the scene has no per-point 'label' field to score against")
    cpu, wall, result = float("inf"), float("inf"), None
    for _ in range(repeats):
        start, start_wall = time.process_time(), time.perf_counter()
        result = segment_scene(scene, config, method=method)
        cpu = min(cpu, time.process_time() - start)
        wall = min(wall, time.perf_counter() - start_wall)
    assert result is not None  # repeats >= 1
    ious = part_ious(scene.labels, result.labels)
    parts = [(o.label, o.part_of) for o in result.objects if o.part_of != o.label]
    owner = _owners(scene.labels, result.labels)
    right = sum(owner[a] == owner[b] >= FIRST_OBJECT for a, b in parts)
    return SceneScore(
        Path(path).stem,
        method,
        tuple(ious.tolist()),
        len(result.objects),
        cpu,
        wall,
        len(parts),
        right,
    )


def _owners(truth: NDArray[np.integer], predicted: NDArray[np.integer]) -> NDArray[np.int64]:
    """Per predicted label, the ground-truth object (part label // 10, >= 2) most of its points
    lie on; 0 when none."""
    objects = np.asarray(truth).reshape(-1) // 10
    predicted = np.asarray(predicted).reshape(-1)
    on = (objects >= FIRST_OBJECT) & (predicted >= FIRST_OBJECT)
    width = int(objects.max()) + 1
    counts = np.bincount(
        predicted[on] * width + objects[on], minlength=(predicted.max() + 1) * width
    )
    counts = counts.reshape(-1, width)
    return np.where(counts.max(axis=1) > 0, counts.argmax(axis=1), 0)


def summarize(scores: Iterable[SceneScore]) -> dict[str, float]:
    """Mean part IoU, share of parts with IoU >= 0.8, parts, scenes, and median / mean CPU ms
    and median wall ms per scene of ``scores`` (one method)."""
    scores = list(scores)
    ious = np.array([iou for s in scores for iou in s.part_ious])
    ms = np.array([s.seconds * 1000 for s in scores])
    return {
        "scenes": len(scores),
        "parts": len(ious),
        "mean_iou": float(ious.mean()) if len(ious) else 0.0,
        "share_iou_0.8": float(np.mean(ious >= GOOD_IOU)) if len(ious) else 0.0,
        "median_ms": float(np.median(ms)) if len(ms) else 0.0,
        "mean_ms": float(ms.mean()) if len(ms) else 0.0,
        "side_parts": int(sum(s.side_parts for s in scores)),
        "side_parts_right": int(sum(s.side_parts_right for s in scores)),
        "median_wall_ms": float(np.median([s.wall_seconds * 1000 for s in scores]))
        if scores
        else 0.0,
    }


def osd_scenes(folder: Path) -> list[Path]:
    """The ``learn<N>.pcd`` scenes of an osd-learn folder, by N."""
    return sorted(Path(folder).glob("learn*.pcd"), key=lambda p: int(p.stem[5:] or -1))
