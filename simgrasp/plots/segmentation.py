"""Picture of a scene segmentation: the label image of an organized cloud (or a top view of an
unorganized one), table grey, each object its own color, invalid points white."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.scene_cloud import SceneCloud
from simgrasp.perception.segmentation.segment import FIRST_OBJECT, TABLE, Segmentation


def label_colors(labels: NDArray[np.integer]) -> NDArray[np.float64]:
    """(N, 3) RGB in [0, 1] per label: 0 white, table grey, objects from a 20-color cycle."""
    import matplotlib

    cycle = matplotlib.colormaps["tab20"](np.arange(20))[:, :3]
    labels = np.asarray(labels).reshape(-1)
    colors = np.ones((len(labels), 3))
    colors[labels == TABLE] = 0.6
    objects = labels >= FIRST_OBJECT
    colors[objects] = cycle[(labels[objects] - FIRST_OBJECT) % 20]
    return colors


def plot_segmentation(
    scene: SceneCloud,
    segmentation: Segmentation,
    out: str | Path,
    truth: NDArray[np.integer] | None = None,
) -> None:
    """Write the picture to ``out`` (PNG); with ``truth`` (per-point labels in the same
    convention) a second panel shows it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [("segmentation", segmentation.labels)]
    if truth is not None:
        panels.append(("ground truth", np.asarray(truth).reshape(-1)))
    fig, axes = plt.subplots(1, len(panels), figsize=(6.4 * len(panels), 5.2), squeeze=False)
    for ax, (title, labels) in zip(axes[0], panels, strict=True):
        _draw(ax, scene, labels)
        ax.set_title(f"{title}: {int(labels.max(initial=1)) - 1} objects")
        ax.set_axis_off()
    fig.suptitle(Path(scene.source).name or "scene")
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def _draw(ax, scene: SceneCloud, labels: NDArray[np.integer]) -> None:
    colors = label_colors(labels)
    if scene.organized:
        ax.imshow(colors.reshape(scene.height, scene.width, 3), interpolation="nearest")
        return
    shown = np.isfinite(scene.points).all(axis=1)
    points = scene.points[shown]
    ax.scatter(points[:, 0], -points[:, 1], c=colors[shown], s=0.5, linewidths=0)
    ax.set_aspect("equal")
