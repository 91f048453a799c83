"""``simgrasp label-grasps OBJECT --grasps FILE``: score every grasp of a file on an object,
resumably, and say which hold it by its handle.

Writes ``OUT/labels.jsonl`` (one record per grasp, appended as each finishes; rerun the same
command to finish an interrupted run), ``labels.npz`` (``success``, ``on_handle``,
``failure`` in input order), ``summary.json`` and ``labels.png``.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from simgrasp.cli import invocation
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.config.checks import PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.grasping.labeling.labeling import LabelConfig

SHOWN_PROBLEMS = 10
"""Invalid rows listed one by one before the rest are counted."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    label: LabelConfig = setting(flatten=True)
    grasps: Path
    """Grasp file in the object frame: .npz/.json (object_T_grasp N x 4 x 4 or poses N x 7
    [x y z qw qx qy qz], optional width), .h5 (ACRONYM) or .npy (graspnetAPI rows)."""
    out: Path | None = None
    """Output directory (default out/labels/OBJECT)."""
    workers: PositiveInt = 1
    """Worker processes (or Ray CPUs)."""
    backend: Literal["local", "ray"] = "local"
    """Label in local worker processes or as Ray tasks."""
    address: str | None = None
    """Ray cluster to join with --backend ray (auto or HOST:PORT)."""
    no_picture: bool = False
    """Skip labels.png."""


def run(options: Options) -> int:
    from simgrasp.assets.model import model_for
    from simgrasp.grasping.labeling.grasp_sets import read_grasp_set
    from simgrasp.grasping.labeling.label_run import label_grasp_set
    from simgrasp.runs.out_dir import claim_out_dir

    config = options.label
    grasps = read_grasp_set(options.grasps)
    _report_problems(grasps.problems, len(grasps))
    model = model_for(config.object, options.ycb_dir)
    out = options.out or Path("out") / "labels" / model.asset.name
    with claim_out_dir(out, invocation()):  # one run at a time per --out, as evaluate
        summary, records = label_grasp_set(
            grasps,
            config,
            out,
            grasp_file=options.grasps,
            ycb_dir=options.ycb_dir,
            workers=options.workers,
            backend=options.backend,
            address=options.address,
        )
        if not options.no_picture:
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
        raise SimgraspError("no row of the grasp file is a valid grasp")


def _picture(model: Any, grasps: Any, records: list, config: LabelConfig, path: Path) -> None:
    import numpy as np

    from simgrasp.grippers import make_gripper
    from simgrasp.plots.grasp_labels import plot_labels

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
