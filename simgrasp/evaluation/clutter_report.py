"""The clutter part of a sweep report: how the cut and the neighbors changed the outcome.

Records of cluttered scenes or segmented cuts carry ``perception``, ``target_iou`` and, in
clutter, ``neighbors_disturbed``; records without them are one object cut by the mask. One row
per sensor x perception: lift and on-handle success, the mean ``target_iou``, the mean count
of disturbed neighbors, the failure modes and the median segmentation time (s).
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Sequence
from typing import Any

import numpy as np

Record = dict[str, Any]
CLUTTER_FAILURES = ("wrong_object", "collision", "no_grasp")


def perception_of(record: Record) -> str:
    """The cut a record's target came from (records without the field: the mask)."""
    return str(record.get("perception", "mask"))


def perception_labeled(records: Sequence[Record]) -> list[Record]:
    """``records``, each detector named ``detector+perception`` when they span several."""
    if len({perception_of(r) for r in records}) < 2:
        return list(records)
    return [{**r, "detector": f"{r['detector']}+{perception_of(r)}"} for r in records]


def clutter_section(records: Sequence[Record]) -> list[str]:
    """Markdown lines of the clutter table; none when no record has a scene cut."""
    if not any("target_iou" in r for r in records):
        return []
    groups: dict[tuple[str, str], list[Record]] = defaultdict(list)
    for record in records:
        groups[(str(record.get("sensor", "ideal")), perception_of(record))].append(record)
    header = ["sensor", "perception", "trials", "lift", "on-handle", "mean target_iou"]
    header += ["neighbors disturbed", *CLUTTER_FAILURES, "other failures", "median segment s"]
    lines = ["## Clutter", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for (sensor, perception), group in sorted(groups.items()):
        lines.append("| " + " | ".join(_row(sensor, perception, group)) + " |")
    return [*lines, ""]


def _row(sensor: str, perception: str, group: list[Record]) -> list[str]:
    failures = Counter(str(r["failure"]) for r in group if r["failure"] is not None)
    ious = [float(r["target_iou"]) for r in group if "target_iou" in r]
    disturbed = [int(r["neighbors_disturbed"]) for r in group if "neighbors_disturbed" in r]
    segment = [r["timings_s"]["segment"] for r in group if "segment" in r["timings_s"]]
    other = sum(n for mode, n in failures.items() if mode not in CLUTTER_FAILURES)
    return [
        sensor,
        perception,
        str(len(group)),
        f"{np.mean([r['success'] is True for r in group]):.3f}",
        f"{np.mean([r['success'] is True and bool(r['on_handle']) for r in group]):.3f}",
        f"{np.mean(ious):.3f}" if ious else "—",
        f"{np.mean(disturbed):.2f}" if disturbed else "—",
        *(str(failures.get(mode, 0)) for mode in CLUTTER_FAILURES),
        str(other),
        f"{np.median(segment):.2f}" if segment else "—",
    ]
