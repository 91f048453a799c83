"""The body-of-revolution test and its stand-off region (simgrasp.autolabel.revolution) on
meshes whose answer is known: a cup with a ring handle, a short wide bowl, a flat blade."""

from __future__ import annotations

from typing import cast

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.autolabel.revolution import (
    RevolutionConfig,
    fit_revolution,
    standoff_pieces,
    standoff_points,
)

CONFIG = RevolutionConfig()
TURN = trimesh.transformations.rotation_matrix(0.7, [1.0, 2.0, 0.5])
TURN[:3, 3] = [0.3, -0.2, 0.1]
"""The test meshes are turned 0.7 rad about a skew axis and moved off the origin: the fit must
not rely on the frame."""
AXIS = TURN[:3, :3] @ np.array([0.0, 0.0, 1.0])
"""The meshes' axis (their z) after the turn."""


def _surface(mesh: trimesh.Trimesh, count: int = 40000) -> tuple[NDArray, NDArray]:
    """Points on ``mesh`` (m) and their faces' unit normals (seeded)."""
    points, faces = trimesh.sample.sample_surface(mesh, count, seed=0)
    return np.asarray(points), np.asarray(mesh.face_normals[faces])


def _tilted(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """``mesh`` moved by :data:`TURN`."""
    return mesh.copy().apply_transform(TURN)


def _cup_with_ring() -> tuple[trimesh.Trimesh, trimesh.Trimesh]:
    """A cup (radius 40 mm, 100 mm tall, along z) and a ring handle (major radius 22 mm,
    minor 5 mm) in the x-z plane whose center lies 50 mm out on x."""
    body = trimesh.creation.cylinder(radius=0.04, height=0.10, sections=96)
    ring = trimesh.creation.torus(major_radius=0.022, minor_radius=0.005)
    ring.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1.0, 0.0, 0.0]))
    ring.apply_translation([0.05, 0.0, 0.0])
    return body, ring


def test_a_cup_is_a_body_of_revolution_and_its_ring_stands_off_it() -> None:
    body, ring = _cup_with_ring()
    cup = _tilted(cast(trimesh.Trimesh, trimesh.util.concatenate([body, ring])))
    points, normals = _surface(cup)
    revolution = fit_revolution(points, normals, CONFIG)
    assert revolution is not None
    assert abs(revolution.axis @ AXIS) >= np.cos(np.radians(2.0))
    offset = revolution.center - TURN[:3, 3]
    assert np.linalg.norm(offset - (offset @ AXIS) * AXIS) <= 0.002
    assert np.allclose(np.median(revolution.wall), 0.04, atol=0.002)
    # The ring's points beyond the wall (its outer 35 mm) are found, the cup's are not.
    local = (points - TURN[:3, 3]) @ TURN[:3, :3]
    radius = np.linalg.norm(local[:, :2], axis=1)
    beyond = radius > 0.04 + CONFIG.margin + 0.002
    standoff = standoff_points(points, revolution, CONFIG.margin)
    assert standoff[beyond].mean() >= 0.98
    assert standoff[radius <= 0.04 + 1e-4].mean() <= 0.005
    pieces = standoff_pieces(points, standoff, CONFIG)
    assert len(pieces) == 1 and np.isin(np.flatnonzero(beyond), pieces[0]).mean() >= 0.98


def test_a_short_wide_bowl_finds_its_axis_though_its_faces_outweigh_its_wall() -> None:
    bowl = _tilted(trimesh.creation.cylinder(radius=0.06, height=0.02, sections=96))
    points, normals = _surface(bowl)
    revolution = fit_revolution(points, normals, CONFIG)
    assert revolution is not None
    assert abs(revolution.axis @ AXIS) >= np.cos(np.radians(2.0))
    assert not standoff_points(points, revolution, CONFIG.margin).any()


def test_a_flat_blade_and_a_box_are_no_bodies_of_revolution() -> None:
    for extents in ([0.03, 0.002, 0.15], [0.06, 0.04, 0.1]):
        points, normals = _surface(_tilted(trimesh.creation.box(extents)))
        assert fit_revolution(points, normals, CONFIG) is None


def test_a_mug_with_a_big_handle_is_one_and_a_drill_is_not() -> None:
    """A generated mug whose big round handle's sides make up much of its wall (radial share
    0.84) is a body of revolution; a generated drill, round about its housing, is not: its
    wall leaves azimuth sectors nearly empty (fill 0.64), so its battery cannot stand off."""
    from simgrasp.assets.generated import generate_tool
    from simgrasp.autolabel.virtual_scan import ScanConfig, scan_mesh

    for kind, seed, expected in (("mug", 0, True), ("drill", 2, False)):
        views = scan_mesh(generate_tool(kind, seed).mesh, ScanConfig())
        points = np.concatenate([v.points for v in views])
        normals = np.concatenate([v.normals for v in views])
        assert (fit_revolution(points, normals, CONFIG) is not None) == expected, kind
