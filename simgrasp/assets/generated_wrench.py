"""The generated wrench (``gen_wrench_s<N>``): a combination spanner lying flat, its flat bar
the exact label; made to check the automatic labeler on a flat handle between two heads that
are thicker and rounder than it (the YCB adjustable wrench's failure,
``docs/results/ycb-auto-labels/``) and kept out of the ``generated`` object set. Object frame
as in :mod:`simgrasp.assets.generated`: meters, z up, before recentering."""

from __future__ import annotations

import numpy as np
import trimesh

from simgrasp.assets.generated_shapes import DENSITY_STEEL, Part, uniform, x_box_region
from simgrasp.labels import Region


def _box(x0: float, x1: float, y0: float, y1: float, half_z: float, z: float) -> trimesh.Trimesh:
    """An axis-aligned box from ``x0`` to ``x1`` and ``y0`` to ``y1``, ``2 half_z`` thick at
    height ``z``."""
    box = trimesh.creation.box(extents=[x1 - x0, y1 - y0, 2 * half_z])
    box.apply_translation([(x0 + x1) / 2, (y0 + y1) / 2, z])
    return box


def _ring(radius: float, hole: float, half_z: float, x: float, z: float) -> trimesh.Trimesh:
    """The box end: a flat ring about z of outer ``radius`` and inner ``hole`` radius."""
    ring = trimesh.creation.annulus(r_min=hole, r_max=radius, height=2 * half_z, sections=48)
    ring.apply_translation([x, 0.0, z])
    return ring


def _open_end(
    radius: float, gap: float, half_z: float, x0: float, z: float
) -> list[trimesh.Trimesh]:
    """The open end from ``x0`` on: a block ``2 radius`` wide and two jaws beside an opening
    ``gap`` wide and about ``radius`` deep."""
    depth = radius
    block = _box(x0, x0 + 0.7 * radius, -radius, radius, half_z, z)
    jaws = [
        _box(x0 + 0.6 * radius, x0 + 0.7 * radius + depth, lo, hi, half_z, z)
        for lo, hi in ((-radius, -gap / 2), (gap / 2, radius))
    ]
    return [block, *jaws]


def wrench(rng: np.random.Generator) -> tuple[list[Part], tuple[Region, ...], bool]:
    """A combination spanner lying flat: a flat steel bar 9-16 cm long, 1.2-2 cm wide and
    5-8 mm thick (the label), a box end (a ring 2.2-3.4 cm across, its hole 55-65 % of that)
    at one end and an open end (jaws 0.8-1.9 cm apart) at the other, both heads 1.2-1.6 times
    the bar's thickness."""
    length = uniform(rng, 0.09, 0.16)
    half_y = uniform(rng, 0.006, 0.010)
    half_z = uniform(rng, 0.0025, 0.004)
    head_half_z = half_z * uniform(rng, 1.2, 1.6)
    radius = max(uniform(rng, 0.011, 0.017), 1.3 * half_y)
    gap = uniform(rng, 0.008, min(0.019, 1.3 * radius))
    z = head_half_z
    overlap = 0.002
    bar = _box(0.0, length, -half_y, half_y, half_z, z)
    ring = _ring(radius, uniform(rng, 0.55, 0.65) * radius, head_half_z, -radius + overlap, z)
    parts = [Part("handle", bar, DENSITY_STEEL, True), Part("box_end", ring, DENSITY_STEEL, False)]
    parts += [
        Part("open_end", mesh, DENSITY_STEEL, False)
        for mesh in _open_end(radius, gap, head_half_z, length - overlap, z)
    ]
    label = x_box_region(0.0, length, half_y, half_z, z)
    return parts, (label,), False
