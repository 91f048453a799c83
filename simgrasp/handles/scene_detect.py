"""Handles in a whole scene: segment the scene cloud, then detect on each object's points
(with its side parts: a pot's tabs come out of the segmentation as segments of their own),
the table plane and the whole scene (what the sensor saw) given to the quadric detector's
plate test.

Normals of a single-view scene are turned toward the sensor: the file's ``VIEWPOINT`` unless
the caller gives another viewpoint. Results are in the scene cloud's frame (m).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from simgrasp.errors import SimgraspError
from simgrasp.handles import DetectorName, default_config, detect
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import TIMING_STEPS, Detection
from simgrasp.handles.single_view.detector import SingleViewConfig
from simgrasp.perception.depth_image import DepthImageConfig
from simgrasp.perception.scene_cloud import read_scene
from simgrasp.perception.segmentation.segment import Segmentation, segment_scene
from simgrasp.perception.segmentation.segment_config import SegmentConfig


@dataclass(frozen=True)
class SceneDetection:
    """The segmentation of a scene and the detection on each chosen object.

    Attributes:
        segmentation: the scene's segmentation (labels, table plane, objects).
        detections: ``(object label, detection)`` pairs, by label.
        viewpoint: (3,) sensor position the normals were turned toward (m, cloud frame).
    """

    segmentation: Segmentation
    detections: tuple[tuple[int, Detection], ...]
    viewpoint: tuple[float, float, float]

    def to_json(self) -> dict[str, Any]:
        """As ``simgrasp detect --json``, each handle and candidate with its ``object``, plus
        the segmentation (as ``simgrasp segment --json``)."""
        handles = [
            {**h.to_json(), "object": label, "detector": d.detector}
            for label, d in self.detections
            for h in d.handles
        ]
        candidates = [
            {**c.to_json(), "object": label} for label, d in self.detections for c in d.candidates
        ]
        timings = {
            step: float(sum(d.timings_s.get(step, 0.0) for _, d in self.detections))
            for step in TIMING_STEPS
        }
        timings["segment"] = float(self.segmentation.timings_s["total"])
        return {
            "detector": self.detections[0][1].detector if self.detections else None,
            "handles": sorted(handles, key=lambda h: -h["score"]),
            "candidates": candidates,
            "neighborhoods": int(sum(d.neighborhoods for _, d in self.detections)),
            "timings_s": timings,
            "viewpoint": list(self.viewpoint),
            "segmentation": self.segmentation.to_json(),
        }


def parse_object_choice(text: str) -> int | None:
    """``--object`` value: ``all`` -> None, else an object label >= 2."""
    if text == "all":
        return None
    try:
        label = int(text)
    except ValueError:
        raise SimgraspError(
            f"--object must be an object label (2, 3, ...) or 'all', got {text!r}"
        ) from None
    if label < 2:
        raise SimgraspError(f"--object must be an object label (2, 3, ...) or 'all', got {label}")
    return label


def detect_in_scene(
    path: str | Path,
    config: QuadricDetectorConfig | TenPasConfig | None = None,
    seed: int = 0,
    *,
    detector: DetectorName = "quadric",
    viewpoint: ArrayLike | None = None,
    single_view: SingleViewConfig | None = None,
    only_object: int | None = None,
    segment_config: SegmentConfig | None = None,
    depth: DepthImageConfig | None = None,
) -> SceneDetection:
    """Segment the scene file at ``path`` and detect handles on each whole object with its
    side parts (a pot with its tabs: :attr:`SegmentedObject.part_of`), or only on the object
    of ``only_object``, a label of the segmentation; ``ValueError`` for an unknown label.
    ``single_view``: the single-view detector's settings for objects measured to be one view
    from the sensor (:func:`simgrasp.handles.detect`). ``depth``: how a depth image file
    becomes the scene (:mod:`simgrasp.perception.depth_image`)."""
    scene = read_scene(path, depth)
    segmentation = segment_scene(scene, segment_config)
    labels = [obj.label for obj in segmentation.objects]
    if only_object is not None:
        if only_object not in labels:
            raise SimgraspError(
                f"{path}: no object {only_object}; the segmentation found "
                f"{len(labels)} (labels {', '.join(map(str, labels)) or 'none'})"
            )
        labels = [segmentation.objects[labels.index(only_object)].part_of]
    else:
        labels = list(segmentation.whole_objects())
    eye = scene.viewpoint if viewpoint is None else np.asarray(viewpoint, dtype=np.float64)
    config = config if config is not None else default_config(detector)
    seen = scene.points[np.isfinite(scene.points).all(axis=1)].astype(np.float64)
    detections = tuple(
        (
            label,
            detect(
                scene.points[segmentation.object_mask(label)].astype(np.float64),
                None,
                config,
                seed,
                detector=detector,
                viewpoint=eye,
                table=segmentation.plane,
                scene=seen,
                single_view=single_view,
            ),
        )
        for label in labels
    )
    x, y, z = (float(v) for v in eye)
    return SceneDetection(segmentation, detections, (x, y, z))


TABLE_EXTENT = 0.3
"""Least extent (m, the inliers' bounding-box diagonal) of a plane that makes a cloud a whole
scene: wider than the objects a hand takes by a handle, narrower than any table seen whole."""


def table_in(points: ArrayLike) -> tuple[float, float] | None:
    """``(share of the points on it, its extent in m)`` of the table plane ``segment`` would
    find in an object cloud (m), when that plane spans :data:`TABLE_EXTENT` or more: the cloud
    is then a whole scene given where one object was expected; None otherwise. For a note, not
    a refusal: a flat tool as wide is rare, and its handles are still found."""
    from simgrasp.perception.scene_cloud import scene_from_array
    from simgrasp.perception.segmentation.segment import fit_table_plane

    scene = scene_from_array(np.asarray(points, dtype=np.float32))
    config = SegmentConfig()
    try:
        plane = fit_table_plane(scene.points, scene.valid, scene, config)
    except SimgraspError:  # no plane flat and large enough: no table
        return None
    on_table = np.abs(scene.points @ plane[:3] + plane[3]) <= config.table_distance
    table = scene.points[on_table]
    extent = float(np.linalg.norm(table.max(axis=0) - table.min(axis=0))) if len(table) else 0.0
    return (float(on_table.mean()), extent) if extent >= TABLE_EXTENT else None
