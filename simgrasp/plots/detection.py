"""A picture of a detection: the cloud, candidates colored by kind, handle axes, and the fitted
quadric surfaces meshed per type, from two viewpoints."""

from __future__ import annotations

from pathlib import Path

import matplotlib

from simgrasp.errors import SimgraspError

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from simgrasp.handles.core.detection import Detection  # noqa: E402
from simgrasp.quadric import surface_mesh  # noqa: E402

KIND_COLORS = {
    "real_ellipsoid": "tab:orange",
    "hyperboloid_one_sheet": "tab:green",
    "real_elliptic_cylinder": "tab:blue",
    "cylinder_shell": "tab:purple",
}
MAX_SURFACES = 24


def plot_detection(
    detection: Detection,
    out: str | Path,
    *,
    title: str = "",
    surface_half_size: float = 0.012,
    max_cloud_points: int = 6000,
) -> Path:
    """Write a PNG showing ``detection`` (cloud frame, meters); returns the path.

    At most ``MAX_SURFACES`` fitted surfaces are drawn (evenly spaced over the candidates),
    each meshed inside a cube of half size ``surface_half_size`` (m) around its handle point.
    """
    out = Path(out)
    if out.suffix.lower() != ".png":
        raise SimgraspError(f"--plot writes PNG files; got {out}")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=(14, 7))
    views = ((25, -60), (85, -90))
    cloud = detection.points if detection.points is not None else np.zeros((0, 3))
    if len(cloud) > max_cloud_points:
        cloud = cloud[np.linspace(0, len(cloud) - 1, max_cloud_points).astype(int)]
    for column, (elevation, azimuth) in enumerate(views):
        ax = fig.add_subplot(1, 2, column + 1, projection="3d")
        _draw(ax, detection, cloud, surface_half_size)
        ax.view_init(elev=elevation, azim=azimuth)
        _equal_axes(ax, cloud if len(cloud) else detection.candidate_centers)
    handles = [
        Line2D([], [], marker="o", ls="", color=color, label=kind.replace("_", " "))
        for kind, color in KIND_COLORS.items()
        if any(c.kind == kind for c in detection.candidates)
    ]
    handles.append(Line2D([], [], color="red", lw=3, label="handle axis"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles))
    summary = (
        f"{detection.detector}: {detection.neighborhoods} neighborhoods, "
        f"{len(detection.candidates)} candidates, {len(detection.handles)} handles"
    )
    fig.suptitle(f"{title}\n{summary}" if title else summary)
    fig.savefig(out, dpi=90)
    plt.close(fig)
    return out


def _draw(ax, detection: Detection, cloud: np.ndarray, half: float) -> None:  # noqa: ANN001
    if len(cloud):
        ax.scatter(*cloud.T, s=0.5, c="0.6", alpha=0.4, depthshade=False)
    for candidate in detection.candidates:
        color = KIND_COLORS.get(candidate.kind, "black")
        ax.scatter(*candidate.center, s=10, c=color, depthshade=False)
    picks = np.unique(
        np.linspace(0, len(detection.candidates) - 1, MAX_SURFACES).astype(int)
        if detection.candidates
        else np.zeros(0, dtype=int)
    )
    for i in picks:
        candidate = detection.candidates[i]
        vertices, faces = surface_mesh(candidate.quadric, candidate.handle_point, half)
        if len(faces):
            ax.plot_trisurf(
                *vertices.T,
                triangles=faces,
                color=KIND_COLORS.get(candidate.kind, "black"),
                alpha=0.25,
                linewidth=0,
            )
    for handle in detection.handles:
        half_length = max(handle.extent, 0.02)
        ends = handle.center + np.outer([-half_length, half_length], handle.axis)
        ax.plot(*ends.T, color="red", lw=3)
        ax.scatter(*handle.center, s=60, c="red", marker="x", depthshade=False)


def _equal_axes(ax, points: np.ndarray) -> None:  # noqa: ANN001
    if len(points) == 0:
        return
    low, high = points.min(axis=0), points.max(axis=0)
    middle, radius = (low + high) / 2, max((high - low).max() / 2, 1e-3)
    ax.set_xlim(middle[0] - radius, middle[0] + radius)
    ax.set_ylim(middle[1] - radius, middle[1] + radius)
    ax.set_zlim(middle[2] - radius, middle[2] + radius)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
