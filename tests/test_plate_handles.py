"""The flat-plate handle test (``QuadricDetectorConfig.plate_test``): a thin horizontal tab
standing off a wall, seen from above and in front, is a handle; the wall, a box's top edge and a
tab whose free edge is hidden are not. Real scene: the face-on tab of learn37's pot (needs
the real data; skipped cleanly without it)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from simgrasp.assets.real import default_real_dir, osd_scene_file, read_labeled_scene
from simgrasp.assets.scene_labels import load_scene_labels
from simgrasp.evaluation.real_pots import labeled_pot, score_pot
from simgrasp.handles import detect
from simgrasp.handles.core.plate import plate_handles
from simgrasp.handles.presets import quadric_preset
from simgrasp.perception.segmentation.segment import segment_scene

TABLE = np.array([0.0, 0.0, 1.0, 0.0])  # z = 0, up +z
EYE = np.array([0.0, -0.6, 0.5])  # in front of the wall (-y) and above it
STEP = 0.002


def grid(xs: tuple[float, float], ys: tuple[float, float], zs: tuple[float, float]) -> np.ndarray:
    """Points on an axis-aligned rectangle (one of the ranges is a single value), 2 mm apart."""
    axes = [
        np.arange(lo, hi + STEP / 2, STEP) if hi > lo else np.array([lo]) for lo, hi in (xs, ys, zs)
    ]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def front_wall(radius: float = 0.08, height: float = 0.1) -> np.ndarray:
    """The seen front half of a pot's wall: a cylinder about the vertical line x = 0,
    y = ``radius``, its front at y = 0 facing the sensor, 2 mm apart (m)."""
    angles = np.arange(-np.pi / 2, np.pi / 2, STEP / radius)
    heights = np.arange(0.0, height + STEP / 2, STEP)
    a, z = np.meshgrid(angles, heights, indexing="ij")
    ring = np.stack([radius * np.sin(a), radius * (1 - np.cos(a)), z], axis=-1)
    return ring.reshape(-1, 3)


WALL = front_wall()
TAB = grid((-0.03, 0.03), (-0.025, -STEP), (0.1, 0.1))  # at the wall's top, toward the sensor
CONFIG = quadric_preset("real_depth")  # with the plate test


def plates(points: np.ndarray, centers: np.ndarray) -> np.ndarray:
    return plate_handles(points, cKDTree(points), centers, TABLE, EYE, CONFIG).accepted


def test_a_tab_standing_off_a_wall_is_a_plate_handle_and_the_wall_is_not() -> None:
    cloud = np.concatenate([WALL, TAB])
    outer_tab = TAB[(TAB[:, 1] < -0.016) & (np.abs(TAB[:, 0]) < 0.02)]
    assert plates(cloud, outer_tab).mean() > 0.9
    wall = WALL[(WALL[:, 2] < 0.08) & (np.abs(WALL[:, 0]) < 0.06)]
    assert not plates(cloud, wall).any()
    middle = outer_tab[np.argmin(np.abs(outer_tab[:, 0]))][None]  # straight out from the pot
    found = plate_handles(cloud, cKDTree(cloud), middle, TABLE, EYE, CONFIG)
    assert abs(found.axes[0] @ np.array([1.0, 0.0, 0.0])) > 0.99  # along the tab's edge
    assert found.widths[0] < 0.002  # a plane sampled exactly: no thickness


def test_the_far_edge_of_a_narrow_box_top_is_not_a_plate_handle() -> None:
    """A 3 cm deep box seen from the front: its top stands 3 cm past its front face, but
    the space under the top's far edge is hidden (its back face is there, unseen)."""
    top = grid((-0.06, 0.06), (-0.03, 0.0), (0.1, 0.1))
    box = np.concatenate([grid((-0.06, 0.06), (-0.03, -0.03), (0.0, 0.1 - STEP)), top])
    far_half = top[(top[:, 1] > -0.012) & (np.abs(top[:, 0]) < 0.03)]
    assert not plates(box, far_half).any()


def test_a_box_edge_and_a_hidden_edge_are_not_plate_handles() -> None:
    top = grid((-0.06, 0.06), (-0.1, 0.0), (0.1, 0.1))  # a box's top, its front face below
    box = np.concatenate([grid((-0.06, 0.06), (-0.1, -0.1), (0.0, 0.1 - STEP)), top])
    near_edge = top[(top[:, 1] < -0.08) & (np.abs(top[:, 0]) < 0.03)]
    assert not plates(box, near_edge).any()  # the body is right under the edge
    cloud = np.concatenate([WALL, TAB])
    screen = grid((-0.06, 0.06), (-0.15, -0.15), (0.1, 0.25))  # hides the space past the tab
    outer_tab = TAB[(TAB[:, 1] < -0.016) & (np.abs(TAB[:, 0]) < 0.02)]
    assert plates(cloud, outer_tab).any()
    assert not plates(np.concatenate([cloud, screen]), outer_tab).any()


def test_plate_candidates_only_with_the_setting_and_a_table() -> None:
    cloud = np.concatenate([WALL, TAB])
    found = detect(cloud, None, CONFIG, seed=0, viewpoint=EYE, table=TABLE)
    kinds = [c.kind for c in found.candidates]
    assert kinds.count("plate") >= 5
    assert found.handles and found.handles[0].center[1] < -0.005  # the top handle: the tab
    assert found.handles[0].center[2] == pytest.approx(0.1, abs=0.003)
    without_plates = quadric_preset("real_depth", plate_test=False)
    for config, table in ((without_plates, TABLE), (CONFIG, None)):
        without = detect(cloud, None, config, seed=0, viewpoint=EYE, table=table)
        assert "plate" not in [c.kind for c in without.candidates]


@pytest.mark.real
def test_the_face_on_tab_of_a_real_pot_is_its_top_handle() -> None:
    """learn37: the pot's only visible tab faces the sensor; no quadric fits it."""
    label = load_scene_labels()["learn37"]
    scene = read_labeled_scene(osd_scene_file("learn37", default_real_dir()))
    pot = labeled_pot(scene, label)
    seen = scene.points[np.isfinite(scene.points).all(axis=1)]
    table = segment_scene(scene.cloud).plane
    with_plates = score_pot(pot, label, CONFIG, seed=0, table=table, scene=seen)
    assert with_plates.top_on_handle
    assert with_plates.accuracy >= 0.8
    without_plates = quadric_preset("real_depth", plate_test=False)
    assert not score_pot(pot, label, without_plates, seed=0, table=table, scene=seen).top_on_handle
