"""Summaries of a grasp sweep: ``summary.csv``, ``report.md`` and plots.

Rates are over all trials of a group: ``lift success`` counts trials whose object was lifted
and survived the perturbation (``success`` true); ``on-handle success`` counts successes whose
fingers held the labeled handle. Diverged simulations (``success`` None, failure
``sim_unstable``) count as neither and are listed among the failure modes. Detection accuracy
(the share of candidate centers inside the handle label, the paper's measure) exists only for
the handle detectors (quadric, tenpas) and is averaged over the trials that had candidates.
"""

from __future__ import annotations

import csv
from collections import Counter, defaultdict
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.scenes.views import VIEWS_BEFORE_RECORDED

Record = dict[str, Any]
SUMMARY_FIELDS = (
    "object",
    "detector",
    "gripper",
    "noise",
    "trials",
    "lift_success",
    "on_handle_success",
    "sim_unstable",
    "no_grasp",
    "detection_accuracy",
    "handle_recall",
    "median_trial_s",
)
TIMING_STAGES = ("scene", "render", "detect_and_plan", "total")


def _group(records: Sequence[Record], *fields: str) -> dict[tuple, list[Record]]:
    groups: dict[tuple, list[Record]] = defaultdict(list)
    for record in records:
        groups[tuple(record[f] for f in fields)].append(record)
    return dict(groups)


def _rate(records: Sequence[Record], test: Callable[[Record], bool]) -> float:
    return sum(1 for r in records if test(r)) / len(records) if records else float("nan")


def _success(record: Record) -> bool:
    return record["success"] is True


def _on_handle(record: Record) -> bool:
    return record["success"] is True and bool(record["on_handle"])


def _accuracies(records: Sequence[Record]) -> list[float]:
    return [float(r["detection_accuracy"]) for r in records if r["detection_accuracy"] is not None]


def _trial_seconds(record: Record) -> float:
    timings = record["timings_s"]
    return sum(timings.get(k, 0.0) for k in ("scene", "render", "detect_and_plan", "total"))


def summary_rows(records: Sequence[Record]) -> list[dict[str, Any]]:
    """One row per object x detector x gripper x noise (see :data:`SUMMARY_FIELDS`)."""
    rows = []
    for (obj, det, grip, noise), group in sorted(
        _group(records, "object", "detector", "gripper", "noise").items()
    ):
        accuracies = _accuracies(group)
        recalls = [bool(r["handle_recall"]) for r in group if r["handle_recall"] is not None]
        rows.append(
            {
                "object": obj,
                "detector": det,
                "gripper": grip,
                "noise": noise,
                "trials": len(group),
                "lift_success": round(_rate(group, _success), 4),
                "on_handle_success": round(_rate(group, _on_handle), 4),
                "sim_unstable": sum(r["failure"] == "sim_unstable" for r in group),
                "no_grasp": sum(r["failure"] == "no_grasp" for r in group),
                "detection_accuracy": round(float(np.mean(accuracies)), 4) if accuracies else "",
                "handle_recall": round(float(np.mean(recalls)), 4) if recalls else "",
                "median_trial_s": round(float(np.median([_trial_seconds(r) for r in group])), 3),
            }
        )
    return rows


def sensor_labeled(records: Sequence[Record]) -> list[Record]:
    """``records``, each detector named ``detector+sensor`` when the records span several
    depth sensors (records without a sensor were seen by the ideal one)."""
    sensors = {r.get("sensor", "ideal") for r in records}
    if len(sensors) < 2:
        return list(records)
    return [{**r, "detector": f"{r['detector']}+{r.get('sensor', 'ideal')}"} for r in records]


def write_summary_csv(records: Sequence[Record], path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=SUMMARY_FIELDS)
        writer.writeheader()
        writer.writerows(summary_rows(records))
    return path


def _mean_std(values: Sequence[float]) -> str:
    return f"{np.mean(values):.2f} ± {np.std(values):.2f}" if values else "—"


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines + [""]


def _detection_tables(records: Sequence[Record], objects: list[str]) -> list[str]:
    """Table I (per object at the lowest noise) and Table II (accuracy vs noise) per detector."""
    lines: list[str] = []
    detectors = [
        d
        for d in dict.fromkeys(r["detector"] for r in records)
        if _accuracies([r for r in records if r["detector"] == d])
    ]
    if not detectors:
        return [
            "No handle detector in this sweep (centroid/random have no detection accuracy).",
            "",
        ]
    for det in detectors:
        mine = [r for r in records if r["detector"] == det]
        noises = sorted({r["noise"] for r in mine})
        lowest = [r for r in mine if r["noise"] == noises[0]]
        lines += [f"### {det}: Table I form (σ = {noises[0]:g}, mean ± std over trials)", ""]
        rows = []
        for obj in objects:
            group = [r for r in lowest if r["object"] == obj]
            recalls = [bool(r["handle_recall"]) for r in group if r["handle_recall"] is not None]
            rows.append(
                [
                    obj,
                    _mean_std(_accuracies(group)),
                    f"{np.mean([r['candidates'] for r in group]):.1f}" if group else "—",
                    f"{np.mean([r['handles'] for r in group]):.1f}" if group else "—",
                    f"{sum(recalls)}/{len(recalls)}",
                ]
            )
        lines += _table(["object", "accuracy", "candidates", "handles", "handle recall"], rows)
        lines += [f"### {det}: Table II form (accuracy vs σ, mean ± std over seeds)", ""]
        rows = []
        for noise in noises:
            cells, means = [], []
            for obj in objects:
                values = _accuracies(
                    [r for r in mine if r["object"] == obj and r["noise"] == noise]
                )
                cells.append(_mean_std(values))
                if values:
                    means.append(float(np.mean(values)))
            rows.append([f"{noise:g}", *cells, f"{np.mean(means):.2f}" if means else "—"])
        lines += _table(["σ", *objects, "mean"], rows)
    return lines


def _success_tables(records: Sequence[Record], objects: list[str]) -> list[str]:
    combos = list(dict.fromkeys((r["detector"], r["gripper"]) for r in records))
    header = ["object", *(f"{d} / {g}" for d, g in combos)]
    lines = ["Cells: lift success / on-handle success (share of trials, all noise levels).", ""]
    rows = []
    for obj in [*objects, "all"]:
        cells = []
        for det, grip in combos:
            group = [
                r
                for r in records
                if r["detector"] == det and r["gripper"] == grip and obj in ("all", r["object"])
            ]
            cells.append(f"{_rate(group, _success):.2f} / {_rate(group, _on_handle):.2f}")
        rows.append([f"**{obj}**" if obj == "all" else obj, *cells])
    lines += _table(header, rows)
    noises = sorted({r["noise"] for r in records})
    lines += ["By noise level (all objects): lift success / on-handle success.", ""]
    rows = []
    for noise in noises:
        cells = []
        for det, grip in combos:
            group = [
                r
                for r in records
                if r["detector"] == det and r["gripper"] == grip and r["noise"] == noise
            ]
            cells.append(f"{_rate(group, _success):.2f} / {_rate(group, _on_handle):.2f}")
        rows.append([f"{noise:g}", *cells])
    return lines + _table(["σ", *header[1:]], rows)


def _failure_table(records: Sequence[Record]) -> list[str]:
    modes = sorted({str(r["failure"]) for r in records if r["failure"] is not None})
    rows = []
    for (det, grip), group in _group(records, "detector", "gripper").items():
        counts = Counter(str(r["failure"]) for r in group if r["failure"] is not None)
        rows.append([det, grip, len(group), sum(map(_success, group)), *(counts[m] for m in modes)])
    return _table(["detector", "gripper", "trials", "success", *modes], rows)


def _timing_table(records: Sequence[Record]) -> list[str]:
    rows = []
    for (det, grip), group in _group(records, "detector", "gripper").items():
        cells = []
        for stage in TIMING_STAGES:
            values = [r["timings_s"][stage] for r in group if stage in r["timings_s"]]
            cells.append(f"{np.median(values):.3f}" if values else "—")
        rows.append([det, grip, *cells, f"{np.median([_trial_seconds(r) for r in group]):.2f}"])
    header = ["detector", "gripper", "scene", "render", "detect + plan", "simulate", "whole trial"]
    return _table(header, rows)


def report_markdown(records: Sequence[Record], title: str = "Grasp sweep") -> str:
    """The sweep report: detection accuracy (paper Tables I/II form), lift and on-handle success
    per object x detector x gripper, failure modes and stage timings (Table III form)."""
    if not records:
        raise SimgraspError("no trial records to report")
    objects = list(dict.fromkeys(r["object"] for r in records))
    noises = sorted({r["noise"] for r in records})
    seeds = sorted({r["seed"] for r in records})
    views = sorted({int(r.get("views", VIEWS_BEFORE_RECORDED)) for r in records})
    lines = [
        f"# {title}",
        "",
        f"{len(records)} trials: {len(objects)} objects, detectors "
        f"{', '.join(dict.fromkeys(r['detector'] for r in records))}, grippers "
        f"{', '.join(dict.fromkeys(r['gripper'] for r in records))}, noise σ "
        f"{', '.join(f'{n:g}' for n in noises)}, {len(seeds)} seeds, "
        f"{' or '.join(map(str, views))} camera views.",
        "",
        "## Detection accuracy (share of candidates inside the handle label)",
        "",
        *_detection_tables(records, objects),
        "## Grasp success",
        "",
        *_success_tables(records, objects),
        "## Failure modes (trial counts)",
        "",
        *_failure_table(records),
        "## Timings (Table III form: median seconds per stage, one worker)",
        "",
        *_timing_table(records),
    ]
    return "\n".join(lines)


def write_plots(records: Sequence[Record], out_dir: Path) -> list[Path]:
    """``accuracy_success_vs_noise.png`` (mean over objects per detector x gripper) and
    ``success_per_object.png`` (bars, all noise levels)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    combos = list(dict.fromkeys((r["detector"], r["gripper"]) for r in records))
    noises = sorted({r["noise"] for r in records})
    objects = list(dict.fromkeys(r["object"] for r in records))

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    panels = (
        ("detection accuracy", lambda g: np.mean(_accuracies(g)) if _accuracies(g) else np.nan),
        ("lift success", lambda g: _rate(g, _success)),
        ("on-handle success", lambda g: _rate(g, _on_handle)),
    )
    for ax, (name, value) in zip(axes, panels, strict=True):
        for det, grip in combos:
            ys = [
                value(
                    [
                        r
                        for r in records
                        if (r["detector"], r["gripper"], r["noise"]) == (det, grip, n)
                    ]
                )
                for n in noises
            ]
            ax.plot(noises, ys, marker="o", label=f"{det} / {grip}")
        ax.set_title(f"{name} vs noise")
        ax.set_xlabel("σ (multiplicative cloud noise)")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    vs_noise = out_dir / "accuracy_success_vs_noise.png"
    fig.savefig(vs_noise, dpi=90)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(max(8, 1.3 * len(objects)), 4.5))
    width = 0.8 / len(combos)
    x = np.arange(len(objects))
    for i, (det, grip) in enumerate(combos):
        mine = [r for r in records if (r["detector"], r["gripper"]) == (det, grip)]
        lift = [_rate([r for r in mine if r["object"] == o], _success) for o in objects]
        handle = [_rate([r for r in mine if r["object"] == o], _on_handle) for o in objects]
        ax.bar(x + i * width, lift, width, alpha=0.35, color=f"C{i}")
        ax.bar(x + i * width, handle, width, color=f"C{i}", label=f"{det} / {grip}")
    ax.set_xticks(x + width * (len(combos) - 1) / 2, objects, rotation=30, ha="right")
    ax.set_ylabel("success (light: lift, dark: on handle)")
    ax.set_ylim(0, 1.02)
    ax.legend(fontsize=8)
    fig.tight_layout()
    per_object = out_dir / "success_per_object.png"
    fig.savefig(per_object, dpi=90)
    plt.close(fig)
    return [vs_noise, per_object]


def write_report(records: Sequence[Record], out_dir: Path, title: str = "Grasp sweep") -> str:
    """Write ``summary.csv``, ``report.md`` and the plots into ``out_dir``; return the report.
    Records of more than one depth sensor are told apart as ``detector+sensor``, of more than
    one cut of the target as ``detector+perception`` (:mod:`.clutter_report`)."""
    from simgrasp.evaluation.clutter_report import clutter_section, perception_labeled

    clutter = clutter_section(records)
    records = perception_labeled(sensor_labeled(records))
    text = "\n".join([report_markdown(records, title), *(["", *clutter] if clutter else [])])
    write_summary_csv(records, out_dir / "summary.csv")
    (out_dir / "report.md").write_text(text + "\n", encoding="utf-8")
    write_plots(records, out_dir)
    return text
