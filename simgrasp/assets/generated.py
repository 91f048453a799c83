"""Procedurally generated handle-bearing objects whose handle labels are exact by construction.

Every object is a union of watertight primitive parts (concatenated, not booleaned: parts
overlap by a few millimeters where they join). Sizes are drawn from realistic ranges by a
seed. The object frame is z up, the object resting on z = 0 in its constructed pose, and the
x/y origin at the center of its footprint (the x/y bounding box). Units are meters and
kilograms.

Handle thicknesses stay within 2-4 cm so a parallel gripper with ~8.5 cm maximum opening can
close on them (but the flat strap of ``strap_mug``, one of the kinds made for training the
single-view classifier); ``can`` and ``fruit`` are graspable everywhere (whole-object labels)
and stay below 8 cm across. The primitives are in :mod:`simgrasp.assets.generated_shapes`,
the knife in :mod:`simgrasp.assets.generated_knife`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.assets.families import FAMILY_BUILDERS, FAMILY_KINDS
from simgrasp.assets.generated_knife import knife
from simgrasp.assets.generated_shapes import (
    DENSITY_ALUMINUM,
    DENSITY_CERAMIC,
    DENSITY_FILLED_CAN,
    DENSITY_FRUIT,
    DENSITY_PLASTIC,
    DENSITY_STEEL,
    DENSITY_WOOD,
    LABEL_MARGIN,
    Built,
    Part,
    arc_capsules,
    torus_arc,
    uniform,
    x_box_region,
    x_cylinder,
)
from simgrasp.assets.generated_wrench import wrench
from simgrasp.assets.object import ObjectAsset
from simgrasp.errors import SimgraspError
from simgrasp.labels import Box, Capsule, HandleLabel, Region
from simgrasp.seeding import rng_for


@dataclass(frozen=True)
class GeneratedTool:
    """A generated object's parts and handle regions, before it becomes an ``ObjectAsset``."""

    kind: str
    seed: int
    parts: tuple[Part, ...]
    handle: HandleLabel

    @property
    def mass(self) -> float:
        """Sum of part volume x density (kg); the few-mm overlaps at joints are counted twice."""
        return float(sum(p.mesh.volume * p.density for p in self.parts))


def _mug_parts(
    radius: float,
    height: float,
    wall: float,
    bottom: float,
    loop: tuple[float, float],
    section: tuple[float, float],
) -> Built:
    """A ceramic mug: an open body of ``radius`` and ``height`` with a ``wall`` and a
    ``bottom`` thickness, and a handle on a loop (``loop``: its radius and how far its center
    lies outside the wall) whose section has semi-axes ``section`` (in the loop's plane,
    across it). The handle enters the wall by half its thickness (centerline x = radius - wall
    / 2); the label covers the arc outside the outer wall (centerline x >= radius)."""
    major, offset = loop
    thick, wide = section
    body = trimesh.creation.annulus(r_min=radius - wall, r_max=radius, height=height, sections=64)
    body.apply_translation([0, 0, height / 2])
    base = trimesh.creation.cylinder(radius=radius - wall + 0.0005, height=bottom, sections=64)
    base.apply_translation([0, 0, bottom / 2])
    center = np.array([radius + offset, 0.0, 0.55 * height])
    inner = np.arccos(-(offset + wall / 2) / major)
    handle = torus_arc(center, major, thick, -inner, inner, width_radius=wide)
    outside = np.arccos(-offset / major)
    regions = arc_capsules(center, major, wide, -outside, outside)
    parts = [
        Part("body", body, DENSITY_CERAMIC, False),
        Part("bottom", base, DENSITY_CERAMIC, False),
        Part("handle", handle, DENSITY_CERAMIC, True),
    ]
    return parts, regions, False


def _mug(rng: np.random.Generator) -> Built:
    """A mug whose handle is a round tube (2-2.5 cm thick) on a loop of 28-34 mm."""
    radius = uniform(rng, 0.037, 0.043)
    height = uniform(rng, 0.085, 0.105)
    wall = uniform(rng, 0.003, 0.0045)
    bottom = uniform(rng, 0.005, 0.007)
    minor = uniform(rng, 0.010, 0.0125)
    major = uniform(rng, 0.028, 0.034)
    offset = uniform(rng, 0.25, 0.4) * major  # torus center outside the wall
    return _mug_parts(radius, height, wall, bottom, (major, offset), (minor, minor))


def _strap_mug(rng: np.random.Generator) -> Built:
    """A mug whose handle is a flat strap (4-7 mm thick in the loop's plane, 9-16 mm wide
    across it) on a loop of 22-34 mm, as most real mugs' handles are, on a body of 3.3-4.5 cm
    radius with a 2.5-4 mm wall."""
    radius = uniform(rng, 0.033, 0.045)
    height = uniform(rng, 0.075, 0.11)
    wall = uniform(rng, 0.0025, 0.004)
    bottom = uniform(rng, 0.004, 0.007)
    thickness = uniform(rng, 0.004, 0.007)
    width = uniform(rng, 0.009, 0.016)
    major = uniform(rng, 0.022, 0.034)
    offset = uniform(rng, 0.15, 0.45) * major  # loop center outside the wall
    return _mug_parts(radius, height, wall, bottom, (major, offset), (thickness / 2, width / 2))


def _drill(rng: np.random.Generator) -> Built:
    """A cordless drill standing on its battery: a pistol grip (an elliptic bar 3.2-4 cm deep
    and 2.6-3.2 cm wide, 8-11 cm long, leaning 8-20 degrees back) between a battery box and
    a motor housing (a cylinder along x) with a chuck in front; the grip is the handle."""
    battery = [uniform(rng, 0.07, 0.09), uniform(rng, 0.055, 0.07), uniform(rng, 0.025, 0.04)]
    half_x, half_y = uniform(rng, 0.016, 0.02), uniform(rng, 0.013, 0.016)
    grip_length = uniform(rng, 0.08, 0.11)
    lean = np.radians(uniform(rng, 8.0, 20.0))
    radius = uniform(rng, 0.025, 0.032)
    housing_length = uniform(rng, 0.15, 0.20)
    embed = 0.004  # the grip's ends reach this far into the battery and the housing
    base = trimesh.creation.box(battery)
    base.apply_translation([0.0, 0.0, battery[2] / 2])
    axis = np.array([-np.sin(lean), 0.0, np.cos(lean)])  # up and back
    bottom = np.array([0.0, 0.0, battery[2] - embed])
    length = grip_length + 2 * embed
    tilt = trimesh.transformations.rotation_matrix(-lean, [0, 1, 0])
    grip = trimesh.creation.cylinder(radius=1.0, height=length, sections=48)
    grip.apply_scale([half_x, half_y, 1.0])
    grip.apply_transform(tilt)
    grip.apply_translation(bottom + axis * length / 2)
    top = bottom + axis * length
    housing = x_cylinder(radius, radius, top[0] - 0.05, top[0] - 0.05 + housing_length, 0.0)
    housing.apply_translation([0.0, 0.0, top[2] - embed + radius])
    chuck_x = top[0] - 0.05 + housing_length
    chuck = x_cylinder(0.6 * radius, 0.6 * radius, chuck_x - 0.003, chuck_x + 0.04, 0.0)
    chuck.apply_translation([0.0, 0.0, top[2] - embed + radius])
    region = Box(
        center=bottom + axis * length / 2,
        object_R_box=tilt[:3, :3],
        half_extents=np.array([half_x, half_y, length / 2]) + LABEL_MARGIN,
    )
    parts = [
        Part("battery", base, DENSITY_FILLED_CAN, False),
        Part("grip", grip, DENSITY_PLASTIC, True),
        Part("housing", housing, DENSITY_PLASTIC, False),
        Part("chuck", chuck, DENSITY_STEEL, False),
    ]
    return parts, (region,), False


def _hammer(rng: np.random.Generator) -> Built:
    length = uniform(rng, 0.22, 0.30)
    half_z = uniform(rng, 0.013, 0.018)  # elliptic grip: 2.6-3.6 cm tall
    half_y = uniform(rng, 0.011, 0.014)  # 2.2-2.8 cm wide
    head_length = uniform(rng, 0.095, 0.12)  # along y
    head_side = uniform(rng, 0.024, 0.028)
    overlap = 0.002
    z_axis = head_side / 2
    handle = x_cylinder(half_y, half_z, 0.0, length, z_axis)
    head = trimesh.creation.box([head_side, head_length, head_side])
    head.apply_translation([length - overlap + head_side / 2, 0.0, z_axis])
    parts = [
        Part("handle", handle, DENSITY_WOOD, True),
        Part("head", head, DENSITY_STEEL, False),
    ]
    return parts, (x_box_region(0.0, length, half_y, half_z, z_axis),), False


def _spatula(rng: np.random.Generator) -> Built:
    handle_length = uniform(rng, 0.15, 0.20)
    handle_radius = uniform(rng, 0.010, 0.014)
    blade_length = uniform(rng, 0.08, 0.11)
    blade_width = uniform(rng, 0.06, 0.08)
    blade_thickness = uniform(rng, 0.002, 0.003)
    overlap = 0.003
    handle = x_cylinder(handle_radius, handle_radius, 0.0, handle_length, handle_radius)
    blade = trimesh.creation.box([blade_length, blade_width, blade_thickness])
    blade.apply_translation([handle_length - overlap + blade_length / 2, 0.0, blade_thickness / 2])
    parts = [
        Part("handle", handle, DENSITY_PLASTIC, True),
        Part("blade", blade, DENSITY_STEEL, False),
    ]
    region = x_box_region(0.0, handle_length, handle_radius, handle_radius, handle_radius)
    return parts, (region,), False


def _screwdriver(rng: np.random.Generator) -> Built:
    handle_length = uniform(rng, 0.09, 0.12)
    handle_radius = uniform(rng, 0.012, 0.017)
    shaft_length = uniform(rng, 0.08, 0.15)
    shaft_radius = uniform(rng, 0.0025, 0.004)
    overlap = 0.005
    handle = x_cylinder(handle_radius, handle_radius, 0.0, handle_length, handle_radius)
    shaft = x_cylinder(
        shaft_radius,
        shaft_radius,
        handle_length - overlap,
        handle_length + shaft_length,
        handle_radius,
    )
    parts = [
        Part("handle", handle, DENSITY_PLASTIC, True),
        Part("shaft", shaft, DENSITY_STEEL, False),
    ]
    region = x_box_region(0.0, handle_length, handle_radius, handle_radius, handle_radius)
    return parts, (region,), False


def _pan(rng: np.random.Generator) -> Built:
    radius = uniform(rng, 0.09, 0.12)
    height = uniform(rng, 0.035, 0.05)
    wall = uniform(rng, 0.003, 0.004)
    handle_length = uniform(rng, 0.15, 0.20)
    handle_radius = uniform(rng, 0.011, 0.015)
    body = trimesh.creation.annulus(r_min=radius - wall, r_max=radius, height=height, sections=96)
    body.apply_translation([0, 0, height / 2])
    base = trimesh.creation.cylinder(radius=radius - wall + 0.0005, height=wall, sections=96)
    base.apply_translation([0, 0, wall / 2])
    z_axis = height - handle_radius
    x0 = radius - wall / 2
    handle = x_cylinder(handle_radius, handle_radius, x0, radius + handle_length, z_axis)
    parts = [
        Part("body", body, DENSITY_ALUMINUM, False),
        Part("bottom", base, DENSITY_ALUMINUM, False),
        Part("handle", handle, DENSITY_WOOD, True),
    ]
    region = x_box_region(x0, radius + handle_length, handle_radius, handle_radius, z_axis)
    return parts, (region,), False


def _can(rng: np.random.Generator) -> Built:
    radius = uniform(rng, 0.030, 0.040)
    height = uniform(rng, 0.08, 0.14)
    body = trimesh.creation.cylinder(radius=radius, height=height, sections=64)
    body.apply_translation([0, 0, height / 2])
    return [Part("body", body, DENSITY_FILLED_CAN, True)], (), True


def _fruit(rng: np.random.Generator) -> Built:
    semi_axes = np.array(
        [uniform(rng, 0.030, 0.038), uniform(rng, 0.028, 0.036), uniform(rng, 0.027, 0.035)]
    )
    body = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    body.apply_scale(semi_axes)
    body.apply_translation([0, 0, semi_axes[2]])
    return [Part("body", body, DENSITY_FRUIT, True)], (), True


_BUILDERS: dict[str, Callable[[np.random.Generator], Built]] = {
    "mug": _mug,
    "hammer": _hammer,
    "spatula": _spatula,
    "screwdriver": _screwdriver,
    "pan": _pan,
    "can": _can,
    "fruit": _fruit,
    "strap_mug": _strap_mug,
    "drill": _drill,
    "knife": knife,
    "wrench": wrench,
}

GENERATED_KINDS: tuple[str, ...] = tuple(_BUILDERS)
"""The kinds of :mod:`simgrasp.assets.generated` itself (the tool families' are
``FAMILY_KINDS``)."""
ALL_GENERATED_KINDS: tuple[str, ...] = GENERATED_KINDS + FAMILY_KINDS
"""Every loadable generated kind: these and the tool families'
(:mod:`simgrasp.assets.families`)."""


def generated_name(kind: str, seed: int) -> str:
    """The object name of a generated tool, e.g. ``gen_hammer_s3``."""
    return f"gen_{kind}_s{seed}"


def _recenter(parts: list[Part]) -> NDArray[np.float64]:
    """Offset putting the footprint center at x = y = 0 and the lowest point on z = 0."""
    bounds = np.array([p.mesh.bounds for p in parts])
    low, high = bounds[:, 0].min(axis=0), bounds[:, 1].max(axis=0)
    return -np.array([(low[0] + high[0]) / 2, (low[1] + high[1]) / 2, low[2]])


def _shift_region(region: Region, offset: NDArray[np.float64]) -> Region:
    if isinstance(region, Capsule):
        return Capsule(region.p0 + offset, region.p1 + offset, region.radius)
    return Box(region.center + offset, region.object_R_box, region.half_extents)


def generate_parts(kind: str, seed: int) -> GeneratedTool:
    """Build the parts and handle label of a generated tool (object frame, see module doc)."""
    builder = _BUILDERS.get(kind) or FAMILY_BUILDERS.get(kind)
    if builder is None:
        raise SimgraspError(
            f"unknown generated object kind {kind!r}; known kinds: {', '.join(ALL_GENERATED_KINDS)}"
        )
    parts, regions, whole = builder(rng_for(seed, "generated", kind))
    offset = _recenter(parts)
    for part in parts:
        part.mesh.apply_translation(offset)
    regions = tuple(_shift_region(r, offset) for r in regions)
    name = generated_name(kind, seed)
    return GeneratedTool(kind, seed, tuple(parts), HandleLabel(name, regions, whole))


def generate_tool(kind: str, seed: int) -> ObjectAsset:
    """A generated object ``gen_<kind>_s<seed>`` (kinds: ``ALL_GENERATED_KINDS``).

    The mesh is the concatenation of the watertight parts; mass is the sum of part volume x
    material density (``DENSITY_*``).
    """
    tool = generate_parts(kind, seed)
    mesh = cast(trimesh.Trimesh, trimesh.util.concatenate([p.mesh for p in tool.parts]))
    return ObjectAsset(
        name=tool.handle.object_name,
        mesh=mesh,
        handle=tool.handle,
        mass=tool.mass,
        source="generated",
    )
