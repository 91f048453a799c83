"""Real sensor scenes for development: the osd-learn scenes (Object Segmentation Database,
learn split), read from a local copy that is never shipped.

Layout: ``<real dir>/osd-learn/learn<N>.pcd``, organized 640 x 480 PCD files with a per-point
ground-truth ``label`` (0 invalid, 1-9 table parts, 20-29 the first object's parts, 30-39 the
second's ...), coordinates in meters in the sensor frame (camera at the origin, OpenCV axes),
NaN for invalid pixels. The real dir is ``$SIMGRASP_REAL_DIR``, else ``../shared/real`` beside
the repository.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.perception.scene_cloud import SceneCloud, read_scene

REAL_DIR_ENV = "SIMGRASP_REAL_DIR"
OSD_LEARN = "osd-learn"


def default_real_dir() -> Path:
    """``$SIMGRASP_REAL_DIR``, else ``<repository>/../shared/real`` (may not exist)."""
    env = os.environ.get(REAL_DIR_ENV)
    if env:
        return Path(env).expanduser()
    return Path(__file__).resolve().parents[3] / "shared" / "real"


def osd_scene_file(scene: str, real_dir: str | os.PathLike[str] | None = None) -> Path:
    """The file of an osd-learn scene named ``learn<N>`` (``FileNotFoundError`` if absent)."""
    if not (scene.startswith("learn") and scene[5:].isdigit()):
        raise SimgraspError(f"osd scene names look like 'learn33', got {scene!r}")
    root = Path(real_dir).expanduser() if real_dir is not None else default_real_dir()
    path = root / OSD_LEARN / f"{scene}.pcd"
    if not path.is_file():
        raise DataNotFoundError(
            f"osd scene {scene}: no file {path}; point --real-dir or ${REAL_DIR_ENV} at the "
            "folder holding osd-learn/"
        )
    return path


@dataclass(frozen=True)
class LabeledScene:
    """A scene cloud with its ground-truth part labels (sensor frame, meters).

    Attributes:
        points: (N, 3) float64, NaN rows for invalid pixels, row-major image order.
        labels: (N,) int64 ground-truth part label of each point (0 invalid).
        cloud: the scene as read (its grid and viewpoint), for segmentation.
    """

    points: NDArray[np.float64]
    labels: NDArray[np.int64]
    cloud: SceneCloud

    def object_points(self, object_id: int) -> NDArray[np.float64]:
        """(M, 3) points of ground-truth object ``object_id`` (labels ``10 k`` .. ``10 k + 9``)."""
        if object_id < 2:
            raise SimgraspError(f"object ids start at 2 (labels 20-29), got {object_id}")
        points = self.points[self.labels // 10 == object_id]
        if len(points) == 0:
            raise SimgraspError(
                f"the scene has no object {object_id} (no label {10 * object_id}..)"
            )
        return points


def read_labeled_scene(path: str | os.PathLike[str]) -> LabeledScene:
    """Read a scene cloud with a ``label`` field, keeping invalid points in place."""
    cloud = read_scene(Path(path))
    if cloud.labels is None:
        raise SimgraspError(f"{path}: not a labeled point cloud (no label field)")
    return LabeledScene(cloud.points.astype(np.float64), cloud.labels, cloud)
