"""The picture of one grasp two label sets disagree on
(:mod:`simgrasp.grasping.labeling.disagreements`): the key moments of our trial of it side by
side (pre-grasp, closed, shaken), under a caption that gives both verdicts."""

from __future__ import annotations

from pathlib import Path

import numpy as np

MOMENTS = ("pre-grasp", "closed", "shaken")
"""The key moments of a free-floating (ACRONYM) trial, in order; a trial that fails at the
close has no later ones."""


def plot_disagreement(frames: list[np.ndarray], caption: str, path: Path) -> Path:
    """Write ``frames`` ((H, W, 3) uint8 key frames, in trial order) in one row under
    ``caption`` to ``path`` (PNG); returns ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    count = max(len(frames), len(MOMENTS))
    figure, axes = plt.subplots(1, count, figsize=(3.6 * count, 3.4), squeeze=False)
    for k, axis in enumerate(axes[0]):
        axis.axis("off")
        name = MOMENTS[k] if k < len(MOMENTS) else f"moment {k + 1}"
        if k < len(frames):
            axis.imshow(frames[k])
            axis.set_title(name, fontsize=9)
        else:
            axis.text(0.5, 0.5, f"{name}: not reached\n(the trial ended)", ha="center", va="center")
    figure.suptitle(caption, fontsize=9)
    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=90)
    plt.close(figure)
    return path
