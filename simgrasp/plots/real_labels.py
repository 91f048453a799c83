"""Pictures of a real cloud's labeled handle for a person to check (``simgrasp labels --real``):
the cloud as detection gets it, handle points in red, each region's outline in blue, in three
orthographic views of the cloud's own frame (meters)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

from simgrasp.labels import HandleLabel  # noqa: E402
from simgrasp.plots.scene_labels import region_outline  # noqa: E402

VIEWS = (("x, y", 0, 1), ("x, z", 0, 2), ("z, y", 2, 1))
MAX_DRAWN = 40000
"""Clouds with more points are thinned (every k-th point) for drawing."""


def draw_real_label(
    points: NDArray[np.float64], label: HandleLabel, title: str, out: Path
) -> tuple[Path, int]:
    """Write a PNG of ``label`` on ``points`` (m); returns its path and the labeled points."""
    handle = label.contains(points)
    step = max(1, len(points) // MAX_DRAWN)
    drawn, drawn_handle = points[::step], handle[::step]
    fig, axes = plt.subplots(1, 3, figsize=(18, 6))
    for ax, (name, i, j) in zip(axes, VIEWS, strict=True):
        for mask, color in ((~drawn_handle, "0.45"), (drawn_handle, "red")):
            ax.scatter(drawn[mask, i], drawn[mask, j], s=0.5, c=color)
        for region in label.regions:
            for a, b in region_outline(region):
                ax.plot([a[i], b[i]], [a[j], b[j]], c="tab:blue", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    fig.suptitle(
        f"{title}: {len(label.regions)} handle region(s), {int(handle.sum())} of "
        f"{len(points)} points in them (red)"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out, int(handle.sum())
