"""Compare two runs' records field by field, wall-clock timings aside.

    python scripts/compare_records.py docs/results/evaluate out/evaluate
    python scripts/compare_records.py docs/results/grasp-sets/048_hammer/fast out/hammer-fast

Each file the first folder holds of ``trials.jsonl``, ``labels.jsonl``, ``labels.npz``,
``detect_eval.csv`` and ``summary.json`` (or its gzipped copy, ``NAME.gz``, as committed runs
keep their records) is compared with the same file of the second:
JSONL records matched by their identity (all fields but timings), CSV rows likewise, NPZ
arrays exactly. Timing fields (``timings_s``, ``t_*`` columns, wall-clock and rate keys) are
dropped first. Prints one line per file and exits 1 when any differs, so a refactor that
must keep records identical can be checked after rerunning the committed commands; a
difference names the fields only one side's records hold. ``--ignore`` leaves more fields out
(a field a newer run adds) and ``--digits`` rounds floats to that many significant digits
(last-bit differences of floating-point arithmetic)::

    python scripts/compare_records.py docs/results/evaluate-sensor out/evaluate-sensor \
        --ignore handle_source --digits 6
"""

from __future__ import annotations

import csv
import gzip
import io
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, NonNegativeInt
from simgrasp.config.fields import setting
from simgrasp.errors import SimgraspError

TIMING_KEYS = {
    "timings_s",
    "wall_s_this_run",
    "grasps_per_s",
    "trial_wall_s",
    "grasps_per_core_s",
    "labeled_this_run",
    "workers",
}
"""Record and summary keys that hold wall-clock time or depend on how a run was split up."""


@dataclass(frozen=True)
class Canon:
    """How records are made comparable: ``ignore`` fields dropped besides the timings, floats
    rounded to ``digits`` significant digits (0: compared exactly)."""

    ignore: frozenset[str] = frozenset()
    digits: int = 0

    def strip(self, record: dict[str, Any]) -> dict[str, Any]:
        dropped = TIMING_KEYS | self.ignore
        return {k: self.round(v) for k, v in record.items() if k not in dropped}

    def round(self, value: Any) -> Any:
        if isinstance(value, float) and self.digits and np.isfinite(value):
            return float(f"{value:.{self.digits}g}")
        if isinstance(value, list):
            return [self.round(v) for v in value]
        if isinstance(value, dict):
            return {k: self.round(v) for k, v in value.items()}
        return value


def _canonical(rows: list[dict[str, Any]]) -> list[str]:
    return sorted(json.dumps(row, sort_keys=True) for row in rows)


def _text(path: Path) -> str:
    """The text of ``path``, or of ``path.gz`` decompressed when only that exists."""
    if path.exists():
        return path.read_text(encoding="utf-8")
    return gzip.decompress(path.with_name(path.name + ".gz").read_bytes()).decode("utf-8")


def _exists(folder: Path, name: str) -> bool:
    return (folder / name).exists() or (folder / f"{name}.gz").exists()


def _jsonl(path: Path, canon: Canon) -> list[str]:
    lines = _text(path).splitlines()
    return _canonical([canon.strip(json.loads(line)) for line in lines if line.strip()])


def _csv(path: Path, canon: Canon) -> list[str]:
    rows = [
        {k: v for k, v in row.items() if not k.startswith("t_") and k not in canon.ignore}
        for row in csv.DictReader(io.StringIO(_text(path), newline=""))
    ]
    return _canonical(rows)


def _json(path: Path, canon: Canon) -> list[str]:
    return [json.dumps(canon.strip(json.loads(_text(path))), sort_keys=True)]


def _fields(records: list[str]) -> set[str]:
    return {key for line in records for key in json.loads(line)}


def _npz_differs(first: Path, second: Path) -> str | None:
    with np.load(first) as a, np.load(second) as b:
        if sorted(a.files) != sorted(b.files):
            return f"arrays {sorted(a.files)} against {sorted(b.files)}"
        for name in a.files:
            if not np.array_equal(a[name], b[name]):
                count = int(np.sum(a[name] != b[name])) if a[name].shape == b[name].shape else -1
                return f"array {name!r} differs ({count} entries)"
    return None


READERS = {"trials.jsonl": _jsonl, "labels.jsonl": _jsonl, "detect_eval.csv": _csv}
READERS["summary.json"] = _json


def compare(first: Path, second: Path, name: str, canon: Canon = Canon()) -> str | None:
    """None when ``first/name`` and ``second/name`` hold the same records, else why not
    (with the fields only one side's records hold)."""
    if not _exists(second, name):
        return f"{second / name} is missing"
    if name.endswith(".npz"):
        return _npz_differs(first / name, second / name)
    a, b = READERS[name](first / name, canon), READERS[name](second / name, canon)
    if a == b:
        return None
    only_a, only_b = len(set(a) - set(b)), len(set(b) - set(a))
    why = f"{len(a)} against {len(b)} records; {only_a} only in the first, {only_b} in the second"
    fields_a, fields_b = _fields(a), _fields(b)
    for side, extra in (("first", fields_a - fields_b), ("second", fields_b - fields_a)):
        if extra:
            why += f"; fields only in the {side}: {', '.join(sorted(extra))}"
    return why


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    first: Path = setting(positional=True, metavar="FIRST_DIR")
    """The run folder whose record files are compared."""
    second: Path = setting(positional=True, metavar="SECOND_DIR")
    """The run folder they are compared with."""
    ignore: tuple[str, ...] = ()
    """Record fields (JSON keys, CSV columns) left out besides the timings."""
    digits: NonNegativeInt = 0
    """Round floats to this many significant digits before comparing (0: exactly)."""


def run(options: Options) -> int:
    """One line per record file of ``first``; the exit status: 1 when any differs."""
    first, second = options.first, options.second
    names = [n for n in (*READERS, "labels.npz") if _exists(first, n)]
    if not names:
        raise SimgraspError(f"{first} holds no records to compare")
    failed = False
    for name in names:
        problem = compare(first, second, name, Canon(frozenset(options.ignore), options.digits))
        failed |= problem is not None
        print(f"{name}: {'identical' if problem is None else problem}")
    return 1 if failed else 0


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
