"""Grasp sampling and ranking settings of the planner (meters, radians); no heavy imports."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np

from simgrasp.config.checks import (
    Checked,
    NonNegative,
    NonNegativeInt,
    Positive,
    PositiveInt,
    Range,
)

Cosine = Annotated[float, Range(ge=-1, le=1)]
"""A cosine, in [-1, 1]."""


@dataclass(frozen=True)
class PlannerConfig(Checked):
    """Grasp sampling and ranking parameters."""

    approaches_per_handle: PositiveInt = 16
    """Approach directions sampled around each handle's axis."""
    approach_pitches: tuple[Annotated[float, Range(ge=0, lt=np.pi / 2)], ...] = (
        0.0,
        np.pi / 12,
        np.pi / 6,
    )
    """Each approach around a handle's axis is also tried tilted down by these angles (rad),
    turned about the jaws' closing direction toward the axis's lower end, so the pads still
    close across the handle: a handle standing upright (a mug's) is then also approached from
    above its side, which keeps the palm off the table (a level approach to a handle 4 cm up
    puts a Robotiq palm at the table top)."""
    fallback_pitches: tuple[Annotated[float, Range(ge=0, lt=np.pi / 2)], ...] = (
        np.pi / 4,
        np.pi / 3,
    )
    """When no approach tilted by ``approach_pitches`` around any handle is clear, the same
    approaches around the sloping axes are tried again tilted down by these (rad; empty: no
    second try). In clutter a neighbor touching an upright mug (5 distractors) blocks the
    12 cm wide palm behind every approach to its standing strap up to 30 degrees down, where a
    45-60 degree approach passes over it; as a second try, no plan that finds a grasp at the
    usual pitches changes."""
    fallback_opening_margins: tuple[NonNegative, ...] = (0.01,)
    """When no approach at ``approach_pitches`` or ``fallback_pitches`` around any handle is
    clear with the jaws fully open, both are tried again (in order, until one is clear) with
    the jaws opened only to the handle's detected width plus each of these margins on either
    side (m, across the handle in the TCP frame's y; empty: no further try). A mug lying on its
    side with its strap flat on the table: the fully open jaws (8.5 cm on the built-in
    gripper) put the inner finger on the mug's body, where a narrower opening puts it inside
    the strap's loop; as a last try, no plan that finds a grasp otherwise changes."""
    root_opening_margin: NonNegative = 0.01
    """A curved handle's root grasp (where a mug's loop meets its body) is checked and opened
    with the jaws at the handle's detected width plus this margin on either side (m): fully
    open, the inner finger lands on the body beside the root."""
    root_min_turn: Annotated[float, Range(ge=0, le=np.pi / 2)] = np.pi / 6
    """A handle's root gets its own grasp where the handle's direction there turns at least
    this much (rad) from its axis, or where the root lies off the axis line by more than half
    the handle's width; otherwise the grasps on that line already close there."""
    pitch_min_slope: Annotated[float, Range(ge=0, le=np.pi / 2)] = np.pi / 12
    """Approaches are tilted only around axes sloping at least this much from level (rad):
    along a flatter axis (a tool lying on the table) a tilt turns the approach sideways more
    than down."""
    max_handles: PositiveInt = 3
    """Grasps are planned on at most this many best-scored handles."""
    table_clearance: NonNegative = 0.008
    """The open gripper's boxes stay this far above the table top at the pre-grasp (m)."""
    grasp_table_clearance: NonNegative = 0.003
    """At the grasp, the open gripper's boxes and the closed fingertips
    (``GripperGeometry.closed_pad_reach``) stay this far above the table top (m): close enough
    that the pads reach down the sides of a tool lying flat."""
    pregrasp_distance: Positive = 0.10
    """How far back along the approach the open gripper is checked for collisions (m)."""
    max_colliding_points: NonNegativeInt = 0
    """Cloud points the open gripper's boxes may hold before a grasp is dropped."""
    obstacle_radius: NonNegative = 0.005
    """A cloud point is an obstacle for the gripper only with at least
    ``obstacle_min_neighbors`` other points within this radius (m); 0 makes every point one.
    Isolated points are a depth sensor's flying pixels at depth edges, not surfaces: with
    ``--sensor kinect`` about 3 % of a mug's fused cloud (none with ideal depth), enough to
    block every approach into the gap of an upright mug's strap but one (which then closed
    at an angle across the strap and let it turn away)."""
    obstacle_min_neighbors: NonNegativeInt = 2
    """Other points within ``obstacle_radius`` a cloud point needs to be an obstacle."""
    view_weight: NonNegative = 0.3
    """Rank bonus for approaching from the camera's side (cosine with the view direction)."""
    top_weight: NonNegative = 0.3
    """Rank bonus for approaching from above (cosine with world -z)."""
    max_tcp_shift: Positive = 0.03
    """A grasp whose fingertips would reach below the table is backed off along its approach by
    up to this much (m), so objects lying flat can still be held above the table."""
    shift_weight: NonNegative = 1.0
    """Rank penalty per ``max_tcp_shift`` of back-off: a grasp backed off the handle holds it
    with the pad edges only, so the least backed-off grasp of a flat handle comes first."""
    lever_weight: NonNegative = 0.5
    """Rank penalty per 10 cm between the grasp point and the cloud centroid along the handle
    (a stand-in for the center of mass: the weight's torque about the grasp grows with it)."""
    clearance_weight: NonNegative = 0.5
    """Rank bonus for the open gripper's clearance, its distance to the nearest cloud point up
    to ``clearance_cap``, as a fraction of the cap: it centers an approach in the gap around a
    handle (a mug's strap, between the mug's body on either side of it)."""
    clearance_cap: Positive = 0.02
    """Clearances beyond this (m) earn no more bonus."""
    antipodal_samples: PositiveInt = 400
    """Point pairs the random antipodal baseline samples."""
    antipodal_cos: Cosine = 0.9
    """Antipodal pairs need normals opposed along the pair to this cosine at least."""
