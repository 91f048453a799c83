"""``simgrasp detect CLOUD``: handles in a point cloud file, as a table or JSON."""

from __future__ import annotations

import argparse
import json
import sys

from simgrasp.handles import DETECTORS, QuadricDetectorConfig, TenPasConfig, default_config, detect
from simgrasp.perception.cloud_io import read_cloud


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cloud", help="point cloud file: .ply, .pcd, .xyz or .npy (meters)")
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
        "--segment",
        action="store_true",
        help="CLOUD is a whole scene: segment it (as `simgrasp segment`) and detect on each "
        "object; normals face the file's VIEWPOINT unless --viewpoint is given",
    )
    parser.add_argument(
        "--object", default="all", metavar="K|all", help="with --segment: only object label K"
    )


def run(args: argparse.Namespace) -> int:
    if args.gripper_width is not None and not args.gripper_width > 0:
        raise ValueError(f"--gripper-width must be positive, got {args.gripper_width}")
    config = default_config(args.detector, args.gripper_width)
    if args.segment:
        return _run_segmented(args, config)
    if args.object != "all":
        raise ValueError("--object needs --segment")
    points, normals = read_cloud(args.cloud)
    detection = detect(
        points, normals, config, args.seed, detector=args.detector, viewpoint=args.viewpoint
    )
    if args.plot:
        from simgrasp.handles.plot import plot_detection

        plot_detection(detection, args.plot, title=f"{args.cloud} ({args.detector})")
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


def _run_segmented(args: argparse.Namespace, config: QuadricDetectorConfig | TenPasConfig) -> int:
    """``--segment``: detect on each object of the scene (``simgrasp.handles.scene_detect``)."""
    from simgrasp.handles.scene_detect import detect_in_scene, parse_object_choice

    if args.plot:
        raise ValueError("--plot is not available with --segment (use `simgrasp segment --plot`)")
    result = detect_in_scene(
        args.cloud,
        config,
        args.seed,
        detector=args.detector,
        viewpoint=args.viewpoint,
        only_object=parse_object_choice(args.object),
    )
    report = result.to_json()
    if args.json:
        json.dump(report, sys.stdout)
        sys.stdout.write("\n")
        return 0
    print(f"{args.detector}: {len(result.detections)} objects, {len(report['handles'])} handles")
    for handle in report["handles"]:
        center = ", ".join(f"{v:+.4f}" for v in handle["center"])
        print(f"  object {handle['object']}: center [{center}] m, score {handle['score']:.2f}")
    return 0
