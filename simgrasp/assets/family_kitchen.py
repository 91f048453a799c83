"""Kitchen families with a long thin handle off a bowl or a wide body: spoons, ladles, frying
pans and saucepans (``gen_spoon_s<N>``, ``gen_ladle_s<N>``, ``gen_frying_pan_s<N>``,
``gen_saucepan_s<N>``). Each builder draws its sizes from ``rng`` and returns its parts, the
exact label of its handle bar and False (not graspable everywhere). Object frame as in
:mod:`simgrasp.assets.generated`: meters, z up, before recentering."""

from __future__ import annotations

import numpy as np
import trimesh

from simgrasp.assets.family_shapes import bar, open_vessel, revolved
from simgrasp.assets.generated_shapes import (
    DENSITY_ALUMINUM,
    DENSITY_PLASTIC,
    DENSITY_STEEL,
    DENSITY_WOOD,
    Built,
    Part,
    uniform,
)


def _dish(depth: float, thickness: float, power: float) -> trimesh.Trimesh:
    """A bowl of unit rim radius (scale it in x and y): its outer surface ``depth *
    r**power`` (m) from its bottom at z = 0, its inner surface ``thickness`` (m) above."""
    radii = np.linspace(0.0, 1.0, 24)
    outer = np.column_stack([radii, depth * radii**power])
    inner = np.column_stack([radii[::-1], thickness + depth * radii[::-1] ** power])
    return revolved(np.concatenate([outer, inner]), sections=48)


def _raised(start: np.ndarray, length: float, angle: float) -> np.ndarray:
    """The point ``length`` (m) from ``start`` along +x raised by ``angle`` (rad)."""
    return start + length * np.array([np.cos(angle), 0.0, np.sin(angle)])


def spoon(rng: np.random.Generator) -> Built:
    """A spoon: an oval bowl 4-7 cm long, 2.8-4.4 cm wide and 0.7-1.3 cm deep (1.5-2.5 mm
    thick), and a flat handle 11-17 cm long, 0.9-1.6 cm wide and 2.5-4.5 mm thick rising
    4-15 degrees from its rim, of steel. The handle is the label."""
    half_length, half_width = uniform(rng, 0.020, 0.035), uniform(rng, 0.014, 0.022)
    depth, thickness = uniform(rng, 0.007, 0.013), uniform(rng, 0.0015, 0.0025)
    bowl = _dish(depth, thickness, 2.0)
    bowl.apply_scale([half_length, half_width, 1.0])
    length = uniform(rng, 0.11, 0.17)
    half_y, half_z = uniform(rng, 0.0045, 0.008), uniform(rng, 0.00125, 0.00225)
    angle = np.radians(uniform(rng, 4.0, 15.0))
    density = DENSITY_STEEL
    start = np.array([0.9 * half_length, 0.0, depth + thickness / 2])
    handle, label = bar(start, _raised(start, length, angle), half_y, half_z)
    parts = [Part("bowl", bowl, density, False), Part("handle", handle, density, True)]
    return parts, (label,), False


def ladle(rng: np.random.Generator) -> Built:
    """A ladle: a round bowl 3.5-5 cm in radius and 0.6-0.9 of that deep (2-3 mm wall),
    and a flat handle 20-30 cm long, 1.2-2 cm wide and 3-5 mm thick rising 35-60 degrees
    from its rim; steel or (half of them) plastic. The handle is the label."""
    radius = uniform(rng, 0.035, 0.05)
    depth, thickness = uniform(rng, 0.6, 0.9) * radius, uniform(rng, 0.002, 0.003)
    bowl = _dish(depth, thickness, 2.0)
    bowl.apply_scale([radius, radius, 1.0])
    length = uniform(rng, 0.20, 0.30)
    half_y, half_z = uniform(rng, 0.006, 0.010), uniform(rng, 0.0015, 0.0025)
    angle = np.radians(uniform(rng, 35.0, 60.0))
    density = DENSITY_PLASTIC if rng.uniform() < 0.5 else DENSITY_STEEL
    start = np.array([radius - 0.002, 0.0, depth + thickness / 2])
    handle, label = bar(start, _raised(start, length, angle), half_y, half_z)
    parts = [Part("bowl", bowl, density, False), Part("handle", handle, density, True)]
    return parts, (label,), False


def frying_pan(rng: np.random.Generator) -> Built:
    """A frying pan: a flared aluminium body (floor radius 8-11 cm, rim 1.5-3 cm wider,
    3.5-5.5 cm high, 3-5 mm wall, straight where the handle joins) and a handle 17-24 cm
    long, 2-3 cm wide and 1.2-2 cm thick rising 8-20 degrees from the rim, of wood or
    plastic. The handle is the label."""
    floor_radius = uniform(rng, 0.08, 0.11)
    rim_radius = floor_radius + uniform(rng, 0.015, 0.03)
    height, wall = uniform(rng, 0.035, 0.055), uniform(rng, 0.003, 0.005)
    length = uniform(rng, 0.17, 0.24)
    half_y, half_z = uniform(rng, 0.010, 0.015), uniform(rng, 0.006, 0.010)
    angle = np.radians(uniform(rng, 8.0, 20.0))
    band = 2 * half_z + 0.004  # the rim's straight band the handle joins
    body = open_vessel(floor_radius, rim_radius, height, wall, wall, band)
    start = np.array([rim_radius - wall / 2, 0.0, height - half_z - 0.002])
    handle, label = bar(start, _raised(start, length, angle), half_y, half_z)
    density = DENSITY_WOOD if rng.uniform() < 0.5 else DENSITY_PLASTIC
    parts = [
        Part("body", body, DENSITY_ALUMINUM, False),
        Part("handle", handle, density, True),
    ]
    return parts, (label,), False


def saucepan(rng: np.random.Generator) -> Built:
    """A saucepan: a straight aluminium body 6.5-10 cm in radius and 7-12 cm high (wall 2-3 mm,
    floor 4-6 mm) and a handle 14-20 cm long, 1.8-2.6 cm wide and 1.2-2.2 cm thick, 1-2.5 cm
    below the rim, level or rising up to 15 degrees. The handle is the label."""
    radius, height = uniform(rng, 0.065, 0.10), uniform(rng, 0.07, 0.12)
    wall, floor = uniform(rng, 0.002, 0.003), uniform(rng, 0.004, 0.006)
    body = open_vessel(radius, radius, height, wall, floor)
    length = uniform(rng, 0.14, 0.20)
    half_y, half_z = uniform(rng, 0.009, 0.013), uniform(rng, 0.006, 0.011)
    angle = np.radians(uniform(rng, 0.0, 15.0))
    start = np.array([radius - wall / 2, 0.0, height - uniform(rng, 0.01, 0.025)])
    handle, label = bar(start, _raised(start, length, angle), half_y, half_z)
    parts = [
        Part("body", body, DENSITY_ALUMINUM, False),
        Part("handle", handle, DENSITY_PLASTIC, True),
    ]
    return parts, (label,), False
