"""Settings of the automatic handle labeler
(:func:`simgrasp.autolabel.auto_label.auto_handle_label`) and the pooled candidates its steps
pass on (mesh frame, meters)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.autolabel.cross_section import CrossSectionConfig
from simgrasp.autolabel.revolution import RevolutionConfig
from simgrasp.autolabel.virtual_scan import ScanConfig
from simgrasp.config.checks import Checked, Fraction, NonNegative, Positive, PositiveInt
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.presets import quadric_preset


def _label_detector() -> QuadricDetectorConfig:
    """The detector for labeling: both passes, a Franka-class 8 cm opening, every handle
    hypothesis kept (the choice between parts is made across views, not per view)."""
    return quadric_preset("two_scales", gripper_max_opening=0.08, min_relative_score=0.0)


@dataclass(frozen=True)
class AutoLabelConfig(Checked):
    """Settings of :func:`auto_handle_label` (lengths in meters)."""

    scan: ScanConfig = field(default_factory=ScanConfig)
    detector: QuadricDetectorConfig = field(default_factory=_label_detector)
    max_width: Positive = 0.04
    """Candidates wider than this (the detector's grasp width) are the object's body."""
    max_flatness: Positive = 2.0
    """Candidates whose larger transverse semi-axis exceeds this many times the smaller are
    flat (a blade, a wall) and are dropped ..."""
    retry_flatness: NonNegative = 3.0
    """... but when no part is found that way on an object with no body-of-revolution fit
    (or no normals, or ``revolution.margin`` 0), the candidates up to this flatness are
    clustered again: a thin flat handle (a table knife's, 3-4 mm thick) broken by finger
    grooves fits as flat as 2-3, and a blade's fits stay flatter (chosen on generated knives,
    docs/results/generated-labels/README.md; at most ``max_flatness``: off). Only on a long
    tool, and only parts whose section (``cross_section.grow_ratio``) is not that of ...
    (:func:`flat_handle_parts`)"""
    max_run_share: Fraction = 0.9
    """... more than this share of the scanned surface (a ruler is no handle; 1: any share,
    as long as it is measured)."""
    cluster_distance: Positive = 0.006
    """Single-linkage distance joining kept candidate centers into one part."""
    free_space_fallback: bool = False
    """When no part passes the flatness test, keep the narrow candidates of any flatness
    that have free space around them (off: it found the rims of two held-out ACRONYM mugs)."""
    max_occupancy: Fraction = 0.2
    """In that fallback, a candidate is kept when surface lies around its axis in at most this
    share of directions ..."""
    free_gap: Positive = 0.003
    """... looking from this far outside their larger transverse semi-axis ..."""
    free_ring: Positive = 0.008
    """... over a ring this wide ..."""
    free_slab: Positive = 0.003
    """... within this distance along their axis."""
    free_max_semi_axis: Positive = 0.03
    """Larger semi-axes count as this much there (the ring starts at most this far out)."""
    free_voxel: Positive = 0.002
    """The scanned surface is thinned to one point per cube of this side for that test."""
    min_views: PositiveInt = 3
    """A part must be found in at least this many views."""
    min_candidates: PositiveInt = 10
    """A part needs at least this many candidates ..."""
    min_relative_support: Fraction = 0.5
    """... and at least this share of the best part's candidates."""
    max_section_ratio: NonNegative = 1.6
    """A part's candidates whose larger transverse semi-axis exceeds this many times the
    part's median are left out of it once it is chosen: a knife's blade root or guard, the
    wall where a strap joins the body (0: off)."""
    section_min_candidates: PositiveInt = 20
    """... when it has at least this many candidates (the median of fewer is no measure of
    its section)."""
    resplit: bool = False
    """Cluster each part again after that: of the pieces the left-out wide sections joined
    (a blade's root hanging on a handle through its guard), keep those that pass the part
    tests of :func:`handle_parts` on their own (the whole part when none does)."""
    region_radius: Positive = 0.01
    """Scanned surface points within this distance of a part's candidates are its surface."""
    axis_reach: NonNegative = 0.02
    """A part's surface also takes the scanned points up to this far along each of its
    candidates' axes ... (0: off)"""
    reach_pad: NonNegative = 0.003
    """... within the candidate's larger transverse semi-axis plus this of the axis ..."""
    reach_max_semi_axis: Positive = 0.015
    """... (the semi-axis counted at most this much) ..."""
    flat_block: NonNegative = 0.005
    """... except points within this distance of a narrow candidate that failed the flatness
    test (a blade's or a wall's evidence) ..."""
    block_width_ratio: NonNegative = 0.0
    """... and, when this is positive, whose grasp width is at most this many times the part's
    median: a blade is thinner than its handle, while a flat handle's own flat fits (knife
    89e8's 12 x 3 mm handle, flatness 2-4) are as thick as its round ones and then do not
    block its reach (0: every such candidate blocks; off: at 0.65 it labeled more of held-out
    knives' blades, see docs/results/handle-labels/README.md)."""
    stop_growth: NonNegative = 0.0
    """A part's surface near a candidate and reached along its axis ends at the first slab
    along the axis whose section spreads more than this many times the candidate's diameter
    (twice its larger transverse semi-axis, counted at most ``reach_max_semi_axis`` and at
    most the part's median): a knife's guard, a blade's root, the body a strap joins
    (:func:`simgrasp.autolabel.axis_reach.section_stops`; 0: off, see
    docs/results/handle-labels/README.md: on ACRONYM tune mugs it trades handle grasps for
    wall) ..."""
    stop_ring: Positive = 0.008
    """... the section taken within the semi-axis plus this of the axis ..."""
    stop_slab: Positive = 0.002
    """... in slabs this thick along it."""
    segments: PositiveInt = 3
    """Boxes per part: its surface split into this many pieces ..."""
    pieces: Literal["slabs", "kmeans"] = "kmeans"
    """... k-means clusters of its points, started from the slabs' centroids (they follow a
    curved strap instead of spanning its opening; docs/results/generated-labels/README.md),
    or slabs of equal point count along its main axis."""
    margin: NonNegative = 0.002
    """Each box is grown by this much."""
    cross_section: CrossSectionConfig = field(default_factory=CrossSectionConfig)
    """On a long tool, a part's region leaves out the slabs much thinner than where the part
    was found (:mod:`simgrasp.autolabel.cross_section`: a knife's blade, a spatula's plate) and
    takes the slabs whose section stays like the part's (the rest of a flat handle).
    Chosen on the tune half of the ACRONYM knives, where it keeps their blade grasps off the
    label (docs/results/handle-labels/README.md). ``cross_section.min_ratio`` 0: off."""
    revolution: RevolutionConfig = field(default_factory=RevolutionConfig)
    """On a body of revolution (a mug, a jug, a pot), the scanned surface standing off the
    body (:mod:`simgrasp.autolabel.revolution`) joins the label where it touches a part's
    surface, and is the label when no part was found (a flat strap, a solid fin). Chosen on
    the tune half of the ACRONYM affordance files (docs/results/handle-labels/README.md):
    more of a mug's handle grasps on the label, its other grasps still off it; knives are
    refused by the test. ``revolution.margin`` 0: off."""
    seed: int = 0
    """Seeds the detector's neighborhood sampling (view k uses seed + k)."""


@dataclass(frozen=True)
class Candidates:
    """The detector's candidates of all views, pooled (mesh frame): ``centers`` (M, 3),
    ``widths`` (M,), ``flatness`` (M,) (larger / smaller transverse semi-axis), ``views``
    (M,) the index of the view each came from, ``axes`` (M, 3) unit handle directions,
    ``handle_points`` (M, 3) points on the handle axis, ``semi_major`` (M,) the larger
    transverse semi-axis (m; NaN or inf where undefined)."""

    centers: NDArray[np.float64]
    widths: NDArray[np.float64]
    flatness: NDArray[np.float64]
    views: NDArray[np.int64]
    axes: NDArray[np.float64]
    handle_points: NDArray[np.float64]
    semi_major: NDArray[np.float64]
