"""``simgrasp evaluate``: sweep objects x detectors x grippers x noise x seeds as full-chain
grasp trials; resumable log ``DIR/trials.jsonl``, then ``summary.csv``, ``report.md`` and plots.

Rerunning with the same ``--out`` skips the trials already in the log, so an interrupted sweep
resumes where it stopped; the report covers exactly the trials of the current command line.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from simgrasp.cli_args import (
    add_placement_argument,
    add_views_argument,
    comma_list,
    float_range,
)

OBJECT_SETS = ("generated", "paper", "all")


def expand_objects(names: tuple[str, ...]) -> list[str]:
    """Expand the sets ``generated`` (the procedural tools), ``paper`` (the paper's eight YCB
    objects) and ``all`` (both plus the other labeled YCB objects); other names pass through."""
    from simgrasp.assets.registry import default_objects
    from simgrasp.handles.evaluation import LABELED_EXTRA, PAPER_OBJECTS

    sets = {
        "generated": default_objects(),
        "paper": list(PAPER_OBJECTS),
        "all": [*default_objects(), *PAPER_OBJECTS, *LABELED_EXTRA],
    }
    expanded = [obj for name in names for obj in sets.get(name, [name])]
    return list(dict.fromkeys(expanded))


def check_plan(
    objects: list[str],
    detectors: tuple[str, ...],
    grippers: tuple[str, ...],
    noises: tuple[float, ...],
    ycb_dir: str | None,
) -> None:
    """Fail before any worker starts on an unknown detector, gripper or object (or missing YCB
    data) or a noise sigma outside [0, 1), naming the offending value."""
    from simgrasp.assets.registry import load_object
    from simgrasp.grasping.chain import CHAIN_DETECTORS
    from simgrasp.scenes.gripper import make_gripper

    for detector in detectors:
        if detector not in CHAIN_DETECTORS:
            raise ValueError(
                f"unknown --detector {detector!r}; choose from {', '.join(CHAIN_DETECTORS)}"
            )
    for noise in noises:
        if not 0 <= noise < 1:
            raise ValueError(f"--noise sigmas must be in [0, 1), got {noise:g}")
    for gripper in grippers:
        make_gripper(gripper)
    for name in objects:
        load_object(name, ycb_dir)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--objects",
        type=comma_list,
        default=("generated",),
        help="comma list of object names and/or the sets generated, paper, all "
        "(default: generated)",
    )
    parser.add_argument(
        "--noise",
        type=float_range,
        default=(0.0,),
        help="multiplicative cloud-noise sigmas, START:STOP:STEP or a comma list (default 0)",
    )
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1 per setting")
    parser.add_argument(
        "--detector",
        type=comma_list,
        default=("quadric", "tenpas", "centroid", "random"),
        help="comma list of quadric, tenpas, centroid, random",
    )
    parser.add_argument(
        "--gripper", type=comma_list, default=("builtin",), help="builtin and/or robotiq_2f85"
    )
    add_placement_argument(parser)
    add_views_argument(parser)
    parser.add_argument("--workers", type=int, default=2, help="parallel worker processes")
    parser.add_argument("--out", type=Path, required=True, help="output directory")
    parser.add_argument("--backend", choices=("local", "ray"), default="local")
    parser.add_argument(
        "--address",
        default=None,
        help="Ray cluster to join with --backend ray, or auto for $RAY_ADDRESS / `ray start` "
        "(default: a new local instance with --workers CPUs)",
    )
    parser.add_argument(
        "--ycb-dir", default=None, help="YCB directory (default: $SIMGRASP_YCB_DIR)"
    )
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args: argparse.Namespace) -> int:
    from simgrasp.evaluation.out_dir import claim_out_dir

    _check_counts(args)
    ycb_dir = args.ycb_dir or os.environ.get("SIMGRASP_YCB_DIR")
    objects = expand_objects(args.objects)
    check_plan(objects, args.detector, args.gripper, args.noise, ycb_dir)
    with claim_out_dir(args.out, sys.argv[1:]):  # checked and held before any trial runs
        return _run(args, objects, ycb_dir)


def _check_counts(args: argparse.Namespace) -> None:
    if args.seeds < 1:
        raise ValueError(f"--seeds must be >= 1, got {args.seeds}")
    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    if args.address and args.backend != "ray":
        raise ValueError(f"--address {args.address} needs --backend ray")


def _run(args: argparse.Namespace, objects: list[str], ycb_dir: str | None) -> int:
    from simgrasp.evaluation.report import write_report
    from simgrasp.evaluation.sweep import plan_trials, run_sweep

    specs = plan_trials(
        objects,
        args.detector,
        args.gripper,
        args.noise,
        range(args.seeds),
        args.placement,
        args.views,
    )
    start = time.perf_counter()
    records = run_sweep(
        specs,
        args.out,
        ycb_dir=ycb_dir,
        workers=args.workers,
        backend=args.backend,
        address=args.address,
        progress=not args.no_progress,
    )
    title = "Grasp sweep" + (", objects placed upright" if args.placement == "upright" else "")
    report = write_report(records, args.out, title)
    print(report)
    print(
        f"{len(records)} trials in {time.perf_counter() - start:.0f} s; log, summary.csv, "
        f"report.md and plots in {args.out}"
    )
    return 0
