"""Depth sensor models on analytic depth images: each model's statistics against its own
formulas, reproducibility, identity of the ideal sensor, input checks."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from simgrasp.perception.sensors import (
    SENSORS,
    IdealConfig,
    KinectConfig,
    StereoConfig,
    apply_sensor,
    sensor_config,
)
from simgrasp.perception.sensors.calibration import plane_depth
from simgrasp.perception.sensors.geometry import depth_edges, incidence_cos
from simgrasp.seeding import rng_for

K = np.array([[525.0, 0.0, 319.5], [0.0, 525.0, 239.5], [0.0, 0.0, 1.0]])
SHAPE = (480, 640)
QUIET_KINECT = KinectConfig(
    axial_a=0.0,
    axial_b=0.0,
    axial_angle=0.0,
    lateral_rad=0.0,
    lateral_angle_rad=0.0,
    inverse_depth_step=0.0,
    depth_resolution=0.0,
    flying_probability=0.0,
    edge_dropout=0.0,
    grazing_start_deg=89.0,
    grazing_end_deg=90.0,
)


def tilted_plane(depth_at_center: float, tilt_deg: float) -> np.ndarray:
    """Depth image of a plane through (0, 0, depth_at_center) whose normal is tilted by
    ``tilt_deg`` from the optical axis about the camera's x axis (the floor-like slope)."""
    tilt = math.radians(tilt_deg)
    normal = np.array([0.0, -math.sin(tilt), -math.cos(tilt)])
    return plane_depth(K, SHAPE, (normal, depth_at_center * math.cos(tilt)))


def box_on_wall(near: float = 0.8, far: float = 1.0) -> np.ndarray:
    """A fronto-parallel wall at ``far`` m with a 160 x 160 px square at ``near`` m."""
    depth = np.full(SHAPE, far)
    depth[160:320, 240:400] = near
    return depth


def incidence_deg(depth: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(incidence_cos(depth, K), 0.0, 1.0)))


@pytest.mark.parametrize("name", sorted(SENSORS))
def test_same_seed_is_bit_identical_and_another_seed_differs(name: str) -> None:
    depth = box_on_wall().astype(np.float32)
    config = sensor_config(name)
    first = apply_sensor(depth, K, config, rng_for(3, "sensor"))
    again = apply_sensor(depth, K, config, rng_for(3, "sensor"))
    assert first.dtype == np.float32 and first.shape == SHAPE
    assert np.array_equal(first, again)
    other = apply_sensor(depth, K, config, rng_for(4, "sensor"))
    assert np.array_equal(first, other) == (name == "ideal")


def test_ideal_is_identity_and_a_copy() -> None:
    depth = tilted_plane(1.0, 50.0)
    depth[0, :5] = 0.0
    out = apply_sensor(depth, K, IdealConfig(), rng_for(0))
    assert out.dtype == depth.dtype and np.array_equal(out, depth)
    assert out is not depth and not np.shares_memory(out, depth)


@pytest.mark.parametrize("z", [0.6, 1.0, 1.5])
def test_kinect_axial_noise_follows_its_formula(z: float) -> None:
    """On a wall at z, (measured - true) / sigma_z(z, theta) has unit spread (no quantization)."""
    config = dataclasses.replace(QUIET_KINECT, axial_a=0.0012, axial_b=0.0019, axial_angle=1e-4)
    depth = np.full(SHAPE, z)
    out = apply_sensor(depth, K, config, rng_for(1, "axial", str(z)))
    theta = np.radians(incidence_deg(depth))
    normalized = (out - depth) / config.axial_sigma(depth, theta)
    assert np.all(out > 0)
    assert abs(normalized.mean()) < 0.01
    assert normalized.std() == pytest.approx(1.0, abs=0.01)


def test_kinect_quantization_step_grows_with_depth_squared() -> None:
    """Noise-free depths of a sloped floor take only the levels 1 / (k step); neighbouring
    levels lie step z^2 apart (Khoshelham & Elberink)."""
    config = dataclasses.replace(QUIET_KINECT, inverse_depth_step=2.85e-3)
    out = apply_sensor(tilted_plane(1.2, 60.0), K, config, rng_for(0))
    levels = np.unique(out[out > 0])
    inverse_levels = 1.0 / (levels * config.inverse_depth_step)
    assert np.allclose(inverse_levels, np.round(inverse_levels), atol=1e-3)  # float32
    gaps = np.diff(levels)
    middle = levels[:-1] + gaps / 2
    assert np.allclose(gaps, config.inverse_depth_step * middle**2, rtol=0.01)
    assert levels.size > 50


def test_kinect_depth_unit_rounds_to_millimeters() -> None:
    out = apply_sensor(tilted_plane(1.0, 40.0), K, KinectConfig(), rng_for(0))
    valid = out[out > 0]
    assert np.allclose(valid * 1000.0, np.round(valid * 1000.0), atol=1e-3)  # float32


def test_kinect_grazing_dropout_matches_its_ramp() -> None:
    """A floor seen at 65-85 degrees: the invalid share per angle band is the ramp's mean."""
    config = dataclasses.replace(QUIET_KINECT, grazing_start_deg=70.0, grazing_end_deg=85.0)
    depth = tilted_plane(1.0, 75.0)
    out = apply_sensor(depth, K, config, rng_for(2, "grazing"))
    theta = incidence_deg(depth)
    expected = config.missing_probability(np.radians(theta))
    for low in (66.0, 72.0, 76.0, 80.0):
        band = (theta >= low) & (theta < low + 3.0) & (depth > 0)
        share = np.mean(out[band] == 0)
        tolerance = 4 * math.sqrt(0.25 / band.sum()) + 0.01
        assert share == pytest.approx(expected[band].mean(), abs=tolerance)


@pytest.mark.parametrize(("baseline", "offset"), [(0.075, 0.0), (0.075, 0.025)])
def test_kinect_shadow_widths_follow_the_baselines(baseline: float, offset: float) -> None:
    """A square 20 cm before a wall: no return in a strip left of it, fx (b - o)(1/z1 - 1/z2)
    px wide (projector), and right of it, fx o (1/z1 - 1/z2) px wide (IR camera)."""
    config = dataclasses.replace(
        QUIET_KINECT, projector_baseline=baseline, registration_offset=offset, min_shadow_px=0
    )
    out = apply_sensor(box_on_wall(0.8, 1.0), K, config, rng_for(0))
    disparity = K[0, 0] * (1 / 0.8 - 1 / 1.0)
    rows = out[200:280]
    left = (rows[:, :240] == 0).sum(axis=1)
    right = (rows[:, 400:] == 0).sum(axis=1)
    assert np.all(np.abs(left - disparity * (baseline - offset)) <= 1)
    assert np.all(np.abs(right - disparity * offset) <= 1)
    assert np.all(out[:150] > 0) and np.all(rows[:, 240:400] > 0)


def test_kinect_fills_shadows_narrower_than_its_window() -> None:
    config = dataclasses.replace(QUIET_KINECT, registration_offset=0.0, min_shadow_px=5.0)
    narrow = apply_sensor(box_on_wall(0.95, 1.0), K, config, rng_for(0))  # 2 px shadow
    wide = apply_sensor(box_on_wall(0.8, 1.0), K, config, rng_for(0))  # 9.8 px
    assert np.all(narrow > 0)
    assert (wide[200:280, :240] == 0).sum(axis=1).min() >= 9


def test_kinect_flying_pixels_lie_between_the_surfaces() -> None:
    """Edge pixels float with the configured probability, uniformly between the depths."""
    config = dataclasses.replace(
        QUIET_KINECT, flying_probability=0.5, projector_baseline=0.0, registration_offset=0.0
    )
    depth = box_on_wall(0.8, 1.0).astype(np.float32)
    out = apply_sensor(depth, K, config, rng_for(5, "flying"))
    changed = out != depth
    floating = (out > 0.805) & (out < 0.995)
    edges = depth_edges(depth, config.edge_jump)
    assert 1200 < edges.sum() <= 4 * 160 * 2  # both sides of the square's four sides
    assert not (changed & ~edges).any()
    assert floating.sum() == pytest.approx(0.5 * 0.95 * edges.sum(), rel=0.1)


def test_kinect_lateral_noise_moves_silhouettes_by_its_sigma() -> None:
    """The background pixel next to a vertical edge of a square takes the foreground depth
    when its column offset round(N(0, sigma_L)) reaches the edge: P = 1 - Phi(0.5 / sigma_L)
    with sigma_L = fx (lateral_rad + lateral_angle_rad theta / (pi/2 - theta)) pixels."""
    from scipy.stats import norm

    defaults = KinectConfig()
    config = dataclasses.replace(
        QUIET_KINECT,
        lateral_rad=defaults.lateral_rad,
        lateral_angle_rad=defaults.lateral_angle_rad,
        projector_baseline=0.0,
        registration_offset=0.0,
    )
    depth = np.full(SHAPE, 1.0, dtype=np.float32)
    depth[40:440, 240:400] = 0.8
    out = apply_sensor(depth, K, config, rng_for(6, "lateral"))
    rows = np.arange(60, 420)
    beside = np.concatenate([out[rows, 239], out[rows, 400]])
    sigma = config.lateral_sigma_px(K[0, 0], incidence_deg(depth)[rows, 239] * math.pi / 180)
    expected = 1.0 - norm.cdf(0.5 / sigma).mean()
    assert 0.15 < expected < 0.35
    tolerance = 4 * math.sqrt(expected * (1 - expected) / beside.size)
    assert np.mean(beside == np.float32(0.8)) == pytest.approx(expected, abs=tolerance)
    assert np.all(out[rows, 236] == 1.0)  # beyond the 2 px jitter zone


def test_stereo_noise_follows_intels_rms_formula() -> None:
    config = StereoConfig(depth_resolution=0.0, edge_dropout=0.0)
    for z in (0.5, 1.0, 2.0):
        depth = np.full(SHAPE, z)
        out = apply_sensor(depth, K, config, rng_for(1, "stereo", str(z)))
        assert np.all(out > 0)
        assert (out - depth).std() == pytest.approx(
            float(config.axial_sigma(np.asarray(z))), rel=0.02
        )


def test_stereo_oblique_dropout_matches_its_ramp() -> None:
    config = StereoConfig(edge_dropout=0.0)
    depth = tilted_plane(1.0, 72.0)
    out = apply_sensor(depth, K, config, rng_for(2, "oblique"))
    theta = incidence_deg(depth)
    expected = config.missing_probability(np.radians(theta))
    for low in (60.0, 68.0, 74.0, 79.0):
        band = (theta >= low) & (theta < low + 3.0) & (depth > 0)
        tolerance = 4 * math.sqrt(0.25 / band.sum()) + 0.01
        assert np.mean(out[band] == 0) == pytest.approx(expected[band].mean(), abs=tolerance)


def test_stereo_fattens_foreground_and_drops_the_occluded_side() -> None:
    """Right of the square (away from the right imager's occlusion) the foreground spreads
    fattening_px columns; left of it the occluded strip gives no return."""
    config = StereoConfig(subpixel_rms=0.0, depth_resolution=0.0, edge_dropout=0.0)
    out = apply_sensor(box_on_wall(0.8, 1.0), K, config, rng_for(0))
    rows = out[200:280]
    width = round(config.fattening_px)
    assert np.allclose(rows[:, 400 : 400 + width], 0.8)
    assert np.allclose(rows[:, 400 + width : 420], 1.0)
    occluded = round(K[0, 0] * config.baseline * (1 / 0.8 - 1 / 1.0))
    assert np.all(np.abs((rows[:, :240] == 0).sum(axis=1) - occluded) <= 1)


def test_stereo_needs_texture_when_given_an_intensity_image() -> None:
    config = StereoConfig(edge_dropout=0.0)
    depth = np.full(SHAPE, 1.0)
    flat = apply_sensor(depth, K, config, rng_for(0), intensity=np.full(SHAPE, 0.5))
    speckle = rng_for(1, "speckle").random(SHAPE)
    textured = apply_sensor(depth, K, config, rng_for(0), intensity=speckle)
    assert np.all(flat == 0)
    assert np.all(textured > 0)


@pytest.mark.parametrize("name", sorted(SENSORS))
def test_no_return_pixels_stay_without_return(name: str) -> None:
    """0, NaN, inf and negative depths are no return: the models give 0 there (edge effects
    may spread a few pixels into a hole, not further), never NaN or inf."""
    depth = np.full(SHAPE, 1.0)
    for i, value in enumerate([0.0, np.nan, np.inf, -1.0]):
        depth[100:140, 100 + 40 * i : 140 + 40 * i] = value
    out = apply_sensor(depth, K, sensor_config(name), rng_for(0))
    if name == "ideal":
        assert np.array_equal(out, depth, equal_nan=True)
        return
    assert np.all(np.isfinite(out))
    for i in range(4):
        assert np.all(out[105:135, 105 + 40 * i : 135 + 40 * i] == 0.0)


@pytest.mark.parametrize(
    ("depth", "K_bad", "message"),
    [
        (np.zeros((4, 4, 3)), K, "depth must be an \\(H, W\\) image"),
        (np.zeros(SHAPE, dtype=np.int32), K, "float image"),
        (np.zeros(SHAPE), np.where(np.eye(3, dtype=bool), np.nan, K), "finite 3x3"),
        (np.zeros(SHAPE), np.eye(2), "finite 3x3"),
        (np.zeros(SHAPE), np.diag([-1.0, 1.0, 1.0]), "positive fx"),
    ],
)
def test_bad_input_raises_a_clear_value_error(depth, K_bad, message: str) -> None:
    for name in SENSORS:
        with pytest.raises(ValueError, match=message):
            apply_sensor(depth, K_bad, sensor_config(name), rng_for(0))


def test_bad_settings_raise_value_errors() -> None:
    with pytest.raises(ValueError, match="KinectConfig.axial_a"):
        KinectConfig(axial_a=-1.0)
    with pytest.raises(ValueError, match=r"KinectConfig.edge_dropout: 1.5 is not in \[0, 1\]"):
        KinectConfig(edge_dropout=1.5)
    with pytest.raises(ValueError, match="StereoConfig.subpixel_rms"):
        StereoConfig(subpixel_rms=math.nan)
    with pytest.raises(ValueError, match="unknown sensor 'lidar'"):
        sensor_config("lidar")
    with pytest.raises(ValueError, match="intensity must be"):
        apply_sensor(np.ones(SHAPE), K, StereoConfig(), rng_for(0), intensity=np.ones((2, 2)))


def test_sensors_import_without_mujoco() -> None:
    import subprocess
    import sys

    code = "import sys, simgrasp.perception.sensors; assert 'mujoco' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)
