"""Handle detection on real single-view clouds: the pots of osd-learn against our labels.

Each labeled scene's pot is cut out of the scene (by its ground-truth part labels, or by the
scene segmentation), its handles detected with normals turned toward the sensor (the origin
of the sensor frame), and scored: candidate accuracy (share of candidate neighborhood centers
inside a labeled handle, the paper's Table I measure) and whether the top-scored handle's
center lies on a labeled handle.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.assets.real import LabeledScene
from simgrasp.assets.scene_labels import SceneHandleLabel, load_scene_labels
from simgrasp.handles import detect
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.detector_config import DetectorName
from simgrasp.handles.single_view.detector import SingleViewConfig
from simgrasp.perception.segmentation.segment import segment_scene
from simgrasp.perception.segmentation.segment_config import SegmentConfig

SENSOR_ORIGIN = np.zeros(3)
POT_SEGMENTATION = SegmentConfig(rim_band=0.005)
"""The segmentation the pots are cut with (and ``real_depth.toml`` gives ``detect
--segment``): the defaults plus rim joins (:mod:`simgrasp.perception.segmentation.segment_rims`), so
an upright pot seen from above is one object, not its outside (with its tabs) and its inside."""


@dataclass(frozen=True)
class PotResult:
    """One detection on one scene's pot.

    Attributes:
        scene: scene name (``learn34``); seed: the detection seed.
        cut: how the pot was cut from the scene (``"labels"`` or ``"segment"``).
        cut_iou: IoU of the cut pot with the ground-truth pot (1 for ``"labels"``).
        handle_kept: share of the labeled pot's handle points that the cut kept.
        points: points of the pot cloud handed to the detector.
        candidates: candidate count; on_handle: how many of their centers are in a label.
        top_on_handle: the top-scored handle's center lies in a labeled handle (False when
            no handle was found).
        handles: handle count; detect_s: wall time of the detection (s).
    """

    scene: str
    seed: int
    cut: str
    cut_iou: float
    handle_kept: float
    points: int
    candidates: int
    on_handle: int
    top_on_handle: bool
    handles: int
    detect_s: float

    @property
    def accuracy(self) -> float:
        """Candidate accuracy; NaN without candidates."""
        return self.on_handle / self.candidates if self.candidates else float("nan")


def labeled_pot(scene: LabeledScene, label: SceneHandleLabel) -> NDArray[np.float64]:
    """The pot's points cut by the ground-truth part labels (sensor frame, m)."""
    return scene.object_points(label.object_id)


def segmented_pot(
    scene: LabeledScene, label: SceneHandleLabel, config: SegmentConfig | None = None
) -> tuple[NDArray[np.float64], float]:
    """The pot's points as the scene segmentation (:func:`segment_scene`) cuts them: the
    segmented object overlapping the ground-truth pot most (the labels only pick which object
    is the pot), with its side parts, as ``detect --segment`` takes it. Returns its points
    (sensor frame, m) and its IoU with the labeled pot."""
    segmentation = segment_scene(scene.cloud, config)
    predicted = segmentation.labels
    truth = scene.labels // 10 == label.object_id
    candidates, overlap = np.unique(predicted[truth & (predicted >= 2)], return_counts=True)
    if len(candidates) == 0:
        return np.zeros((0, 3)), 0.0
    best = int(candidates[np.argmax(overlap)])
    pot = segmentation.object_mask(segmentation.objects[best - 2].part_of)
    iou = float((pot & truth).sum() / (pot | truth).sum())
    return scene.points[pot], iou


def score_pot(
    points: NDArray[np.float64],
    label: SceneHandleLabel,
    config: QuadricDetectorConfig | TenPasConfig,
    seed: int,
    detector: DetectorName = "quadric",
    cut: tuple[str, float, float] = ("labels", 1.0, 1.0),
    table: NDArray[np.float64] | None = None,
    scene: NDArray[np.float64] | None = None,
    single_view: SingleViewConfig | None = None,
) -> PotResult:
    """Detect handles on one pot cloud and score them against its label; ``cut`` records
    how the cloud was cut (method, IoU with the labeled pot, handle points kept), ``table`` is
    the table plane and ``scene`` the scene's valid points (sensor frame) for the
    plate test, as ``detect --segment`` gives them."""
    start = time.perf_counter()
    detection = detect(
        points,
        None,
        config,
        seed,
        detector=detector,
        viewpoint=SENSOR_ORIGIN,
        table=table,
        scene=scene,
        single_view=single_view,
    )
    elapsed = time.perf_counter() - start
    centers = detection.candidate_centers
    top = detection.handles[0].center[None] if detection.handles else np.zeros((0, 3))
    return PotResult(
        scene=label.scene,
        seed=seed,
        cut=cut[0],
        cut_iou=cut[1],
        handle_kept=cut[2],
        points=len(points),
        candidates=len(centers),
        on_handle=int(label.label.contains(centers).sum()) if len(centers) else 0,
        top_on_handle=bool(label.label.contains(top).any()),
        handles=len(detection.handles),
        detect_s=elapsed,
    )


def labeled_scenes(path: Path | None = None) -> dict[str, SceneHandleLabel]:
    """The scene labels with at least one visible handle region, by scene name."""
    return {k: v for k, v in load_scene_labels(path).items() if v.label.regions}
