"""The standoff test and the single-view detector: a handle has free space for the fingers on
both sides as the sensor sees it; a patch of a wide body does not. Synthetic geometry, a
simulated single view of the YCB mug (needs YCB) and the real close-range mug (needs the real
clouds)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from simgrasp.evaluation.real_detect import detect_named, score_cloud
from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest
from simgrasp.evaluation.sim_views import SimView, score_view
from simgrasp.handles.core.detection import Candidate
from simgrasp.handles.single_view.detector import SingleViewConfig, detect_single_view
from simgrasp.handles.single_view.standoff import standoff_mask
from simgrasp.quadric.quadric import Quadric

EYE = np.array([0.0, 0.0, 0.0])


def _candidate(width: float) -> Candidate:
    """A cylinder of diameter ``width`` along x, its axis 0.5 m in front of the eye."""
    radius2 = (width / 2) ** 2  # y^2 + (z - 0.5)^2 = r^2
    coefficients = [0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.25 - radius2]
    return Candidate(
        center=np.array([0.0, 0.0, 0.5 - width / 2]),
        quadric=Quadric(np.array(coefficients)),
        kind="real elliptic cylinder",
        axis=np.array([1.0, 0.0, 0.0]),
        width=width,
        handle_point=np.array([0.0, 0.0, 0.5]),
    )


def _grid(half_width: float, step: float = 0.002) -> np.ndarray:
    """A flat patch facing the eye (z = 0.5 m), ``half_width`` across (y), 10 cm along x."""
    x, y = np.meshgrid(np.arange(-0.05, 0.05, step), np.arange(-half_width, half_width, step))
    return np.column_stack([x.ravel(), y.ravel(), np.full(x.size, 0.5)])


def test_a_slim_bar_has_room_for_the_fingers_and_a_wide_patch_does_not() -> None:
    candidate = _candidate(0.012)
    assert standoff_mask((candidate,), _grid(0.006), EYE, 0.085).tolist() == [True]
    assert standoff_mask((candidate,), _grid(0.04), EYE, 0.085).tolist() == [False]


def test_a_part_wider_than_the_jaws_with_their_gap_fails() -> None:
    assert standoff_mask((_candidate(0.084),), _grid(0.042), EYE, 0.085).tolist() == [False]


@pytest.mark.usefixtures("ycb_dir")
def test_a_simulated_single_view_of_the_lying_mug_ranks_its_strap_first() -> None:
    view = SimView(pose="lying", distance=0.30, elevation_deg=90.0, sensor="stereo")
    row = score_view(view, "standoff", 0)
    assert row.top_on_handle and row.on_handle >= 0.8 * row.candidates > 0


@pytest.mark.real
def test_the_standoff_test_with_axis_centers_ranks_the_real_close_range_mugs_handle_first(
    real_dir: Path,
) -> None:
    """On the held-out AffordanceGrasp mug (docs/results/real-detect: 5 of 5 seeds), seed 0,
    the single-view detector's standoff test with handle centers on the fitted axes puts its
    top handle on the handle: a record of a measured figure, not a tuned one."""
    (cloud,) = [c for c in read_manifest(None, real_dir) if c.name == "affordancegrasp_mug1"]
    points = load_real_cloud(cloud)
    axis = detect_single_view(points, SingleViewConfig(anchor="axis"), 0, cloud.viewpoint)
    assert cloud.label.contains(axis.handles[0].center[None]).all()
    assert detect_named(points, "standoff", 0, cloud.viewpoint).handles


@pytest.mark.real
def test_the_default_holds_the_real_close_range_mug_by_its_handle(real_dir: Path) -> None:
    """The default on the held-out AffordanceGrasp mug lying on its side (docs/results/
    real-detect: 1.00, 5 of 5 seeds since the classifier learned flat-strap mugs), seed 0:
    every candidate on the handle and the top handle on it. A record, not a tuned figure."""
    (cloud,) = [c for c in read_manifest(None, real_dir) if c.name == "affordancegrasp_mug1"]
    row = score_cloud(cloud, load_real_cloud(cloud), "default", 0)
    assert row.top_on_handle and row.on_handle == row.candidates > 0
