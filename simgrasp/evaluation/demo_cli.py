"""``simgrasp demo``: the main job, a small full-chain grasp sweep on the embedded default.

The procedurally generated tools (and, with ``SIMGRASP_YCB_DIR`` set, the paper's eight YCB
objects), the quadric detector against the centroid baseline, the built-in gripper, a few seeds
at the noise-free and a noisy cloud: render -> detect -> plan -> execute in MuJoCo, then the
report (detection accuracy, lift and on-handle success, failure modes, timings). Sized to finish
in about three minutes on two cores once the object decompositions are cached.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

DETECTORS = ("quadric", "centroid")
NOISE = (0.0, 0.02)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--seeds", type=int, default=None, help="seeds per setting (default 2, 1 with YCB)"
    )
    parser.add_argument("--workers", type=int, default=2, help="parallel worker processes")
    parser.add_argument("--out", type=Path, default=Path("out/demo"), help="output directory")


def run(args: argparse.Namespace) -> int:
    from simgrasp.assets.registry import default_objects
    from simgrasp.evaluation.out_dir import claim_out_dir
    from simgrasp.evaluation.report import write_report
    from simgrasp.evaluation.sweep import TRIALS_FILE, plan_trials, run_sweep
    from simgrasp.handles.evaluation import PAPER_OBJECTS

    ycb_dir = os.environ.get("SIMGRASP_YCB_DIR")
    objects = default_objects() + (list(PAPER_OBJECTS) if ycb_dir else [])
    seeds = args.seeds if args.seeds is not None else (1 if ycb_dir else 2)
    if seeds < 1 or args.workers < 1:
        raise ValueError(f"--seeds and --workers must be >= 1, got {seeds} and {args.workers}")
    specs = plan_trials(objects, DETECTORS, ("builtin",), NOISE, range(seeds))
    start = time.perf_counter()
    with claim_out_dir(args.out, sys.argv[1:]):
        (args.out / TRIALS_FILE).unlink(missing_ok=True)  # the demo always runs afresh
        records = run_sweep(specs, args.out, ycb_dir=ycb_dir, workers=args.workers)
    print(write_report(records, args.out, title="simgrasp demo"))
    print(
        f"{len(records)} trials on {len(objects)} objects in "
        f"{time.perf_counter() - start:.0f} s; report in {args.out / 'report.md'}"
    )
    return 0
