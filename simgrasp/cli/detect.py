"""``simgrasp detect CLOUD``: handles in a point cloud file, as a table or JSON.

Every threshold of both detectors is a flag (``--detector.quadric.shell-test false``), or set
it from a file (``--config detect.toml``); ``--print-config`` lists them all.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

from simgrasp.config import setting
from simgrasp.errors import SimgraspError
from simgrasp.handles.detection import Detection
from simgrasp.handles.detector_config import DetectorConfig
from simgrasp.perception.units import Units


@dataclass(frozen=True, kw_only=True)
class Options:
    cloud: Path = setting(positional=True, metavar="CLOUD")
    """Point cloud file: .ply, .pcd, .xyz or .npy (in --units)."""
    units: Units = "m"
    """Units of the file's coordinates and of --viewpoint (results are in meters)."""
    json: bool = False
    """Print one JSON object instead of a table."""
    seed: int = 0
    """Seed of the neighborhood sampling."""
    detector: DetectorConfig = field(default_factory=DetectorConfig)
    gripper_width: float | None = None
    """Maximum gripper opening (m); sets the chosen detector's gripper_max_opening."""
    viewpoint: tuple[float, float, float] | None = setting(None, metavar=("X", "Y", "Z"))
    """Camera position for a single-view cloud (m, the cloud's frame): normals are turned
    toward it."""
    plot: Path | None = setting(None, metavar="OUT.png")
    """Write a picture of the detection."""


def run(options: Options) -> int:
    from simgrasp.stdout_guard import stdout_to_stderr

    with stdout_to_stderr():  # library warnings must not mix with the output (--json)
        detection = _detect(options)
    kind = options.detector.kind
    if options.json:
        json.dump(detection.to_json(), sys.stdout)
        sys.stdout.write("\n")
        return 0
    print(
        f"{kind}: {detection.neighborhoods} neighborhoods, "
        f"{len(detection.candidates)} candidates, {len(detection.handles)} handles"
    )
    for i, handle in enumerate(detection.handles):
        center = ", ".join(f"{v:+.4f}" for v in handle.center)
        axis = ", ".join(f"{v:+.3f}" for v in handle.axis)
        print(
            f"  handle {i}: center [{center}] m, axis [{axis}], width {handle.width * 100:.1f} cm,"
            f" score {handle.score:.2f}, support {handle.support}"
        )
    steps = ", ".join(f"{k} {v * 1000:.0f} ms" for k, v in detection.timings_s.items())
    print(f"  timings: {steps}")
    if options.plot:
        print(f"  plot written to {options.plot}")
    return 0


def _detect(options: Options) -> Detection:
    from simgrasp.handles import detect
    from simgrasp.perception.cloud_io import read_cloud
    from simgrasp.perception.units import UNIT_SCALE, cloud_in_meters

    config = options.detector.chosen()
    if options.gripper_width is not None:
        if not options.gripper_width > 0:
            raise SimgraspError(f"--gripper-width must be positive, got {options.gripper_width}")
        config = replace(config, gripper_max_opening=options.gripper_width)
    points, normals = read_cloud(options.cloud)
    points = cloud_in_meters(points, options.units, str(options.cloud))
    scale = UNIT_SCALE[options.units]
    viewpoint = None if options.viewpoint is None else [v * scale for v in options.viewpoint]
    kind = options.detector.kind
    detection = detect(points, normals, config, options.seed, detector=kind, viewpoint=viewpoint)
    if options.plot:
        from simgrasp.handles.plot import plot_detection

        plot_detection(detection, options.plot, title=f"{options.cloud} ({kind})")
    return detection
