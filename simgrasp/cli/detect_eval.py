"""``simgrasp detect-eval``: detection accuracy on object meshes over noise and seeds (the
paper's Tables I and II, Fig. 8), resumable: rerunning with the same ``--out`` runs only the
detections not yet in ``OUT/detections.jsonl``; ``--real MANIFEST``: on the real clouds of a
manifest (:mod:`simgrasp.evaluation.real_detect`).

The detectors run with their plain defaults, as ``simgrasp detect`` does; ``trial`` and
``evaluate`` add a fine pass to the quadric detector for fused depth-camera clouds (see
``simgrasp detect --help``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from simgrasp.cli import invocation
from simgrasp.cli.options import YcbSource, float_range
from simgrasp.config import setting
from simgrasp.config.checks import Positive, PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import NoiseSigma
from simgrasp.handles.detector_config import DETECTORS, DetectorName
from simgrasp.handles.presets import preset_names

if TYPE_CHECKING:
    from simgrasp.evaluation.detection_run import DetectionItem
    from simgrasp.runs.engine import RunConfig


MESH_ONLY = ("objects", "noise", "detector", "gripper_width", "workers", "backend", "address")
"""Settings of the evaluation on object meshes that ``--real`` has no use for (it runs in
this process: a manifest's clouds take seconds each)."""
REAL_ONLY = ("real_configs", "real_dir")
"""Settings of ``--real`` only."""


EXAMPLES = ("simgrasp detect-eval --objects paper --noise 0:0.1:0.01 --seeds 10 --workers 2",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    objects: tuple[str, ...] = setting(("paper",), main=True)
    """Object names and/or the sets paper, ycb, generated, all."""
    noise: tuple[NoiseSigma, ...] = setting((0.0,), parse=float_range, metavar="SIGMAS", main=True)
    """Multiplicative noise sigmas: START:STOP:STEP (e.g. 0:0.1:0.01) or a comma list."""
    seeds: PositiveInt = setting(10, main=True)
    """Seeds 0..N-1 per object and sigma."""
    detector: tuple[DetectorName, ...] = setting(DETECTORS, main=True)
    """Detectors to compare."""
    gripper_width: Positive | None = setting(None, metavar="M")
    """Maximum gripper opening (m; default the detectors' 0.085)."""
    workers: PositiveInt = setting(1, main=True)
    """Parallel worker processes (or Ray CPUs)."""
    backend: Literal["local", "ray"] = "local"
    """Run detections in local worker processes or as Ray tasks."""
    address: str | None = None
    """Ray cluster to join with --backend ray (auto or HOST:PORT)."""
    no_progress: bool = False
    """Hide the progress bar."""
    out: Path = setting(Path("out/detect-eval"), main=True)
    """Output directory (detections.jsonl, resumed by the same command; run.json, the CSV,
    tables and plot)."""
    real: Path | None = setting(None, metavar="MANIFEST")
    """Score the real clouds of this manifest instead (TOML, see
    simgrasp/evaluation/real_manifest.py; the shipped one: models/handles/real_detect.toml)."""
    real_configs: tuple[str, ...] = setting(("default",), choices=preset_names, metavar="PRESET")
    """With --real: the detector presets to compare (simgrasp.handles.presets, each with what
    it is for and its results page; default: what `simgrasp detect` runs)."""
    real_dir: Path | None = None
    """With --real: folder the manifest's cloud paths are relative to (default:
    $SIMGRASP_REAL_DIR, else ../shared/real)."""

    def _check(self) -> None:
        """Refuse flags the chosen evaluation would ignore (given at a value other than their
        default: one at its default cannot be told from one not given)."""
        changed = [
            "--" + f.name.replace("_", "-")
            for f in fields(self)
            if f.name in (REAL_ONLY if self.real is None else MESH_ONLY)
            and getattr(self, f.name) != f.default
        ]
        if self.real is None and changed:
            raise SimgraspError(f"{changed[0]} needs --real (it applies to the manifest's clouds)")
        if changed:
            raise SimgraspError(
                f"{changed[0]} and --real conflict: --real scores the manifest's clouds with "
                "--real-configs"
            )
        if not self.objects:
            raise SimgraspError(
                "--objects is empty: give object names or a set (paper, ycb, generated, all)"
            )


def run(options: Options) -> int:
    from simgrasp.assets.object_sets import expand_objects
    from simgrasp.evaluation.detection_run import plan_detections
    from simgrasp.runs.engine import RunConfig
    from simgrasp.runs.out_dir import claim_out_dir

    if options.real is not None:
        with claim_out_dir(options.out, invocation()):  # one run at a time per --out
            return _run_real(options, options.real)
    run = RunConfig(options.workers, options.backend, options.address, not options.no_progress)
    objects = tuple(expand_objects(options.objects))
    items = plan_detections(
        objects, options.detector, options.noise, range(options.seeds), options.ycb_dir
    )
    with claim_out_dir(options.out, invocation()):  # one run at a time per --out
        return _run(options, items, run)


def _run(options: Options, items: list[DetectionItem], run: RunConfig) -> int:
    from simgrasp.evaluation.detection_eval import (
        accuracy_tables,
        plot_accuracy_vs_noise,
        write_csv,
    )
    from simgrasp.evaluation.detection_run import run_evaluation

    start = time.perf_counter()
    records = run_evaluation(
        items,
        options.out,
        run=run,
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


def _run_real(options: Options, manifest: Path) -> int:
    """``--real``: every cloud of ``manifest`` x named setting x seed (rows already in the
    output's CSV are kept, not redone, when the manifest, real data folder and clouds are the
    ones recorded in its ``real_run.json`` and each setting's values the ones recorded in its
    ``real_settings.json``; otherwise refused)."""
    from simgrasp.assets.real import default_real_dir
    from simgrasp.evaluation.real_detect import run_identity, run_real_detect, tables
    from simgrasp.evaluation.real_manifest import read_manifest, shipped_if_absent

    start = time.perf_counter()
    manifest = shipped_if_absent(manifest)
    real_dir = options.real_dir if options.real_dir is not None else default_real_dir()
    clouds = read_manifest(manifest, real_dir)
    identity = run_identity(manifest, real_dir, clouds)
    csv_path = options.out / "real_detect.csv"
    seeds = range(options.seeds)
    rows = run_real_detect(clouds, options.real_configs, seeds, csv_path, identity)
    text = tables(rows)
    print(text)
    (options.out / "real_detect.md").write_text(text + "\n")
    print(f"wrote {csv_path} and {options.out / 'real_detect.md'}")
    print(f"{len(rows)} detections in {time.perf_counter() - start:.0f} s")
    return 0
