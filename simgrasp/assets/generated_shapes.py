"""Shape primitives of the generated objects (:mod:`simgrasp.assets.generated`): the part
record, material densities, and the meshes and label regions the builders assemble (object
frame, z up, meters)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.labels import Box, Capsule, Region

# Densities (kg/m^3) of the materials the parts are made of.
DENSITY_WOOD = 700.0
DENSITY_PLASTIC = 1100.0
DENSITY_STEEL = 7850.0
DENSITY_ALUMINUM = 2700.0
DENSITY_CERAMIC = 2400.0
DENSITY_FILLED_CAN = 1000.0  # a full food can: contents dominate, about water
DENSITY_FRUIT = 850.0

LABEL_MARGIN = 0.001  # meters added around the handle part so its surface is inside the label


@dataclass(frozen=True)
class Part:
    """One watertight primitive of a generated object (object frame, meters)."""

    name: str
    mesh: trimesh.Trimesh
    density: float
    is_handle: bool


Built = tuple[list[Part], tuple[Region, ...], bool]
"""What an object builder returns: its parts, the exact label regions of its handle, and
whether the whole object counts as its handle (a can, a fruit:
:class:`~simgrasp.labels.HandleLabel`'s ``whole``)."""


def uniform(rng: np.random.Generator, low: float, high: float) -> float:
    return float(rng.uniform(low, high))


def along_x(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Rotate a z-axis primitive so its axis lies along +x."""
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    return mesh


def x_cylinder(radius_y: float, radius_z: float, x0: float, x1: float, z: float) -> trimesh.Trimesh:
    """An elliptic cylinder along x from ``x0`` to ``x1`` with its axis at height ``z``."""
    mesh = along_x(trimesh.creation.cylinder(radius=1.0, height=x1 - x0, sections=48))
    mesh.apply_scale([1.0, radius_y, radius_z])
    mesh.apply_translation([(x0 + x1) / 2, 0.0, z])
    return mesh


def x_box_region(
    x0: float, x1: float, half_y: float, half_z: float, z: float, margin: float = LABEL_MARGIN
) -> Box:
    """An axis-aligned label box around a straight handle part along x, padded by ``margin``."""
    return Box(
        center=np.array([(x0 + x1) / 2, 0.0, z]),
        object_R_box=np.eye(3),
        half_extents=np.array([(x1 - x0) / 2 + margin, half_y + margin, half_z + margin]),
    )


def _radial(angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """(N, 3) unit directions ``(cos a, 0, sin a)`` in the x-z plane of the ``angles`` (rad)."""
    return np.stack([np.cos(angles), np.zeros_like(angles), np.sin(angles)], axis=1)


def torus_arc(
    center: NDArray[np.float64],
    major_radius: float,
    minor_radius: float,
    angle_start: float,
    angle_end: float,
    arc_sections: int = 48,
    tube_sections: int = 24,
    width_radius: float | None = None,
) -> trimesh.Trimesh:
    """A closed tube along a circular arc in the x-z plane (capped ends, outward normals).

    The centerline is ``center + major_radius * (cos a, 0, sin a)`` for ``a`` in
    [``angle_start``, ``angle_end``] (radians); the tube's section is an ellipse of semi-axis
    ``minor_radius`` in the arc's plane and ``width_radius`` (None: ``minor_radius``, a round
    tube) across it, along y (a flat strap when wider than thick).
    """
    width_radius = minor_radius if width_radius is None else width_radius
    angles = np.linspace(angle_start, angle_end, arc_sections + 1)
    phis = np.linspace(0.0, 2 * np.pi, tube_sections, endpoint=False)
    radial = _radial(angles)
    centerline = center + major_radius * radial
    binormal = np.array([0.0, 1.0, 0.0])
    rings = (
        centerline[:, None, :]
        + minor_radius * np.cos(phis)[None, :, None] * radial[:, None, :]
        + width_radius * np.sin(phis)[None, :, None] * binormal
    )
    vertices = np.concatenate([rings.reshape(-1, 3), centerline[[0, -1]]])
    n_ring = tube_sections
    faces = []
    for i in range(arc_sections):
        for j in range(n_ring):
            a, b = i * n_ring + j, i * n_ring + (j + 1) % n_ring
            c, d = a + n_ring, b + n_ring
            faces += [[a, c, b], [b, c, d]]
    start_center, end_center = len(vertices) - 2, len(vertices) - 1
    last = arc_sections * n_ring
    for j in range(n_ring):
        faces.append([start_center, j, (j + 1) % n_ring])
        faces.append([end_center, last + (j + 1) % n_ring, last + j])
    mesh = trimesh.Trimesh(vertices, np.array(faces), process=False)
    if mesh.volume < 0:
        mesh.invert()
    return mesh


def arc_capsules(
    center: NDArray[np.float64],
    major_radius: float,
    minor_radius: float,
    angle_start: float,
    angle_end: float,
    count: int = 8,
) -> tuple[Capsule, ...]:
    """Capsules along the chords of an arc, padded by the chord's sagitta plus the margin."""
    angles = np.linspace(angle_start, angle_end, count + 1)
    step = abs(angle_end - angle_start) / count
    sagitta = major_radius * (1 - np.cos(step / 2))
    radius = minor_radius + sagitta + LABEL_MARGIN
    points = center + major_radius * _radial(angles)
    return tuple(Capsule(points[i], points[i + 1], float(radius)) for i in range(count))
