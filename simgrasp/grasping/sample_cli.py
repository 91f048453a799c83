"""``simgrasp sample-grasps``: antipodal grasps on an object's mesh, saved as a grasp set.

The grasps are in the object's mesh frame (``object_T_grasp``, ``width``) and, unless
``--no-table``, clear of the table under the object's rest pose in the scene of ``--seed``
(the scene ``label-grasps --seed`` labels them in).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from simgrasp.cli_args import add_placement_argument


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("object", help="YCB id (048_hammer or hammer) or generated tool")
    parser.add_argument("--n", type=int, required=True, help="number of grasps")
    parser.add_argument("--out", type=Path, required=True, help="output .npz")
    parser.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed of the sampling and of the scene whose table "
        "the grasps clear (label them with the same --seed)",
    )
    parser.add_argument("--gripper", choices=("builtin", "robotiq_2f85"), default="builtin")
    add_placement_argument(parser)
    parser.add_argument(
        "--no-table", action="store_true", help="sample all around the object (free space)"
    )
    parser.add_argument("--ycb-dir", default=None, help="YCB root (default $SIMGRASP_YCB_DIR)")


def run(args: argparse.Namespace) -> int:
    from simgrasp.grasping.antipodal import Table, sample_antipodal
    from simgrasp.grasping.chain import gripper_geometry, model_for
    from simgrasp.grasping.grasp_sets import write_grasp_set
    from simgrasp.scenes.gripper import make_gripper
    from simgrasp.scenes.scene import SceneConfig, build_scene

    if args.out.suffix.lower() != ".npz":
        raise ValueError(f"--out must end in .npz, got {args.out}")
    gripper = make_gripper(args.gripper)
    model = model_for(args.object, args.ycb_dir)
    table = None
    if not args.no_table:
        scene = build_scene(model, gripper, SceneConfig(placement=args.placement), args.seed)
        table = Table(scene.world_T_object, scene.config.table_top_z)
    start = time.perf_counter()
    poses, widths = sample_antipodal(
        model.asset.mesh, gripper_geometry(gripper), args.n, args.seed, table=table
    )
    write_grasp_set(args.out, poses, widths)
    seconds = time.perf_counter() - start
    short = f" (only {len(poses)} of {args.n} found)" if len(poses) < args.n else ""
    sys.stdout.write(f"{len(poses)} grasps{short} in {seconds:.1f} s -> {args.out}\n")
    return 0
