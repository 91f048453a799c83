"""Pictures of objects with their labeled handle regions, for a person to check the labels."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from simgrasp.assets.object import ObjectAsset  # noqa: E402
from simgrasp.perception import sample_surface  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

VIEWS = (("top (x, y)", 0, 1), ("side (x, z)", 0, 2), ("end (y, z)", 1, 2))


def draw_label(asset: ObjectAsset, out: Path, points: int = 20000) -> Path:
    """Write a PNG with three orthographic views of ``asset``; handle points in red."""
    cloud, _ = sample_surface(asset.mesh, points, rng_for(0, "labels", asset.name))
    inside = asset.handle.contains(cloud)
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    for ax, (name, i, j) in zip(axes, VIEWS, strict=True):
        ax.scatter(cloud[~inside, i], cloud[~inside, j], s=0.3, c="0.6")
        ax.scatter(cloud[inside, i], cloud[inside, j], s=0.3, c="red")
        ax.set_aspect("equal")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    kind = "whole object" if asset.handle.whole_object else f"{len(asset.handle.regions)} region(s)"
    fig.suptitle(f"{asset.name}: handle = {kind}, {inside.mean():.0%} of the surface (red)")
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out
