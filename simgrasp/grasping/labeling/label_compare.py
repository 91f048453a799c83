"""Agreement of two labelings of one grasp set (e.g. the ``fast`` and ``full`` protocols).

Reads the ``labels.npz`` of two ``label-grasps`` output directories (same grasps, same order).
Grasps that either run could not score (``invalid`` or ``sim_unstable``) are left out; over the
rest, the confusion matrix of the ``success`` verdicts and the agreement (the share of equal
verdicts), and the agreement of ``on_handle`` among grasps both runs held.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import DataNotFoundError, SimgraspError

UNSCORED = ("invalid", "sim_unstable")


def load_labels(out_dir: Path) -> dict[str, np.ndarray]:
    path = Path(out_dir) / "labels.npz"
    if not path.is_file():
        raise DataNotFoundError(f"{path} does not exist: label the grasps with label-grasps first")
    with np.load(path) as labels:
        return {key: labels[key] for key in labels.files}


def compare_labels(reference_dir: Path, other_dir: Path) -> dict[str, Any]:
    """Confusion counts of ``success`` (reference x other) and agreements, over the grasps
    both label (a run of a file's first N grasps against one of more: the first N); two
    directories made from different grasp files (``run.json``) are refused."""
    from simgrasp.grasping.labeling.label_run import labeled_file_digest

    digests = labeled_file_digest(reference_dir), labeled_file_digest(other_dir)
    if None not in digests and digests[0] != digests[1]:
        raise SimgraspError(f"{reference_dir} and {other_dir} label different grasp files")
    reference, other = load_labels(reference_dir), load_labels(other_dir)
    common = min(len(reference["success"]), len(other["success"]))
    reference = {key: values[:common] for key, values in reference.items()}
    other = {key: values[:common] for key, values in other.items()}
    scored = ~np.isin(reference["failure"], UNSCORED) & ~np.isin(other["failure"], UNSCORED)
    ref, oth = reference["success"][scored], other["success"][scored]
    both = reference["success"] & other["success"] & scored
    same_handle = reference["on_handle"][both] == other["on_handle"][both]
    return {
        "scored": int(scored.sum()),
        "held_held": int(np.sum(ref & oth)),
        "held_failed": int(np.sum(ref & ~oth)),
        "failed_held": int(np.sum(~ref & oth)),
        "failed_failed": int(np.sum(~ref & ~oth)),
        "agreement": float(np.mean(ref == oth)) if len(ref) else 0.0,
        "on_handle_agreement": float(np.mean(same_handle)) if len(same_handle) else 0.0,
    }


def confusion_text(comparison: dict[str, Any], reference: str, other: str) -> str:
    """The comparison as a small table (rows: reference verdicts, columns: other's)."""
    c = comparison
    return "\n".join(
        [
            f"{'':16} {other + ' held':>14} {other + ' failed':>14}",
            f"{reference + ' held':16} {c['held_held']:14d} {c['held_failed']:14d}",
            f"{reference + ' failed':16} {c['failed_held']:14d} {c['failed_failed']:14d}",
            f"agreement {c['agreement']:.3f} over {c['scored']} scored grasps; on_handle "
            f"agreement {c['on_handle_agreement']:.3f} among grasps both held",
        ]
    )
