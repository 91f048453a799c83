"""``simgrasp compare-labels REFERENCE OTHER``: the confusion matrix of two label-grasps runs
of one grasp set (e.g. the full and the fast protocol); ``compare-labels OURS --reference
FILE.h5|GLOB|DIR``: our labels against a grasp file's own (FleX's), per object and overall
(:mod:`simgrasp.grasping.labeling.reference_compare`)."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, fields
from pathlib import Path

from simgrasp.config import setting
from simgrasp.config.checks import Checked, NonNegativeInt, PositiveInt
from simgrasp.errors import SimgraspError

EXAMPLES = (
    "simgrasp compare-labels out/full out/fast",
    "simgrasp compare-labels out/ours --reference flex.h5 --plot agreement.png",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    reference: Path = setting(positional=True, metavar="REFERENCE")
    """label-grasps output directory (e.g. of the full protocol; with --reference FILE: ours)."""
    other: Path | None = setting(None, positional=True, metavar="OTHER")
    """label-grasps output directory (e.g. of the fast protocol)."""
    reference_file: Path | None = setting(None, flag="--reference")
    """Grasp file(s) with labels (ACRONYM .h5: FleX's; a glob or folder) to compare
    REFERENCE's labels with, instead of OTHER."""
    plot: Path | None = setting(None, output="plot", main=True)
    """With --reference: write the agreement plot (PNG) here."""
    examples: Path | None = setting(None, output="dir")
    """With --reference: replay a few grasps of each kind of disagreement (the reference held
    the object and we did not, and the other way round) and write a picture of each, with
    examples.json, to this folder."""
    examples_per_kind: PositiveInt = 3
    """With --examples: how many grasps of each kind."""
    interval_draws: NonNegativeInt = 2000
    """With --reference: resamples of the files (drawn again with replacement) for the 95 %
    interval of each group's accuracy and balanced accuracy, which says how much a figure
    depends on which objects were labeled; 0: no intervals."""
    seed: NonNegativeInt = 0
    """With --reference: the seed of the intervals' resamples and of the examples' draw."""
    json: bool = setting(False, main=True)
    """Print the counts as JSON."""

    def _check(self) -> None:
        """Refuse flags that would be ignored: those of --reference without it (a plot,
        examples and intervals show agreement with a file's own labels), those of --examples
        without it (given at a value other than their default)."""
        defaults = {f.name: f.default for f in fields(self)}
        changed = {f.name for f in fields(self) if getattr(self, f.name) != defaults[f.name]}
        for name in ("plot", "examples", "interval_draws", "seed"):
            if name in changed and self.reference_file is None:
                flag = f"--{name.replace('_', '-')}"
                raise SimgraspError(f"{flag} needs --reference (a grasp file with its own labels)")
        if self.examples is None and "examples_per_kind" in changed:
            raise SimgraspError("--examples-per-kind needs --examples")


def run(options: Options) -> int:
    from simgrasp.grasping.labeling.label_compare import compare_labels, confusion_text

    if options.reference_file is not None:
        return _against_file(options)
    if options.other is None:
        raise SimgraspError("compare-labels needs OTHER (a second label directory) or --reference")
    comparison = compare_labels(options.reference, options.other)
    if options.json:
        print(json.dumps(comparison))
    else:
        names = [path.name or str(path) for path in (options.reference, options.other)]
        sys.stdout.write(confusion_text(comparison, *names) + "\n")
    return 0


def _against_file(options: Options) -> int:
    from simgrasp.grasping.labeling.grasp_files import expand_grasp_files
    from simgrasp.grasping.labeling.label_compare import check_reference_object
    from simgrasp.grasping.labeling.reference_compare import (
        compare_with_reference,
        comparison_text,
        plot_comparison,
    )

    assert options.reference_file is not None
    if options.other is not None:
        raise SimgraspError("give OTHER or --reference, not both")
    files = expand_grasp_files(options.reference_file)
    for file in files:
        check_reference_object(options.reference, file)
    comparison = compare_with_reference(
        options.reference, files, options.interval_draws, options.seed
    )
    if options.plot is not None:
        plot_comparison(comparison, options.reference, options.plot)
    if options.examples is not None:
        from simgrasp.grasping.labeling.disagreements import write_examples

        write_examples(
            options.reference, files, options.examples, options.examples_per_kind, options.seed
        )
    if options.json:
        print(json.dumps(comparison))
    else:
        sys.stdout.write(comparison_text(comparison) + "\n")
    return 0
