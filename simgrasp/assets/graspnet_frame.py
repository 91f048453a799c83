"""A GraspNet-1Billion RealSense frame as an organized scene cloud: ``depth.png`` (uint16,
``factor_depth`` units per meter) back-projected through ``meta.mat``'s intrinsics, every
pixel in image order, NaN where the sensor returned nothing; camera frame (OpenCV axes,
meters, the sensor at the origin). The frames are not shipped (``../shared/real``'s
``graspnet-example/``, academic non-commercial licence)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import DataNotFoundError

GRASPNET_EXAMPLE = "graspnet-example"


def read_graspnet_frame(folder: str | Path) -> NDArray[np.float32]:
    """(H, W, 3) points of the frame in ``folder`` (``depth.png`` and ``meta.mat``)."""
    from simgrasp.perception.depth_image import read_depth_image

    folder = Path(folder)
    depth_file, meta_file = folder / "depth.png", folder / "meta.mat"
    for path in (depth_file, meta_file):
        if not path.is_file():
            raise DataNotFoundError(
                f"{folder}: no {path.name} (a GraspNet frame has depth.png and meta.mat)"
            )
    return read_depth_image(depth_file)
