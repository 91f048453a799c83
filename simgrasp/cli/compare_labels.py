"""``simgrasp compare-labels REFERENCE OTHER``: the confusion matrix of two label-grasps runs
of one grasp set (e.g. the full and the fast protocol)."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

from simgrasp.config import setting
from simgrasp.config.checks import Checked


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    reference: Path = setting(positional=True, metavar="REFERENCE")
    """label-grasps output directory (e.g. of the full protocol)."""
    other: Path = setting(positional=True, metavar="OTHER")
    """label-grasps output directory (e.g. of the fast protocol)."""
    json: bool = False
    """Print the counts as JSON."""


def run(options: Options) -> int:
    from simgrasp.grasping.labeling.label_compare import compare_labels, confusion_text

    comparison = compare_labels(options.reference, options.other)
    if options.json:
        print(json.dumps(comparison))
    else:
        names = [path.name or str(path) for path in (options.reference, options.other)]
        sys.stdout.write(confusion_text(comparison, *names) + "\n")
    return 0
