"""Agreement with FleX per half of the ACRONYM affordance files (issue 25's claim).

``docs/results/acronym/halves.json`` names the two halves (``tune/files``: chosen on,
``held_out/files``: the claim; files sorted by name within each category, even indices
tune). This script keeps those lists and rewrites the figures beside them from a
``label-grasps`` run: per half, per category and overall, the pooled grasps scored, accuracy,
balanced accuracy and the AUROC of our ``score``, with the 95 % interval of accuracy and
balanced accuracy over 2,000 resamples of the group's files from seed 0 (how much a figure
depends on which objects fell in the half;
:func:`simgrasp.grasping.labeling.reference_compare.compare_with_reference`).

    python scripts/acronym_halves.py --data $SIMGRASP_ACRONYM_DIR/affordance/grasps \\
        --run out/acronym/affordance --halves docs/results/acronym/halves.json
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.grasping.labeling.reference_compare import compare_with_reference

KEYS = ("grasps", "accuracy", "balanced_accuracy", "auroc", "interval")
DRAWS = 2000
"""Resamples of a group's files for its interval."""


def halves(data: Path, run: Path, lists: dict[str, Any]) -> dict[str, Any]:
    """The figures of ``run`` per half and category, beside the halves' file lists."""
    result: dict[str, Any] = {}
    for half in ("tune", "held_out"):
        names = lists[f"{half}/files"]
        files = [data / name for name in names]
        groups = compare_with_reference(run, files, DRAWS, seed=0)["groups"]
        for category in sorted(k for k in groups if k != "overall"):
            result[f"{half}/{category}"] = {k: groups[category][k] for k in KEYS}
        result[f"{half}/all"] = {k: groups["overall"][k] for k in KEYS}
        result[f"{half}/files"] = names
    return result


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    data: Path
    """Folder of the ACRONYM grasp files."""
    run: Path
    """The label-grasps run (its --out) of those files."""
    halves: Path
    """halves.json to update (its file lists kept, its figures rewritten)."""


def run(options: Options) -> None:
    """Rewrite the halves' figures from the run; print them."""
    figures = halves(options.data, options.run, json.loads(options.halves.read_text()))
    options.halves.write_text(json.dumps(figures, indent=2) + "\n")
    for key, row in figures.items():
        if not key.endswith("/files"):
            accuracy, balanced = row["interval"]["accuracy"], row["interval"]["balanced_accuracy"]
            print(
                f"{key}: {row['grasps']} grasps, accuracy {row['accuracy']:.3f} "
                f"({accuracy[0]:.3f}-{accuracy[1]:.3f}), balanced {row['balanced_accuracy']:.3f} "
                f"({balanced[0]:.3f}-{balanced[1]:.3f}), AUROC {row['auroc']:.3f}"
            )


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
