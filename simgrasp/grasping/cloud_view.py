"""What a grasp proposer sees of one object: its cloud, the cameras that saw it, the table.

One frozen bundle instead of loose arrays, passed from the chain
(:func:`simgrasp.grasping.trials.chain.propose_grasps`) and the gymnasium policy
(:class:`simgrasp.envs.policy.DetectorPolicy`) to every proposer
(:mod:`simgrasp.grasping.proposers`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError


@dataclass(frozen=True)
class CloudView:
    """One object's observed cloud (world frame, meters).

    Attributes:
        points_world: (N, 3) object points.
        normals_world: (N, 3) unit normals turned toward the camera that saw each point (as
            :func:`simgrasp.scenes.observe.viewpoint_normals` makes them).
        cameras_world: (K, 3) optical centers of the cameras that saw the cloud, each once.
        table_top_z: world z of the table top the object rests on.
        scene_obstacles_world: (M, 3) the rest of a cluttered scene, which the open gripper
            must keep clear of as of the object's own points; None alone on the table.
    """

    points_world: NDArray[np.float64]
    normals_world: NDArray[np.float64]
    cameras_world: NDArray[np.float64]
    table_top_z: float
    scene_obstacles_world: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        points = np.asarray(self.points_world).reshape(-1, 3)  # dtype kept: detection uses it
        normals = np.asarray(self.normals_world).reshape(-1, 3)
        if normals.shape != points.shape:
            raise SimgraspError(
                f"CloudView: {len(normals)} normals for {len(points)} points (one each)"
            )
        object.__setattr__(self, "points_world", points)
        object.__setattr__(self, "normals_world", normals)
        cameras = np.asarray(self.cameras_world).reshape(-1, 3)
        object.__setattr__(self, "cameras_world", cameras)
        object.__setattr__(self, "table_top_z", float(self.table_top_z))

    @classmethod
    def from_views(
        cls,
        points_world: ArrayLike,
        normals_world: ArrayLike,
        viewpoints_world: ArrayLike,
        table_top_z: float,
        scene_obstacles_world: NDArray[np.float64] | None = None,
    ) -> CloudView:
        """The view of a cloud whose points each carry the (K', 3) position of the camera
        that saw them (``viewpoints_world``, repeated per point): the cameras once each."""
        cameras = np.unique(np.asarray(viewpoints_world).reshape(-1, 3), axis=0)
        points, normals = np.asarray(points_world), np.asarray(normals_world)
        return cls(points, normals, cameras, table_top_z, scene_obstacles_world)

    def __len__(self) -> int:
        return len(self.points_world)
