"""``simgrasp evaluate``: sweep objects x detectors x grippers x noise x seeds as full-chain
grasp trials; resumable log ``OUT/trials.jsonl``, then ``summary.csv``, ``report.md`` and plots.

Rerunning with the same ``--out`` skips the trials already in the log, so an interrupted sweep
resumes where it stopped; the report covers exactly the trials of the current command line.
Every other chain setting (``--views``, ``--placement``, ``--detector.quadric.*``,
``--trial.*``, ...) applies to all trials and is part of each trial's identity in the log.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from simgrasp.cli import invocation
from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource, float_range
from simgrasp.config import setting
from simgrasp.config.checks import PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.grasping.proposers import BUILTIN_PROPOSERS, proposer_names
from simgrasp.grasping.trials.chain_config import (
    PERCEPTIONS,
    ChainConfig,
    NoiseSigma,
    Perception,
)
from simgrasp.grippers.registry import gripper_names
from simgrasp.perception.sensors.registry import sensor_names

if TYPE_CHECKING:
    from simgrasp.evaluation.sweep import TrialSpec

SWEPT = ("detector.kind", "gripper", "noise", "sensor.kind", "perception")


EXAMPLES = (
    "simgrasp evaluate --objects generated --detector quadric,centroid --seeds 3 --out out/eval",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    objects: tuple[str, ...] = setting(("generated",), main=True)
    """Object names, mesh files (read with --scale/--units/--mass/...) and/or the sets
    generated, families, paper, ycb, all."""
    detector: tuple[str, ...] = setting(BUILTIN_PROPOSERS, choices=proposer_names, main=True)
    """Grasp proposers to sweep (:mod:`simgrasp.grasping.proposers`)."""
    gripper: tuple[str, ...] = setting(("builtin",), choices=gripper_names, main=True)
    """Grippers to sweep."""
    noise: tuple[NoiseSigma, ...] = setting((0.0,), parse=float_range, metavar="SIGMAS", main=True)
    """Multiplicative cloud-noise sigmas: START:STOP:STEP or a comma list."""
    sensor: tuple[str, ...] = setting(("ideal",), choices=sensor_names, main=True)
    """Depth sensors to sweep."""
    perception: tuple[Perception, ...] = setting(("auto",), choices=PERCEPTIONS)
    """Cuts of the target to sweep (auto, segment, mask; auto: segment in clutter, else mask)."""
    seeds: PositiveInt = setting(3, main=True)
    """Seeds 0..N-1 per setting."""
    workers: PositiveInt = setting(2, main=True)
    """Parallel worker processes (or Ray CPUs)."""
    out: Path
    """Output directory (trials.jsonl, summary.csv, report.md, plots)."""
    backend: Literal["local", "ray"] = "local"
    """Run trials in local worker processes or as Ray tasks."""
    address: str | None = None
    """Ray cluster to join with --backend ray, or auto for $RAY_ADDRESS / `ray start` (default:
    a new local instance with --workers CPUs)."""
    no_progress: bool = False
    """Hide the progress bar."""
    chain: ChainConfig = setting(default_factory=ChainConfig, flatten=True, exclude=SWEPT)

    def _check(self) -> None:
        if not self.objects:
            raise SimgraspError(
                "--objects is empty: give object names, mesh files or a set (generated, paper, "
                "ycb, all)"
            )
        if self.address and self.backend != "ray":
            self.refuse("address", "needs backend ray")


def run(options: Options) -> int:
    from simgrasp.assets.object_sets import expand_objects
    from simgrasp.evaluation.sweep import check_plan, plan_trials
    from simgrasp.runs.out_dir import claim_out_dir

    ycb_dir = options.ycb_dir or os.environ.get("SIMGRASP_YCB_DIR")
    axes = {
        "detector.kind": options.detector,
        "gripper": options.gripper,
        "noise": options.noise,
        "sensor.kind": options.sensor,
        "perception": options.perception,
    }
    objects = [options.object_name(name) for name in expand_objects(options.objects)]
    specs = plan_trials(objects, axes, range(options.seeds), options.chain)
    check_plan(specs, ycb_dir)
    with claim_out_dir(options.out, invocation()):  # checked and held before any trial runs
        return _run(options, specs, ycb_dir)


def _run(options: Options, specs: list[TrialSpec], ycb_dir: str | None) -> int:
    from simgrasp.evaluation.report import write_report
    from simgrasp.evaluation.sweep import run_sweep

    start = time.perf_counter()
    records = run_sweep(
        specs,
        options.out,
        ycb_dir=ycb_dir,
        workers=options.workers,
        backend=options.backend,
        address=options.address,
        progress=not options.no_progress,
    )
    upright = options.chain.scene.placement == "upright"
    report = write_report(
        records, options.out, "Grasp sweep" + (", objects placed upright" if upright else "")
    )
    print(report)
    print(
        f"{len(records)} trials in {time.perf_counter() - start:.0f} s; log, summary.csv, "
        f"report.md and plots in {options.out}"
    )
    return 0
