"""Single-view candidates pooled over voxel grids turned about the viewing axis
(:mod:`simgrasp.handles.single_view.grid_rolls`): turned back onto the view, invariant to the
camera's roll by a third of a turn, and holding the real close-range mug however it is rolled."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from simgrasp.evaluation.sim_views import SimView, capture
from simgrasp.handles.core.detection import Candidate
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.detector import detect_single_view, single_view_candidates
from simgrasp.handles.single_view.grid_rolls import roll_about

EYE = np.zeros(3)


def _strap_mug_view() -> np.ndarray:
    """A flat-strap mug no classifier saw, lying, seen by the stereo model from 0.3 m straight
    above (the real close-range capture's setup): (N, 3) points, sensor frame (m)."""
    shot = capture(SimView("gen_strap_mug_s47", "lying", 0.3, 90.0, "stereo"), 0)
    return np.asarray(shot.points_cam, dtype=np.float64)


def _rolled(points: np.ndarray, angle_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """``points`` turned by ``angle_deg`` about the line from the sensor through their
    centroid, and the 4x4 ``rolled_T_view``."""
    axis = points.mean(axis=0) / np.linalg.norm(points.mean(axis=0))
    rolled_T_view = roll_about(axis, EYE, np.radians(angle_deg))
    return points @ rolled_T_view[:3, :3].T + rolled_T_view[:3, 3], rolled_T_view


def _off_quadric(candidate: Candidate) -> float:
    """First-order distance (m) of the candidate's center from its quadric's zero set."""
    value = float(candidate.quadric.evaluate(candidate.center))
    return abs(value) / max(
        float(np.linalg.norm(candidate.quadric.gradient(candidate.center))), 1e-12
    )


def test_pooled_candidates_are_turned_back_onto_the_view_with_their_quadrics() -> None:
    """Three grids find more candidates than the view's own grid, and every one found on a
    turned grid is turned back: its center lies on the view's surface and on its own quadric
    (a candidate left in a turned frame would sit centimeters off both)."""
    points = _strap_mug_view()
    one = single_view_preset(grid_rolls=1)
    raw_one, _, _ = single_view_candidates(points, one, 0, EYE)
    raw, _, _ = single_view_candidates(points, replace(one, grid_rolls=3), 0, EYE)
    assert len(raw.candidates) > len(raw_one.candidates) > 0
    gap, _ = cKDTree(points).query(raw.candidate_centers)
    assert gap.max() < 0.003
    off = [_off_quadric(c) for c in raw.candidates]  # one grid's own: up to 1.6 mm (noise)
    assert np.median(off) < 0.001 and max(off) < 0.003
    assert len(raw.neighborhood_centers) > len(raw_one.neighborhood_centers)


def test_three_grids_give_the_same_candidates_when_the_camera_rolls_a_third_of_a_turn() -> None:
    """Rolled by 120 degrees, the view's three grids are the same three grids in another order:
    the pooled candidates, turned back, are the unrolled view's (to within 1 mm), where the
    view's own grid alone finds other ones."""
    points = _strap_mug_view()
    pooled = single_view_preset()
    assert pooled.grid_rolls == 3
    rolled, rolled_T_view = _rolled(points, 120.0)

    def centers(config, cloud, back):  # noqa: ANN001, ANN202
        raw, _, _ = single_view_candidates(cloud, config, 0, EYE)
        return raw.candidate_centers @ back[:3, :3].T + back[:3, 3]

    view_T_rolled = np.linalg.inv(rolled_T_view)
    same = centers(pooled, points, np.eye(4)), centers(pooled, rolled, view_T_rolled)
    assert len(same[0]) == len(same[1]) > 0
    assert cKDTree(same[0]).query(same[1])[0].max() < 0.001
    single = replace(pooled, grid_rolls=1)
    other = centers(single, points, np.eye(4)), centers(single, rolled, view_T_rolled)
    assert len(other[0]) != len(other[1]) or cKDTree(other[0]).query(other[1])[0].max() > 0.001


@pytest.mark.real
def test_the_real_close_range_mug_keeps_its_strap_where_one_grid_loses_it(real_dir: Path) -> None:
    """The held-out close-range lying mug, the camera rolled 120 and 240 degrees: with the
    view's own grid alone no handle forms and the fallback ranks the body first; with three
    grids the top handle is on the strap (docs/results/real-detect, the roll survey)."""
    from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest

    (cloud,) = [c for c in read_manifest(None, real_dir) if c.name == "affordancegrasp_mug1"]
    points = load_real_cloud(cloud)
    for angle in (120.0, 240.0):
        rolled, rolled_T_view = _rolled(points, angle)
        view_T_rolled = np.linalg.inv(rolled_T_view)
        for rolls, held in ((1, False), (3, True)):
            config = single_view_preset(grid_rolls=rolls)
            found = detect_single_view(rolled, config, 0, EYE)
            top = np.array([h.center for h in found.handles[:1]]).reshape(-1, 3)
            top = top @ view_T_rolled[:3, :3].T + view_T_rolled[:3, 3]
            assert bool(cloud.label.contains(top).any()) is held, (angle, rolls)
