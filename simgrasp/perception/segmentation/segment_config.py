"""Every setting of the scene segmentation, in one frozen dataclass (meters, pixels)."""

from __future__ import annotations

from dataclasses import dataclass

from simgrasp.config.checks import (
    Checked,
    Fraction,
    NonNegative,
    NonNegativeInt,
    Positive,
    PositiveInt,
)

INVALID, TABLE, FIRST_OBJECT = 0, 1, 2
"""Segmentation labels: no valid point, the table, the first object (objects count up)."""


@dataclass(frozen=True)
class SegmentConfig(Checked):
    """Parameters of :func:`simgrasp.perception.segmentation.segment.segment_scene`.

    Defaults suit a Kinect-class sensor 0.4 - 2 m from a tabletop. Lengths are meters,
    ``*_px`` settings are image pixels of an organized cloud.
    """

    max_range: Positive = 4.0
    """Points farther than this from the sensor (m) are ignored (label 0)."""
    plane_distance: Positive = 0.012
    """RANSAC inlier distance to the table plane (m)."""
    table_distance: Positive = 0.005
    """Points within this distance of the final, least-squares plane (m) are the table; points
    higher are object candidates (a pan's handle lies 1 cm above the table). The plane is
    refit on the points within this distance of it (``segment.TABLE_REFITS``)."""
    plane_samples: PositiveInt = 2000
    """Valid points drawn (seeded) for the plane RANSAC."""
    plane_iterations: PositiveInt = 100
    """RANSAC plane hypotheses."""
    refine_samples: PositiveInt = 10000
    """Valid points drawn (seeded) to refine the plane by least squares on its inliers."""
    min_plane_share: Fraction = 0.2
    """The plane must hold at least this share of the valid points, else the scene has no
    table (``ValueError``)."""
    min_plane_flatness: Fraction = 0.8
    """At least this share of the plane's inliers (within ``plane_distance``) must lie within
    ``table_distance``, else the best plane is a curved surface (an object filling the view),
    not a table (``ValueError``). Real tables at 0.6 - 1.6 m measure 0.97 - 0.99."""
    floor_share: Fraction = 0.05
    """Organized clouds: a connected patch of table points smaller than this share of the
    largest patch ..."""
    floor_enclosed: Fraction = 0.5
    """... with at least this share of its one-pixel ring on objects is an object's own
    floor (the inner bottom of a bowl, labeled as a part of its own), not the table."""
    max_object_height: Positive = 1.0
    """Points higher than this above the table (m) are not objects (label 0)."""
    depth_jump: Positive = 0.02
    """Neighbouring pixels are disconnected when their ranges differ by more than this (m)
    times the squared range in meters (Kinect depth steps grow with the square of range)."""
    normal_bin_px: PositiveInt = 1
    """Normals and concavity are computed on blocks of this many pixels a side (px), each
    the mean of its object pixels, at the reference footprint (``reference_footprint``
    multiplies it for finer frames). 2 with window 3, step 1 and concave step 2 keeps about
    the same surface sizes on 4 x fewer blocks: osd-learn mean part IoU 0.933 against the
    defaults' 0.925, simulated kinect clutter 0.736 against 0.748 (not the default;
    docs/results/segment-cv)."""
    normal_window_px: PositiveInt = 5
    """Edge of the window of blocks averaged before normals are taken (blocks)."""
    normal_step_px: PositiveInt = 2
    """Half baseline of the central differences that give the normals (blocks)."""
    concave_step_px: PositiveInt = 3
    """Baseline (blocks) over which neighbouring normals are compared for concavity."""
    concave_threshold: NonNegative = 0.25
    """Cut between pixels ``i`` and ``j`` when ``(n_j - n_i) . u_ij < -concave_threshold``
    (unit normals toward the sensor, ``u_ij`` the unit direction i -> j): a concave crease
    sharper than about 2 asin(threshold / 2) (0.35: 20 degrees) over ``concave_step_px``."""
    cut_close_px: NonNegativeInt = 0
    """Gaps of up to twice this many pixels in the cuts are closed before the pixels between
    them are joined into segments (a morphological closing, 4-neighbour steps, of the cut
    pixels together with everything outside the candidates: the outline and holes), and the
    closing's pixels are attached back like every cut pixel. A crease traced with a one-pixel
    gap, or ending a pixel short of the outline (a box lying across another), then still
    separates the two objects. 1 holds out on the Kinect-class osd-learn scenes, leaving one
    scene group out, but splits single objects at their own creases elsewhere (the RealSense
    GraspNet frame's drill, the simulated pans and clamps; figures in
    ``docs/results/segment-cv``), so it is off: 0, the cuts as traced."""
    attach_distance: Positive = 0.015
    """A cut-edge pixel joins the segment of its 3-D nearest pixel within
    ``attach_radius_px`` if that pixel is within this distance (m) ..."""
    attach_radius_px: PositiveInt = 5
    """... and this many pixels in the image (px)."""
    attach_passes: NonNegativeInt = 2
    """Attaching is repeated this many times, so a run of mixed pixels along an occluding edge
    joins one pixel-step at a time."""
    reference_footprint: NonNegative = 0.0014
    """Organized clouds: the width (m) a pixel covers at the scene's median range, facing the
    sensor, at which the pixel settings here hold: 1.4 mm, the median over osd-learn's 45
    scenes (1.3 - 1.6 mm), where they were chosen. A cloud whose pixels cover at least 1.5
    times less runs them at the integer scale ``k`` nearest the ratio: normal blocks ``k``
    times larger, pixel reaches ``k`` times longer, point counts ``k * k`` times larger
    (:mod:`simgrasp.perception.segmentation.segment_scale`; the RealSense GraspNet frame, 0.65
    mm, runs at 2). 0: the settings as given, at any scale."""
    fragment_passes: NonNegativeInt = 2
    """Organized clouds: a segment under ``min_object_points`` joins the segment it touches
    most within ``attach_distance`` (a bumpy object's pieces between short creases), this
    many passes (:mod:`simgrasp.perception.segmentation.segment_fragments`; 0: fragments
    are dropped). 2 chosen on osd-learn and simulated clutter
    (``docs/results/segment-cv``)."""
    part_min_contact: NonNegativeInt = 10
    """Organized clouds: a segment of at most ``part_max_points`` whose height above the table
    spans at most ``part_max_thickness`` is a side part (a pot's tab, a pan's handle) of the
    larger segment it touches with at least this many pixels (0: no parts). It keeps its own
    label; :attr:`SegmentedObject.part_of` names that segment, and ``detect --segment`` detects
    on the object with its parts."""
    part_max_points: PositiveInt = 2500
    """Largest side part (points)."""
    part_max_thickness: Positive = 0.02
    """Largest 5th-95th percentile span of a side part's height above the table (m): a
    horizontal plate, not a box standing on another."""
    part_contact_px: PositiveInt = 3
    """A side part's pixel touches a larger segment when a pixel of it lies this many pixels
    away (rows and columns at offsets -r, -1, 0, 1, r) ..."""
    part_contact_distance: Positive = 0.01
    """... and within this distance (m) in 3-D."""
    part_edge_px: NonNegativeInt = 3
    """A side part claims the table pixels within this many pixels of it (px; 0: none) ..."""
    part_edge_height: NonNegative = 0.002
    """... that lie more than this above the table (m) and within ``part_contact_distance``
    of it: the sensor's depth ramp from a tab 1 cm above the table down to the table."""
    rim_band: NonNegative = 0.0
    """Organized clouds: join the inside of a round container seen over its rim (its back
    wall's inside and its floor) to its outside
    (:mod:`simgrasp.perception.segmentation.segment_rims`), taking each object's points
    within this distance (m) below its top as its top edge (0: no joins)."""
    rim_height_tolerance: Positive = 0.01
    """The two objects' top heights (98th percentile above the table) agree within this (m)."""
    rim_tolerance: Positive = 0.005
    """Largest RMS distance (m) of both top edges from the circle fitted to them."""
    rim_max_radius: Positive = 0.15
    """Largest radius (m) of that circle: a container, not two straight edges in line."""
    min_object_points: PositiveInt = 150
    """Segments with fewer points are dropped (label 0)."""
    cluster_voxel: Positive = 0.005
    """Unorganized clouds: voxel edge (m) of the grid DBSCAN clusters."""
    cluster_eps: Positive = 0.015
    """Unorganized clouds: DBSCAN neighbour distance (m) between voxels of one object."""
    cluster_min_points: PositiveInt = 10
    """Unorganized clouds: DBSCAN core-point neighbour count (voxels)."""
    seed: NonNegativeInt = 0
    """Seed of the plane RANSAC sample."""

    @classmethod
    def simulated(cls, **overrides: object) -> SegmentConfig:
        """For rendered tabletop frames (the chain's ``perception`` segment): the simulated
        table is exactly flat, so a 3.5 mm table band (not 5 mm) keeps a thin tool lying flat
        (a fork's head 5-7 mm up) above it under the kinect model's noise, and segments down
        to 40 points are kept, so the fragments such a tool breaks into reach the target pick
        (:data:`simgrasp.scenes.perceive.MAJORITY`). Chosen on clutter scenes of seeds 100-102
        (13 objects, kinect; mean target_iou 0.887 -> 0.926 with the majority pick). On the
        real osd-learn scenes it keeps mean part IoU (0.916) but makes 163 side parts of noise
        fragments instead of 15, so the real-scene default stays."""
        base: dict[str, object] = dict(table_distance=0.0035, min_object_points=40)
        base.update(overrides)
        return cls(**base)  # type: ignore[arg-type]
