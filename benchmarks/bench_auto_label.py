"""Time of an automatic handle label (``simgrasp label-handles``, the label a mesh object gets
when it comes with none), by stage, single core.

Run: ``.venv/bin/python benchmarks/bench_auto_label.py [--objects strap_mug,spatula,hammer]
[--repeats 3]``. Threads are pinned to one before numpy is imported. Per generated object: the
median wall time of the scans (24 views), the detector over them, and the label made from
the detector's candidates with the default settings against the same step with the body-of-
revolution and cross-section steps off and boxes cut in slabs instead of k-means pieces (the
baseline, same run); their ratio says what those steps cost. The whole label is computed
once per mesh and kept in the cache.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_variable] = "1"

import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass, replace  # noqa: E402
from functools import partial  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from simgrasp.assets.generated import GENERATED_KINDS, generate_tool  # noqa: E402
from simgrasp.autolabel.auto_label import (  # noqa: E402
    AutoLabelConfig,
    label_from_candidates,
    pooled_candidates,
)
from simgrasp.autolabel.cross_section import CrossSectionConfig  # noqa: E402
from simgrasp.autolabel.revolution import RevolutionConfig  # noqa: E402
from simgrasp.autolabel.virtual_scan import scan_mesh  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.config.fields import setting  # noqa: E402


def median_seconds(run: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Median wall seconds of ``run()`` over ``repeats`` calls, and its last result."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), result


def time_object(kind: str, config: AutoLabelConfig, baseline: AutoLabelConfig, repeats: int) -> str:
    """One table row: the median seconds of each stage for generated object ``kind`` (seed 0)."""
    asset = generate_tool(kind, 0)
    scan_s, views = median_seconds(partial(scan_mesh, asset.mesh, config.scan), repeats)
    detect_s, candidates = median_seconds(partial(pooled_candidates, views, config), repeats)
    surface = np.concatenate([v.points for v in views])
    normals = np.concatenate([v.normals for v in views])
    label = partial(label_from_candidates, candidates, surface, asset.name)
    label_s, _ = median_seconds(partial(label, config, normals), repeats)
    base_s, _ = median_seconds(partial(label, baseline, normals), repeats)
    return (
        f"{asset.name:14s} {scan_s:6.2f} {detect_s:7.2f} {label_s:6.2f} {base_s:8.2f} "
        f"{label_s / base_s:6.2f}"
    )


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    objects: tuple[str, ...] = setting(("strap_mug", "spatula", "hammer"), choices=GENERATED_KINDS)
    """Generated object kinds to label (seed 0 each), one table row each."""
    repeats: PositiveInt = 3
    """Timed runs of each stage; the median is printed."""


def run(options: Options) -> None:
    """Print the table of stage times (see the module doc)."""
    config = AutoLabelConfig()
    baseline = replace(
        config,
        revolution=RevolutionConfig(margin=0.0),
        cross_section=CrossSectionConfig(min_ratio=0.0, grow_ratio=0.0),
        pieces="slabs",
    )
    print("one process (one core); median of", options.repeats, "runs, seconds")
    print(
        f"{'object':14s} {'scan':>6s} {'detect':>7s} {'label':>6s} {'baseline':>8s} {'ratio':>6s}"
    )
    for kind in options.objects:
        print(time_object(kind, config, baseline, options.repeats), flush=True)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
