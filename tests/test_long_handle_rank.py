"""Handle ranking by centrality measures the lever arm to the nearest point of a handle's
covered stretch, where the planner grasps it, not to its center: a pan's long handle against
a short arc of its rim (synthetic candidates, no ../shared data), with
``centrality_to_stretch``; by default the center's distance is measured, as before."""

from __future__ import annotations

import numpy as np

from simgrasp.handles.cluster import cluster_handles


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

    def rank(to_stretch: bool):
        return cluster_handles(
            points,
            axes,
            np.full(64, 0.03),
            distance=0.02,
            min_support=2,
            object_center=np.array([0.0, 0.0, 0.03]),
            centrality_length=0.074,
            centrality_to_stretch=to_stretch,
            max_opening=0.085,
            min_relative_score=0.5,
        )

    by_center, _ = rank(False)
    assert len(by_center) == 1 and by_center[0].center[0] < 0.01  # the arc alone
    handles, members = rank(True)
    assert len(handles) == 1 and len(members[0]) == 60
    assert handles[0].center[0] > 0.1 and np.allclose(np.abs(handles[0].axis), [1.0, 0.0, 0.0])
    assert np.isclose(handles[0].center[0] + handles[0].span[0], 0.08)
