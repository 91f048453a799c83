"""``simgrasp segment SCENE``: the table plane and the objects on it, as a table or JSON."""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from simgrasp.perception.scene_cloud import read_scene
from simgrasp.perception.segment import segment_scene


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "scene", help="scene cloud: .pcd (organized or not, NaN pixels kept), .ply or .npy (m)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--labels",
        metavar="OUT.npy",
        help="write one int32 label per input point, in the input's order "
        "(0 invalid, 1 table, 2.. objects nearest first)",
    )
    parser.add_argument("--plot", metavar="OUT.png", help="write a picture of the labels")


def run(args: argparse.Namespace) -> int:
    if args.labels and not args.labels.endswith(".npy"):
        raise ValueError(f"--labels must name a .npy file, got {args.labels!r}")
    scene = read_scene(args.scene)
    result = segment_scene(scene)
    if args.labels:
        np.save(args.labels, result.labels)
    if args.plot:
        from simgrasp.perception.segment_plot import plot_segmentation

        plot_segmentation(scene, result, args.plot)
    if args.json:
        json.dump(result.to_json(), sys.stdout)
        sys.stdout.write("\n")
        return 0
    plane = ", ".join(f"{v:+.4f}" for v in result.plane)
    print(f"table: plane [{plane}], {result.table_points} points")
    for obj in result.objects:
        center = ", ".join(f"{v:+.3f}" for v in obj.center)
        extent = " x ".join(f"{v * 100:.1f}" for v in obj.extent)
        print(f"  object {obj.label}: {obj.points} points, center [{center}] m, {extent} cm")
    if not result.objects:
        print("  no object on the table")
    print(f"  {result.timings_s['total'] * 1000:.0f} ms")
    return 0
