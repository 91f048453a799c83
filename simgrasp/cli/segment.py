"""``simgrasp segment SCENE``: the table plane and the objects on it, as a table or JSON.

Labels: 0 invalid, 1 table, 2.. objects ordered by distance to the sensor; every segmentation
setting is a ``--segment.*`` flag.
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path

from simgrasp.config import setting
from simgrasp.config.checks import Checked
from simgrasp.perception.depth_image import DepthImageConfig
from simgrasp.perception.segmentation.segment_config import SegmentConfig

EXAMPLES = (
    "simgrasp segment scene.pcd --labels labels.npy --plot scene.png",
    "simgrasp segment depth.png --depth.intrinsics 615 615 320 240 --depth.scale 0.001",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    scene: Path = setting(positional=True, metavar="SCENE")
    """Scene cloud: .pcd (organized or not, NaN pixels kept), .ply or .npy (meters), or a
    depth image .png / .tif (one sensor frame: --depth.intrinsics, --depth.scale)."""
    json: bool = setting(False, main=True)
    """Print one JSON object (with ``settings``: the segmentation settings, seed included)."""
    labels: Path | None = setting(
        None, metavar="OUT.npy", output="file", suffixes=(".npy",), main=True
    )
    """Write one int32 label per input point, in the input's order (0 invalid, 1 table, 2..
    objects nearest first)."""
    plot: Path | None = setting(None, metavar="OUT.png", output="plot", main=True)
    """Write a picture of the labels."""
    clouds: Path | None = setting(None, metavar="DIR", output="dir", main=True)
    """Write each whole object (with its side parts) as DIR/object_<label>.ply: points in the
    scene's frame (m), normals toward the sensor; earlier object_*.ply there are replaced."""
    depth: DepthImageConfig = field(default_factory=DepthImageConfig)
    segment: SegmentConfig = field(default_factory=SegmentConfig)


def run(options: Options) -> int:
    import numpy as np

    from simgrasp.perception.scene_cloud import read_scene
    from simgrasp.perception.segmentation.segment import segment_scene

    scene = read_scene(options.scene, options.depth)
    result = segment_scene(scene, options.segment)
    if options.labels:
        np.save(options.labels, result.labels)
    if options.plot:
        from simgrasp.plots.segmentation import plot_segmentation

        plot_segmentation(scene, result, options.plot)
    if options.clouds:
        from simgrasp.perception.segmentation.segment_clouds import write_object_clouds

        written = write_object_clouds(scene, result, options.clouds)
        print(f"{len(written)} object clouds written to {options.clouds}", file=sys.stderr)
    if options.json:
        json.dump({**result.to_json(), "settings": asdict(options.segment)}, sys.stdout)
        sys.stdout.write("\n")
        return 0
    plane = ", ".join(f"{v:+.4f}" for v in result.plane)
    print(f"table: plane [{plane}], {result.table_points} points")
    for obj in result.objects:
        center = ", ".join(f"{v:+.3f}" for v in obj.center)
        extent = " x ".join(f"{v * 100:.1f}" for v in obj.extent)
        part = f" (side part of {obj.part_of})" if obj.part_of != obj.label else ""
        print(f"  object {obj.label}: {obj.points} points, center [{center}] m, {extent} cm{part}")
    if not result.objects:
        print("  no object on the table")
    scale = f", pixel settings at scale {result.pixel_scale}" if result.pixel_scale > 1 else ""
    print(f"  {result.timings_s['total'] * 1000:.0f} ms{scale}")
    return 0
