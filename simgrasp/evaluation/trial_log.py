"""The append-only trial log of a sweep: one JSON record per line in ``trials.jsonl``.

Every finished trial is appended as one line and flushed to disk (``flush`` + ``fsync``) before
the next, so a killed sweep loses at most the trial that was being written. When the log is
opened again, a last line without its newline is kept (the newline added) if it is a whole
trial record, and otherwise cut off as torn (the process died mid-write) with a message on
stderr saying what was cut; any other line that is not a trial record (a JSON object with every
field of :data:`RECORD_FIELDS` the report reads, of its type) is an error naming the file and
line, raised before the file is changed.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from simgrasp.config.tree import build, diff, flatten
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.scenes.views import VIEWS_BEFORE_RECORDED

TrialKey = tuple[str, int, str]
KEY_FIELDS = ("object", "seed")

_NUMBER = (int, float)
RECORD_FIELDS: dict[str, tuple[type, ...]] = {
    "object": (str,),
    "detector": (str,),
    "gripper": (str,),
    "noise": _NUMBER,
    "seed": (int,),
    "success": (bool, type(None)),
    "failure": (str, type(None)),
    "on_handle": (bool,),
    "detection_accuracy": (*_NUMBER, type(None)),
    "handle_recall": (bool, type(None)),
    "candidates": (int,),
    "handles": (int,),
    "timings_s": (dict,),
}
"""The fields the report reads from every record, with their JSON types (``bool`` is not taken
for a number)."""

NOISE_DIGITS = 9
"""Noise levels are compared after rounding to this many decimals."""

LEGACY_SETTINGS = {
    "detector": "detector.kind",
    "gripper": "gripper",
    "noise": "noise",
    "placement": "scene.placement",
    "views": "scene.num_views",
}
"""Top-level fields of records written before the ``settings`` field, and the settings they
name. Such a record without ``views`` was seen by two cameras, without ``placement`` placed
``"stable"``: then the only values."""


def trial_settings(config: ChainConfig) -> dict[str, Any]:
    """How ``config`` differs from the default chain config (dotted keys, plain values): with
    the object and seed, a sweep trial's identity. A new setting at its default changes no
    identity, so logs written before it existed still resume."""
    settings = diff(config, ChainConfig())
    if "noise" in settings:
        settings["noise"] = round(float(settings["noise"]), NOISE_DIGITS)
    return settings


DEFAULTS_FILE = "defaults.json"
"""The chain defaults (every setting, dotted keys) a sweep directory's ``settings`` fields are
relative to."""


def check_defaults(out_dir: Path) -> None:
    """Write ``out_dir/defaults.json``, or refuse a directory whose trials were recorded under
    other chain defaults: their identities (settings that differ from the defaults) would
    name other settings now, and a resume would mix them with new trials. Settings one of the
    two lacks (added or removed since) are not compared: a new setting starts at its default."""
    path = Path(out_dir) / DEFAULTS_FILE
    current = json.loads(json.dumps(flatten(ChainConfig())))
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(current, indent=1) + "\n", encoding="utf-8")
        return
    try:
        earlier = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise SimgraspError(f"{path} is not JSON ({error})") from error
    if not isinstance(earlier, dict):
        raise SimgraspError(f"{path} is not a table of chain settings")
    changed = [key for key in current if key in earlier and earlier[key] != current[key]]
    if changed:
        shown = ", ".join(f"{k}: {earlier[k]!r} -> {current[k]!r}" for k in changed[:3])
        more = f" and {len(changed) - 3} more" if len(changed) > 3 else ""
        raise SimgraspError(
            f"{out_dir} holds trials recorded under other chain defaults ({shown}{more}); "
            f"use another --out, or delete its trials.jsonl and {DEFAULTS_FILE} to rerun"
        )


def record_settings(record: dict[str, Any]) -> dict[str, Any]:
    """The settings a trial record was run with (see :func:`trial_settings`); records written
    before the ``settings`` field are read from their top-level fields."""
    if "settings" in record:
        given = record["settings"]
        if not isinstance(given, dict):
            raise SimgraspError(f"trial record with a bad settings field {given!r:.80}")
    else:
        given = {key: record[name] for name, key in LEGACY_SETTINGS.items() if name in record}
        given.setdefault("scene.num_views", VIEWS_BEFORE_RECORDED)
    return trial_settings(build(ChainConfig, given, source="trial record settings"))


def trial_key(record: Any) -> TrialKey:
    """The identity of a trial: (object, seed, its settings as canonical JSON)."""
    if not isinstance(record, dict):
        raise SimgraspError(f"a trial record is a JSON object, not {type(record).__name__}")
    missing = [name for name in KEY_FIELDS if name not in record]
    if missing:
        raise SimgraspError(f"trial record without {', '.join(missing)}: {record!r:.200}")
    seed = record["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise SimgraspError(f"trial record with a bad seed {seed!r}")
    settings = json.dumps(record_settings(record), sort_keys=True)
    return str(record["object"]), seed, settings


def check_record(record: Any) -> TrialKey:
    """The key of a whole trial record; a ValueError naming the missing fields of
    :data:`RECORD_FIELDS`, or the first mistyped one (or timing), otherwise."""
    key = trial_key(record)
    missing = [name for name in RECORD_FIELDS if name not in record]
    if missing:
        raise SimgraspError(f"trial record without {', '.join(missing)}, which the report needs")
    for name, types in RECORD_FIELDS.items():
        value = record[name]
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
            expected = " or ".join("null" if t is type(None) else t.__name__ for t in types)
            raise SimgraspError(f"trial record field {name!r} is {value!r:.60}, not {expected}")
    for stage, seconds in record["timings_s"].items():
        if isinstance(seconds, bool) or not isinstance(seconds, _NUMBER):
            raise SimgraspError(f"trial record timing {stage!r} is {seconds!r:.60}, not a number")
    return key


class TrialLog:
    """``trials.jsonl`` of one sweep directory (created on the first append). ``key`` checks
    a record and returns its identity (a ValueError for a line that is no record): a sweep's
    :func:`check_record` by default, e.g. the grasp index for ``label-grasps``."""

    def __init__(self, path: Path, key: Callable[[Any], Any] = check_record) -> None:
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
            problem = str(exc).split(": ", 1)[1].split("; the trial log")[0]
            sys.stderr.write(
                f"{self.path}:{number}: cut a torn last line ({len(last)} bytes, {problem}): "
                f"{last[:60].decode(errors='replace')!r}...; its trial runs again\n"
            )
            self._truncate(start)
            return []
        with self.path.open("ab") as handle:
            handle.write(b"\n")
            handle.flush()
            os.fsync(handle.fileno())
        return [record]

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
        raise SimgraspError(
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
