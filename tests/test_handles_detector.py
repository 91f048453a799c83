"""The quadric handle detector on generated clouds with known handles, on real YCB meshes, and
on degenerate input."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from simgrasp.assets.registry import load_object
from simgrasp.handles import QuadricDetectorConfig, detect
from simgrasp.handles.accuracy import detection_accuracy, handle_recall
from simgrasp.handles.presets import quadric_preset
from simgrasp.perception import sample_surface
from simgrasp.seeding import rng_for

from shapes import hammer_like, mug_like


@pytest.mark.parametrize("make", [mug_like, hammer_like], ids=["mug_like", "hammer_like"])
def test_generated_handles_are_found_on_the_handle(make) -> None:
    cloud = make()
    detection = detect(cloud.points, seed=1)
    assert detection.candidates, "no candidate at all"
    # Most candidates on the handle (the best handle on it is the stronger check below).
    assert cloud.handle_share(detection.candidate_centers) >= 0.75
    best = detection.handles[0]
    assert cloud.handle_share(best.center[None]) == 1.0
    assert 0.01 <= best.width <= 0.04


def test_hammer_axis_and_width_match_the_cylinder() -> None:
    cloud = hammer_like()
    handle = detect(cloud.points, seed=2).handles[0]
    assert abs(handle.axis[0]) > np.cos(np.radians(10)), handle.axis
    assert handle.width == pytest.approx(0.03, rel=0.25)


def test_too_wide_cylinder_is_not_a_handle() -> None:
    cloud = hammer_like()
    narrow = QuadricDetectorConfig(gripper_max_opening=0.02)
    assert detect(cloud.points, config=narrow, seed=0).handles == ()


def test_same_seed_same_detection() -> None:
    cloud = mug_like()
    a, b = detect(cloud.points, seed=5), detect(cloud.points, seed=5)
    assert np.array_equal(a.candidate_centers, b.candidate_centers)
    assert [h.to_json() for h in a.handles] == [h.to_json() for h in b.handles]


def test_result_is_in_the_cloud_frame_and_units() -> None:
    cloud = hammer_like()
    shift = np.array([3.0, -2.0, 1.0])
    moved = detect(cloud.points + shift, seed=3).handles[0]
    original = detect(cloud.points, seed=3).handles[0]
    # The voxel grid does not move with the cloud, so compare geometry, not samples.
    offset = moved.center - shift - original.center
    off_axis = offset - (offset @ original.axis) * original.axis
    assert np.linalg.norm(off_axis) < 2e-3
    assert abs(moved.axis @ original.axis) > np.cos(np.radians(3))
    assert moved.width == pytest.approx(original.width, rel=0.1)


@pytest.mark.parametrize("object_id", ["033_spatula", "048_hammer", "025_mug"])
def test_ycb_handle_recall(object_id: str, ycb_dir: str) -> None:
    asset = load_object(object_id, ycb_dir=ycb_dir)
    points, _ = sample_surface(asset.mesh, 30000, rng_for(0, "test", object_id))
    detection = detect(points, seed=0)
    assert len(detection.candidates) >= 5
    assert handle_recall(detection, asset.handle)
    assert detection_accuracy(detection, asset.handle) >= 0.7


def test_nan_and_empty_clouds_give_clear_errors() -> None:
    cloud = hammer_like().points.copy()
    cloud[5] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        detect(cloud)
    with pytest.raises(ValueError, match="empty"):
        detect(np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        detect(np.zeros((10, 2)))


def test_tiny_planar_and_huge_clouds_do_not_crash() -> None:
    rng = np.random.default_rng(0)
    tiny = rng.normal(size=(5, 3)) * 0.01
    assert detect(tiny).handles == ()
    for count in (1, 2):  # fewer points than a normal needs: empty, like any tiny cloud
        for detector in ("quadric", "tenpas"):
            assert detect(tiny[:count], detector=detector).candidates == ()
    plane = np.column_stack([rng.uniform(-0.1, 0.1, (5000, 2)), np.zeros(5000)])
    assert detect(plane).handles == ()
    line = np.outer(np.linspace(0, 0.2, 500), [1.0, 0.0, 0.0])
    assert detect(line).handles == ()
    huge = hammer_like(density=4e7).points
    assert len(huge) > 500_000
    assert detect(huge, seed=0).handles


def test_open3d_is_imported_before_the_first_timed_step() -> None:
    """A fresh process's first detection must not charge Open3D's one-time import (about a
    second) to its voxelize step: the detectors import it before their timers start."""
    script = (
        "import sys; from simgrasp.handles.core.step_timer import new_timings\n"
        "assert 'open3d' not in sys.modules, 'imported with simgrasp already'\n"
        "assert new_timings() == {} and 'open3d' in sys.modules\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_a_second_fit_method_keeps_every_first_fit_candidate() -> None:
    """Each center is a candidate when either fit passes, its first-method candidate kept:
    the candidate centers with a second Taubin fit include those of Birdal's alone."""
    cloud = mug_like()
    first = detect(cloud.points, seed=1)
    both = detect(cloud.points, config=QuadricDetectorConfig(second_fit_method="taubin"), seed=1)
    first_centers = {tuple(c) for c in first.candidate_centers.round(6)}
    both_centers = {tuple(c) for c in both.candidate_centers.round(6)}
    assert first_centers <= both_centers
    assert len(both_centers) > len(first_centers)
    assert cloud.handle_share(both.handles[0].center[None]) == 1.0


@pytest.mark.parametrize("make", [mug_like, hammer_like], ids=["mug_like", "hammer_like"])
def test_a_fine_pass_handle_counts_only_where_the_first_pass_found_none(make) -> None:
    """The fine pass finds these handles as well (on its own), but next to the first pass's
    handle its own is dropped: two_scales() detects the first pass's handles and candidates
    (their scores now shares of both passes' candidates)."""
    cloud = make()
    first = detect(cloud.points, seed=1)
    fine = quadric_preset("two_scales")
    fine_alone = QuadricDetectorConfig(
        neighborhood_half_size=fine.fine_half_size,
        voxels_per_neighborhood=fine.fine_voxels_per_neighborhood,
        fit_method=fine.fine_fit_method,
        shell_thickness=fine.fine_shell_thickness,
    )
    alone = detect(cloud.points, config=fine_alone, seed=1)
    assert alone.handles and cloud.handle_share(alone.handles[0].center[None]) == 1.0
    both = detect(cloud.points, config=fine, seed=1)
    assert len(both.handles) == len(first.handles)
    for mine, theirs in zip(both.handles, first.handles, strict=True):
        np.testing.assert_array_equal(mine.center, theirs.center)
        assert 0 < mine.score < theirs.score
    np.testing.assert_array_equal(both.candidate_centers, first.candidate_centers)
