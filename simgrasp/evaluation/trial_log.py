"""The append-only trial log of a sweep: one JSON record per line in ``trials.jsonl``.

Every finished trial is appended as one line and flushed to disk (``flush`` + ``fsync``) before
the next, so a killed sweep loses at most the trial that was being written. A torn last line
(no trailing newline: the process died mid-write) is cut off when the log is opened again;
a malformed line anywhere else is an error naming the file and line.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

TrialKey = tuple[str, str, str, float, int]

NOISE_DIGITS = 9
"""Noise levels are compared after rounding to this many decimals."""


def trial_key(record: dict[str, Any]) -> TrialKey:
    """The identity of a trial: (object, detector, gripper, noise, seed)."""
    try:
        return (
            str(record["object"]),
            str(record["detector"]),
            str(record["gripper"]),
            round(float(record["noise"]), NOISE_DIGITS),
            int(record["seed"]),
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"trial record without a valid {exc} field: {record!r:.200}") from None


class TrialLog:
    """``trials.jsonl`` of one sweep directory (created on the first append)."""

    def __init__(self, path: Path) -> None:
        self.path = Path(path)

    def load(self) -> list[dict[str, Any]]:
        """All complete records, in file order, after cutting off a torn last line."""
        if not self.path.exists():
            return []
        self._drop_torn_tail()
        records = []
        with self.path.open(encoding="utf-8") as handle:
            for number, line in enumerate(handle, start=1):
                if not line.strip():
                    continue
                try:
                    records.append(json.loads(line))
                except json.JSONDecodeError as exc:
                    raise ValueError(
                        f"{self.path}:{number}: not a JSON record ({exc.msg}); the trial log is "
                        "corrupt beyond a torn last line"
                    ) from None
        return records

    def append(self, record: dict[str, Any]) -> None:
        """Append one record as a single line and force it to disk."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
        with self.path.open("a", encoding="utf-8") as handle:
            handle.write(line)
            handle.flush()
            os.fsync(handle.fileno())

    def _drop_torn_tail(self) -> None:
        """Truncate the file after its last newline (a line cut short by a kill)."""
        with self.path.open("rb+") as handle:
            data = handle.read()
            if not data or data.endswith(b"\n"):
                return
            handle.truncate(data.rfind(b"\n") + 1)
            handle.flush()
            os.fsync(handle.fileno())
