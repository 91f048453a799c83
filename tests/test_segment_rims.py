"""Rim joins (``SegmentConfig.rim_band``): the inside of a round container seen over its rim
joins its outside; two cans, two boxes in line and the defaults (no joins) do not. Real scene:
learn37's upright pot (needs the real data; skipped cleanly without it)."""

from __future__ import annotations

import numpy as np
import pytest

from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.perception.segmentation.segment_rims import rim_parents

TABLE = np.array([0.0, 0.0, 1.0, 0.0])  # z = 0; the sensor looks from -y
JOINS = SegmentConfig(rim_band=0.005)


def arc(center: tuple[float, float], radius: float, angles: np.ndarray, top: float) -> np.ndarray:
    """A wall's points: an arc of a vertical cylinder from the table up to ``top`` (m)."""
    heights = np.arange(0.0, top + 1e-9, 0.004)
    a, z = np.meshgrid(angles, heights, indexing="ij")
    x = center[0] + radius * np.cos(a)
    y = center[1] + radius * np.sin(a)
    return np.stack([x, y, z], axis=-1).reshape(-1, 3)


def joined(objects: list[np.ndarray], config: SegmentConfig = JOINS) -> np.ndarray:
    """``rim_parents`` of the objects labeled 2, 3, ... (no side parts)."""
    points = np.concatenate(objects).astype(np.float32)
    labels = np.concatenate([np.full(len(o), k + 2, np.int32) for k, o in enumerate(objects)])
    parents = np.arange(len(objects) + 2, dtype=np.int32)
    return rim_parents(labels, points, points[:, 2], TABLE, parents, config)


FRONT = np.linspace(-np.pi + 0.3, -0.3, 40)  # the half facing the sensor (-y)
BACK = np.linspace(0.3, np.pi - 0.3, 40)


def test_a_pots_inside_joins_its_outside() -> None:
    outside = arc((0.0, 0.0), 0.09, FRONT, 0.10)  # the front wall's outside
    inside = np.concatenate(
        [arc((0.0, 0.0), 0.086, BACK, 0.10), [[0.0, 0.03, 0.004], [0.02, 0.04, 0.004]]]
    )  # the back wall's inside, seen over the front rim, and the floor
    parents = joined([outside, inside])
    assert parents[2] == parents[3]  # one object (the smaller a part of the larger)
    assert joined([outside, inside], SegmentConfig()).tolist() == [0, 1, 2, 3]  # the default


def test_two_cans_and_two_boxes_in_line_stay_apart() -> None:
    cans = [arc((0.0, 0.0), 0.04, FRONT, 0.12), arc((0.15, 0.05), 0.04, FRONT, 0.12)]
    assert joined(cans).tolist() == [0, 1, 2, 3]
    xs = np.arange(-0.05, 0.05, 0.004)
    edge = np.stack([xs, np.zeros_like(xs), np.full_like(xs, 0.1)], axis=1)
    boxes = [edge, edge + [0.12, 0.0, 0.0]]
    assert joined(boxes).tolist() == [0, 1, 2, 3]  # straight top edges in line: no small circle


def test_a_lower_object_behind_a_pot_stays_apart() -> None:
    outside = arc((0.0, 0.0), 0.09, FRONT, 0.10)
    behind = arc((0.0, 0.0), 0.086, BACK, 0.06)  # a rim 4 cm lower: not the same rim
    assert joined([outside, behind]).tolist() == [0, 1, 2, 3]


@pytest.mark.real
def test_an_upright_real_pot_is_one_object_with_rim_joins() -> None:
    """learn37: the pot seen from above; without joins its outside (with the tab) and its
    inside are two objects."""
    from simgrasp.assets.real import default_real_dir, osd_scene_file, read_labeled_scene
    from simgrasp.evaluation.real_pots import POT_SEGMENTATION, labeled_scenes, segmented_pot

    label = labeled_scenes()["learn37"]
    scene = read_labeled_scene(osd_scene_file("learn37", default_real_dir()))
    points, iou = segmented_pot(scene, label, POT_SEGMENTATION)
    assert iou > 0.9
    assert label.label.contains(points).sum() > 500  # the tab is on the pot
    _, iou_without = segmented_pot(scene, label)
    assert iou_without < 0.7
