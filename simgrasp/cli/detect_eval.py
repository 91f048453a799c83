"""``simgrasp detect-eval``: detection accuracy on object meshes over noise and seeds (the
paper's Tables I and II, Fig. 8).

The detectors run with their plain defaults, as ``simgrasp detect`` does; ``trial`` and
``evaluate`` add a fine pass to the quadric detector for fused depth-camera clouds (see
``simgrasp detect --help``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from simgrasp.cli.options import YcbSource, float_range
from simgrasp.config import setting
from simgrasp.config.checks import Positive, PositiveInt
from simgrasp.grasping.trials.chain_config import NoiseSigma
from simgrasp.handles.detector_config import DETECTORS, DetectorName


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    objects: tuple[str, ...] = ("paper",)
    """Object names and/or the sets paper, ycb, generated, all."""
    noise: tuple[NoiseSigma, ...] = setting((0.0,), parse=float_range, metavar="SIGMAS")
    """Multiplicative noise sigmas: START:STOP:STEP (e.g. 0:0.1:0.01) or a comma list."""
    seeds: PositiveInt = 10
    """Seeds 0..N-1 per object and sigma."""
    detector: tuple[DetectorName, ...] = DETECTORS
    """Detectors to compare."""
    gripper_width: Positive | None = setting(None, metavar="M")
    """Maximum gripper opening (m; default the detectors' 0.085)."""
    workers: PositiveInt = 1
    """Parallel worker processes."""
    out: Path = Path("out/detect-eval")
    """Output directory."""


def run(options: Options) -> int:
    from simgrasp.assets.object_sets import expand_objects
    from simgrasp.evaluation.detection_eval import (
        accuracy_tables,
        plot_accuracy_vs_noise,
        run_evaluation,
        write_csv,
    )

    start = time.perf_counter()
    records = run_evaluation(
        tuple(expand_objects(options.objects)),
        options.detector,
        options.noise,
        range(options.seeds),
        workers=options.workers,
        ycb_dir=options.ycb_dir,
        gripper_max_opening=options.gripper_width,
    )
    tables = accuracy_tables(records)
    print(tables)
    csv_path = write_csv(records, options.out / "detect_eval.csv")
    plot_path = plot_accuracy_vs_noise(records, options.out / "accuracy_vs_noise.png")
    (options.out / "detect_eval.md").write_text(tables + "\n")
    print(f"wrote {csv_path}, {plot_path} and {options.out / 'detect_eval.md'}")
    print(f"{len(records)} detections in {time.perf_counter() - start:.0f} s")
    return 0
