"""Pictures of a real scene's labeled handles for a person to check: the scene cloud around the
labeled object, handle points in red, each region's box outline in blue (sensor frame)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

from simgrasp.assets.real import LabeledScene  # noqa: E402
from simgrasp.assets.scene_labels import SceneHandleLabel  # noqa: E402
from simgrasp.labels import Box, Capsule, Region  # noqa: E402

# (title, horizontal axis, vertical axis, flip vertical): sensor frame x right, y down, z forward
VIEWS = (("camera (x, -y)", 0, 1, True), ("top (x, z)", 0, 2, False), ("side (z, -y)", 2, 1, True))
MARGIN = 0.05
"""Scene points within this distance (m) of the object's bounding box are drawn."""


def region_outline(region: Region) -> NDArray[np.float64]:
    """(K, 2, 3) line segments outlining a region (a box's 12 edges, a capsule's axis)."""
    if isinstance(region, Capsule):
        return np.stack([region.p0, region.p1])[None]
    assert isinstance(region, Box)
    corners = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    world = region.center + (corners * region.half_extents) @ region.object_R_box.T
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    return np.stack([world[[a, b]] for a, b in edges])


def draw_scene_label(scene: LabeledScene, label: SceneHandleLabel, out: Path) -> Path:
    """Write a PNG of ``label`` on ``scene``: three orthographic views of the object's
    surroundings (grey scene, dark object, red handle points, blue region outlines)."""
    valid = np.isfinite(scene.points).all(axis=1)
    points, parts = scene.points[valid], scene.labels[valid]
    on_object = parts // 10 == label.object_id
    low = points[on_object].min(axis=0) - MARGIN
    high = points[on_object].max(axis=0) + MARGIN
    near = np.all((points >= low) & (points <= high), axis=1)
    points, on_object = points[near], on_object[near]
    handle = label.label.contains(points)
    fig, axes = plt.subplots(1, 3, figsize=(18, 6))
    for ax, (name, i, j, flip) in zip(axes, VIEWS, strict=True):
        sign = -1.0 if flip else 1.0
        for mask, color in ((~on_object, "0.8"), (on_object & ~handle, "0.35"), (handle, "red")):
            ax.scatter(points[mask, i], sign * points[mask, j], s=0.5, c=color)
        for region in label.label.regions:
            for a, b in region_outline(region):
                ax.plot([a[i], b[i]], [sign * a[j], sign * b[j]], c="tab:blue", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    fig.suptitle(
        f"{label.scene}: object {label.object_id}, {len(label.label.regions)} handle region(s), "
        f"{int(handle.sum())} of {int(on_object.sum())} object points in them (red)"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out
