"""The generated knife (``gen_knife_s<N>``): a kitchen or table knife lying flat, its handle
the exact label; made to check the automatic labeler on long tools
(``scripts/generated_labels.py``) and kept out of the ``generated`` object set. Object frame
as in :mod:`simgrasp.assets.generated`: meters, z up, before recentering."""

from __future__ import annotations

from typing import cast

import numpy as np
import trimesh

from simgrasp.assets.generated_shapes import (
    DENSITY_STEEL,
    DENSITY_WOOD,
    Part,
    uniform,
    x_box_region,
    x_cylinder,
)
from simgrasp.labels import Box, Region


def _blade(length: float, height: float, spine: float, x0: float, z: float) -> trimesh.Trimesh:
    """A knife blade lying flat: a wedge from its spine (``spine`` thick, at y = 0) to its
    edge (0.5 mm, at y = -``height``), ``length`` long from ``x0`` along x to a point at the
    spine, centred at height ``z`` (the convex hull of its corners: watertight)."""
    edge = 0.0005
    root = [[x0, 0.0, z + s * spine / 2] for s in (-1, 1)]
    root += [[x0, -height, z + s * edge / 2] for s in (-1, 1)]
    tip = [[x0 + length, -0.1 * height, z + s * edge / 2] for s in (-1, 1)]
    return cast(trimesh.Trimesh, trimesh.Trimesh(np.array(root + tip)).convex_hull)


def knife(rng: np.random.Generator) -> tuple[list[Part], tuple[Region, ...], bool]:
    """A kitchen or table knife lying flat: a handle 9-13 cm long, either round-ish (an
    elliptic bar 2.2-2.8 cm in the blade's plane and 1.4-2 cm across it) or flat (1.2-2.2 cm
    by 3-9 mm: a table knife's, or scales on a tang), plain, with finger grooves or with a
    pommel (:func:`_knife_grip`), a flat one riveted on about half of them; optionally a
    bolster (a short bar 5-20 % wider) where the blade begins, and a wedge blade 9-20 cm long
    and 1.8-4.5 cm high whose spine is 1.5-4 mm thick and at most 3/4 of the handle's
    thickness; the handle is the label. Made to check the automatic labeler on long tools
    (``scripts/generated_labels.py``), kept out of the ``generated`` set."""
    handle_length = uniform(rng, 0.09, 0.13)
    flat = rng.uniform() < 0.5
    half_y = uniform(rng, 0.006, 0.011) if flat else uniform(rng, 0.011, 0.014)
    half_z = uniform(rng, 0.0015, 0.0045) if flat else uniform(rng, 0.007, 0.010)
    grip, rivets, label = _knife_grip(rng, handle_length, half_y, half_z, flat)
    bolster = uniform(rng, 0.008, 0.015) if rng.uniform() < 0.5 else 0.0
    blade_length = uniform(rng, 0.09, 0.20)
    blade_height = uniform(rng, 0.018, 0.045)
    spine = uniform(rng, 0.0015, min(0.004, 1.5 * half_z))
    overlap = 0.003
    parts = [Part("handle", mesh, DENSITY_WOOD, True) for mesh in grip]
    parts += [Part("handle", mesh, DENSITY_STEEL, True) for mesh in rivets]
    x_blade = handle_length - overlap
    if bolster > 0:
        grow = uniform(rng, 1.05, 1.2)
        end = handle_length + bolster
        ring = x_cylinder(grow * half_y, min(grow * half_z, half_z + 0.002), x_blade, end, half_z)
        parts.append(Part("bolster", ring, DENSITY_STEEL, False))
        x_blade = end - overlap
    blade = _blade(blade_length, blade_height, spine, x_blade, half_z)
    blade.apply_translation([0.0, 0.6 * half_y, 0.0])
    parts.append(Part("blade", blade, DENSITY_STEEL, False))
    return parts, (label,), False


def _knife_grip(
    rng: np.random.Generator, length: float, half_y: float, half_z: float, flat: bool
) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh], Box]:
    """A knife's handle along x from 0 to ``length`` (axis at height ``half_z``): its meshes,
    its rivets (steel; none on most) and its label box. Plain, with 3-4 finger grooves (every
    other section 15-25 % narrower in the blade's plane) or with a pommel (a butt cap 1-1.5 cm
    long and 15-30 % wider); a flat handle has 2-3 rivets through it (2-2.5 mm radius,
    standing 0.5 mm proud of each side) on about half of them. Features that could split the
    detector's candidates along a handle."""
    style = rng.integers(3)
    start, wide_y, wide_z = 0.0, half_y, half_z
    if style == 1:
        grooves = int(rng.integers(3, 5))
        narrow = uniform(rng, 0.75, 0.85)
        pieces = 2 * grooves + 1
        step = length / pieces
        grip = [
            x_cylinder(
                half_y * (narrow if k % 2 else 1.0), half_z, k * step, (k + 1) * step, half_z
            )
            for k in range(pieces)
        ]
    else:
        grip = [x_cylinder(half_y, half_z, 0.0, length, half_z)]
    if style == 2:
        grow = uniform(rng, 1.15, 1.3)
        start = -uniform(rng, 0.010, 0.015)
        wide_y, wide_z = grow * half_y, min(grow * half_z, half_z + 0.002)
        grip.append(x_cylinder(wide_y, wide_z, start, 0.002, half_z))
    rivets: list[trimesh.Trimesh] = []
    if flat and rng.uniform() < 0.5:
        radius = uniform(rng, 0.002, 0.0025)
        for x in np.linspace(0.2, 0.8, int(rng.integers(2, 4))) * length:
            rivet = trimesh.creation.cylinder(radius=radius, height=2 * half_z + 0.001, sections=24)
            rivet.apply_translation([x, 0.0, half_z])
            rivets.append(rivet)
        wide_z = max(wide_z, half_z + 0.0005)
    return grip, rivets, x_box_region(start, length, wide_y, wide_z, half_z)
