"""Each object of a segmented scene as a point cloud file with normals: what a user's own
grasp planner takes from ``simgrasp segment --clouds DIR``.

An object is written whole, with its side parts (a pot with its tabs), as
``object_<label>.ply``: points in the scene cloud's frame (m), normals estimated on the object
alone and turned toward the sensor (the scene's viewpoint), since one view sees only the
sensor's side of it. Files of that name left in the folder by an earlier run are removed
first, so the folder holds this scene's objects only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from simgrasp.perception.cloud_io import write_cloud
from simgrasp.perception.normals import estimate_normals
from simgrasp.perception.scene_cloud import SceneCloud
from simgrasp.perception.segmentation.segment import Segmentation

PATTERN = "object_{label}.ply"


def write_object_clouds(scene: SceneCloud, segmentation: Segmentation, folder: Path) -> list[Path]:
    """Write every whole object of ``segmentation`` (of ``scene``) into ``folder`` (module
    docstring); returns the files written, by label."""
    folder.mkdir(parents=True, exist_ok=True)
    for stale in folder.glob(PATTERN.format(label="*")):
        stale.unlink()
    written = []
    for label in segmentation.whole_objects():
        points = scene.points[segmentation.object_mask(label)].astype(np.float64)
        normals = estimate_normals(points, orient="viewpoint", viewpoint=scene.viewpoint)
        path = folder / PATTERN.format(label=label)
        write_cloud(path, points, normals)
        written.append(path)
    return written
