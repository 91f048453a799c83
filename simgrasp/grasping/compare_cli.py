"""``simgrasp compare-labels``: confusion matrix of two label-grasps runs of one grasp set."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("reference", type=Path, help="label-grasps output dir (e.g. full)")
    parser.add_argument("other", type=Path, help="label-grasps output dir (e.g. fast)")
    parser.add_argument("--json", action="store_true", help="print the counts as JSON")


def run(args: argparse.Namespace) -> int:
    from simgrasp.grasping.label_compare import compare_labels, confusion_text

    comparison = compare_labels(args.reference, args.other)
    if args.json:
        print(json.dumps(comparison))
    else:
        names = [path.name or str(path) for path in (args.reference, args.other)]
        sys.stdout.write(confusion_text(comparison, *names) + "\n")
    return 0
