"""Test clouds with known handles, sampled from trimesh primitives (object frame, meters)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from scipy.spatial import cKDTree


@dataclass(frozen=True)
class LabeledCloud:
    """Surface points with a per-point flag: does the point belong to the handle part?"""

    points: np.ndarray
    normals: np.ndarray
    on_handle: np.ndarray

    def handle_share(self, query: np.ndarray) -> float:
        """Share of query points whose nearest cloud point is on the handle part."""
        _, index = cKDTree(self.points).query(query)
        return float(self.on_handle[index].mean())


def _sample(
    parts: list[tuple[trimesh.Trimesh, bool]], density: float, seed: int, min_x: float = -np.inf
) -> LabeledCloud:
    """Sample every part; handle parts keep only points with x > ``min_x``."""
    points, normals, flags = [], [], []
    for i, (mesh, is_handle) in enumerate(parts):
        count = max(int(mesh.area * density), 50)
        p, face = trimesh.sample.sample_surface(mesh, count, seed=seed + i)
        keep = p[:, 0] > min_x if is_handle else np.ones(len(p), dtype=bool)
        points.append(p[keep])
        normals.append(mesh.face_normals[face][keep])
        flags.append(np.full(int(keep.sum()), is_handle))
    return LabeledCloud(np.concatenate(points), np.concatenate(normals), np.concatenate(flags))


def mug_parts() -> list[tuple[trimesh.Trimesh, bool]]:
    """A 4 cm-radius open cylindrical mug body, its bottom and a torus handle (minor radius
    7 mm) in the x-z plane on the +x side, each with whether it is the handle part."""
    wall = trimesh.creation.annulus(r_min=0.037, r_max=0.040, height=0.09)
    wall.apply_translation([0, 0, 0.045])
    bottom = trimesh.creation.cylinder(radius=0.037, height=0.005)
    bottom.apply_translation([0, 0, 0.0025])
    torus = trimesh.creation.torus(major_radius=0.028, minor_radius=0.007)
    torus.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    torus.apply_translation([0.040, 0, 0.045])
    return [(wall, False), (bottom, False), (torus, True)]


def mug_like(seed: int = 0, density: float = 4e6) -> LabeledCloud:
    """:func:`mug_parts` sampled; the handle keeps its half outside the wall (a half-torus)."""
    return _sample(mug_parts(), density, seed, min_x=0.0405)


def hammer_like(seed: int = 0, density: float = 4e6) -> LabeledCloud:
    """A 25 cm long, 1.5 cm-radius cylindrical handle along x with a 12 cm box head."""
    handle = trimesh.creation.cylinder(radius=0.015, height=0.25)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    head = trimesh.creation.box([0.035, 0.12, 0.035])
    head.apply_translation([0.125 + 0.0175, 0, 0])
    return _sample([(handle, True), (head, False)], density, seed)
