"""Rerun committed results: every ``simgrasp ... --out docs/results/NAME`` command written in
``docs/results/README.md`` (the one place each run's command lives), and the label renders.

    python scripts/regenerate_results.py              # list the runs
    python scripts/regenerate_results.py evaluate chain
    python scripts/regenerate_results.py labels       # out/labels: check the labels by eye

Committed runs keep their records gzipped (``trials.jsonl.gz``), so a rerun into the committed
folder runs every trial and writes ``trials.jsonl`` beside them; ``scripts/compare_records.py``
then compares the two. A rerun resumes an existing ``trials.jsonl`` (only missing trials run)
and is refused when the chain defaults changed since it was recorded (``defaults.json``).
"""

from __future__ import annotations

import re
import shlex
import sys
from pathlib import Path

from simgrasp.cli import main as simgrasp

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "docs" / "results" / "README.md"
EXTRA = {"labels": ["labels", "--objects", "all", "--out", "out/labels"]}
"""Runs whose output is not committed (renders of third-party meshes)."""


def documented_runs() -> dict[str, list[str]]:
    """Run name (its ``docs/results/`` folder) -> simgrasp arguments, from the README."""
    runs = {}
    for line in README.read_text(encoding="utf-8").splitlines():
        match = re.match(r"^\s{4}simgrasp (.*--out docs/results/([\w/-]+).*)$", line)
        if match:
            runs[match[2]] = shlex.split(match[1])
    return runs


def main(names: list[str]) -> int:
    runs = {**documented_runs(), **EXTRA}
    if not names:
        for name, argv in runs.items():
            print(f"{name:16} simgrasp {shlex.join(argv)}")
        return 0
    unknown = [n for n in names if n not in runs]
    if unknown:
        print(f"unknown run {unknown[0]!r}; runs: {', '.join(runs)}", file=sys.stderr)
        return 2
    for name in names:
        print(f"== {name}: simgrasp {shlex.join(runs[name])}", flush=True)
        if simgrasp(runs[name]) != 0:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
