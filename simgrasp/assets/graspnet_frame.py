"""A GraspNet-1Billion RealSense frame as an organized scene cloud: ``depth.png`` (uint16,
``factor_depth`` units per meter) back-projected through ``meta.mat``'s intrinsics, every
pixel in image order, NaN where the sensor returned nothing; camera frame (OpenCV axes,
meters, the sensor at the origin). The frames are not shipped (``../shared/real``'s
``graspnet-example/``, academic non-commercial licence)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import DataNotFoundError, SimgraspError

GRASPNET_EXAMPLE = "graspnet-example"


def read_graspnet_frame(folder: str | Path) -> NDArray[np.float32]:
    """(H, W, 3) points of the frame in ``folder`` (``depth.png`` and ``meta.mat``)."""
    from PIL import Image
    from scipy.io import loadmat

    folder = Path(folder)
    depth_file, meta_file = folder / "depth.png", folder / "meta.mat"
    for path in (depth_file, meta_file):
        if not path.is_file():
            raise DataNotFoundError(
                f"{folder}: no {path.name} (a GraspNet frame has depth.png and meta.mat)"
            )
    meta = loadmat(meta_file)
    if "intrinsic_matrix" not in meta or "factor_depth" not in meta:
        raise SimgraspError(f"{meta_file}: no intrinsic_matrix or factor_depth")
    k = np.asarray(meta["intrinsic_matrix"], dtype=np.float64)
    depth = np.asarray(Image.open(depth_file), dtype=np.float64)
    if depth.ndim != 2:
        raise SimgraspError(f"{depth_file}: expected a one-channel depth image, got {depth.shape}")
    depth = depth / float(np.asarray(meta["factor_depth"]).squeeze())
    depth[depth <= 0] = np.nan
    rows, cols = np.mgrid[0 : depth.shape[0], 0 : depth.shape[1]]
    x = (cols - k[0, 2]) * depth / k[0, 0]
    y = (rows - k[1, 2]) * depth / k[1, 1]
    return np.dstack([x, y, depth]).astype(np.float32)
