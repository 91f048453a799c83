"""Handle ranking by centrality measures the lever arm to where the planner grasps a handle:
with ``centrality_measure`` ``"stretch"`` (the nearest point of its covered stretch) or
``"grasps"`` (the default: the mean square of that and its center's distance) a pan's long
handle outranks a short arc of its rim, which the center's distance alone ranked first
(synthetic candidates, no ../shared data); and a second part ranked by its stretch must pass
the relative cut by its center's distance too."""

from __future__ import annotations

import numpy as np

from simgrasp.handles.core.cluster import best_first, cluster_handles
from simgrasp.handles.core.config import CentralityMeasure


def test_a_long_handle_far_from_the_centroid_outranks_a_short_near_arc() -> None:
    """60 candidates along a handle from 8 to 23 cm off the centroid (its center 15.5 cm off)
    and 4 on a short arc 7 cm off, the centrality length 7.4 cm (a pan's): scored by the
    center's distance the arc came first (support share 0.06 x 0.41 against 0.94 x 0.012);
    by the nearest covered point (8 cm off) the handle does, and the arc falls below half
    its score."""
    handle_x = np.linspace(0.08, 0.23, 60)
    handle_points = np.stack([handle_x, np.zeros(60), np.full(60, 0.03)], axis=1)
    arc_points = np.array([[0.0, 0.07, 0.03 + 0.005 * i] for i in range(4)])
    points = np.concatenate([handle_points, arc_points])
    axes = np.concatenate([np.tile([1.0, 0.0, 0.0], (60, 1)), np.tile([0.0, 0.0, 1.0], (4, 1))])

    def rank(measure: CentralityMeasure):
        ranked = cluster_handles(
            points,
            axes,
            np.full(64, 0.03),
            distance=0.02,
            min_support=2,
            object_center=np.array([0.0, 0.0, 0.03]),
            centrality_length=0.074,
            centrality_measure=measure,
            max_opening=0.085,
            min_relative_score=0.5,
        )
        return [r.handle for r in ranked], [r.members for r in ranked]

    by_center, _ = rank("center")
    assert len(by_center) == 1 and by_center[0].center[0] < 0.01  # the arc alone
    for measure in ("stretch", "grasps"):
        handles, members = rank(measure)
        assert len(handles) == 1 and len(members[0]) == 60
        assert handles[0].center[0] > 0.1
        assert np.allclose(np.abs(handles[0].axis), [1.0, 0.0, 0.0])
        assert np.isclose(handles[0].center[0] + handles[0].span[0], 0.08)


def test_a_second_part_must_pass_the_cut_by_its_center_too() -> None:
    """A drill-like object: a grip of 40 candidates standing 2-6 cm below the centroid and a
    barrel of 40 along x from 4 to 20 cm, 2 cm above it, its center 12 cm off but its
    stretch's near end 4.5 cm off. By the stretch alone the barrel scores 0.66 of the grip
    and would survive the relative cut; by its center 0.03 of the grip: it is dropped (the
    center's rule alone drops it too), and the grip is the only handle kept."""
    grip = np.stack([np.full(40, 0.01), np.zeros(40), np.linspace(-0.02, -0.06, 40)], axis=1)
    barrel = np.stack([np.linspace(0.04, 0.20, 40), np.zeros(40), np.full(40, 0.02)], axis=1)
    axes = np.concatenate([np.tile([0.0, 0.0, 1.0], (40, 1)), np.tile([1.0, 0.0, 0.0], (40, 1))])
    scored = cluster_handles(  # min_relative_score 0: every cluster
        np.concatenate([grip, barrel]),
        axes,
        np.full(80, 0.03),
        distance=0.02,
        min_support=2,
        object_center=np.zeros(3),
        centrality_length=0.06,
        centrality_measure="stretch",
        max_opening=0.085,
    )
    grip_ranked, barrel_ranked = sorted(scored, key=lambda r: -r.handle.score)
    assert len(grip_ranked.members) == 40 and barrel_ranked.members.min() >= 40
    assert barrel_ranked.handle.score > 0.5 * grip_ranked.handle.score
    assert barrel_ranked.guard < 0.5 * grip_ranked.guard
    kept = best_first(scored, 0.5)
    assert [len(r.members) for r in kept] == [40]
    assert np.allclose(np.abs(kept[0].handle.axis), [0.0, 0.0, 1.0])
