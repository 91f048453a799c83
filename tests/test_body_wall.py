"""The body-wall test of the single-view detector (simgrasp.handles.single_view.body_wall): a
half wall seen from one side is found with its radius and axis, a flat face or blade, a thin round
handle or a long one is no body, a seed gives one wall, the settings refuse an empty radius
range, and on rendered mug views the wall is found and the detector with the test on keeps no
candidate on it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from simgrasp.errors import SimgraspError
from simgrasp.evaluation.sim_views import SimView, capture, score_view
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.body_wall import BodyWallConfig, fit_body_wall
from simgrasp.handles.single_view.detector import detect_single_view


def _seen_half_cylinder(
    radius: float, height: float, rng: np.random.Generator, noise: float = 0.0
) -> np.ndarray:
    """Points (m) of the half of an upright cylinder about the z axis through (0, 0.5, 0)
    that a camera on the -y side sees, every 2 mm, with ``noise`` (m) of radial noise."""
    angles = np.arange(np.pi, 2 * np.pi, 0.002 / radius)
    heights = np.arange(0.0, height, 0.002)
    a, z = np.meshgrid(angles, heights)
    r = radius + noise * rng.standard_normal(a.shape)
    return np.stack([r * np.cos(a), 0.5 + r * np.sin(a), z], axis=-1).reshape(-1, 3)


@pytest.mark.parametrize("noise", [0.0, 0.001, 0.002])
def test_a_half_wall_seen_from_one_side_gives_its_radius_and_axis(noise: float) -> None:
    rng = np.random.default_rng(0)
    wall = fit_body_wall(_seen_half_cylinder(0.04, 0.09, rng, noise), BodyWallConfig(), 0)
    assert wall is not None
    assert wall.radius == pytest.approx(0.04, abs=0.002)
    assert abs(wall.axis[2]) > 0.99
    assert np.linalg.norm(wall.center[:2] - [0.0, 0.5]) < 0.003
    assert wall.wall_share > 0.9


def test_a_handle_standing_off_the_wall_is_far_from_it() -> None:
    rng = np.random.default_rng(1)
    body = _seen_half_cylinder(0.04, 0.09, rng)
    wall = fit_body_wall(body, BodyWallConfig(), 0)
    assert wall is not None
    strap = np.array([[-0.065, 0.5, 0.045], [0.0, 0.5 - 0.065, 0.045]])  # 2.5 cm off the wall
    assert np.all(wall.distance(strap) > 0.02)
    assert np.all(wall.distance(body[::50]) < 0.004)


def test_a_flat_face_or_a_thin_round_handle_is_no_body() -> None:
    rng = np.random.default_rng(2)
    grid = np.stack(np.meshgrid(np.arange(0, 0.1, 0.002), np.arange(0, 0.1, 0.002)), -1)
    flat = np.column_stack([grid.reshape(-1, 2), np.zeros(grid.size // 2)])
    assert fit_body_wall(flat, BodyWallConfig(), 0) is None
    assert fit_body_wall(_seen_half_cylinder(0.015, 0.12, rng), BodyWallConfig(), 0) is None


def test_a_long_round_handle_is_no_body_by_its_length() -> None:
    """A hammer-like round handle, 2.7 cm in radius and 34 cm long, is a circle RANSAC finds
    (the generated hammer's false wall, docs/results/real-detect/README.md); its points span
    12.6 radii along the axis, over ``max_length_radii``, so it is no body."""
    rng = np.random.default_rng(3)
    handle = _seen_half_cylinder(0.027, 0.34, rng, 0.001)
    assert fit_body_wall(handle, BodyWallConfig(), 0) is None
    uncapped = fit_body_wall(handle, BodyWallConfig(max_length_radii=20.0), 0)
    assert uncapped is not None and uncapped.radius == pytest.approx(0.027, abs=0.002)


def test_a_blade_seen_along_its_length_is_no_body_by_its_arc() -> None:
    """A 3 cm wide, 25 cm long blade, slightly bevelled (curved across its width on 8 cm),
    with 1 mm of noise, seen along its length: its points lie on a circle of about 8 cm with
    their normals along its radius (the real knives' false walls,
    docs/results/real-detect/README.md), but on an arc of about 20 degrees, under
    ``min_arc_deg``, so it is no body."""
    rng = np.random.default_rng(5)
    grid = np.stack(np.meshgrid(np.arange(-0.015, 0.015, 0.002), np.arange(0, 0.25, 0.002)), -1)
    across, along = grid.reshape(-1, 2).T
    bevel = across**2 / (2 * 0.08) + 0.001 * rng.standard_normal(len(across))
    blade = np.column_stack([across, 0.5 + bevel, along])
    assert fit_body_wall(blade, BodyWallConfig(), 0) is None
    any_arc = fit_body_wall(blade, BodyWallConfig(min_arc_deg=1.0), 0)
    assert any_arc is not None and any_arc.radius > 0.06


def test_the_same_seed_finds_the_same_wall() -> None:
    rng = np.random.default_rng(4)
    body = _seen_half_cylinder(0.04, 0.09, rng, 0.002)
    first, again = (fit_body_wall(body, BodyWallConfig(), 7) for _ in range(2))
    assert first is not None and again is not None
    assert first.radius == again.radius
    assert np.array_equal(first.center, again.center)


def test_the_settings_refuse_an_empty_radius_range() -> None:
    with pytest.raises(SimgraspError, match="min_radius"):
        BodyWallConfig(min_radius=0.1, max_radius=0.05)


def test_with_the_wall_on_a_strap_mug_seen_from_afar_is_held_by_its_strap() -> None:
    """A flat-strap mug no classifier saw (seed 142), upright, its handle turned 120 degrees
    from profile, through the stereo model from 0.78 m (the regime the single-view detector is
    weakest in): without the body-wall test (the default before 7 December 2026) the body is
    ranked first (measured: 0 of 3 candidates on the strap); the default, with the test, drops
    those candidates and all that remain are on the strap
    (docs/results/real-detect/body-wall/unseen-mugs-s130)."""
    view = SimView("gen_strap_mug_s142", "upright", 0.78, 32.0, "stereo", azimuth_deg=120.0)
    unwalled = replace(single_view_preset(), body_wall=BodyWallConfig(enabled=False))
    assert not score_view(view, "default", 0, None, unwalled).top_on_handle
    row = score_view(view, "default", 0)
    assert row.top_on_handle and row.on_handle == row.candidates > 0


def test_no_kept_candidate_lies_on_the_wall_of_a_rendered_mug() -> None:
    """The YCB-free generated mug (seed 0), upright, kinect model from 0.6 m: the wall is
    found at the body's radius (3.7-4.3 cm by construction) and the single-view detector with
    the test on keeps no candidate within its drop distance of it."""
    view = SimView("gen_mug", "upright", 0.6, 40.0, "kinect")
    shot = capture(view, 0)
    points = np.asarray(shot.points_cam, dtype=np.float64)
    config = single_view_preset()
    assert config.body_wall.enabled  # the default since 7 December 2026
    detection = detect_single_view(points, config, 0, np.zeros(3))
    assert detection.points is not None
    wall = fit_body_wall(detection.points, config.body_wall, 0)
    assert wall is not None and 0.035 <= wall.radius <= 0.045
    centers = np.stack([c.center for c in detection.candidates])
    assert np.all(wall.distance(centers) >= config.body_wall.drop_distance)


def test_a_tube_mug_with_its_handle_turned_away_has_its_wall_found() -> None:
    """A round-tube mug (seed 15; bodies 3.7-4.3 cm in radius), upright, its handle turned
    120 degrees from profile, through the stereo model from 0.78 m: the handle's normals tilt
    the view's least normal direction, and the normal lines' centre used before 7 December
    2026 found no wall there (its radius 2.5-3.3 cm); the RANSAC circle, then the axis taken
    again near it, finds the body (docs/results/real-detect/README.md)."""
    view = SimView("gen_mug_s15", "upright", 0.78, 32.0, "stereo", azimuth_deg=120.0)
    points = np.asarray(capture(view, 0).points_cam, dtype=np.float64)
    config = single_view_preset()
    detection = detect_single_view(points, config, 0, np.zeros(3))
    assert detection.points is not None
    wall = fit_body_wall(detection.points, config.body_wall, 0)
    assert wall is not None and 0.035 <= wall.radius <= 0.045
    assert wall.wall_share >= config.body_wall.min_wall_share


def test_where_nothing_holds_the_candidates_off_a_mug_sized_wall_are_taken() -> None:
    """A strap mug (seed 31), upright, its handle turned 120 degrees from profile, stereo from
    0.78 m: the classifier keeps no candidate at 0.7 and the fallback ranks the body first
    (measured: 5 candidates, none on the strap). The retry keeps the candidates off its
    3.3 cm wall at 0.5, and all it keeps are on the strap; with the retry off, or limited to
    walls under 2 cm, the view fails as before (docs/results/real-detect/README.md)."""
    view = SimView("gen_strap_mug_s31", "upright", 0.78, 32.0, "stereo", azimuth_deg=120.0)
    default = single_view_preset()
    for wall in (
        replace(default.body_wall, retry_threshold=None),
        replace(default.body_wall, retry_max_radius=0.02),
    ):
        assert not score_view(
            view, "default", 0, None, replace(default, body_wall=wall)
        ).top_on_handle
    row = score_view(view, "default", 0)
    assert row.top_on_handle and row.on_handle == row.candidates > 0
