"""Perception stage: point clouds from meshes and files, noise, voxels, normals, neighbourhoods.

Arrays are float64 in meters; variable names carry their frame (``points_cam``,
``points_world``). Every random draw comes from an ``np.random.Generator`` the caller makes
with :func:`simgrasp.seeding.rng_for`.
"""

from simgrasp.perception._arrays import import_open3d
from simgrasp.perception.cloud_io import read_cloud, write_cloud
from simgrasp.perception.mesh_cloud import sample_surface
from simgrasp.perception.neighborhoods import Neighborhoods, gather_neighborhoods, sample_centers
from simgrasp.perception.noise import DepthNoiseConfig, depth_camera_noise, multiplicative_noise
from simgrasp.perception.normals import estimate_normals, point_spacing
from simgrasp.perception.voxel import voxel_count, voxel_downsample

__all__ = [
    "DepthNoiseConfig",
    "Neighborhoods",
    "depth_camera_noise",
    "estimate_normals",
    "gather_neighborhoods",
    "import_open3d",
    "multiplicative_noise",
    "point_spacing",
    "read_cloud",
    "sample_centers",
    "sample_surface",
    "voxel_count",
    "voxel_downsample",
    "write_cloud",
]
