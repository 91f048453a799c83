"""``simgrasp label-grasps``: score every grasp of a file on an object, resumably.

Writes ``OUT/labels.jsonl`` (one record per grasp, appended as each finishes; rerun the same
command to finish an interrupted run), ``labels.npz``, ``summary.json`` and ``labels.png``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from simgrasp.cli_args import add_placement_argument
from simgrasp.grasping.protocol import DEFAULT_PROTOCOL, PROTOCOLS

SHOWN_PROBLEMS = 10
"""Invalid rows listed one by one before the rest are counted."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("object", help="YCB id (048_hammer or hammer) or generated tool")
    parser.add_argument(
        "--grasps",
        type=Path,
        required=True,
        help="grasp file in the object frame: .npz/.json (object_T_grasp N x 4 x 4 or poses "
        "N x 7 [x y z qw qx qy qz], optional width), .h5 (ACRONYM) or .npy (graspnetAPI rows)",
    )
    parser.add_argument("--gripper", choices=("builtin", "robotiq_2f85"), default="builtin")
    parser.add_argument("--out", type=Path, default=None, help="output dir (out/labels/OBJECT)")
    parser.add_argument("--workers", type=int, default=1, help="worker processes or Ray CPUs")
    parser.add_argument("--backend", choices=("local", "ray"), default="local")
    parser.add_argument("--address", default=None, help="Ray cluster (auto or HOST:PORT)")
    parser.add_argument(
        "--protocol",
        choices=PROTOCOLS,
        default=DEFAULT_PROTOCOL,
        help="trial protocol: full (as trial/evaluate) or fast (shorter phases)",
    )
    parser.add_argument("--seed", type=int, default=0, help="scene seed (rest pose and yaw)")
    parser.add_argument(
        "--free-floating",
        action="store_true",
        help="label in free space as ACRONYM does: the object floats (its weight compensated) "
        "above its rest pose, the gripper closes at the grasp itself, then the weight comes on "
        "and the tugs follow (no table, pre-grasp, approach or lift)",
    )
    add_placement_argument(parser)
    parser.add_argument("--ycb-dir", default=None, help="YCB root (default $SIMGRASP_YCB_DIR)")
    parser.add_argument("--no-picture", action="store_true", help="skip labels.png")


def run(args: argparse.Namespace) -> int:
    from simgrasp.grasping.chain import model_for
    from simgrasp.grasping.grasp_sets import read_grasp_set
    from simgrasp.grasping.label_run import label_grasp_set
    from simgrasp.grasping.labeling import LabelConfig

    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    config = LabelConfig(
        args.object,
        args.gripper,
        args.protocol,
        args.seed,
        args.placement,
        args.free_floating,
    )
    grasps = read_grasp_set(args.grasps)
    _report_problems(grasps.problems, len(grasps))
    model = model_for(args.object, args.ycb_dir)
    out = args.out or Path("out") / "labels" / model.asset.name
    summary, records = label_grasp_set(
        grasps,
        config,
        out,
        grasp_file=args.grasps,
        ycb_dir=args.ycb_dir,
        workers=args.workers,
        backend=args.backend,
        address=args.address,
    )
    if not args.no_picture:
        _picture(model, grasps, records, config, out / "labels.png")
    _print_summary(summary, out)
    return 0


def _report_problems(problems: dict[int, str], count: int) -> None:
    """List the rows that are not grasps on stderr (they are labeled ``invalid``)."""
    for index, problem in list(problems.items())[:SHOWN_PROBLEMS]:
        print(f"row {index}: {problem}: skipped (invalid)", file=sys.stderr)
    if len(problems) > SHOWN_PROBLEMS:
        print(f"... and {len(problems) - SHOWN_PROBLEMS} more invalid rows", file=sys.stderr)
    if len(problems) == count:
        raise ValueError("no row of the grasp file is a valid grasp")


def _picture(model: Any, grasps: Any, records: list, config: Any, path: Path) -> None:
    import numpy as np

    from simgrasp.grasping.label_plot import plot_labels
    from simgrasp.scenes.gripper import make_gripper

    widths = np.where(
        np.isfinite(grasps.width), grasps.width, make_gripper(config.gripper).max_opening
    )
    title = (
        f"{model.asset.name}, {config.gripper} gripper, {config.protocol} protocol, "
        f"seed {config.seed}" + (", free-floating" if config.free_floating else "")
    )
    plot_labels(model.asset.mesh, grasps.object_T_tcp, widths, records, path, title)


def _print_summary(summary: dict[str, Any], out: Path) -> None:
    rate = summary["grasps_per_s"]
    lines = [
        f"grasps       {summary['grasps']} ({summary['invalid']} invalid, "
        f"{summary['sim_unstable']} sim unstable, {summary['scored']} scored)",
        f"held         {summary['success']} ({summary['success_rate']:.1%} of scored): "
        f"{summary['success_on_handle']} on the handle, {summary['success_off_handle']} off it",
        "failures     "
        + (", ".join(f"{k} {v}" for k, v in sorted(summary["failures"].items())) or "none"),
        f"this run     {summary['labeled_this_run']} labeled in {summary['wall_s_this_run']:.1f} s"
        + (f" ({rate:.1f} grasps/s)" if rate else ""),
        f"output       {out}/labels.jsonl, labels.npz, summary.json",
    ]
    sys.stdout.write("\n".join(lines) + "\n")
