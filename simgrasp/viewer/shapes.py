"""Plotly traces of simgrasp's geometry: meshes, merged line segments, handle labels, grippers.

Thousands of segments go into ONE line trace (segments separated by NaN, plotly's gap), so a
2,000-grasp set is a handful of WebGL draw calls and turns smoothly. Coordinates are meters in
whatever frame the caller's arrays are in.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import plotly.graph_objects as go
import trimesh
from numpy.typing import NDArray

from simgrasp.labels import Box, Capsule, HandleLabel

COLORS = {"on_handle": "#2ca02c", "off_handle": "#1f77b4", "failed": "#d62728"}
"""Outcome colors, as ``labels.png`` draws them (matplotlib's tab:green, tab:blue, tab:red)."""


def mesh_trace(
    mesh: trimesh.Trimesh, name: str, color: str = "#9a9a9a", opacity: float = 1.0, **extra: Any
) -> go.Mesh3d:
    """A triangle mesh, flat-shaded with a little ambient light."""
    vertices, faces = np.asarray(mesh.vertices, dtype=np.float32), np.asarray(mesh.faces)
    return go.Mesh3d(
        x=vertices[:, 0],
        y=vertices[:, 1],
        z=vertices[:, 2],
        i=faces[:, 0],
        j=faces[:, 1],
        k=faces[:, 2],
        color=color,
        opacity=opacity,
        name=name,
        hoverinfo="name",
        flatshading=True,
        lighting={"ambient": 0.55, "diffuse": 0.7},
        **{"showlegend": True, **extra},
    )


def segment_arrays(segments: NDArray[np.float64]) -> NDArray[np.float32]:
    """(N, 2, 3) segments as (3N, 3) polyline points with a NaN row after each segment."""
    gap = np.full((len(segments), 1, 3), np.nan)
    return np.concatenate([segments, gap], axis=1).reshape(-1, 3).astype(np.float32)


def lines_trace(
    segments: NDArray[np.float64], name: str, color: str, width: float = 2.0, **extra: Any
) -> go.Scatter3d:
    """All ``segments`` (N, 2, 3) as one line trace."""
    points = segment_arrays(np.asarray(segments, dtype=float).reshape(-1, 2, 3))
    return go.Scatter3d(
        x=points[:, 0],
        y=points[:, 1],
        z=points[:, 2],
        mode="lines",
        line={"color": color, "width": width},
        name=name,
        hoverinfo="skip",
        connectgaps=False,
        **extra,
    )


def region_mesh(region: Capsule | Box) -> trimesh.Trimesh:
    """A handle label region as a closed mesh (object frame)."""
    if isinstance(region, Box):
        transform = np.eye(4)
        transform[:3, :3], transform[:3, 3] = region.object_R_box, region.center
        return trimesh.creation.box(extents=2 * region.half_extents, transform=transform)
    return trimesh.creation.capsule(
        height=float(np.linalg.norm(region.p1 - region.p0)), radius=region.radius, count=[12, 12]
    ).apply_transform(_segment_frame(region.p0, region.p1))


def _segment_frame(p0: NDArray[np.float64], p1: NDArray[np.float64]) -> NDArray[np.float64]:
    """The transform taking trimesh's capsule (from z=0 up its z axis) onto ``p0``-``p1``."""
    axis = p1 - p0
    length = float(np.linalg.norm(axis))
    transform = trimesh.geometry.align_vectors([0, 0, 1], axis / length if length else [0, 0, 1])
    transform[:3, 3] = p0
    return transform


def handle_traces(handle: HandleLabel, world_T_object: NDArray[np.float64]) -> list[go.Mesh3d]:
    """The labeled handle regions (translucent yellow), placed by ``world_T_object``."""
    return [
        mesh_trace(
            region_mesh(region).apply_transform(world_T_object),
            name="handle label",
            color="#e5c100",
            opacity=0.3,
            legendgroup="handle",
            showlegend=k == 0,
        )
        for k, region in enumerate(handle.regions)
    ]
