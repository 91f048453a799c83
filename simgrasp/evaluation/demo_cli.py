"""``simgrasp demo``: the main job on the embedded default objects.

Runs both handle detectors on clouds of the procedurally generated tools (and, with
``SIMGRASP_YCB_DIR`` set, the paper's YCB objects) and prints the accuracy summary.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

from simgrasp.assets.registry import default_objects
from simgrasp.handles import DETECTORS
from simgrasp.handles.evaluation import PAPER_OBJECTS, accuracy_tables, run_evaluation, write_csv


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--seeds", type=int, default=2, help="seeds per object")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/demo"))


def run(args: argparse.Namespace) -> int:
    objects = list(default_objects())
    if os.environ.get("SIMGRASP_YCB_DIR"):
        objects += list(PAPER_OBJECTS)
    start = time.perf_counter()
    records = run_evaluation(
        objects, DETECTORS, (0.0, 0.02), range(args.seeds), workers=args.workers
    )
    print(accuracy_tables(records))
    path = write_csv(records, args.out / "demo_detections.csv")
    print(
        f"{len(records)} detections on {len(objects)} objects in "
        f"{time.perf_counter() - start:.0f} s; records in {path}"
    )
    return 0
