"""A picture of an automatic handle label for a person to review: three orthographic views of
the scanned mesh surface, the points inside the label in red, the detector's kept candidates
(width and flatness tests passed) as small dots, those of the chosen parts in black."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from simgrasp.autolabel.auto_label import AutoLabel  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

VIEWS = (("x, y", 0, 1), ("x, z", 0, 2), ("y, z", 1, 2))


def draw_auto_label(result: AutoLabel, out: Path, points: int = 30000) -> Path:
    """Write a PNG of ``result`` (mesh frame, m) to ``out``."""
    rng = rng_for(0, "auto_label_plot", result.label.object_name)
    surface = result.surface
    if len(surface) > points:
        surface = surface[rng.choice(len(surface), points, replace=False)]
    inside = result.label.contains(surface)
    kept = result.candidates.centers[result.kept]
    chosen = np.concatenate([result.candidates.centers[p] for p in result.parts] or [kept[:0]])
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    for ax, (name, i, j) in zip(axes, VIEWS, strict=True):
        ax.scatter(surface[~inside, i], surface[~inside, j], s=0.2, c="0.75")
        ax.scatter(surface[inside, i], surface[inside, j], s=0.4, c="red")
        ax.scatter(kept[:, i], kept[:, j], s=1.5, c="tab:blue")
        ax.scatter(chosen[:, i], chosen[:, j], s=1.5, c="black")
        ax.set_aspect("equal")
        ax.set_title(f"{name} (m)")
        ax.grid(alpha=0.3)
    label = result.label
    fig.suptitle(
        f"{label.object_name}: {len(result.parts)} handle part(s), {len(result.standoff)} "
        f"piece(s) standing off a body of revolution, {len(label.regions)} box(es)\n"
        f"{inside.mean():.0%} of the scanned surface in the label (red); candidates kept "
        "(blue), chosen (black)"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out
