"""A bench run's scores: ``summary.json`` and ``report.md``, against what was possible.

Each scene's record is joined with the oracle's record of its world
(:mod:`simgrasp.bench.oracle`): ``solvable`` (some handle grasp held there), ``liftable``
(some grasp held there). The scores are shares of the scenes: ``success`` (the object lifted
and held), ``on_handle`` (held by its handle), ``solvable``, and ``on_handle_of_solvable``
(held by the handle among the solvable scenes: the method's score against what was
possible; None without a solvable scene). ``counts.beyond_oracle`` counts the scenes held by
the handle where the oracle found no handle grasp: the oracle samples, so it is a lower
bound of what was possible. ``report.md`` shows them per object, placement,
clutter and sensor, with the failures named in the records.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

AXES = ("object", "placement", "clutter", "sensor")


def _share(count: int, total: int) -> float | None:
    return round(count / total, 4) if total else None


def scores(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """The scores of ``rows`` (records with the oracle's ``solvable`` and ``liftable``)."""
    solvable = [r for r in rows if r["solvable"]]
    counts = {
        "success": sum(bool(r["success"]) for r in rows),
        "on_handle": sum(bool(r["on_handle"]) for r in rows),
        "solvable": len(solvable),
        "liftable": sum(bool(r["liftable"]) for r in rows),
        "on_handle_in_solvable": sum(bool(r["on_handle"]) for r in solvable),
        "beyond_oracle": sum(bool(r["on_handle"]) and not r["solvable"] for r in rows),
    }
    return {
        "scenes": len(rows),
        "success": _share(counts["success"], len(rows)),
        "on_handle": _share(counts["on_handle"], len(rows)),
        "solvable": _share(counts["solvable"], len(rows)),
        "liftable": _share(counts["liftable"], len(rows)),
        "on_handle_of_solvable": _share(counts["on_handle_in_solvable"], len(solvable)),
        "counts": counts,
    }


def joined(
    records: list[dict[str, Any]], oracle: dict[str, dict[str, Any]]
) -> list[dict[str, Any]]:
    """``records`` with their world's ``solvable`` and ``liftable`` (the oracle's)."""
    rows = []
    for record in records:
        verdict = oracle[record["world"]]
        rows.append({**record, "solvable": verdict["solvable"], "liftable": verdict["liftable"]})
    return rows


def summarize(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """``summary.json``'s table: the suite, the source, the scores, the scores per axis value
    and the failures' counts."""
    first = rows[0] if rows else {}
    by = {
        axis: {
            str(value): scores([r for r in rows if r[axis] == value])
            for value in sorted({r[axis] for r in rows}, key=str)
        }
        for axis in AXES
    }
    failures = Counter(str(r.get("failure")) for r in rows if not r["success"])
    return {
        "suite": first.get("suite"),
        "suite_sha256": first.get("suite_sha256"),
        "method": first.get("method"),
        **scores(rows),
        "failures": dict(sorted(failures.items())),
        "by": by,
    }


def _cell(scored: dict[str, Any], key: str) -> str:
    share = scored[key]
    return "-" if share is None else f"{share:.2f}"


def report_text(summary: dict[str, Any], title: str) -> str:
    """``report.md``: the overall scores, one table per axis and the failures."""
    head = "| {} | scenes | success | on handle | solvable | on handle of solvable |"
    keys = ("success", "on_handle", "solvable", "on_handle_of_solvable")
    lines = [f"# {title}", "", head.format("all"), "|---|---:|---:|---:|---:|---:|"]
    lines.append(
        f"| all | {summary['scenes']} | " + " | ".join(_cell(summary, k) for k in keys) + " |"
    )
    for axis in AXES:
        lines += ["", head.format(axis), "|---|---:|---:|---:|---:|---:|"]
        for value, scored in summary["by"][axis].items():
            cells = " | ".join(_cell(scored, k) for k in keys)
            lines.append(f"| {value} | {scored['scenes']} | {cells} |")
    beyond = summary["counts"]["beyond_oracle"]
    lines += ["", f"Held by the handle where the oracle found no handle grasp: {beyond}."]
    lines += ["", "| failure | scenes |", "|---|---:|"]
    lines += [f"| {name} | {count} |" for name, count in summary["failures"].items()]
    return "\n".join(lines) + "\n"


def write_scores(
    out: Path, records: list[dict[str, Any]], oracle: dict[str, dict[str, Any]]
) -> dict[str, Any]:
    """Write ``out/summary.json`` and ``out/report.md``; returns the summary."""
    summary = summarize(joined(records, oracle))
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    title = f"Bench {summary['suite']}: {summary['method']}"
    (out / "report.md").write_text(report_text(summary, title), encoding="utf-8")
    return summary
