"""Vessel families with loop handles: cups, jugs and kettles (``gen_cup_s<N>``,
``gen_jug_s<N>``, ``gen_kettle_s<N>``), built standing; the scenes lay them on their side or
stand them up (``--placement``). Each builder draws its sizes from ``rng`` and returns its
parts, the exact label of its loop (capsules along the loop outside the wall) and False.
Object frame as in :mod:`simgrasp.assets.generated`: meters, z up, before recentering."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import trimesh

from simgrasp.assets.family_shapes import bar, open_vessel, revolved, side_loop
from simgrasp.assets.generated_shapes import (
    DENSITY_ALUMINUM,
    DENSITY_CERAMIC,
    DENSITY_PLASTIC,
    Built,
    Part,
    arc_capsules,
    torus_arc,
    uniform,
)
from simgrasp.labels import Region


def _section(rng: np.random.Generator, round_radius: tuple[float, float]) -> tuple[float, float]:
    """A loop's section semi-axes (in its plane, across it): round (radius drawn in
    ``round_radius``) on half of them, else a flat strap 4-7 mm thick and 9-18 mm wide."""
    if rng.uniform() < 0.5:
        radius = uniform(rng, *round_radius)
        return radius, radius
    return uniform(rng, 0.002, 0.0035), uniform(rng, 0.0045, 0.009)


def _tapered(bottom: float, top: float, height: float) -> Callable[[float], float]:
    """The outer radius at height z (m) of a straight wall from ``bottom`` to ``top``."""
    return lambda z: bottom + (top - bottom) * float(np.clip(z / height, 0.0, 1.0))


def cup(rng: np.random.Generator) -> Built:
    """A cup: a ceramic body 2.6-3.6 cm in radius at its foot, up to 0.8 cm wider at its rim,
    5.5-9 cm high (2.5-4 mm wall), and a loop 1.4-2.4 cm in radius, round (3.5-5.5 mm) or a
    strap, half way up. The loop is the label."""
    bottom, height = uniform(rng, 0.026, 0.036), uniform(rng, 0.055, 0.09)
    top, wall = bottom + uniform(rng, 0.0, 0.008), uniform(rng, 0.0025, 0.004)
    body = open_vessel(bottom, top, height, wall, uniform(rng, 0.004, 0.006))
    radius = _tapered(bottom, top, height)
    major = uniform(rng, 0.014, 0.024)
    center_z = uniform(rng, 0.5, 0.6) * height
    center_z = min(center_z, height - major - 0.003)
    center = np.array([radius(center_z) + uniform(rng, 0.2, 0.45) * major, 0.0, center_z])
    loop, label = side_loop(center, major, _section(rng, (0.0035, 0.0055)), radius, wall)
    parts = [
        Part("body", body, DENSITY_CERAMIC, False),
        Part("handle", loop, DENSITY_CERAMIC, True),
    ]
    return parts, label, False


def jug(rng: np.random.Generator) -> Built:
    """A jug: a body 4.5-6.5 cm in radius, narrowing by up to 1 cm to its rim, 14-22 cm high
    (3-4.5 mm wall), ceramic or plastic, and a loop 3.5-5.5 cm in radius, round (7-11 mm)
    or a strap, about half way up. The loop is the label."""
    bottom, height = uniform(rng, 0.045, 0.065), uniform(rng, 0.14, 0.22)
    top, wall = bottom - uniform(rng, 0.0, 0.01), uniform(rng, 0.003, 0.0045)
    body = open_vessel(bottom, top, height, wall, uniform(rng, 0.005, 0.008))
    radius = _tapered(bottom, top, height)
    major = uniform(rng, 0.035, 0.055)
    center_z = min(uniform(rng, 0.5, 0.6) * height, height - major - 0.005)
    center = np.array([radius(center_z) + uniform(rng, 0.1, 0.35) * major, 0.0, center_z])
    loop, label = side_loop(center, major, _section(rng, (0.007, 0.011)), radius, wall)
    density = DENSITY_CERAMIC if rng.uniform() < 0.5 else DENSITY_PLASTIC
    return [Part("body", body, density, False), Part("handle", loop, density, True)], label, False


def _kettle_body(
    rng: np.random.Generator,
) -> tuple[list[trimesh.Trimesh], Callable[[float], float], float, float]:
    """A kettle's body (bulging wall 2-3 mm, lid, knob), its outer radius at height z, its
    lid's top height and the lid's radius."""
    base, bulge = uniform(rng, 0.06, 0.08), uniform(rng, 0.07, 0.095)
    top, height = uniform(rng, 0.04, 0.055), uniform(rng, 0.14, 0.20)
    wall, belly = uniform(rng, 0.002, 0.003), 0.45 * height
    body = revolved(
        [
            [0.0, 0.0],
            [base, 0.0],
            [bulge, belly],
            [top, height],
            [top - wall, height],
            [bulge - wall, belly],
            [base - wall, wall],
            [0.0, wall],
        ]
    )
    lid_top = height + 0.002
    lid = trimesh.creation.cylinder(radius=top - wall / 2, height=0.007, sections=64)
    lid.apply_translation([0.0, 0.0, lid_top - 0.0035])
    knob = trimesh.creation.cylinder(radius=0.008, height=0.014, sections=24)
    knob.apply_translation([0.0, 0.0, lid_top + 0.006])

    def radius(z: float) -> float:
        if z < belly:
            return base + (bulge - base) * max(z, 0.0) / belly
        return bulge + (top - bulge) * min((z - belly) / (height - belly), 1.0)

    return [body, lid, knob], radius, lid_top, top - wall / 2


def _arch(
    rng: np.random.Generator, lid_top: float, lid_radius: float
) -> tuple[trimesh.Trimesh, tuple[Region, ...]]:
    """An arch over the lid from x = -X to +X (X 0.6-0.8 of the lid's radius, less the
    section) rising 5-9 cm, round (8-12 mm) or a strap; capsules cover it above the lid."""
    thick, wide = _section(rng, (0.008, 0.012))
    reach = uniform(rng, 0.6, 0.8) * lid_radius - thick
    rise = uniform(rng, 0.05, 0.09)
    major = (reach**2 + rise**2) / (2 * rise)
    center = np.array([0.0, 0.0, lid_top + rise - major])
    start = np.arcsin(np.clip((lid_top - 0.003 - center[2]) / major, -1.0, 1.0))
    tube = torus_arc(center, major, thick, start, np.pi - start, width_radius=wide)
    clear = np.arcsin(np.clip((lid_top - center[2]) / major, -1.0, 1.0))
    return tube, arc_capsules(center, major, max(thick, wide), clear, np.pi - clear)


def kettle(rng: np.random.Generator) -> Built:
    """A kettle: an aluminium body bulging to 7-9.5 cm in radius, 14-20 cm high, a lid with
    a knob and a spout (a bar 0.8-1.2 cm in radius rising 40-55 degrees from the bulge on the
    -x side); its
    handle an arch over the lid (half of them) or a loop on the +x side. The handle is the
    label."""
    shell, radius, lid_top, lid_radius = _kettle_body(rng)
    if rng.uniform() < 0.5:
        handle, label = _arch(rng, lid_top, lid_radius)
    else:
        major = uniform(rng, 0.03, 0.045)
        center_z = lid_top - major - 0.01
        center = np.array([radius(center_z) + uniform(rng, 0.15, 0.35) * major, 0.0, center_z])
        handle, label = side_loop(center, major, _section(rng, (0.007, 0.011)), radius, 0.002)
    spout_radius, low = uniform(rng, 0.008, 0.012), 0.45 * lid_top  # at the bulge
    angle = np.radians(uniform(rng, 40.0, 55.0))
    start = np.array([-(radius(low) - 2 * spout_radius), 0.0, low])
    reach = (2 * spout_radius + uniform(rng, 0.04, 0.06)) / np.cos(angle)
    tip = start + reach * np.array([-np.cos(angle), 0.0, np.sin(angle)])
    spout, _ = bar(start, tip, spout_radius, spout_radius)
    names = ("body", "lid", "knob")
    parts = [Part(n, m, DENSITY_ALUMINUM, False) for n, m in zip(names, shell, strict=True)]
    parts += [
        Part("spout", spout, DENSITY_ALUMINUM, False),
        Part("handle", handle, DENSITY_PLASTIC, True),
    ]
    return parts, label, False
