"""Agreement of our labels with a reference's (e.g. ACRONYM's FleX ``object_in_gripper``).

Over the grasps both label (ours: scored, not ``invalid`` or ``sim_unstable``): the confusion
matrix (reference success / failure x ours), accuracy, balanced accuracy (the mean of the
true-positive and true-negative rates: chance is 0.5 whatever the share of successes) and the
AUROC of our continuous ``score`` against the reference labels (the chance that a reference
success scores above a reference failure, ties counted half; 0.5 is chance).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.stats import rankdata


def auroc(reference: ArrayLike, score: ArrayLike) -> float | None:
    """AUROC of ``score`` for the boolean ``reference`` (Mann-Whitney U); None without both
    classes."""
    truth = np.asarray(reference, dtype=bool)
    values = np.asarray(score, dtype=float)
    positives, negatives = int(truth.sum()), int((~truth).sum())
    if positives == 0 or negatives == 0:
        return None
    ranks = rankdata(values)
    u = ranks[truth].sum() - positives * (positives + 1) / 2
    return float(u / (positives * negatives))


def agreement(
    reference: ArrayLike, ours: ArrayLike, score: ArrayLike | None = None
) -> dict[str, Any]:
    """Confusion counts (``ref_success_ours_success`` ...), ``accuracy``, ``balanced_accuracy``
    and ``auroc`` (of ``score``, if given) of boolean labels ``ours`` against ``reference``."""
    truth = np.asarray(reference, dtype=bool)
    mine = np.asarray(ours, dtype=bool)
    counts = {
        "ref_success_ours_success": int((truth & mine).sum()),
        "ref_success_ours_failure": int((truth & ~mine).sum()),
        "ref_failure_ours_success": int((~truth & mine).sum()),
        "ref_failure_ours_failure": int((~truth & ~mine).sum()),
    }
    rates = [float(mine[truth].mean()) if truth.any() else None]
    rates.append(float((~mine[~truth]).mean()) if (~truth).any() else None)
    known = [r for r in rates if r is not None]
    return {
        "grasps": int(len(truth)),
        **counts,
        "accuracy": float((truth == mine).mean()) if len(truth) else None,
        "true_positive_rate": rates[0],
        "true_negative_rate": rates[1],
        "balanced_accuracy": float(np.mean(known)) if known else None,
        "auroc": auroc(truth, score) if score is not None else None,
    }
