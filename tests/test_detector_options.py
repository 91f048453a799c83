"""The quadric detector's sampling density and handle anchor options, on a generated cloud
with a known handle."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from simgrasp.errors import SimgraspError
from simgrasp.handles import QuadricDetectorConfig, detect
from simgrasp.handles.presets import quadric_preset
from simgrasp.perception import estimate_normals, voxel_downsample

from shapes import hammer_like, mug_like


def test_voxels_per_neighborhood_sets_the_sampling_density() -> None:
    cloud = hammer_like()
    sparse = detect(cloud.points, config=QuadricDetectorConfig(), seed=0)
    dense = detect(cloud.points, config=QuadricDetectorConfig(voxels_per_neighborhood=2), seed=0)
    assert dense.neighborhoods == pytest.approx(5 * sparse.neighborhoods, rel=0.05)


def test_surface_anchor_puts_handle_centers_on_the_cloud() -> None:
    cloud = hammer_like()
    tree = cKDTree(cloud.points)
    axis = detect(cloud.points, seed=1).handles[0]
    surface = detect(
        cloud.points, config=QuadricDetectorConfig(handle_anchor="surface"), seed=1
    ).handles[0]
    # The hammer handle is a 3 cm cylinder: its axis is 1.5 cm inside, its surface on it.
    assert tree.query(axis.center)[0] > 0.01
    assert tree.query(surface.center)[0] < 0.003
    assert cloud.handle_share(surface.center[None]) == 1.0
    assert np.allclose(axis.axis, surface.axis) and axis.support == surface.support


@pytest.mark.parametrize(
    ("field", "value"), [("handle_anchor", "middle"), ("voxels_per_neighborhood", 0.0)]
)
def test_bad_option_values_are_refused(field: str, value: object) -> None:
    with pytest.raises(ValueError, match=field):
        QuadricDetectorConfig(**{field: value})  # type: ignore[arg-type]  # a bad value on purpose


def test_real_depth_preset_keeps_overrides() -> None:
    config = quadric_preset("real_depth", gripper_max_opening=0.05)
    assert config.handle_anchor == "surface" and config.gripper_max_opening == 0.05


def test_own_normals_replace_the_given_directions_and_keep_their_signs() -> None:
    cloud = mug_like()
    points, outward = voxel_downsample(cloud.points, 0.003, normals=cloud.normals)
    assert outward is not None
    # Given normals on the right side of the surface but tilted at random by up to ~60 deg.
    rng = np.random.default_rng(0)
    tilted = outward + rng.normal(size=outward.shape) * 0.7
    tilted /= np.linalg.norm(tilted, axis=1)[:, None]
    tilted[np.einsum("ij,ij->i", tilted, outward) < 0] *= -1
    own = detect(
        points, tilted, QuadricDetectorConfig(voxel_size=0, own_normals=True, normal_radius=6e-3)
    )
    # ... equal to handing in a fresh 6 mm estimate signed as the given normals:
    fresh = estimate_normals(points, radius=6e-3, orient="none")
    fresh[np.einsum("ij,ij->i", fresh, tilted) < 0] *= -1
    expected = detect(points, fresh, QuadricDetectorConfig(voxel_size=0, normal_radius=6e-3))
    assert np.array_equal(own.candidate_centers, expected.candidate_centers)
    assert cloud.handle_share(own.handles[0].center[None]) == 1.0


@pytest.mark.parametrize("with_config", [False, True])
def test_an_unknown_detector_name_is_refused_in_one_line(with_config: bool) -> None:
    config = QuadricDetectorConfig() if with_config else None
    with pytest.raises(
        SimgraspError, match=r"^unknown detector 'gpd'; choose one of quadric, tenpas$"
    ):
        detect(hammer_like().points, config=config, detector="gpd")  # type: ignore[arg-type]
