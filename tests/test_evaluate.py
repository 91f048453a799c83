"""`simgrasp evaluate` (the grasp sweep) and `simgrasp demo` end to end: real processes, real
MuJoCo trials, a local Ray instance; small sweeps on two generated tools (about 1 s a trial).

The module shares two sweeps: ``reference`` (8 trials, one process) and ``resumed`` (16 trials,
killed with SIGKILL part way and run again); keep its tests together under xdist.
"""

from __future__ import annotations

import contextlib
import csv
import itertools
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from simgrasp.assets.object_sets import GENERATED_OBJECTS
from simgrasp.cli import main
from simgrasp.evaluation.sweep import plan_trials
from simgrasp.evaluation.trial_log import DEFAULTS_FILE, trial_key
from simgrasp.scenes.render import select_backend
from simgrasp.scenes.views import CHAIN_VIEWS

pytestmark = pytest.mark.xdist_group("evaluate")

OBJECTS = ("gen_hammer", "gen_can")
DETECTORS = ("centroid", "quadric")
NOISES = (0.0, 0.02)
PLAN = ["--objects", ",".join(OBJECTS), "--detector", ",".join(DETECTORS), "--noise", "0,0.02"]
KEY_FIELDS = ("object", "detector", "gripper", "noise", "seed")
OUTCOME_FIELDS = (
    "success",
    "on_handle",
    "failure",
    "grasp",
    "object_pose",
    "lift_height",
    "candidates",
)
REPORT_FILES = (
    "summary.csv",
    "report.md",
    "accuracy_success_vs_noise.png",
    "success_per_object.png",
)
SUMMARY_COLUMNS = [
    "object",
    "detector",
    "gripper",
    "noise",
    "trials",
    "lift_success",
    "on_handle_success",
    "sim_unstable",
    "no_grasp",
    "detection_accuracy",
    "handle_recall",
    "median_trial_s",
]
TIMEOUT_S = 600
Record = dict[str, Any]
Key = tuple[Any, ...]


def evaluate_args(out: Path, seeds: int, *extra: str) -> list[str]:
    """``simgrasp evaluate`` arguments for the module's plan with ``seeds`` seeds."""
    return ["evaluate", *PLAN, "--seeds", str(seeds), "--out", str(out), "--no-progress", *extra]


def planned_keys(seeds: int) -> list[Key]:
    """The (object, detector, gripper, noise, seed) of every trial the plan lists."""
    return list(itertools.product(OBJECTS, DETECTORS, ["builtin"], NOISES, range(seeds)))


def run_simgrasp(
    args: list[str], env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    """``python -m simgrasp ARGS`` as a fresh process; fails the test on a non-zero exit."""
    done = subprocess.run(
        [sys.executable, "-m", "simgrasp", *args],
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        env=env,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return done


def read_log(out: Path) -> list[Record]:
    """The records of ``out/trials.jsonl``, in file order."""
    lines = (out / "trials.jsonl").read_text(encoding="utf-8").splitlines()
    return [json.loads(line) for line in lines]


def key_of(record: Record) -> Key:
    return tuple(record[field] for field in KEY_FIELDS)


def without_timings(records: list[Record]) -> dict[Key, Record]:
    """Each record by key, without its wall-clock timings (everything else is seeded)."""
    return {key_of(r): {k: v for k, v in r.items() if k != "timings_s"} for r in records}


def outcomes(records: list[Record]) -> dict[Key, tuple[Any, ...]]:
    """Each record's :data:`OUTCOME_FIELDS` by key."""
    return {key_of(r): tuple(r[field] for field in OUTCOME_FIELDS) for r in records}


def complete_lines(path: Path) -> list[bytes]:
    """The newline-terminated lines of ``path`` (none if it does not exist yet)."""
    data = path.read_bytes() if path.exists() else b""
    return data.split(b"\n")[:-1]


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The 1-seed plan run in this process (``--workers 1``); its output directory."""
    out = tmp_path_factory.mktemp("reference")
    assert main(evaluate_args(out, 1, "--workers", "1")) == 0
    return out


@dataclass(frozen=True)
class ResumedSweep:
    """The output directory of the resumed sweep and its complete log lines at the kill."""

    out: Path
    before_kill: list[bytes]


def kill_part_way(args: list[str], log: Path, min_lines: int, total: int) -> list[bytes]:
    """Start ``simgrasp ARGS`` in its own session, SIGKILL its whole process group (workers
    included) once ``log`` holds ``min_lines`` records; the complete lines at that moment."""
    with tempfile.TemporaryFile() as stderr:
        process = subprocess.Popen(
            [sys.executable, "-m", "simgrasp", *args],
            stdout=subprocess.DEVNULL,
            stderr=stderr,
            start_new_session=True,
        )
        try:
            deadline = time.monotonic() + TIMEOUT_S
            while len(complete_lines(log)) < min_lines:
                if process.poll() is not None:
                    stderr.seek(0)
                    pytest.fail(f"the sweep ended early:\n{stderr.read().decode()[-3000:]}")
                assert time.monotonic() < deadline, "the sweep recorded too few trials in time"
                time.sleep(0.05)
        finally:
            with contextlib.suppress(ProcessLookupError):  # gone already if it ended early
                os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    lines = complete_lines(log)
    assert min_lines <= len(lines) < total, "the kill came too late to test resuming"
    return lines


@pytest.fixture(scope="module")
def resumed(tmp_path_factory: pytest.TempPathFactory) -> ResumedSweep:
    """The 2-seed plan on 2 worker processes, killed after 3 trials, then run to completion."""
    out = tmp_path_factory.mktemp("resumed")
    args = evaluate_args(out, 2, "--workers", "2")
    before = kill_part_way(args, out / "trials.jsonl", 3, len(planned_keys(2)))
    run_simgrasp(args)
    return ResumedSweep(out, before)


def test_resume_after_sigkill_records_every_trial_once(
    resumed: ResumedSweep, reference: Path
) -> None:
    records = read_log(resumed.out)
    assert Counter(map(key_of, records)) == Counter(planned_keys(2))
    after = complete_lines(resumed.out / "trials.jsonl")
    assert after[: len(resumed.before_kill)] == resumed.before_kill
    for name in REPORT_FILES:
        assert (resumed.out / name).stat().st_size > 0, name
    # A resumed sweep records what an uninterrupted one does (the 1-seed trials).
    resumed_records = without_timings(records)
    for key, record in without_timings(read_log(reference)).items():
        assert resumed_records[key] == record, key


def test_rerunning_a_finished_sweep_runs_nothing(
    resumed: ResumedSweep, capsys: pytest.CaptureFixture[str]
) -> None:
    log = resumed.out / "trials.jsonl"
    before = log.read_bytes()
    (resumed.out / "report.md").unlink()
    assert main(evaluate_args(resumed.out, 2, "--workers", "2")) == 0
    assert log.read_bytes() == before
    assert "16 trials in" in capsys.readouterr().out
    assert (resumed.out / "report.md").exists()


def test_a_sweep_recorded_under_other_defaults_is_refused(
    resumed: ResumedSweep, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A trial's identity is its settings that differ from the chain defaults: after a
    default changed, resuming would mix trials of two configurations, so it is refused."""
    out = tmp_path / "sweep"
    shutil.copytree(resumed.out, out)
    defaults = json.loads((out / DEFAULTS_FILE).read_text())
    assert defaults["detector.kind"] == "quadric"
    log = (out / "trials.jsonl").read_bytes()
    defaults["detector.quadric.shell_thickness"] *= 2
    defaults["a.setting.removed.since"] = 1
    (out / DEFAULTS_FILE).write_text(json.dumps(defaults))
    capsys.readouterr()
    assert main(evaluate_args(out, 2)) == 2
    err = capsys.readouterr().err
    assert "other chain defaults (detector.quadric.shell_thickness:" in err, err
    assert "removed.since" not in err
    assert (out / "trials.jsonl").read_bytes() == log


def test_a_sweep_rendered_by_another_backend_is_refused(
    resumed: ResumedSweep, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Ray-cast and GL depth differ slightly, and so do the trials: a resume on a machine
    (or a worker) that renders otherwise would mix them."""
    out = tmp_path / "sweep"
    shutil.copytree(resumed.out, out)
    defaults = json.loads((out / DEFAULTS_FILE).read_text())
    assert defaults["render_backend"] == select_backend()
    defaults["render_backend"] = "raycast" if select_backend() != "raycast" else "egl"
    (out / DEFAULTS_FILE).write_text(json.dumps(defaults))
    capsys.readouterr()
    assert main(evaluate_args(out, 2)) == 2
    assert "other chain defaults (render_backend:" in capsys.readouterr().err


def test_torn_last_line_is_cut_off_and_the_trial_rerun(tmp_path: Path, reference: Path) -> None:
    lines = complete_lines(reference / "trials.jsonl")
    log = tmp_path / "trials.jsonl"
    log.write_bytes(b"\n".join(lines[:-1]) + b"\n" + lines[-1][: len(lines[-1]) // 2])
    assert main(evaluate_args(tmp_path, 1, "--workers", "1")) == 0
    after = complete_lines(log)
    assert after[:-1] == lines[:-1]
    assert Counter(map(key_of, read_log(tmp_path))) == Counter(planned_keys(1))
    rerun, original = json.loads(after[-1]), json.loads(lines[-1])
    assert without_timings([rerun]) == without_timings([original])


@pytest.mark.parametrize(
    "bad_line",
    ['{"object": "gen_hammer", "detec', "[1, 2, 3]", '{"object": "gen_hammer"}'],
    ids=["not-json", "not-an-object", "no-key-fields"],
)
def test_malformed_middle_line_is_an_error_naming_file_and_line(
    tmp_path: Path, reference: Path, bad_line: str, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = complete_lines(reference / "trials.jsonl")
    lines[2] = bad_line.encode()
    log = tmp_path / "trials.jsonl"
    log.write_bytes(b"\n".join(lines) + b'\n{"object": "gen_')  # and a torn last line
    before = log.read_bytes()
    assert main(evaluate_args(tmp_path, 1, "--workers", "1")) == 2
    assert f"{log}:3: " in capsys.readouterr().err
    assert log.read_bytes() == before, "a corrupt log must be left as it was"


def test_one_and_two_workers_give_the_same_records(tmp_path: Path, reference: Path) -> None:
    run_simgrasp(evaluate_args(tmp_path, 1, "--workers", "2"))
    two = read_log(tmp_path)
    assert Counter(map(key_of, two)) == Counter(planned_keys(1))
    assert without_timings(two) == without_timings(read_log(reference))


def test_ray_backend_gives_the_same_records_as_local(tmp_path: Path, reference: Path) -> None:
    """A local Ray instance with 2 CPUs. ``RAY_ADDRESS`` names no cluster: without
    ``--address`` the sweep must start its own instance rather than look for one."""
    env = {**os.environ, "RAY_ADDRESS": "127.0.0.1:9"}
    run_simgrasp(evaluate_args(tmp_path, 1, "--backend", "ray", "--workers", "2"), env=env)
    ray_records = read_log(tmp_path)
    assert Counter(map(key_of, ray_records)) == Counter(planned_keys(1))
    assert outcomes(ray_records) == outcomes(read_log(reference))
    for name in REPORT_FILES:
        assert (tmp_path / name).exists(), name


@pytest.mark.parametrize(
    ("address", "message"),
    [("127.0.0.1:9", "no Ray cluster answers there"), ("localhost", "expected HOST:PORT")],
)
def test_a_ray_cluster_that_is_not_there_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], address: str, message: str
) -> None:
    """An ``--address`` where nothing listens (Ray alone would retry it for minutes) or that
    is no address: one line naming it, before Ray starts."""
    args = evaluate_args(tmp_path, 1, "--backend", "ray", "--address", address)
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert f"--address {address}: {message}" in err and len(err.splitlines()) == 1


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (["--detector", "quadric,nope"], "'nope'"),
        (["--gripper", "builtin,nope"], "'nope'"),
        (["--objects", "gen_hammer,nope_object"], "'nope_object'"),
        (["--seeds", "0"], "seeds: 0 is not >= 1"),
        (["--address", "10.1.2.3:6379"], "10.1.2.3:6379"),
        (["--noise", "0,1.5"], "1.5"),
    ],
    ids=["detector", "gripper", "object", "seeds", "address", "noise"],
)
def test_bad_arguments_exit_2_naming_the_value(
    tmp_path: Path, change: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    assert main([*evaluate_args(out, 1), *change]) == 2
    err = capsys.readouterr().err
    assert err.startswith("simgrasp evaluate: error: ") and message in err, err
    assert not out.exists(), "nothing may run before the plan is checked"


def test_summary_has_one_row_per_setting(resumed: ResumedSweep) -> None:
    with (resumed.out / "summary.csv").open(newline="", encoding="utf-8") as handle:
        reader = csv.DictReader(handle)
        assert reader.fieldnames == SUMMARY_COLUMNS
        rows = list(reader)
    settings = [(r["object"], r["detector"], r["gripper"], float(r["noise"])) for r in rows]
    assert sorted(settings) == sorted(itertools.product(OBJECTS, DETECTORS, ["builtin"], NOISES))
    records = read_log(resumed.out)
    for row, setting in zip(rows, settings, strict=True):
        group = [r for r in records if key_of(r)[:4] == setting]
        assert int(row["trials"]) == len(group) == 2
        lifted = sum(r["success"] is True for r in group) / len(group)
        assert float(row["lift_success"]) == pytest.approx(lifted, abs=1e-4)
        held = sum(r["success"] is True and r["on_handle"] for r in group) / len(group)
        assert float(row["on_handle_success"]) == pytest.approx(held, abs=1e-4)
        has_accuracy = row["detector"] == "quadric"
        assert (row["detection_accuracy"] != "") == has_accuracy, row


def test_report_has_the_paper_tables_and_the_success_table(resumed: ResumedSweep) -> None:
    report = (resumed.out / "report.md").read_text(encoding="utf-8")
    assert report.startswith("# Grasp sweep\n\n16 trials: 2 objects")
    for heading in (
        "### quadric: Table I form (σ = 0,",
        "### quadric: Table II form",
        "| σ | gen_hammer | gen_can | mean |",
        "## Grasp success",
        "| object | centroid / builtin | quadric / builtin |",
        "| **all** |",
        "## Failure modes",
        "## Timings",
    ):
        assert heading in report, heading
    assert "### centroid" not in report, "the centroid baseline has no detection accuracy"


@pytest.mark.slow
def test_demo_prints_the_report_and_writes_it(tmp_path: Path) -> None:
    """The README's main job without YCB: the generated tools x 2 detectors x 2 noise levels,
    starting afresh even over an unreadable old log."""
    out = tmp_path / "demo"
    out.mkdir()
    (out / "trials.jsonl").write_text("left over from an older demo\n", encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if k != "SIMGRASP_YCB_DIR"}
    done = run_simgrasp(["demo", "--seeds", "1", "--out", str(out)], env=env)
    objects = len(GENERATED_OBJECTS)
    trials = objects * 2 * 2
    assert done.stdout.startswith(f"# simgrasp demo\n\n{trials} trials: {objects} objects")
    assert "## Grasp success" in done.stdout
    assert f"{trials} trials on {objects} objects in " in done.stdout
    report = (out / "report.md").read_text(encoding="utf-8")
    assert report in done.stdout
    assert len(read_log(out)) == trials
    for name in REPORT_FILES:
        assert (out / name).exists(), name
    assert "[view.html](view.html)" in report  # the report links its views
    assert "## What was possible: the oracle" in report  # every object has its oracle row
    assert all(f"| {name} | " in report.split("the oracle")[1] for name in GENERATED_OBJECTS)
    page = (out / "view.html").read_text(encoding="utf-8")
    assert page.count('<tr class="trial"') == trials and page.count("<figure><img") == 2


def test_demo_run_again_keeps_its_finished_trials(tmp_path: Path) -> None:
    """A demo run again on its folder (after an interruption, or finished) reruns none of its
    finished trials: the log is left byte for byte; one recorded under other chain defaults
    (an older version's) starts afresh."""
    out = tmp_path / "demo"
    env = {k: v for k, v in os.environ.items() if k != "SIMGRASP_YCB_DIR"}
    args = ["demo", "--seeds", "1", "--workers", "1", "--out", str(out)]
    run_simgrasp(args, env=env)
    log = (out / "trials.jsonl").read_bytes()
    again = run_simgrasp(args, env=env)
    assert (out / "trials.jsonl").read_bytes() == log
    assert f"{len(GENERATED_OBJECTS) * 4} trials" in again.stdout
    defaults = json.loads((out / "defaults.json").read_text())
    defaults["scene.num_views"] = defaults["scene.num_views"] + 1  # an older version's
    (out / "defaults.json").write_text(json.dumps(defaults))
    run_simgrasp(args, env=env)
    assert (out / "trials.jsonl").read_bytes() != log and len(read_log(out)) == len(
        log.splitlines()
    )


def test_placement_is_part_of_a_trials_identity(reference: Path) -> None:
    assert {r["placement"] for r in read_log(reference)} == {"stable"}
    stable = plan_trials(["gen_mug"], {}, range(2))
    upright = plan_trials(["gen_mug"], {"scene.placement": ["upright"]}, range(2))
    assert not {s.key for s in stable} & {s.key for s in upright}
    # Logs written before placements existed hold stable-placement trials.
    old = {
        k: v for k, v in stable[0].summary_fields().items() if k not in ("placement", "settings")
    }
    assert trial_key(old) == stable[0].key


def test_camera_views_are_part_of_a_trials_identity(reference: Path) -> None:
    assert {r["views"] for r in read_log(reference)} == {CHAIN_VIEWS}
    four = plan_trials(["gen_mug"], {}, range(2))
    two = plan_trials(["gen_mug"], {"scene.num_views": [2]}, range(2))
    assert not {s.key for s in four} & {s.key for s in two}
    # Logs written before views were recorded hold two-camera trials.
    old = {k: v for k, v in two[0].summary_fields().items() if k not in ("views", "settings")}
    assert trial_key(old) == two[0].key


def test_the_oracle_column_counts_handle_holds_in_the_solvable_scenes() -> None:
    from simgrasp.cli.demo import oracle_section

    records = [
        {"object": "gen_mug", "detector": "quadric", "seed": seed, "on_handle": held}
        for seed, held in ((0, True), (0, False), (1, True))
    ]
    lines = oracle_section(records, {("gen_mug", 0): True, ("gen_mug", 1): False})
    assert lines[-1] == "| gen_mug | 1/2 | 1/2 (2/3) |"
