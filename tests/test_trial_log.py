"""The trial log's line checks: whole records are validated, a complete last record
without its newline is kept, a torn one is cut with a message. The
records are real ones, from the committed sweep in docs/results/evaluate."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import pytest

from simgrasp.evaluation.report import write_report
from simgrasp.evaluation.trial_log import trial_log

COMMITTED = Path(__file__).parents[1] / "docs" / "results"
EVALUATE_LOG = COMMITTED / "evaluate" / "trials.jsonl.gz"
"""Committed runs keep their records gzipped."""


def real_lines(count: int) -> list[bytes]:
    """The first ``count`` lines of the committed 720-trial sweep, without newlines."""
    return gzip.decompress(EVALUATE_LOG.read_bytes()).split(b"\n")[:count]


@pytest.mark.parametrize(
    "committed", sorted(COMMITTED.glob("*/trials.jsonl.gz")), ids=lambda p: p.parent.name
)
def test_every_committed_log_passes_the_record_check(committed: Path, tmp_path: Path) -> None:
    log = tmp_path / "trials.jsonl"
    log.write_bytes(gzip.decompress(committed.read_bytes()))
    assert len(trial_log(log).load()) == len(log.read_bytes().splitlines())


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        (lambda r: {k: r[k] for k in ("object", "detector", "gripper", "noise", "seed")},
         "detection_accuracy"),
        (lambda r: {**r, "detection_accuracy": "high"}, "detection_accuracy"),
        (lambda r: {**r, "success": "yes"}, "success"),
        (lambda r: {**r, "timings_s": [1, 2]}, "timings_s"),
        (lambda r: {**r, "handles": 1.5}, "handles"),
        (lambda r: {**r, "seed": True}, "seed"),
    ],
    ids=["key-fields-only", "accuracy-text", "success-text", "timings-list", "handles-float",
         "seed-bool"],
)  # fmt: skip
def test_a_record_the_report_cannot_use_is_an_error_naming_file_line_and_field(
    tmp_path: Path, change, problem: str
) -> None:
    lines = real_lines(3)
    lines[1] = json.dumps(change(json.loads(lines[1]))).encode()
    log = tmp_path / "trials.jsonl"
    log.write_bytes(b"\n".join(lines) + b"\n")
    with pytest.raises(ValueError, match=rf"{log}:2: .*{problem}"):
        trial_log(log).load()


def test_the_report_runs_on_every_record_the_check_accepts(tmp_path: Path) -> None:
    """A record with a detection but no trial (no_grasp) and one with nulls where the report
    allows them pass the check, and the report is written from them."""
    lines = real_lines(2)
    record = json.loads(lines[1])
    record.update(detection_accuracy=None, handle_recall=None, success=None, failure=None)
    log = tmp_path / "trials.jsonl"
    log.write_bytes(lines[0] + b"\n" + json.dumps(record).encode() + b"\n")
    records = trial_log(log).load()
    assert len(records) == 2
    assert "Grasp sweep" in write_report(records, tmp_path, "Grasp sweep")


def test_a_complete_last_record_without_newline_is_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Another tool (or an editor) wrote the last record without its newline: it is a whole
    record, so it is kept and the newline added, not cut."""
    lines = real_lines(3)
    log = tmp_path / "trials.jsonl"
    log.write_bytes(b"\n".join(lines))
    records = trial_log(log).load()
    assert [r["seed"] for r in records] == [json.loads(line)["seed"] for line in lines]
    assert log.read_bytes() == b"\n".join(lines) + b"\n"
    trial_log(log).append(records[0])
    assert log.read_bytes().split(b"\n")[:3] == lines


def test_a_torn_last_line_is_cut_with_a_message_saying_what_and_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = real_lines(3)
    torn = lines[2][:100]
    log = tmp_path / "trials.jsonl"
    log.write_bytes(lines[0] + b"\n" + lines[1] + b"\n" + torn)
    assert len(trial_log(log).load()) == 2
    assert log.read_bytes() == lines[0] + b"\n" + lines[1] + b"\n"
    err = capsys.readouterr().err
    assert f"{log}:3" in err and "100 bytes" in err and "torn" in err
    assert torn[:40].decode() in err
