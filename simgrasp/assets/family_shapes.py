"""Shape primitives of the procedural tool families (:mod:`simgrasp.assets.families`): bodies
of revolution, straight bars at any angle, loops on a wall and flat rings, each with the label
region that covers it exactly (object frame, z up, meters; see
:mod:`simgrasp.assets.generated_shapes` for the older primitives)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import cast

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray

from simgrasp.assets.generated_shapes import LABEL_MARGIN, arc_capsules, torus_arc
from simgrasp.labels import Box, Capsule


def revolved(profile: ArrayLike, sections: int = 64) -> trimesh.Trimesh:
    """The closed surface swept by a ``profile`` of (radius, z) points (m) about the z axis;
    the profile starts and ends on the axis (radius 0). Outward normals."""
    mesh = trimesh.creation.revolve(np.asarray(profile, dtype=float), sections=sections)
    if mesh.volume < 0:
        mesh.invert()
    return mesh


def open_vessel(
    bottom_radius: float,
    top_radius: float,
    height: float,
    wall: float,
    floor: float,
    band: float = 0.0,
) -> trimesh.Trimesh:
    """An open vessel: a flat floor ``floor`` thick and a wall ``wall`` thick flaring from
    ``bottom_radius`` at z = 0 to ``top_radius`` at ``height - band``, then straight up to
    ``height`` (a vertical band for a handle to join)."""
    top = height - band
    return revolved(
        [
            [0.0, 0.0],
            [bottom_radius, 0.0],
            [top_radius, top],
            [top_radius, height],
            [top_radius - wall, height],
            [top_radius - wall, top],
            [bottom_radius - wall, floor],
            [0.0, floor],
        ]
    )


def frame_along(direction: ArrayLike, side: ArrayLike) -> NDArray[np.float64]:
    """A rotation whose columns are ``side`` (made orthogonal to ``direction``), the third
    axis, and ``direction`` (unit)."""
    axis = np.asarray(direction, dtype=float)
    axis = axis / np.linalg.norm(axis)
    across = np.asarray(side, dtype=float) - axis * (np.asarray(side, dtype=float) @ axis)
    across /= np.linalg.norm(across)
    return np.column_stack([across, np.cross(axis, across), axis])


def bar(
    start: ArrayLike,
    end: ArrayLike,
    half_side: float,
    half_other: float,
    side: ArrayLike = (0.0, 1.0, 0.0),
    sections: int = 48,
) -> tuple[trimesh.Trimesh, Box]:
    """An elliptic bar from ``start`` to ``end`` with semi-axes ``half_side`` along ``side``
    and ``half_other`` across both, and its label box (padded by the label margin)."""
    p0, p1 = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(p1 - p0))
    rotation = frame_along(p1 - p0, side)
    mesh = trimesh.creation.cylinder(radius=1.0, height=length, sections=sections)
    mesh.apply_scale([half_side, half_other, 1.0])
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation, (p0 + p1) / 2
    mesh.apply_transform(pose)
    half = np.array([half_side, half_other, length / 2]) + LABEL_MARGIN
    return mesh, Box(center=(p0 + p1) / 2, object_R_box=rotation, half_extents=half)


def slab(corners: Sequence[ArrayLike]) -> trimesh.Trimesh:
    """The convex hull of ``corners`` (a blade, a jaw, a wedge: watertight)."""
    return cast(trimesh.Trimesh, trimesh.Trimesh(np.asarray(corners, dtype=float)).convex_hull)


def flat_ring(
    center: ArrayLike, outer: float, inner: float, half_z: float
) -> tuple[trimesh.Trimesh, tuple[Capsule, ...]]:
    """A flat ring about z (a scissors' finger loop) of radii ``outer`` and ``inner`` and
    thickness ``2 half_z``, and the capsules along its centerline that cover its section."""
    ring = trimesh.creation.annulus(r_min=inner, r_max=outer, height=2 * half_z, sections=48)
    ring.apply_translation(np.asarray(center, dtype=float))
    count = 12
    middle = (outer + inner) / 2
    sagitta = middle * (1 - np.cos(np.pi / count))
    radius = float(np.hypot((outer - inner) / 2, half_z) + sagitta + LABEL_MARGIN)
    angles = np.linspace(0.0, 2 * np.pi, count + 1)
    points = np.asarray(center, dtype=float) + middle * np.stack(
        [np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1
    )
    return ring, tuple(Capsule(points[i], points[i + 1], radius) for i in range(count))


def _crossing(
    center: NDArray[np.float64], major: float, wall_x: Callable[[float], float], sign: float
) -> float:
    """The smallest angle ``a`` (rad) from 0 toward ``sign`` pi at which the loop's centerline
    ``center + major (cos a, 0, sin a)`` reaches ``wall_x`` (the wall's x at its height)."""
    angles = sign * np.linspace(0.0, np.pi, 2001)
    x = center[0] + major * np.cos(angles)
    z = center[2] + major * np.sin(angles)
    inside = np.nonzero(x <= np.array([wall_x(h) for h in z]))[0]
    return float(angles[inside[0]]) if len(inside) else float(angles[-1])


def side_loop(
    center: ArrayLike,
    major: float,
    section: tuple[float, float],
    wall_radius: Callable[[float], float],
    wall: float,
) -> tuple[trimesh.Trimesh, tuple[Capsule, ...]]:
    """A loop handle in the x-z plane on the +x side of a wall of revolution whose outer
    radius at height z is ``wall_radius(z)``: a tube of section semi-axes ``section`` (in the
    loop's plane, across it) whose ends enter the wall to its middle, and capsules covering
    the loop outside the wall's outer surface."""
    middle = np.asarray(center, dtype=float)
    thick, wide = section
    ends = [_crossing(middle, major, lambda z: wall_radius(z) - wall / 2, s) for s in (-1, 1)]
    tube = torus_arc(middle, major, thick, ends[0], ends[1], width_radius=wide)
    outside = [_crossing(middle, major, wall_radius, s) for s in (-1, 1)]
    return tube, arc_capsules(middle, major, max(thick, wide), outside[0], outside[1])
