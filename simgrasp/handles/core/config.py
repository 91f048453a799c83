"""Every threshold of the quadric handle detector, in one frozen dataclass (meters, radians)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal

from simgrasp.config.checks import (
    Checked,
    Fraction,
    MinLength,
    NonNegative,
    Positive,
    PositiveInt,
    Range,
)

FitMethod = Literal["birdal", "taubin", "algebraic"]
CentralityMeasure = Literal["center", "stretch", "grasps"]
"""Where a handle's lever arm to the centroid is measured
(``QuadricDetectorConfig.centrality_measure``)."""


@dataclass(frozen=True)
class QuadricDetectorConfig(Checked):
    """Parameters of :func:`simgrasp.handles.core.quadric_detector.detect_quadric_handles`.

    Lengths are meters. The paper's criteria are (a) the fitted kind is a real ellipsoid,
    a hyperboloid of one sheet or a real elliptic cylinder, (b) the quadric center (the axis,
    for the cylinder) is near the neighborhood center, (c) the smaller transverse semi-axis is
    at most half the gripper's maximum opening. The ``*_test`` switches add the paper's
    suggested extras.
    """

    gripper_max_opening: Positive = 0.085
    """Maximum jaw opening of the parallel gripper (m); widths above half of it fail (c)."""
    voxel_size: NonNegative = 0.003
    """Voxel edge for down-sampling the input cloud (m); 0 disables down-sampling."""
    normal_radius: Positive = 0.01
    """Search radius for normal estimation (m)."""
    own_normals: bool = False
    """Estimate normals with ``normal_radius`` even when the caller passes normals, keeping
    the caller's signs (its viewpoints orient them). The chain's fused camera clouds come with
    normals over five voxel spacings (15 mm), wider than a mug's strap section (8 x 14 mm):
    the fits on a lying strap come out about twice its size and the shell test rejects them."""
    neighborhood_half_size: Positive = 0.016
    """Half edge of the cube-shaped neighborhood (m), or its radius for spheres."""
    neighborhood_scales: Annotated[tuple[Positive, ...], MinLength(1)] = (1.0,)
    """Neighborhoods are gathered at these multiples of ``neighborhood_half_size`` around each
    center; a center becomes a candidate at its smallest passing scale (large scales let wide
    handles be fitted, small ones keep thin handles)."""
    neighborhood_shape: Literal["cube", "sphere"] = "cube"
    """Neighborhood shape: an axis-aligned cube (the paper's) or a sphere."""
    max_points: Annotated[int, Range(ge=9)] = 128
    """Neighborhoods with more points are subsampled (seeded) to this many (more points
    average noise out: σ = 0.05 accuracy over the paper's objects 0.83 with 64, 0.92 with 128)."""
    min_points: Annotated[int, Range(ge=9)] = 16
    """Neighborhoods with fewer points are not fitted."""
    neighborhoods: PositiveInt | None = None
    """Number of neighborhood centers; ``None`` scales it with object size (voxel count)."""
    voxels_per_neighborhood: Positive = 10.0
    """With ``neighborhoods=None``: one neighborhood center per this many occupied voxels
    (of ``voxel_size``). Smaller values sample small handles (a pot's side tabs, a few percent
    of a real single-view cloud) with enough centers to reach ``min_support``."""
    fit_method: FitMethod = "birdal"
    """Quadric fit: Birdal et al. 2018 (points and normals), Taubin, or plain algebraic."""
    second_fit_method: FitMethod | None = None
    """Also fit every neighborhood with this method; a center becomes a candidate if either
    fit passes the tests (the ``fit_method`` one preferred). Taubin fits use no normals and
    keep a thin part's size where noisy normals widen Birdal's; Birdal's keep wide, gently
    curved parts (a can's side) that a Taubin fit of a small patch does not constrain."""
    fine_half_size: NonNegative = 0.0
    """With a positive half size (m), a second, fine pass: neighborhoods of this half size
    around centers of their own, fitted by ``fine_fit_method`` and tested with a
    ``fine_shell_thickness`` shell. Its candidates are clustered on their own, and its handles
    count only where the first pass found none (no candidate within ``cluster_distance`` of a
    first-pass handle's); the handles of both passes are then ranked by score. The first pass
    keeps wide, gently curved handles (a can's side), the fine one thin parts whose
    first-pass fits come out wider than the part (a lying mug's strap). 0: no fine pass."""
    fine_voxels_per_neighborhood: Positive = 3.0
    """The fine pass's neighborhood density (as ``voxels_per_neighborhood``)."""
    fine_fit_method: FitMethod = "taubin"
    """The fine pass's quadric fit; Taubin's uses no normals, so noisy normals (a Kinect's)
    do not widen the fits of a thin part."""
    fine_shell_thickness: Positive = 0.006
    """The fine pass's shell thickness (m), as ``shell_thickness``: a thin part's shell stays
    clear of the body next to it."""
    kind_rtol: Positive = 1e-2
    """Relative tolerance for rank decisions when classifying noisy fits (a smallest
    eigenvalue below ``kind_rtol`` x the largest counts as zero, i.e. a cylinder)."""
    center_tolerance: Positive = 1.1
    """Criterion (b): the quadric center (cylinder: its axis) must lie within this many half
    gripper openings of the neighborhood center. The neighborhood center is a surface point,
    so a graspable handle's center lies about one transverse radius (at most half the opening)
    away from it; a farther center means a fit that is not a closed handle around the point."""
    eccentricity_test: bool = False
    """Reject sphere-like ellipsoids (see ``min_elongation``; a paper suggestion)."""
    min_elongation: Annotated[float, Range(ge=1)] = 1.3
    """Ellipsoids whose longest/shortest semi-axis ratio is below this are rejected."""
    width_test: bool = True
    """Also require the larger transverse semi-axis to fit the gripper (x ``width_slack``)."""
    width_slack: Positive = 1.0
    """Factor on the gripper's half opening allowed for the larger transverse semi-axis."""
    shell_test: bool = True
    """Reject candidates with points in a thin shell just outside the fitted surface (ten Pas's
    test, a paper suggestion)."""
    shell_half_length: Positive = 0.008
    """Half length (m) along the handle axis over which the shell must be clear (about half
    a finger pad's width plus a margin)."""
    shell_gap: NonNegative = 0.006
    """The shell starts this far outside the fitted surface (m) (wide enough that noisy
    surface points of the handle itself stay out of it) ..."""
    shell_thickness: Positive = 0.01
    """... and is this thick (m)."""
    max_shell_fraction: Fraction = 0.1
    """Candidates with more than this fraction of nearby points in the shell are rejected."""
    inside_test: bool = True
    """Reject quadrics whose center lies outside the object (behind no surface, by normals)."""
    inside_neighbors: PositiveInt = 8
    """Nearest cloud points whose normals vote whether a quadric center is inside the object."""
    cluster_distance: Positive = 0.02
    """Single-linkage distance (m) joining candidates into one handle hypothesis."""
    min_support: PositiveInt = 2
    """A handle hypothesis needs at least this many candidates."""
    prefer_central: bool = True
    """Weight handle scores by closeness to the cloud's centroid (grasps near the center of
    mass lift with less torque): exp(-(d / L)^2), d the distance (m) from the centroid to the
    handle (see ``centrality_measure``), with the length
    L = max(centrality_min_length, centrality_scale x the cloud's RMS radius)."""
    centrality_measure: CentralityMeasure = "grasps"
    """Where d is measured to: ``"center"``, the handle's center; ``"stretch"``, the nearest
    point of the stretch of axis its candidates cover; ``"grasps"``, both, d^2 the mean of
    the two squares: the planner grasps a handle at those two points. A pan's long handle,
    its center 15 cm off the centroid and its near end 8 cm, ranked below arcs of its rim by
    the center. Unless ``"center"``, a handle other than the best must also pass the relative
    score cut by its center's distance (a power drill's barrel, whose stretch passes near the
    centroid)."""
    centrality_scale: Positive = 0.7
    """Multiple of the cloud's RMS radius giving the centrality length L (``prefer_central``)."""
    centrality_min_length: Positive = 0.06
    """Floor of L (m): on a compact object (a mug) every part is near the center, so an
    off-center handle is not penalized against the body."""
    prefer_clearance: bool = True
    """Weight handle scores by the jaw clearance min(1, (opening - width) / (opening / 2)), so
    a part barely narrower than the open jaws (a mug's body) ranks below a slim handle."""
    handle_anchor: Literal["axis", "surface"] = "axis"
    """Where a handle's center is taken: ``"axis"``, the candidates' points on their fitted
    axes; ``"surface"``, their neighborhood centers, cloud points on the seen surface. In a
    one-sided view of a thin part (a pot's flat side tab seen from above) the fitted
    transverse radius reflects the sensor's smoothed edge, not the part's thickness, and
    puts the axis centimeters behind the part; the seen surface is within half the
    part's thickness of its middle."""
    plate_test: bool = False
    """Also accept flat-plate handles (:mod:`simgrasp.handles.core.plate`): a thin horizontal
    plate standing off the body (a pot's side tab seen face-on, which no quadric fits),
    grasped across its thickness. Needs the table plane (``detect(..., table=...)``; also
    ``scene=``, everything seen; ``detect --segment`` gives both) and a viewpoint; without
    them it is off."""
    plate_reach: Positive = 0.05
    """Radius (m) around a center within which the plate's body and edge are looked for."""
    plate_max_thickness: Positive = 0.008
    """Largest height span (m, 5th-95th percentile) of a plate's neighborhood; points
    farther above or below the plate are its body."""
    plate_min_body: PositiveInt = 10
    """A plate needs at least this many body points within ``plate_reach``."""
    plate_finger_half_width: Positive = 0.01
    """Half width (m) of the corridor the fingers take, across the outward direction."""
    plate_finger_clearance: Positive = 0.03
    """Height (m) above and below the plate the fingers need free of the body."""
    plate_max_blocked: Fraction = 0.05
    """Largest share of body points in the fingers' corridor from the center outward."""
    plate_min_protrusion: NonNegative = 0.015
    """The plate's free edge must lie at least this far (m) beyond the body's front: room
    for a finger pad's contact."""
    plate_max_depth: Positive = 0.035
    """The free edge must lie at most this far (m) beyond the center: the fingers reach the
    grasp point from the edge."""
    plate_edge_margin: NonNegative = 0.005
    """Margin (m): the center must stand this far off the body, and the point this far past
    the free edge must be seen (no occluder nearer the sensor)."""
    plate_ray_radius: Positive = 0.004
    """A cloud point within this distance (m) of the ray to the point past the free edge
    occludes it."""
    min_relative_score: Fraction = 0.5
    """Handles scoring below this fraction of the best handle are dropped, and with them
    their candidates; candidates supporting no handle are always dropped. 0 keeps all."""

    def _check(self) -> None:
        self.require_below("min_points", "max_points", strict=False)
