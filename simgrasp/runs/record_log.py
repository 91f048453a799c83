"""The append-only record log of a run: one JSON record per line (``trials.jsonl``,
``labels.jsonl``, ``detections.jsonl``).

Every finished record is appended as one line and flushed to the operating system before the
next, so a killed run (``kill -9`` included) loses at most the record that was being written;
a background thread then forces it to disk (``fsync``), so the run does not wait the
milliseconds a disk sync takes per record, and :meth:`RecordLog.close` waits for the last
sync (a machine crash may lose only the records of the sync in flight). When the log
is opened again, a last line without its newline is kept (the newline added) if it is a whole
record, and otherwise cut off as torn (the process died mid-write) with a message on stderr
saying what was cut; any other line that is not a record (as the log's ``key`` function judges
it) is an error naming the file and line, raised before the file is changed.
"""

from __future__ import annotations

import json
import os
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from simgrasp.errors import SimgraspError


class RecordLog:
    """A JSONL log of records (the file is created on the first append). ``key`` checks a
    record and returns its identity (a ValueError for a line that is no record), e.g. a sweep's
    ``(object, seed, settings)`` or a label's grasp index."""

    def __init__(self, path: Path, key: Callable[[Any], Any]) -> None:
        self.path = Path(path)
        self.key = key
        self._syncer: _Syncer | None = None

    def load(self) -> list[dict[str, Any]]:
        """All complete records, in file order. A torn last line is then cut off the file; a
        bad complete line raises before anything is changed."""
        if not self.path.exists():
            return []
        data = self.path.read_bytes()
        complete = data[: data.rfind(b"\n") + 1]
        lines = complete.split(b"\n")[:-1]
        records = [self._parse(line, n) for n, line in enumerate(lines, start=1) if line.strip()]
        last = data[len(complete) :]
        if last:
            records += self._end_last_line(last, len(lines) + 1, len(complete))
        return records

    def _end_last_line(self, last: bytes, number: int, start: int) -> list[dict[str, Any]]:
        """A last line without its newline: kept (newline added) if it is a whole record,
        else cut off with a message on stderr."""
        try:
            record = self._parse(last, number)
        except ValueError as exc:
            problem = str(exc).split(": ", 1)[1].split("; the log is corrupt")[0]
            sys.stderr.write(
                f"{self.path}:{number}: cut a torn last line ({len(last)} bytes, {problem}): "
                f"{last[:60].decode(errors='replace')!r}...; it runs again\n"
            )
            self._truncate(start)
            return []
        with self.path.open("ab") as handle:
            handle.write(b"\n")
            handle.flush()
            os.fsync(handle.fileno())
        return [record]

    def _parse(self, line: bytes, number: int) -> dict[str, Any]:
        """The record on line ``number``; a ValueError naming the file and line if the line
        is not one."""
        try:
            record = json.loads(line)
            self.key(record)
        except json.JSONDecodeError as exc:
            problem = f"not a JSON record ({exc.msg})"
        except ValueError as exc:  # not UTF-8, or not a record
            problem = str(exc)
        else:
            return record
        raise SimgraspError(
            f"{self.path}:{number}: {problem}; the log is corrupt beyond a torn last line"
        )

    def append(self, record: dict[str, Any]) -> None:
        """Append one record as a single line, hand it to the operating system and have the
        background thread force it to disk."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
        with self.path.open("a", encoding="utf-8") as handle:
            handle.write(line)
        if self._syncer is None:
            self._syncer = _Syncer(self.path)
        self._syncer.request()

    def close(self) -> None:
        """Wait until every appended record is on disk (the log can be appended to again)."""
        if self._syncer is not None:
            self._syncer.close()
            self._syncer = None

    def _truncate(self, size: int) -> None:
        """Cut the file to ``size`` bytes (a line torn by a kill) and force that to disk."""
        with self.path.open("rb+") as handle:
            handle.truncate(size)
            handle.flush()
            os.fsync(handle.fileno())


class _Syncer:
    """Forces one file to disk in a background thread whenever asked, without making the
    asker wait; :meth:`close` returns once every request made before it is synced."""

    def __init__(self, path: Path) -> None:
        self._fd = os.open(path, os.O_RDONLY)  # fsync of any descriptor syncs the file
        self._changed = threading.Condition()
        self._requested = self._synced = 0
        self._closing = False
        self._thread = threading.Thread(target=self._run, name="record-log-sync", daemon=True)
        self._thread.start()

    def request(self) -> None:
        with self._changed:
            self._requested += 1
            self._changed.notify_all()

    def _run(self) -> None:
        while True:
            with self._changed:
                self._changed.wait_for(lambda: self._requested > self._synced or self._closing)
                if self._requested == self._synced:
                    return
                target = self._requested
            os.fsync(self._fd)
            with self._changed:
                self._synced = target
                self._changed.notify_all()

    def close(self) -> None:
        with self._changed:
            self._closing = True
            self._changed.notify_all()
        self._thread.join()
        os.close(self._fd)
