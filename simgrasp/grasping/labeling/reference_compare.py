"""``compare-labels OURS --reference FILE.h5|GLOB|DIR``: our labels against a grasp file's own
(FleX's ``object_in_gripper`` in ACRONYM files, GraspGen's), per object and overall.

``OURS`` is a ``label-grasps`` output directory: of one file (its ``labels.npz``), or of a data
set (``OURS/<file stem>/labels.npz``). Grasps we could not score (``invalid``,
``sim_unstable``) are left out; a run of a file's first N grasps is compared on those N. The
metrics are :func:`simgrasp.grasping.labeling.agreement.agreement`'s, with an interval over
resampled files for each group of several; the plot shows each object's
accuracy and balanced accuracy and the overall ROC curve of our ``score``.

Beside every accuracy, per file and per category, stand its floor and its ceiling
(:mod:`simgrasp.grasping.labeling.reference_consistency`): the majority-class baseline, and the
reference's own consistency (its label of the nearest other grasp of the file within 8 mm and
15 degrees, on the grasps that have one) with our accuracy on those same grasps.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.grasping.labeling.agreement import agreement, file_interval
from simgrasp.grasping.labeling.reference_consistency import (
    NEIGHBOUR_DEG,
    NEIGHBOUR_MM,
    ceiling_and_floor,
    neighbour_agreement,
)


def labels_dir_of(ours: Path, reference: Path) -> Path:
    """Where the labels of ``reference`` are under ``ours``: ``ours/<file stem>`` (a data
    set's) or ``ours`` itself, made from that very file (``run.json``'s digest), never labels
    of another grasp file that happen to sit there."""
    from simgrasp.grasping.labeling.label_run import labeled_file_digest
    from simgrasp.runs.identity import file_digest

    digest = file_digest(reference)
    for candidate in (ours / reference.stem, ours):
        if not (candidate / "labels.npz").is_file():
            continue
        made_from = labeled_file_digest(candidate)
        if made_from == digest or (made_from is None and candidate != ours):
            return candidate
        if candidate != ours:
            raise SimgraspError(f"{candidate} holds labels of another grasp file than {reference}")
    raise DataNotFoundError(f"no labels of {reference.name} in {ours} (label-grasps it first)")


def _empty_parts() -> tuple[list[np.ndarray], ...]:
    """Empty stores of a group's per-file parts (:func:`_file_parts`)."""
    return ([], [], [], [], [])


def compare_with_reference(
    ours: Path, references: list[Path], draws: int = 0, seed: int = 0
) -> dict[str, Any]:
    """Per-file and overall agreement (also per category: the file name's part before the
    first ``_``, as ACRONYM names files ``Category_id_scale.h5``), each with its ceiling and
    floor (:func:`~simgrasp.grasping.labeling.reference_consistency.ceiling_and_floor`: the
    reference's own consistency on the same grasps and the majority-class baseline). With
    ``draws``, each group of two or more files also gets the 95 % ``interval`` of its accuracy
    and balanced accuracy over ``draws`` resamples of its files, from ``seed``
    (:func:`file_interval`)."""
    rows: list[dict[str, Any]] = []
    pooled: dict[str, tuple[list[np.ndarray], ...]] = {}
    for reference in references:
        parts = _file_parts(ours, reference)
        beside = ceiling_and_floor(parts[0], *parts[3:])
        rows.append({"file": reference.name, **agreement(*parts[:3]), **beside})
        for key in (reference.name.split("_", 1)[0], "overall"):
            for store, part in zip(pooled.setdefault(key, _empty_parts()), parts, strict=True):
                store.append(part)
    groups = {}
    for key, stores in pooled.items():
        joined = [np.concatenate(store) for store in stores]
        groups[key] = {**agreement(*joined[:3]), **ceiling_and_floor(joined[0], *joined[3:])}
        interval = file_interval(list(zip(stores[0], stores[1], strict=True)), draws, seed)
        if interval is not None:
            groups[key]["interval"] = interval
    return {"files": rows, "groups": groups}


def _file_parts(ours: Path, reference: Path) -> tuple[np.ndarray, ...]:
    """(reference labels, our success, our score) of the scored grasps of one file, then (the
    reference's neighbour label right, ours right) on those that have a neighbour
    (:func:`~simgrasp.grasping.labeling.reference_consistency.neighbour_agreement`)."""
    from simgrasp.grasping.labeling.dataset_run import _our_labels
    from simgrasp.grasping.labeling.grasp_files import reference_labels
    from simgrasp.grasping.labeling.grasp_sets import read_grasp_set

    labels = reference_labels(reference)
    if labels is None:
        raise SimgraspError(f"{reference} has no reference labels (object_in_gripper)")
    success, score, scored = _our_labels(labels_dir_of(ours, reference))
    truth = labels[0][: len(success)][scored]
    grasps = read_grasp_set(reference)
    if len(grasps) != len(labels[0]):
        raise SimgraspError(
            f"{reference} has {len(grasps)} grasps but {len(labels[0])} reference labels"
        )
    reference_right, ours_right = neighbour_agreement(
        grasps, labels[0], np.flatnonzero(scored), success[scored]
    )
    return truth, success[scored], score[scored], reference_right, ours_right


def comparison_text(comparison: dict[str, Any]) -> str:
    """A table: one line per file, then per category and overall; beside our accuracy the
    majority-class baseline (its floor) and the reference's own consistency (its ceiling)."""
    head = f"{'file':44s} {'grasps':>6s} {'acc':>5s} {'bal':>5s} {'auroc':>5s} {'major':>5s} "
    head += f"{'self':>5s} {'on':>5s} {'ours':>5s}  {'SS':>5s} {'SF':>5s} {'FS':>5s} {'FF':>5s}"
    body = [_line(r["file"], r) for r in comparison["files"]]
    body += [_line(f"[{k}]", a) for k, a in comparison["groups"].items()]
    body += [
        _interval_line(k, a["interval"]) for k, a in comparison["groups"].items() if "interval" in a
    ]
    legend = (
        "reference x ours: S success, F failure; major: the majority-class baseline; self: "
        "the reference's own consistency (its label of the nearest other grasp of the file "
        f"within {NEIGHBOUR_MM:g} mm and {NEIGHBOUR_DEG:g} deg agrees) on the 'on' grasps that "
        "have one, where ours: our accuracy"
    )
    return "\n".join([head, *body, legend])


def _line(name: str, a: dict[str, Any]) -> str:
    """One row of :func:`comparison_text`."""

    def figure(value: float | None) -> str:
        return "  -  " if value is None else f"{value:.3f}"

    return (
        f"{name[:44]:44s} {a['grasps']:6d} {figure(a['accuracy'])} "
        f"{figure(a['balanced_accuracy'])} {figure(a['auroc'])} {figure(a['majority'])} "
        f"{figure(a['consistency'])} {a['consistency_grasps']:5d} "
        f"{figure(a['ours_on_consistency_grasps'])}  {a['ref_success_ours_success']:5d} "
        f"{a['ref_success_ours_failure']:5d} {a['ref_failure_ours_success']:5d} "
        f"{a['ref_failure_ours_failure']:5d}"
    )


def _interval_line(group: str, interval: dict[str, Any]) -> str:
    """One line of a group's interval (:func:`file_interval`'s dict)."""
    accuracy, balanced = interval["accuracy"], interval["balanced_accuracy"]
    return (
        f"[{group}] {100 * interval['level']:.0f} % interval over its {interval['files']} files "
        f"({interval['draws']} resamples): accuracy {accuracy[0]:.3f}-{accuracy[1]:.3f}, "
        f"balanced {balanced[0]:.3f}-{balanced[1]:.3f}"
    )


def plot_comparison(comparison: dict[str, Any], ours: Path, path: Path) -> None:
    """Per-file accuracy / balanced accuracy bars and the overall ROC curve of ``score``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = comparison["files"]
    figure, (bars, roc) = plt.subplots(1, 2, figsize=(13, 4.5), width_ratios=(2.2, 1))
    x = np.arange(len(rows))
    bars.bar(x - 0.2, [r["accuracy"] for r in rows], 0.4, label="accuracy")
    bars.bar(x + 0.2, [r["balanced_accuracy"] or 0 for r in rows], 0.4, label="balanced")
    bars.axhline(0.9, color="k", lw=0.8, ls="--")
    bars.set_xticks(x, [r["file"].split("_")[0] + "_" + r["file"].split("_")[1][:6] for r in rows])
    bars.tick_params(axis="x", rotation=70, labelsize=7)
    bars.set_ylim(0, 1)
    bars.legend(loc="lower right")
    bars.set_title("agreement with the reference labels, per file")
    _roc_curve(roc, comparison, ours)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def _roc_curve(axes: Any, comparison: dict[str, Any], ours: Path) -> None:
    overall = comparison["groups"]["overall"]
    axes.plot([0, 1], [0, 1], color="0.6", lw=0.8)
    axes.scatter(
        [1 - (overall["true_negative_rate"] or 0)],
        [overall["true_positive_rate"] or 0],
        color="C3",
        zorder=3,
        label=f"our verdicts (acc {overall['accuracy']:.3f})",
    )
    axes.set_xlabel("reference failures we call held")
    axes.set_ylabel("reference successes we call held")
    auroc = overall["auroc"]
    axes.set_title(f"overall, AUROC of score {auroc:.3f}" if auroc is not None else "overall")
    axes.legend(loc="lower right")
