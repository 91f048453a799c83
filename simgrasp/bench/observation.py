"""What a benchmarked method sees of one scene, in memory and as files.

A :class:`BenchObservation` holds the cut target's cloud, the whole scene's cloud, each
view's depth image with its camera, the table height and the gripper's geometry: the same
for a method run in process (``simgrasp bench run``) and one that reads the exported folder
(``simgrasp bench export``). Everything is in the world frame (z up, meters); cameras follow
OpenCV (x right, y down, z forward). :func:`write_observation` writes ``observation.json``
beside ``.npy`` arrays, readable with ``json`` and ``numpy`` alone (docs/commands/bench.md).
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.grippers.geometry import GripperGeometry

FORMAT = "simgrasp-bench-observation/1"
"""The ``format`` field of ``observation.json``: a change of its meaning is a new number."""
TCP_CONVENTION = (
    "world_T_tcp puts the TCP midway between the finger pads; +z is the approach (palm "
    "toward the object), +y the direction the jaws open and close"
)


@dataclass(frozen=True, eq=False)
class BenchView:
    """One camera's depth image: ``depth`` (H, W) meters along the optical axis (0: no
    return), the pinhole ``intrinsics`` (``width``, ``height``, ``fx``, ``fy``, ``cx``,
    ``cy`` in pixels) and ``world_T_camera`` (4 x 4, OpenCV camera frame in the world)."""

    name: str
    depth: NDArray[np.float32]
    intrinsics: dict[str, float]
    world_T_camera: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class BenchObservation:
    """One scene as a method sees it (world frame, meters).

    Attributes:
        suite: the suite's name; ``suite_sha256`` its definition's digest.
        scene: the scene's id; ``seed`` its seed (for a method's own random draws).
        cloud: (N, 3) the target's points, cut by the renderer's segmentation (the same cut
            for every method).
        cloud_viewpoints: (N, 3) the optical center of the camera each point was seen from
            (turn normals toward it).
        scene_cloud: (M, 3) every point the cameras saw: table, target and neighbors.
        obstacle_cloud: (K, 3) the neighbors' points (empty alone on the table).
        views: each camera's depth image.
        table_top_z: world z of the table top.
        gripper: the gripper's name and planning geometry (:func:`gripper_description`).
    """

    suite: str
    suite_sha256: str
    scene: str
    seed: int
    cloud: NDArray[np.float64]
    cloud_viewpoints: NDArray[np.float64]
    scene_cloud: NDArray[np.float64]
    obstacle_cloud: NDArray[np.float64]
    views: tuple[BenchView, ...]
    table_top_z: float
    gripper: dict[str, Any]

    @property
    def max_opening(self) -> float:
        """The gripper's widest jaw opening (m)."""
        return float(self.gripper["max_opening"])


def gripper_description(name: str, geometry: GripperGeometry) -> dict[str, Any]:
    """The gripper as ``observation.json`` names it: ``max_opening`` and the finger and palm
    boxes (m; :class:`~simgrasp.grippers.geometry.GripperGeometry`) and the TCP convention."""
    return {"name": name, **asdict(geometry), "tcp": TCP_CONVENTION}


def write_observation(observation: BenchObservation, folder: Path) -> Path:
    """Write ``folder/observation.json`` and its ``.npy`` arrays (float32 depth images,
    float64 clouds); the JSON is written last, atomically, so a folder with it is complete.
    Returns the JSON's path."""
    folder.mkdir(parents=True, exist_ok=True)
    arrays = {
        "cloud": observation.cloud,
        "cloud_viewpoints": observation.cloud_viewpoints,
        "scene_cloud": observation.scene_cloud,
        "obstacle_cloud": observation.obstacle_cloud,
    }
    for name, array in arrays.items():
        np.save(folder / f"{name}.npy", np.asarray(array, dtype=np.float64))
    views = []
    for index, view in enumerate(observation.views):
        depth_file = f"depth_{index}.npy"
        np.save(folder / depth_file, view.depth.astype(np.float32))
        views.append(
            {
                "name": view.name,
                "depth": depth_file,
                "intrinsics": view.intrinsics,
                "world_T_camera": np.asarray(view.world_T_camera).tolist(),
            }
        )
    table = {
        "format": FORMAT,
        "suite": observation.suite,
        "suite_sha256": observation.suite_sha256,
        "scene": observation.scene,
        "seed": observation.seed,
        "frame": "world: z up, meters; cameras: OpenCV (x right, y down, z forward)",
        "table_top_z": observation.table_top_z,
        **{name: f"{name}.npy" for name in arrays},
        "depth_units": "meters along the optical axis, 0 where the sensor returned nothing",
        "views": views,
        "gripper": observation.gripper,
        "answer": f"GRASPS/{observation.scene}.json",
    }
    path = folder / "observation.json"
    partial = folder / f".observation.json.{os.getpid()}"
    partial.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")
    partial.replace(path)
    return path
