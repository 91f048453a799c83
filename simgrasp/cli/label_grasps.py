"""``simgrasp label-grasps [OBJECT] --grasps FILE|GLOB|DIR``: score every grasp of a file on
an object, resumably, and say which hold it by its handle.

Writes ``OUT/labels.jsonl`` (one record per grasp, appended as each finishes; rerun the same
command to finish an interrupted run), ``labels.npz`` (``success``, ``on_handle``,
``failure`` in input order; ``score`` for protocols with one), ``summary.json`` and
``labels.png``. OBJECT may be left out for ACRONYM ``.h5`` and GraspGen ``.json`` files,
which name their object (:mod:`simgrasp.grasping.labeling.grasp_files`). A glob or a folder
labels every file into ``OUT/<file stem>/`` with one ``OUT/summary.json``
(:mod:`simgrasp.grasping.labeling.dataset_run`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from simgrasp.cli import invocation
from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.config.checks import PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.grasping.labeling.labeling import LabelConfig

SHOWN_PROBLEMS = 10
"""Invalid rows listed one by one before the rest are counted."""


EXAMPLES = ("simgrasp label-grasps 048_hammer --grasps grasps.npz --workers 2 --out out/labels",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    label: LabelConfig = setting(default_factory=LabelConfig, flatten=True)
    grasps: Path
    """Grasp file in the object frame: .npz/.json (object_T_grasp N x 4 x 4 or poses N x 7
    [x y z qw qx qy qz], optional width), .h5 (ACRONYM), .json (GraspGen) or .npy (graspnetAPI
    rows); or a glob or folder of them (each into OUT/<stem>/)."""
    mesh_root: Path | None = None
    """Folder that ACRONYM/GraspGen object/file paths are relative to (default: the folder
    holding the grasp file's grasps/ folder)."""
    max_grasps: int | None = None
    """Label only each file's first N grasps."""
    export: Literal["acronym", "graspgen"] | None = setting(None, main=True)
    """Also write each input file with our labels (object_in_gripper, score, on_handle) under
    grasps/qualities/simgrasp (OUT/export/)."""
    out: Path | None = setting(None, main=True)
    """Output directory (default out/labels/OBJECT)."""
    workers: PositiveInt = setting(1, main=True)
    """Worker processes (or Ray CPUs)."""
    backend: Literal["local", "ray"] = "local"
    """Label in local worker processes or as Ray tasks."""
    address: str | None = None
    """Ray cluster to join with --backend ray (auto or HOST:PORT)."""
    no_picture: bool = False
    """Skip labels.png."""


def run(options: Options) -> int:
    from simgrasp.assets.mesh_object import file_stem
    from simgrasp.assets.model import model_for
    from simgrasp.grasping.labeling.dataset_run import (
        check_export,
        grasps_for,
        label_files,
        object_for,
    )
    from simgrasp.grasping.labeling.grasp_files import expand_grasp_files
    from simgrasp.grasping.labeling.label_run import check_run_dir, label_grasp_set, run_identity
    from simgrasp.runs.out_dir import claim_out_dir

    if options.max_grasps is not None and options.max_grasps < 1:
        raise SimgraspError(f"--max-grasps must be >= 1, got {options.max_grasps}")
    files = expand_grasp_files(options.grasps)
    if not options.grasps.is_file():  # a folder or a glob, of any number of files: OUT/<stem>/
        return label_files(files, options, invocation())
    config = object_for(options, files[0])
    grasps = grasps_for(options.grasps, options.max_grasps)
    if options.export:
        check_export(options.grasps, options.export)
    report_problems(grasps.problems)
    if options.out is not None:  # a changed setting is refused before the object is built
        check_run_dir(options.out, run_identity(grasps, config, options.grasps))
    model = model_for(config.object, options.ycb_dir)
    out = options.out or Path("out") / "labels" / file_stem(model.asset.name)
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
        if options.export:
            from simgrasp.grasping.labeling.dataset_run import export_run

            export_run(files[0], out, options.export, out)
    print_summary(summary, out, picture=not options.no_picture)
    return 0


def report_problems(problems: dict[int, str]) -> None:
    """List the rows that are not grasps on stderr (they are labeled ``invalid``)."""
    for index, problem in list(problems.items())[:SHOWN_PROBLEMS]:
        print(f"row {index}: {problem}: skipped (invalid)", file=sys.stderr)
    if len(problems) > SHOWN_PROBLEMS:
        print(f"... and {len(problems) - SHOWN_PROBLEMS} more invalid rows", file=sys.stderr)


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


def print_summary(summary: dict[str, Any], out: Path, *, picture: bool) -> None:
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
        f"output       {out}/labels.jsonl, labels.npz, summary.json"
        + (", labels.png" if picture else ""),
    ]
    sys.stdout.write("\n".join(lines) + "\n")
