"""``simgrasp demo``: the main job, a small full-chain grasp sweep on the embedded default.

The procedurally generated tools (and, with ``SIMGRASP_YCB_DIR`` set, the paper's eight YCB
objects), the quadric detector against the centroid baseline, the built-in gripper, a few seeds
at the noise-free and a noisy cloud: render -> detect -> plan -> execute in MuJoCo, then the
report (detection accuracy, lift and on-handle success, failure modes, timings, and what was
possible in each scene: the column of ``simgrasp bench``'s oracle) and ``view.html``, the report
page of ``simgrasp view`` that report.md links. Sized to finish
in about three minutes on two cores once the object decompositions are cached. Run again on its
folder after an interruption, it keeps the finished trials and runs the rest (as ``evaluate``);
a folder whose trials were recorded under other chain defaults (an older version's demo) starts
afresh, and one holding another command's run is refused. Other chain settings (``--views``,
``--trial.*``, ...) apply to every trial.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

from simgrasp.cli import invocation
from simgrasp.config import setting
from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig

DETECTORS = ("quadric", "centroid")
VIEW_PAGE = "view.html"
VIEW_LINK = (
    f"Every trial, its record and a 3D view of its grasp: [{VIEW_PAGE}]({VIEW_PAGE}) "
    "(one offline page; `simgrasp view OUT` serves it)."
)
"""The last paragraph of the demo's report.md: the link to its views."""
NOISE = (0.0, 0.02)
RUN_FILES = (
    "trials.jsonl",
    "defaults.json",
    "labels.jsonl",
    "run.json",
    "summary.json",
    "detections.jsonl",
    "real_detect.csv",
)
"""Records a run of demo, evaluate, label-grasps or detect-eval leaves in its output folder."""


EXAMPLES = ("simgrasp demo --seeds 1 --workers 2 --out out/demo",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    seeds: int | None = setting(None, main=True)
    """Seeds per setting (default 2, 1 with YCB)."""
    workers: int = setting(2, main=True)
    """Parallel worker processes."""
    out: Path = setting(Path("out/demo"), main=True)
    """Output directory."""
    chain: ChainConfig = setting(
        default_factory=ChainConfig, flatten=True, exclude=("detector.kind", "gripper", "noise")
    )


def run(options: Options) -> int:
    from simgrasp.assets.object_sets import GENERATED_OBJECTS, PAPER_OBJECTS
    from simgrasp.evaluation.report import write_report
    from simgrasp.evaluation.sweep import plan_trials, run_sweep
    from simgrasp.runs.out_dir import claim_out_dir

    ycb_dir = os.environ.get("SIMGRASP_YCB_DIR")
    objects = GENERATED_OBJECTS + (PAPER_OBJECTS if ycb_dir else ())
    seeds = options.seeds if options.seeds is not None else (1 if ycb_dir else 2)
    if seeds < 1 or options.workers < 1:
        raise SimgraspError(
            f"--seeds and --workers must be >= 1, got {seeds} and {options.workers}"
        )
    axes = {"detector.kind": DETECTORS, "gripper": ("builtin",), "noise": NOISE}
    specs = plan_trials(objects, axes, range(seeds), options.chain)
    start = time.perf_counter()
    with claim_out_dir(options.out, invocation(), partial(_refuse_other_runs, options.out)):
        _afresh_if_stale(options.out)
        records = run_sweep(specs, options.out, ycb_dir=ycb_dir, workers=options.workers)
    solvable = _oracle(objects, seeds, options)
    report = "\n\n".join(
        [
            write_report(records, options.out, title="simgrasp demo"),
            "\n".join(oracle_section(records, solvable)),
            VIEW_LINK,
        ]
    )
    (options.out / "report.md").write_text(report + "\n", encoding="utf-8")
    _write_view(options.out, ycb_dir)
    print(report)
    print(
        f"{len(records)} trials on {len(objects)} objects in "
        f"{time.perf_counter() - start:.0f} s; report in {options.out / 'report.md'}"
    )
    return 0


ORACLE_BUDGET_SAMPLES = 64
"""Grasps the oracle samples per demo scene (``simgrasp bench``'s small budget)."""


def _oracle(objects: tuple[str, ...], seeds: int, options: Options) -> dict[tuple[str, int], bool]:
    """(object, seed) -> whether a grasp sampled on the object's true mesh held it by its
    labeled handle in the demo's scene of that seed (:mod:`simgrasp.bench.oracle`, the same
    scene: stable placement, alone, the chain's views), cached and resumed as the bench's."""
    from simgrasp.bench.runner import oracle_records
    from simgrasp.bench.suites import OracleBudget, SceneBlock, SuiteDefinition
    from simgrasp.runs.engine import RunConfig

    block = SceneBlock(objects, ("stable",), (0,), ("ideal",), tuple(range(seeds)))
    suite = SuiteDefinition(
        "demo",
        "the demo's scenes",
        (block,),
        views=options.chain.scene.num_views,
        oracle=OracleBudget(
            samples=ORACLE_BUDGET_SAMPLES, handle_trials=6, lift_trials=3, rounds=6
        ),
    )
    records = oracle_records(suite, RunConfig(options.workers, progress=False))
    return {(r["object"], int(r["seed"])): bool(r["solvable"]) for r in records.values()}


def oracle_section(
    records: list[dict[str, Any]], solvable: dict[tuple[str, int], bool]
) -> list[str]:
    """The report's table of what was possible: per object, the scenes (seeds) the oracle held
    by the handle, beside each detector's trials held by the handle in those scenes and in
    all of them."""
    detectors = list(dict.fromkeys(r["detector"] for r in records))
    lines = [
        "## What was possible: the oracle",
        "",
        "Grasps sampled on each object's true mesh and executed in the same scene (`simgrasp "
        "bench`'s oracle): a scene is solvable when one of them held the object by its labeled "
        "handle. Each detector's column: trials held by the handle in the solvable scenes / "
        "trials there (all scenes in brackets).",
        "",
        "| object | solvable scenes | " + " | ".join(detectors) + " |",
        "|---|---|" + "---|" * len(detectors),
    ]
    for name in dict.fromkeys(r["object"] for r in records):
        seeds = sorted({int(r["seed"]) for r in records if r["object"] == name})
        solved = [s for s in seeds if solvable.get((name, s), False)]
        cells = []
        for detector in detectors:
            mine = [r for r in records if r["object"] == name and r["detector"] == detector]
            there = [r for r in mine if int(r["seed"]) in solved]
            held = sum(bool(r["on_handle"]) for r in there)
            cells.append(
                f"{held}/{len(there)} ({sum(bool(r['on_handle']) for r in mine)}/{len(mine)})"
            )
        lines.append(f"| {name} | {len(solved)}/{len(seeds)} | " + " | ".join(cells) + " |")
    return lines


def _refuse_other_runs(out: Path, last_command: str | None) -> None:
    """Refuse ``out`` when it holds the records of a run (:data:`RUN_FILES`) that no demo
    wrote: ``last_command``, the command that held it last (its lock file), is not demo. The
    demo starts afresh and would delete them. A folder whose lock names no command (an older
    version's, or none) is refused only where a record would be lost: a readable trial record
    or another command's files."""
    present = [name for name in RUN_FILES if (out / name).exists()]
    if not present or last_command == "demo":
        return
    trials_only = set(present) <= {"trials.jsonl", "defaults.json"}
    if last_command is None and trials_only and not _holds_a_record(out / "trials.jsonl"):
        return
    found = present[0]
    if not last_command:
        what = "another command's run"
    else:
        what = f"{'an' if last_command[0] in 'aeiou' else 'a'} {last_command} run"
    raise SimgraspError(f"{out} holds {what} ({found}); use another --out")


def _afresh_if_stale(out: Path) -> None:
    """Delete an earlier demo's log when it holds no trial record or its trials were recorded
    under other chain defaults (``check_defaults`` refuses them: an older version's demo), so
    the demo starts afresh where ``evaluate`` would refuse; trials under today's defaults are
    kept, and the sweep resumes them."""
    from simgrasp.evaluation.sweep import TRIALS_FILE
    from simgrasp.evaluation.trial_log import DEFAULTS_FILE, check_defaults

    stale = not _holds_a_record(out / TRIALS_FILE)
    if not stale:
        try:
            check_defaults(out)
        except SimgraspError:
            stale = True
    if stale:
        for name in (TRIALS_FILE, DEFAULTS_FILE):
            (out / name).unlink(missing_ok=True)


def _holds_a_record(trials: Path) -> bool:
    """Whether ``trials.jsonl`` exists and holds a JSON object on some line (a trial record)."""
    if not trials.is_file():
        return False
    for line in trials.read_text(encoding="utf-8", errors="replace").splitlines():
        try:
            if isinstance(json.loads(line), dict):
                return True
        except ValueError:
            continue
    return False


def _write_view(out: Path, ycb_dir: str | None) -> None:
    """The report page of ``out`` (``simgrasp view OUT --export OUT/view.html``)."""
    from simgrasp.viewer.report_page import report_page

    (out / VIEW_PAGE).write_text(report_page(out, ycb_dir), encoding="utf-8")
