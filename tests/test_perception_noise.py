"""Noise models: seeded, and with the documented statistics."""

from __future__ import annotations

import numpy as np
import pytest

from simgrasp.perception import DepthNoiseConfig, depth_camera_noise, multiplicative_noise
from simgrasp.seeding import rng_for


def test_multiplicative_noise_scales_each_point_about_the_origin() -> None:
    points = rng_for(0, "pts").uniform(-0.1, 0.1, size=(50000, 3))
    noisy = multiplicative_noise(points, 0.05, rng_for(1, "noise"))
    factor = noisy / points
    np.testing.assert_allclose(factor, factor[:, :1].repeat(3, axis=1), rtol=1e-9)
    assert abs(factor[:, 0].mean() - 1) < 0.002 and abs(factor[:, 0].std() - 0.05) < 0.002
    np.testing.assert_array_equal(noisy, multiplicative_noise(points, 0.05, rng_for(1, "noise")))
    assert not np.array_equal(noisy, multiplicative_noise(points, 0.05, rng_for(2, "noise")))
    np.testing.assert_array_equal(multiplicative_noise(points, 0.0, rng_for(1)), points)
    with pytest.raises(ValueError, match="sigma"):
        multiplicative_noise(points, -0.1, rng_for(1))


def test_depth_noise_follows_the_kinect_model() -> None:
    config = DepthNoiseConfig()
    for depth in (0.5, 1.5):
        points_cam = np.column_stack(
            [np.full(40000, 0.1), np.full(40000, -0.05), np.full(40000, depth)]
        )
        noisy, kept = depth_camera_noise(points_cam, rng_for(0, "depth", str(depth)), config)
        assert len(kept) == len(noisy) == 40000
        # axial: along the viewing ray, sigma_z(z) = a + b (z - c)^2
        dz = noisy[:, 2] - depth
        expected = 0.0012 + 0.0019 * (depth - 0.4) ** 2
        assert abs(dz.std() / expected - 1) < 0.03 and abs(dz.mean()) < 3e-5
        # lateral: x, y perturbed with sigma = k z (plus the ray scaling of the axial noise)
        lateral = noisy[:, 0] - 0.1 * noisy[:, 2] / depth
        assert abs(lateral.std() / (0.8 / 585 * depth) - 1) < 0.03


def test_depth_noise_dropout_seeding_and_label_index() -> None:
    points_cam = rng_for(0, "cloud").uniform([-0.2, -0.2, 0.5], [0.2, 0.2, 1.0], (10000, 3))
    config = DepthNoiseConfig(dropout=0.25)
    noisy, kept = depth_camera_noise(points_cam, rng_for(3, "depth"), config)
    assert len(kept) == 7500 and np.all(np.diff(kept) > 0)
    assert np.max(np.linalg.norm(noisy - points_cam[kept], axis=1)) < 0.05
    again, kept_again = depth_camera_noise(points_cam, rng_for(3, "depth"), config)
    np.testing.assert_array_equal(noisy, again)
    np.testing.assert_array_equal(kept, kept_again)
    other, _ = depth_camera_noise(points_cam, rng_for(4, "depth"), config)
    assert not np.array_equal(noisy, other)


def test_depth_noise_errors() -> None:
    with pytest.raises(ValueError, match="behind the camera"):
        depth_camera_noise(np.array([[0.0, 0, -1.0]]), rng_for(0))
    with pytest.raises(ValueError, match="dropout"):
        DepthNoiseConfig(dropout=1.0)
    with pytest.raises(ValueError, match="axial_a"):
        DepthNoiseConfig(axial_a=-1.0)
