"""Tool families lying flat: scissors and pliers (two grips), knives with a bolster, table
knives whose blade is as thick as their handle, and brushes (``gen_scissors_s<N>``,
``gen_pliers_s<N>``, ``gen_chef_knife_s<N>``, ``gen_table_knife_s<N>``, ``gen_brush_s<N>``).
Each builder draws its sizes from ``rng`` and returns its parts, the exact label of its grip(s)
and False. Object frame as in :mod:`simgrasp.assets.generated`: meters, z up, before
recentering; the tools lie in the x-y plane."""

from __future__ import annotations

import numpy as np
import trimesh

from simgrasp.assets.family_shapes import bar, flat_ring, slab
from simgrasp.assets.generated_shapes import (
    DENSITY_PLASTIC,
    DENSITY_STEEL,
    DENSITY_WOOD,
    Built,
    Part,
    uniform,
)
from simgrasp.labels import Region

DENSITY_BRISTLES = 450.0
"""kg/m^3: a bundle of nylon bristles with the air between them."""


def _plate(outline: list[tuple[float, float]], z: float, half_z: float) -> trimesh.Trimesh:
    """A flat plate: the convex hull of an x-y ``outline`` (m), ``2 half_z`` thick at ``z``."""
    return slab([(x, y, z + s * half_z) for x, y in outline for s in (-1, 1)])


def _in_plane(direction: np.ndarray, along: float, across: float) -> tuple[float, float]:
    """The x-y point ``along`` a unit in-plane ``direction`` and ``across`` to its left."""
    return (
        float(along * direction[0] - across * direction[1]),
        float(along * direction[1] + across * direction[0]),
    )


def scissors(rng: np.random.Generator) -> Built:
    """Scissors, closed to 6-16 degrees: two steel blades 6-11 cm long (1.5-2.5 mm thick,
    stacked), a pivot screw, and two plastic grips, each a shank 2-3.5 cm long and a finger
    ring (hole 8-12 mm in radius, rim 3-5 mm wide, 5-8 mm thick). Both grips are the label."""
    half_z, blade = uniform(rng, 0.0025, 0.004), uniform(rng, 0.00075, 0.00125)
    length, root = uniform(rng, 0.06, 0.11), uniform(rng, 0.010, 0.016)
    opening, shank = np.radians(uniform(rng, 3.0, 8.0)), uniform(rng, 0.02, 0.035)
    hole, rim = uniform(rng, 0.008, 0.012), uniform(rng, 0.003, 0.005)
    middle, outer = hole + rim / 2, hole + rim
    spread = max(
        np.radians(uniform(rng, 10.0, 20.0)), np.arcsin((outer + 0.002) / (shank + middle))
    )
    screw = _pivot(0.004, min(2 * blade + 0.0005, half_z), half_z)
    parts = [Part("pivot", screw, DENSITY_STEEL, False)]
    regions: list[Region] = []
    for side in (-1.0, 1.0):
        ahead = np.array([np.cos(opening), side * np.sin(opening), 0.0])
        outline = [_in_plane(ahead, -0.008, s * root / 2) for s in (-1, 1)]
        outline += [_in_plane(ahead, length, s * 0.001) for s in (-1, 1)]
        plate = _plate(outline, half_z + side * blade, blade)
        parts.append(Part("blade", plate, DENSITY_STEEL, False))
        back = np.array([-np.cos(spread), side * np.sin(spread), 0.0])
        center = np.array([0.0, 0.0, half_z])
        joint, _ = bar(center, center + 0.012 * back, 0.8 * half_z, 0.004, (0, 0, 1))
        root_end, ring_end = center + 0.01 * back, center + (shank + rim / 2) * back
        grip, box = bar(root_end, ring_end, 0.8 * half_z, 0.004, (0, 0, 1))
        ring, capsules = flat_ring(center + (shank + middle) * back, outer, hole, half_z)
        parts += [Part("joint", joint, DENSITY_PLASTIC, False)]
        parts += [Part("handle", m, DENSITY_PLASTIC, True) for m in (grip, ring)]
        regions += [box, *capsules]
    return parts, tuple(regions), False


def _pivot(radius: float, half_height: float, z: float) -> trimesh.Trimesh:
    """A disk (a pivot screw, a joint) about z of ``radius``, ``2 half_height`` tall at ``z``."""
    disk = trimesh.creation.cylinder(radius=radius, height=2 * half_height, sections=32)
    disk.apply_translation([0.0, 0.0, z])
    return disk


def pliers(rng: np.random.Generator) -> Built:
    """Pliers: steel jaws 3-5 cm long (2-2.6 cm wide at the joint, 0.6-1 cm at the tip,
    8-12 mm thick), a joint 1-1.3 cm in radius, and two handles 10-14 cm long spreading
    5-10 degrees from it, steel near the joint, then plastic grips 1.4-2 cm wide and 1-1.4 cm
    thick from 2 cm on. Both grips are the label."""
    half_z, grip_z = uniform(rng, 0.004, 0.006), uniform(rng, 0.005, 0.007)
    jaw, root, tip = uniform(rng, 0.03, 0.05), uniform(rng, 0.020, 0.026), uniform(rng, 0.006, 0.01)
    joint, length = uniform(rng, 0.010, 0.013), uniform(rng, 0.10, 0.14)
    spread, grip_y = np.radians(uniform(rng, 5.0, 10.0)), uniform(rng, 0.007, 0.010)
    z = grip_z
    jaws = _plate([(0.0, -root / 2), (0.0, root / 2), (jaw, -tip / 2), (jaw, tip / 2)], z, half_z)
    parts = [
        Part("jaws", jaws, DENSITY_STEEL, False),
        Part("joint", _pivot(joint, half_z, z), DENSITY_STEEL, False),
    ]
    regions: list[Region] = []
    center = np.array([0.0, 0.0, z])
    for side in (-1.0, 1.0):
        back = np.array([-np.cos(spread), side * np.sin(spread), 0.0])
        steel, _ = bar(center, center + 0.022 * back, 0.9 * half_z, 0.005, (0, 0, 1))
        grip, box = bar(center + 0.02 * back, center + length * back, grip_z, grip_y, (0, 0, 1))
        parts += [
            Part("shank", steel, DENSITY_STEEL, False),
            Part("handle", grip, DENSITY_PLASTIC, True),
        ]
        regions.append(box)
    return parts, tuple(regions), False


def _wedge_blade(
    x0: float, length: float, height: float, spine: float, edge: float, y: float, z: float
) -> trimesh.Trimesh:
    """A blade lying flat from ``x0`` along x: its spine (``spine`` thick) at ``y``, its edge
    (``edge`` thick) ``height`` below it in y, its point at the spine's side (m)."""
    corners = [(x0, y, z + s * spine / 2) for s in (-1, 1)]
    corners += [(x0, y - height, z + s * edge / 2) for s in (-1, 1)]
    corners += [(x0 + length, y - 0.1 * height, z + s * edge / 2) for s in (-1, 1)]
    corners += [(x0 + 0.8 * length, y, z + s * spine / 4) for s in (-1, 1)]
    return slab(corners)


def chef_knife(rng: np.random.Generator) -> Built:
    """A chef's knife lying flat: a wooden handle 10-13 cm long (2-2.8 cm by 1.4-2 cm), a
    steel bolster 0.8-1.5 cm long and 5-20 % wider, and a blade 15-23 cm long and 3.5-5 cm
    high with a 2-3 mm spine. The handle is the label; the bolster is not."""
    length, half_y, half_z = (
        uniform(rng, 0.10, 0.13),
        uniform(rng, 0.010, 0.014),
        uniform(rng, 0.007, 0.010),
    )
    grow, bolster = uniform(rng, 1.05, 1.2), uniform(rng, 0.008, 0.015)
    z = grow * half_z
    handle, label = bar((0.0, 0.0, z), (length, 0.0, z), half_y, half_z, (0, 1, 0))
    start, end = (length - 0.003, 0.0, z), (length + bolster, 0.0, z)
    collar, _ = bar(start, end, grow * half_y, grow * half_z, (0, 1, 0))
    height = uniform(rng, 0.035, 0.05)
    blade_length, spine = uniform(rng, 0.15, 0.23), uniform(rng, 0.002, 0.003)
    x0 = length + bolster - 0.003
    blade = _wedge_blade(x0, blade_length, height, spine, 0.0005, 0.7 * half_y, z)
    parts = [
        Part("handle", handle, DENSITY_WOOD, True),
        Part("bolster", collar, DENSITY_STEEL, False),
        Part("blade", blade, DENSITY_STEEL, False),
    ]
    return parts, (label,), False


def table_knife(rng: np.random.Generator) -> Built:
    """A table knife of one piece of steel lying flat: a flat handle 9-12 cm long, 1.2-1.8 cm
    wide and 4-7 mm thick, and a blade 9-12 cm long and 1.4-2.2 cm high whose spine is as
    thick as the handle and whose edge is 0.6-1 of that. The handle is the label."""
    length, half_y, half_z = (
        uniform(rng, 0.09, 0.12),
        uniform(rng, 0.006, 0.009),
        uniform(rng, 0.002, 0.0035),
    )
    handle, label = bar((0.0, 0.0, half_z), (length, 0.0, half_z), half_y, half_z, (0, 1, 0))
    blade_length, height = uniform(rng, 0.09, 0.12), uniform(rng, 0.014, 0.022)
    edge = 2 * half_z * uniform(rng, 0.6, 1.0)
    blade = _wedge_blade(length - 0.003, blade_length, height, 2 * half_z, edge, half_y, half_z)
    parts = [
        Part("handle", handle, DENSITY_STEEL, True),
        Part("blade", blade, DENSITY_STEEL, False),
    ]
    return parts, (label,), False


def _block(x0: float, x1: float, half_y: float, half_z: float, z: float) -> trimesh.Trimesh:
    """An axis-aligned box from ``x0`` to ``x1`` along x, ``2 half_y`` by ``2 half_z``."""
    box = trimesh.creation.box([x1 - x0, 2 * half_y, 2 * half_z])
    box.apply_translation([(x0 + x1) / 2, 0.0, z])
    return box


def brush(rng: np.random.Generator) -> Built:
    """A flat paint brush lying flat: a wooden handle 10-18 cm long (1.4-2.4 cm by 1-2 cm),
    a steel ferrule 1.5-2.5 cm long, 2.4-6 cm wide and 1.2-2 cm thick, and bristles 3-5.5 cm
    long, a little narrower and thinner. The handle is the label."""
    length, half_y, half_z = (
        uniform(rng, 0.10, 0.18),
        uniform(rng, 0.007, 0.012),
        uniform(rng, 0.005, 0.010),
    )
    ferrule, wide = uniform(rng, 0.015, 0.025), max(uniform(rng, 0.012, 0.03), 1.2 * half_y)
    thick = max(uniform(rng, 0.006, 0.010), half_z + 0.001)
    handle, label = bar((0.0, 0.0, thick), (length, 0.0, thick), half_y, half_z, (0, 1, 0))
    end = length - 0.003 + ferrule
    hair = uniform(rng, 0.03, 0.055)
    collar = _block(length - 0.003, end, wide, thick, thick)
    bristles = _block(end - 0.002, end + hair, 0.95 * wide, 0.8 * thick, thick)
    parts = [
        Part("handle", handle, DENSITY_WOOD, True),
        Part("ferrule", collar, DENSITY_STEEL, False),
        Part("bristles", bristles, DENSITY_BRISTLES, False),
    ]
    return parts, (label,), False
