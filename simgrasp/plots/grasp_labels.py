"""The picture of a labeled grasp set: the object with its grasps as gripper wireframes.

Headless matplotlib 3D, in the object's mesh frame (meters). Each grasp is drawn as its two
open fingers, the bar joining them and a stem back toward the palm, colored by outcome: held on
the handle (green, a star at the TCP), held off the handle (blue), failed (red, faint). Invalid
and ``sim_unstable`` rows are not drawn. At most ``max_grasps`` per panel, drawn by a seeded
subsample.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.perception import sample_surface
from simgrasp.seeding import rng_for

FINGER_LENGTH = 0.05
"""Drawn finger length behind the TCP (m)."""
STEM_LENGTH = 0.02
"""Drawn stem behind the bar joining the fingers (m), toward the palm."""
COLORS = {"on_handle": "tab:green", "off_handle": "tab:blue", "failed": "tab:red"}


def wireframe(object_T_tcp: NDArray[np.float64], width: float) -> NDArray[np.float64]:
    """(5, 2, 3) segments of a gripper at ``object_T_tcp`` opened ``width`` (object frame)."""
    half, back = width / 2, -FINGER_LENGTH
    points_tcp = np.array(
        [
            [[0, -half, 0.01], [0, -half, back]],
            [[0, half, 0.01], [0, half, back]],
            [[0, -half, back], [0, half, back]],
            [[0, 0, back], [0, 0, back - STEM_LENGTH]],
            [[0, 0, 0], [0, 0, 0]],
        ],
        dtype=float,
    )
    return points_tcp @ object_T_tcp[:3, :3].T + object_T_tcp[:3, 3]


def outcome(record: dict[str, Any]) -> str | None:
    """The drawn class of a label record (None: not drawn)."""
    if record["failure"] in ("invalid", "sim_unstable"):
        return None
    if record["success"]:
        return "on_handle" if record["on_handle"] else "off_handle"
    return "failed"


def plot_labels(
    mesh: trimesh.Trimesh,
    object_T_tcp: NDArray[np.float64],
    widths: NDArray[np.float64],
    records: list[dict[str, Any]],
    path: Path,
    title: str,
    max_grasps: int = 150,
) -> Path:
    """Write the picture (PNG) of held and failed grasps side by side; returns ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure = plt.figure(figsize=(12, 6))
    surface = np.asarray(mesh.vertices)
    if len(mesh.faces):
        surface, _ = sample_surface(mesh, 6000, rng_for(0, "label_plot", "surface"))
    classes = [outcome(r) for r in records]
    panels = (("held", ("on_handle", "off_handle")), ("failed", ("failed",)))
    for column, (name, wanted) in enumerate(panels, start=1):
        axes = figure.add_subplot(1, 2, column, projection="3d")
        axes.scatter(*surface.T, s=0.6, c="0.35", alpha=0.5)
        chosen = [i for i, c in enumerate(classes) if c in wanted]
        rng = rng_for(0, "label_plot", name)
        if len(chosen) > max_grasps:
            chosen = sorted(rng.choice(chosen, max_grasps, replace=False).tolist())
        for kind in wanted:
            mine = [i for i in chosen if classes[i] == kind]
            _draw_grasps(axes, object_T_tcp[mine], widths[mine], kind)
        counts = {c: classes.count(c) for c in wanted}
        axes.set_title(f"{name}: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
        _equal_axes(axes, mesh.bounds)
    figure.suptitle(title)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(figure)
    return path


def _draw_grasps(axes: Any, object_T_tcp: NDArray, widths: NDArray, kind: str) -> None:
    """The wireframes of grasps of one class as one line collection (one artist: a picture
    of hundreds of grasps draws in a fraction of a second), stars at on-handle TCPs."""
    from mpl_toolkits.mplot3d.art3d import Line3DCollection  # type: ignore[import-untyped]

    if not len(object_T_tcp):
        return
    segments = np.stack([wireframe(t, w) for t, w in zip(object_T_tcp, widths, strict=True)])
    alpha = 0.25 if kind == "failed" else 0.8
    lines = Line3DCollection(segments[:, :4].reshape(-1, 2, 3), colors=COLORS[kind], lw=0.7)
    lines.set_alpha(alpha)
    axes.add_collection3d(lines)
    if kind == "on_handle":
        axes.scatter(*segments[:, 4, 0].T, marker="*", s=18, color=COLORS[kind])


def _equal_axes(axes: Any, bounds: NDArray[np.float64]) -> None:
    center = bounds.mean(axis=0)
    radius = (bounds[1] - bounds[0]).max() / 2 + FINGER_LENGTH
    for setter, c in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), center, strict=True):
        setter(c - radius, c + radius)
    axes.set_box_aspect((1, 1, 1))
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_zlabel("z (m)")
