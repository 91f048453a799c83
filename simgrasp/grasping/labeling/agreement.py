"""Agreement of our labels with a reference's (e.g. ACRONYM's FleX ``object_in_gripper``).

Over the grasps both label (ours: scored, not ``invalid`` or ``sim_unstable``): the confusion
matrix (reference success / failure x ours), accuracy, balanced accuracy (the mean of the
true-positive and true-negative rates: chance is 0.5 whatever the share of successes) and the
AUROC of our continuous ``score`` against the reference labels (the chance that a reference
success scores above a reference failure, ties counted half; 0.5 is chance). Over several
files, an interval of the pooled accuracy and balanced accuracy from resampling the files
themselves: how much a figure depends on which objects happened to be labeled.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.stats import rankdata

CONFUSION = (
    "ref_success_ours_success",
    "ref_success_ours_failure",
    "ref_failure_ours_success",
    "ref_failure_ours_failure",
)
"""The confusion counts' names, in :func:`_confusion`'s order."""


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
    counts = dict(zip(CONFUSION, (int(n) for n in _confusion(truth, mine)), strict=True))
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


def _confusion(reference: ArrayLike, ours: ArrayLike) -> NDArray:
    """(4,) counts: reference success x ours success, success x failure, failure x success,
    failure x failure."""
    truth = np.asarray(reference, dtype=bool)
    mine = np.asarray(ours, dtype=bool)
    return np.array([(a & b).sum() for a in (truth, ~truth) for b in (mine, ~mine)], dtype=float)


def file_interval(
    files: Sequence[tuple[ArrayLike, ArrayLike]], draws: int, seed: int, level: float = 0.95
) -> dict[str, Any] | None:
    """The central ``level`` interval of the pooled accuracy and balanced accuracy of
    ``files`` (each a (reference, ours) pair of boolean labels) when the files are drawn again
    with replacement, ``draws`` times from ``seed``; None for fewer than two files with labels
    or no draws. A draw's balanced accuracy lacking one class is the other class's rate."""
    counts = np.array([_confusion(reference, ours) for reference, ours in files]).reshape(-1, 4)
    counts = counts[counts.sum(axis=1) > 0]
    if len(counts) < 2 or draws == 0:
        return None
    picks = np.random.default_rng(seed).integers(0, len(counts), size=(draws, len(counts)))
    pooled = counts[picks].sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        accuracy = (pooled[:, 0] + pooled[:, 3]) / pooled.sum(axis=1)
        rates = np.stack(
            [pooled[:, 0] / pooled[:, :2].sum(axis=1), pooled[:, 3] / pooled[:, 2:].sum(axis=1)]
        )
    balanced = np.nanmean(rates, axis=0)
    tails = [50 * (1 - level), 100 - 50 * (1 - level)]
    return {
        "level": level,
        "draws": draws,
        "seed": seed,
        "files": len(counts),
        "accuracy": [float(v) for v in np.nanpercentile(accuracy, tails)],
        "balanced_accuracy": [float(v) for v in np.nanpercentile(balanced, tails)],
    }
