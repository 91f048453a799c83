"""``simgrasp bench list|run|export|score``: the handle-grasping benchmark.

  simgrasp bench list
  simgrasp bench run SUITE --method quadric --out DIR       (a proposer or MODULE:FUNCTION)
  simgrasp bench export SUITE DIR                           (what a method outside sees)
  simgrasp bench score SUITE GRASPS --out DIR               (GRASPS/SCENE.json answers)

run and score write DIR/trials.jsonl (one record per scene; resumable), DIR/summary.json and
DIR/report.md, scored against the suite's oracle (cached in $SIMGRASP_CACHE_DIR/bench).
Formats and an example: docs/commands/bench.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from simgrasp.cli import invocation
from simgrasp.config import setting
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.errors import SimgraspError

Action = Literal["list", "run", "export", "score"]


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    action: Action = setting(positional=True, metavar="ACTION")
    """list the suites; run a method; export the scenes; score a folder of grasp files."""
    suite: str | None = setting(None, positional=True, metavar="SUITE")
    """The suite (see bench list)."""
    path: Path | None = setting(None, positional=True, metavar="DIR")
    """export: the folder to write; score: the folder of grasp files (SCENE.json)."""
    scenes: tuple[int, ...] = setting((), many=True, metavar="INDEX", main=True)
    """Only these scenes of the suite (their indices): a part, with its own digest."""
    method: str | None = setting(None, main=True)
    """run: quadric, tenpas, centroid, random (registered proposers), antipodal (random pairs
    until 8 grasps: best of N with --attempts N) or MODULE:FUNCTION."""
    attempts: PositiveInt = setting(1, main=True)
    """Grasps of each answer executed at most, best first, until one holds."""
    out: Path | None = setting(None, output="dir", main=True)
    """run, score: the output folder (trials.jsonl, summary.json, report.md)."""
    workers: PositiveInt = setting(1, main=True)
    """Parallel worker processes (or Ray CPUs)."""
    backend: Literal["local", "ray"] = "local"
    """Run scenes in local worker processes or as Ray tasks."""
    address: str | None = None
    """Ray cluster to join with --backend ray (auto: $RAY_ADDRESS)."""
    no_progress: bool = False
    """Hide the progress bar."""

    def _check(self) -> None:
        if self.action != "list" and self.suite is None:
            raise SimgraspError(f"bench {self.action} needs a SUITE (see simgrasp bench list)")
        if self.action in ("export", "score") and self.path is None:
            what = "folder to write" if self.action == "export" else "folder of grasp files"
            raise SimgraspError(f"bench {self.action} needs the {what} after SUITE")
        if self.action in ("run", "score") and self.out is None:
            raise SimgraspError(f"bench {self.action} needs --out DIR")
        if self.action == "run" and self.method is None:
            raise SimgraspError("bench run needs --method (a proposer or MODULE:FUNCTION)")
        if self.address and self.backend != "ray":
            self.refuse("address", "needs backend ray")


def run(options: Options) -> int:
    from simgrasp.bench.suites import SUITES, suite_by_name

    if options.action == "list":
        for name, suite in SUITES.items():
            print(f"{name:14} {len(suite.scenes()):4d} scenes  {suite.summary}")
        return 0
    suite = suite_by_name(options.suite or "")
    if options.scenes:
        suite = suite.part(options.scenes)
    if options.action == "export":
        return _export(options, suite)
    return _score(options, suite)


def _run_config(options: Options):  # noqa: ANN202 (RunConfig imported late)
    from simgrasp.runs.engine import RunConfig

    return RunConfig(
        workers=options.workers,
        backend=options.backend,
        address=options.address,
        progress=not options.no_progress,
    )


def _export(options: Options, suite) -> int:  # noqa: ANN001
    from simgrasp.bench.export import export_suite

    assert options.path is not None
    done = export_suite(suite, options.path, _run_config(options), invocation())
    print(f"{suite.name}: exported {len(done)} scenes now to {options.path}")
    return 0


def _score(options: Options, suite) -> int:  # noqa: ANN001
    from simgrasp.bench.runner import oracle_records, score_suite
    from simgrasp.bench.scene_task import AnswerSource
    from simgrasp.bench.summary import write_scores

    assert options.out is not None
    grasps = str(options.path) if options.action == "score" else None
    if grasps is not None and not Path(grasps).is_dir():
        raise SimgraspError(f"{grasps}: no such folder of grasp files")
    source = AnswerSource(options.method if grasps is None else None, grasps, options.attempts)
    run_config = _run_config(options)
    records = score_suite(suite, options.out, source, run_config, invocation())
    summary = write_scores(options.out, records, oracle_records(suite, run_config))
    solvable = summary["on_handle_of_solvable"]
    print(
        f"{suite.name} ({summary['scenes']} scenes), {summary['method']}: success "
        f"{summary['success']:.2f}, on handle {summary['on_handle']:.2f}, solvable "
        f"{summary['solvable']:.2f}, on handle of solvable "
        f"{'-' if solvable is None else f'{solvable:.2f}'}; report in {options.out}/report.md"
    )
    return 0
