"""The append-only trial log of a sweep: one JSON record per line in ``trials.jsonl``.

Every finished trial is appended as one line and flushed to disk (``flush`` + ``fsync``) before
the next, so a killed sweep loses at most the trial that was being written. A torn last line
(no trailing newline: the process died mid-write) is cut off when the log is opened again;
any other line that is not a trial record (a JSON object with the :data:`KEY_FIELDS`) is an
error naming the file and line, raised before the file is changed.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from simgrasp.assets.placement import DEFAULT_PLACEMENT
from simgrasp.scenes.views import VIEWS_BEFORE_RECORDED

TrialKey = tuple[str, str, str, float, int, str, int]
KEY_FIELDS = ("object", "detector", "gripper", "noise", "seed")

NOISE_DIGITS = 9
"""Noise levels are compared after rounding to this many decimals."""


def trial_key(record: Any) -> TrialKey:
    """The identity of a trial: (object, detector, gripper, noise, seed, placement, views).
    Records written before placements or views were recorded read as placed ``"stable"`` and
    seen by two cameras, as they were."""
    if not isinstance(record, dict):
        raise ValueError(f"a trial record is a JSON object, not {type(record).__name__}")
    missing = [name for name in KEY_FIELDS if name not in record]
    if missing:
        raise ValueError(f"trial record without {', '.join(missing)}: {record!r:.200}")
    try:
        return (
            str(record["object"]),
            str(record["detector"]),
            str(record["gripper"]),
            round(float(record["noise"]), NOISE_DIGITS),
            int(record["seed"]),
            str(record.get("placement", DEFAULT_PLACEMENT)),
            int(record.get("views", VIEWS_BEFORE_RECORDED)),
        )
    except (TypeError, ValueError):
        raise ValueError(
            f"trial record with a bad noise {record['noise']!r} or seed {record['seed']!r}"
        ) from None


class TrialLog:
    """``trials.jsonl`` of one sweep directory (created on the first append). ``key`` checks
    a record and returns its identity (a ValueError for a line that is no record): a sweep's
    :func:`trial_key` by default, e.g. the grasp index for ``label-grasps``."""

    def __init__(self, path: Path, key: Callable[[Any], Any] = trial_key) -> None:
        self.path = Path(path)
        self.key = key

    def load(self) -> list[dict[str, Any]]:
        """All complete records, in file order. A torn last line is then cut off the file; a
        bad complete line raises before anything is changed."""
        if not self.path.exists():
            return []
        data = self.path.read_bytes()
        complete = data[: data.rfind(b"\n") + 1]
        lines = complete.split(b"\n")[:-1]
        records = [self._parse(line, n) for n, line in enumerate(lines, start=1) if line.strip()]
        if len(complete) < len(data):
            self._truncate(len(complete))
        return records

    def _parse(self, line: bytes, number: int) -> dict[str, Any]:
        """The trial record on line ``number``; a ValueError naming the file and line if the
        line is not one."""
        try:
            record = json.loads(line)
            self.key(record)
        except json.JSONDecodeError as exc:
            problem = f"not a JSON record ({exc.msg})"
        except ValueError as exc:  # not UTF-8, or not a trial record
            problem = str(exc)
        else:
            return record
        raise ValueError(
            f"{self.path}:{number}: {problem}; the trial log is corrupt beyond a torn last line"
        )

    def append(self, record: dict[str, Any]) -> None:
        """Append one record as a single line and force it to disk."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
        with self.path.open("a", encoding="utf-8") as handle:
            handle.write(line)
            handle.flush()
            os.fsync(handle.fileno())

    def _truncate(self, size: int) -> None:
        """Cut the file to ``size`` bytes (a line torn by a kill) and force that to disk."""
        with self.path.open("rb+") as handle:
            handle.truncate(size)
            handle.flush()
            os.fsync(handle.fileno())
