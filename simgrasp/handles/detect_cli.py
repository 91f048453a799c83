"""``simgrasp detect CLOUD``: handles in a point cloud file, as a table or JSON."""

from __future__ import annotations

import argparse
import json
import sys

from simgrasp.handles import DETECTORS, default_config, detect
from simgrasp.perception.cloud_io import read_cloud
from simgrasp.perception.units import UNIT_SCALE, cloud_in_meters
from simgrasp.stdout_guard import stdout_to_stderr


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cloud", help="point cloud file: .ply, .pcd, .xyz or .npy (see --units)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--seed", type=int, default=0, help="seed for neighborhood sampling")
    parser.add_argument("--detector", choices=DETECTORS, default="quadric")
    parser.add_argument(
        "--gripper-width",
        type=float,
        default=None,
        metavar="M",
        help="maximum gripper opening in meters (default 0.085)",
    )
    parser.add_argument(
        "--viewpoint",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="camera position for a single-view cloud (normals are turned toward it)",
    )
    parser.add_argument("--plot", metavar="OUT.png", help="write a picture of the detection")
    parser.add_argument(
        "--units",
        choices=tuple(UNIT_SCALE),
        default="m",
        help="units of the file's coordinates and --viewpoint (results are in meters)",
    )


def run(args: argparse.Namespace) -> int:
    if args.gripper_width is not None and not args.gripper_width > 0:
        raise ValueError(f"--gripper-width must be positive, got {args.gripper_width}")
    with stdout_to_stderr():  # library warnings must not mix with the output (--json)
        detection = _detect(args)
    if args.json:
        json.dump(detection.to_json(), sys.stdout)
        sys.stdout.write("\n")
        return 0
    print(
        f"{args.detector}: {detection.neighborhoods} neighborhoods, "
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
    if args.plot:
        print(f"  plot written to {args.plot}")
    return 0


def _detect(args: argparse.Namespace):  # -> HandleDetection
    points, normals = read_cloud(args.cloud)
    points = cloud_in_meters(points, args.units, args.cloud)
    viewpoint = args.viewpoint and [v * UNIT_SCALE[args.units] for v in args.viewpoint]
    config = default_config(args.detector, args.gripper_width)
    detection = detect(
        points, normals, config, args.seed, detector=args.detector, viewpoint=viewpoint
    )
    if args.plot:
        from simgrasp.handles.plot import plot_detection

        plot_detection(detection, args.plot, title=f"{args.cloud} ({args.detector})")
    return detection
