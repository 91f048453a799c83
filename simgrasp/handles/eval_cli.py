"""``simgrasp detect-eval``: detection accuracy on YCB meshes (paper Tables I, II, Fig. 8)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from simgrasp.cli_args import comma_list, float_range
from simgrasp.handles import DETECTORS
from simgrasp.handles.evaluation import (
    LABELED_EXTRA,
    PAPER_OBJECTS,
    accuracy_tables,
    plot_accuracy_vs_noise,
    run_evaluation,
    write_csv,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--objects",
        type=comma_list,
        default=("paper",),
        help="'paper' (the paper's 8 objects), 'all' (every labeled object) or YCB ids",
    )
    parser.add_argument("--noise", type=float_range, default=(0.0,), help="sigmas, e.g. 0:0.1:0.01")
    parser.add_argument("--seeds", type=int, default=10, help="number of seeds (0..N-1)")
    parser.add_argument("--detector", type=comma_list, default=DETECTORS, help="quadric,tenpas")
    parser.add_argument("--gripper-width", type=float, default=None, metavar="M")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--ycb-dir", default=None, help="YCB root (default: $SIMGRASP_YCB_DIR)")
    parser.add_argument("--out", type=Path, default=Path("out/detect-eval"), help="output dir")


def _objects(names: tuple[str, ...]) -> tuple[str, ...]:
    if names == ("paper",):
        return PAPER_OBJECTS
    if names == ("all",):
        return PAPER_OBJECTS + LABELED_EXTRA
    return names


def run(args: argparse.Namespace) -> int:
    unknown = [d for d in args.detector if d not in DETECTORS]
    if unknown:
        raise ValueError(f"unknown detector(s) {unknown}; choose from {', '.join(DETECTORS)}")
    if args.seeds < 1:
        raise ValueError(f"--seeds must be >= 1, got {args.seeds}")
    start = time.perf_counter()
    records = run_evaluation(
        _objects(args.objects),
        args.detector,
        args.noise,
        range(args.seeds),
        workers=args.workers,
        ycb_dir=args.ycb_dir,
        gripper_max_opening=args.gripper_width,
    )
    tables = accuracy_tables(records)
    print(tables)
    csv_path = write_csv(records, args.out / "detect_eval.csv")
    plot_path = plot_accuracy_vs_noise(records, args.out / "accuracy_vs_noise.png")
    (args.out / "detect_eval.md").write_text(tables + "\n")
    print(f"wrote {csv_path}, {plot_path} and {args.out / 'detect_eval.md'}")
    print(f"{len(records)} detections in {time.perf_counter() - start:.0f} s")
    return 0
