"""The ``acronym-fast`` protocol against ``acronym`` and FleX on ACRONYM's own grasps.

    python scripts/acronym_fast.py --data $SIMGRASP_ACRONYM_DIR/affordance/grasps \
        --full out/acronym/affordance --fast out/acronym-fast/affordance \
        --out docs/results/acronym-fast

``--full`` and ``--fast`` are ``label-grasps`` data-set runs of the same grasp files (the
commands in ``docs/results/README.md``). Per half of ``docs/results/acronym/halves.json``
(tune, held-out) and category: the agreement of the two protocols' verdicts
(:func:`simgrasp.grasping.labeling.label_compare.compare_labels`, grasps both scored), each
protocol's agreement with FleX (:func:`simgrasp.grasping.labeling.reference_compare
.compare_with_reference`) and its speed (executed grasps over the trials' wall time, one
worker: grasps/s per core). Writes ``comparison.json`` and ``comparison.md`` (no grasp poses,
no mesh data).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.grasping.labeling.label_compare import compare_labels
from simgrasp.grasping.labeling.reference_compare import compare_with_reference

HALVES = Path(__file__).resolve().parents[1] / "docs" / "results" / "acronym" / "halves.json"
PAIR_KEYS = ("scored", "held_held", "held_failed", "failed_held", "failed_failed")


def _speed(run: Path, names: list[str]) -> float:
    """Grasps per second per core of ``run``'s files ``names`` (``summary.json``)."""
    files = {f["file"]: f for f in json.loads((run / "summary.json").read_text())["files"]}
    grasps = sum(files[n]["grasps"] for n in names)
    return grasps / sum(files[n]["trial_wall_s"] for n in names)


def _pair(full: Path, fast: Path, names: list[str]) -> dict[str, Any]:
    """Pooled confusion counts of the two protocols' verdicts over the files ``names``."""
    pooled = dict.fromkeys(PAIR_KEYS, 0)
    for name in names:
        counts = compare_labels(full / Path(name).stem, fast / Path(name).stem)
        for key in PAIR_KEYS:
            pooled[key] += counts[key]
    same = pooled["held_held"] + pooled["failed_failed"]
    return {**pooled, "agreement": same / pooled["scored"]}


def _group(data: Path, full: Path, fast: Path, names: list[str]) -> dict[str, Any]:
    """Both protocols on the grasp files ``names``: pair agreement, FleX agreement, speed."""
    files = [data / n for n in names]
    row: dict[str, Any] = {"files": len(names), "pair": _pair(full, fast, names)}
    for key, run in (("acronym", full), ("acronym-fast", fast)):
        flex = compare_with_reference(run, files)["groups"]["overall"]
        row[key] = {
            "flex_accuracy": flex["accuracy"],
            "flex_balanced": flex["balanced_accuracy"],
            "flex_auroc": flex["auroc"],
            "grasps_per_core_s": _speed(run, names),
        }
    return row


def compare(data: Path, full: Path, fast: Path) -> dict[str, dict[str, Any]]:
    """Per half (``tune``, ``held_out``) and category (file name before ``_``), and all."""
    halves = json.loads(HALVES.read_text())
    groups: dict[str, list[str]] = {}
    for half in ("tune", "held_out"):
        for name in halves[f"{half}/files"]:
            for key in (f"{half}/{name.split('_', 1)[0]}", f"{half}/all", "all"):
                groups.setdefault(key, []).append(name)
    return {key: _group(data, full, fast, names) for key, names in sorted(groups.items())}


def table(rows: dict[str, dict[str, Any]]) -> str:
    """The comparison as a markdown table."""
    lines = [
        "| set | files | scored by both | verdicts the same | acronym: FleX acc / bal / AUROC "
        "| acronym-fast: FleX acc / bal / AUROC | grasps/s per core, acronym -> fast |",
        "|---|---|---|---|---|---|---|",
    ]
    for key, row in rows.items():
        full, fast, pair = row["acronym"], row["acronym-fast"], row["pair"]
        lines.append(
            f"| {key} | {row['files']} | {pair['scored']} | {pair['agreement']:.3f} "
            f"| {_flex(full)} | {_flex(fast)} "
            f"| {full['grasps_per_core_s']:.1f} -> {fast['grasps_per_core_s']:.1f} |"
        )
    return "\n".join(lines) + "\n"


def _flex(row: dict[str, Any]) -> str:
    auroc = "-" if row["flex_auroc"] is None else f"{row['flex_auroc']:.3f}"
    return f"{row['flex_accuracy']:.3f} / {row['flex_balanced']:.3f} / {auroc}"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    data: Path
    """Folder of the ACRONYM grasp files."""
    full: Path
    """The label-grasps run of those files with --protocol acronym."""
    fast: Path
    """The same with --protocol acronym-fast."""
    out: Path
    """Folder of comparison.json and comparison.md."""


def run(options: Options) -> None:
    """Compare the two runs per half and category; print the table."""
    rows = compare(options.data, options.full, options.fast)
    options.out.mkdir(parents=True, exist_ok=True)
    (options.out / "comparison.json").write_text(json.dumps(rows, indent=2) + "\n")
    (options.out / "comparison.md").write_text(table(rows))
    print(table(rows), end="")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
