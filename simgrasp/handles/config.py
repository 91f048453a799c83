"""Every threshold of the quadric handle detector, in one frozen dataclass (meters, radians)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from simgrasp.errors import SimgraspError

_POSITIVE = (
    "gripper_max_opening",
    "normal_radius",
    "neighborhood_half_size",
    "kind_rtol",
    "center_tolerance",
    "shell_thickness",
    "shell_half_length",
    "centrality_scale",
    "centrality_min_length",
    "cluster_distance",
    "voxels_per_neighborhood",
    "plate_reach",
    "plate_max_thickness",
    "plate_finger_half_width",
    "plate_finger_clearance",
    "plate_max_depth",
    "plate_ray_radius",
    "fine_voxels_per_neighborhood",
    "fine_shell_thickness",
)
"""The :class:`QuadricDetectorConfig` settings that must be positive."""


@dataclass(frozen=True)
class QuadricDetectorConfig:
    """Parameters of :func:`simgrasp.handles.quadric_detector.detect_quadric_handles`.

    Lengths are meters. The paper's criteria are (a) the fitted kind is a real ellipsoid,
    a hyperboloid of one sheet or a real elliptic cylinder, (b) the quadric center (the axis,
    for the cylinder) is near the neighborhood center, (c) the smaller transverse semi-axis is
    at most half the gripper's maximum opening. The ``*_test`` switches add the paper's
    suggested extras.
    """

    gripper_max_opening: float = 0.085
    """Maximum jaw opening of the parallel gripper (m); widths above half of it fail (c)."""
    voxel_size: float = 0.003
    """Voxel edge for down-sampling the input cloud (m); 0 disables down-sampling."""
    normal_radius: float = 0.01
    """Search radius for normal estimation (m)."""
    own_normals: bool = False
    """Estimate normals with ``normal_radius`` even when the caller passes normals, keeping
    the caller's signs (its viewpoints orient them). The chain's fused camera clouds come with
    normals over five voxel spacings (15 mm), wider than a mug's strap section (8 x 14 mm):
    the fits on a lying strap come out about twice its size and the shell test rejects them."""
    neighborhood_half_size: float = 0.016
    """Half edge of the cube-shaped neighborhood (m), or its radius for spheres."""
    neighborhood_scales: tuple[float, ...] = (1.0,)
    """Neighborhoods are gathered at these multiples of ``neighborhood_half_size`` around each
    center; a center becomes a candidate at its smallest passing scale (large scales let wide
    handles be fitted, small ones keep thin handles)."""
    neighborhood_shape: Literal["cube", "sphere"] = "cube"
    """Neighborhood shape: an axis-aligned cube (the paper's) or a sphere."""
    max_points: int = 128
    """Neighborhoods with more points are subsampled (seeded) to this many (more points
    average noise out: σ = 0.05 accuracy over the paper's objects 0.83 with 64, 0.92 with 128)."""
    min_points: int = 16
    """Neighborhoods with fewer points are not fitted."""
    neighborhoods: int | None = None
    """Number of neighborhood centers; ``None`` scales it with object size (voxel count)."""
    voxels_per_neighborhood: float = 10.0
    """With ``neighborhoods=None``: one neighborhood center per this many occupied voxels
    (of ``voxel_size``). Smaller values sample small handles (a pot's side tabs, a few percent
    of a real single-view cloud) with enough centers to reach ``min_support``."""
    fit_method: Literal["birdal", "taubin", "algebraic"] = "birdal"
    """Quadric fit: Birdal et al. 2018 (points and normals), Taubin, or plain algebraic."""
    second_fit_method: Literal["birdal", "taubin", "algebraic"] | None = None
    """Also fit every neighborhood with this method; a center becomes a candidate if either
    fit passes the tests (the ``fit_method`` one preferred). Taubin fits use no normals and
    keep a thin part's size where noisy normals widen Birdal's; Birdal's keep wide, gently
    curved parts (a can's side) that a Taubin fit of a small patch does not constrain."""
    fine_half_size: float = 0.0
    """With a positive half size (m), a second, fine pass: neighborhoods of this half size
    around centers of their own, fitted by ``fine_fit_method`` and tested with a
    ``fine_shell_thickness`` shell. Its candidates are clustered on their own, and its handles
    count only where the first pass found none (no candidate within ``cluster_distance`` of a
    first-pass handle's); the handles of both passes are then ranked by score. The first pass
    keeps wide, gently curved handles (a can's side), the fine one thin parts whose
    first-pass fits come out wider than the part (a lying mug's strap). 0: no fine pass."""
    fine_voxels_per_neighborhood: float = 3.0
    """The fine pass's neighborhood density (as ``voxels_per_neighborhood``)."""
    fine_fit_method: Literal["birdal", "taubin", "algebraic"] = "taubin"
    """The fine pass's quadric fit; Taubin's uses no normals, so noisy normals (a Kinect's)
    do not widen the fits of a thin part."""
    fine_shell_thickness: float = 0.006
    """The fine pass's shell thickness (m), as ``shell_thickness``: a thin part's shell stays
    clear of the body next to it."""
    kind_rtol: float = 1e-2
    """Relative tolerance for rank decisions when classifying noisy fits (a smallest
    eigenvalue below ``kind_rtol`` x the largest counts as zero, i.e. a cylinder)."""
    center_tolerance: float = 1.1
    """Criterion (b): the quadric center (cylinder: its axis) must lie within this many half
    gripper openings of the neighborhood center. The neighborhood center is a surface point,
    so a graspable handle's center lies about one transverse radius (at most half the opening)
    away from it; a farther center means a fit that is not a closed handle around the point."""
    eccentricity_test: bool = False
    """Reject sphere-like ellipsoids (see ``min_elongation``; a paper suggestion)."""
    min_elongation: float = 1.3
    """Ellipsoids whose longest/shortest semi-axis ratio is below this are rejected."""
    width_test: bool = True
    """Also require the larger transverse semi-axis to fit the gripper (x ``width_slack``)."""
    width_slack: float = 1.0
    """Factor on the gripper's half opening allowed for the larger transverse semi-axis."""
    shell_test: bool = True
    """Reject candidates with points in a thin shell just outside the fitted surface (ten Pas's
    test, a paper suggestion)."""
    shell_half_length: float = 0.008
    """Half length (m) along the handle axis over which the shell must be clear (about half
    a finger pad's width plus a margin)."""
    shell_gap: float = 0.006
    """The shell starts this far outside the fitted surface (m) (wide enough that noisy
    surface points of the handle itself stay out of it) ..."""
    shell_thickness: float = 0.01
    """... and is this thick (m)."""
    max_shell_fraction: float = 0.1
    """Candidates with more than this fraction of nearby points in the shell are rejected."""
    inside_test: bool = True
    """Reject quadrics whose center lies outside the object (behind no surface, by normals)."""
    inside_neighbors: int = 8
    """Nearest cloud points whose normals vote whether a quadric center is inside the object."""
    cluster_distance: float = 0.02
    """Single-linkage distance (m) joining candidates into one handle hypothesis."""
    min_support: int = 2
    """A handle hypothesis needs at least this many candidates."""
    prefer_central: bool = True
    """Weight handle scores by closeness to the cloud's centroid (grasps near the center of
    mass lift with less torque): exp(-(d / L)^2), d in meters, with the length
    L = max(centrality_min_length, centrality_scale x the cloud's RMS radius)."""
    centrality_scale: float = 0.7
    """Multiple of the cloud's RMS radius giving the centrality length L (``prefer_central``)."""
    centrality_min_length: float = 0.06
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
    """Also accept flat-plate handles (:mod:`simgrasp.handles.plate`): a thin horizontal
    plate standing off the body (a pot's side tab seen face-on, which no quadric fits),
    grasped across its thickness. Needs the table plane (``detect(..., table=...)``; also
    ``scene=``, everything seen; ``detect --segment`` gives both) and a viewpoint; without
    them it is off."""
    plate_reach: float = 0.05
    """Radius (m) around a center within which the plate's body and edge are looked for."""
    plate_max_thickness: float = 0.008
    """Largest height span (m, 5th-95th percentile) of a plate's neighborhood; points
    farther above or below the plate are its body."""
    plate_min_body: int = 10
    """A plate needs at least this many body points within ``plate_reach``."""
    plate_finger_half_width: float = 0.01
    """Half width (m) of the corridor the fingers take, across the outward direction."""
    plate_finger_clearance: float = 0.03
    """Height (m) above and below the plate the fingers need free of the body."""
    plate_max_blocked: float = 0.05
    """Largest share of body points in the fingers' corridor from the center outward."""
    plate_min_protrusion: float = 0.015
    """The plate's free edge must lie at least this far (m) beyond the body's front: room
    for a finger pad's contact."""
    plate_max_depth: float = 0.035
    """The free edge must lie at most this far (m) beyond the center: the fingers reach the
    grasp point from the edge."""
    plate_edge_margin: float = 0.005
    """Margin (m): the center must stand this far off the body, and the point this far past
    the free edge must be seen (no occluder nearer the sensor)."""
    plate_ray_radius: float = 0.004
    """A cloud point within this distance (m) of the ray to the point past the free edge
    occludes it."""
    min_relative_score: float = 0.5
    """Handles scoring below this fraction of the best handle are dropped, and with them
    their candidates; candidates supporting no handle are always dropped. 0 keeps all."""

    def __post_init__(self) -> None:
        for name in _POSITIVE:
            value = getattr(self, name)
            if not (isinstance(value, int | float) and value > 0):
                raise SimgraspError(f"detector config: {name} must be positive, got {value!r}")
        for name in ("voxel_size", "fine_half_size"):
            if getattr(self, name) < 0:
                raise SimgraspError(
                    f"detector config: {name} must be >= 0, got {getattr(self, name)}"
                )
        if self.min_points < 9 or self.max_points < self.min_points:
            raise SimgraspError(
                "detector config: need 9 <= min_points <= max_points, got "
                f"{self.min_points}, {self.max_points}"
            )
        if not self.neighborhood_scales or any(not s > 0 for s in self.neighborhood_scales):
            raise SimgraspError(
                "detector config: neighborhood_scales must be positive, got "
                f"{self.neighborhood_scales}"
            )
        if self.neighborhoods is not None and self.neighborhoods < 1:
            raise SimgraspError(
                f"detector config: neighborhoods must be >= 1, got {self.neighborhoods}"
            )
        if self.neighborhood_shape not in ("cube", "sphere"):
            raise SimgraspError(
                f"detector config: unknown neighborhood_shape {self.neighborhood_shape!r}"
            )
        if not 0 <= self.plate_max_blocked <= 1 or self.plate_min_body < 1:
            raise SimgraspError(
                "detector config: need 0 <= plate_max_blocked <= 1 and plate_min_body >= 1, "
                f"got {self.plate_max_blocked}, {self.plate_min_body}"
            )
        if self.handle_anchor not in ("axis", "surface"):
            raise SimgraspError(f"detector config: unknown handle_anchor {self.handle_anchor!r}")
        for name in ("fit_method", "second_fit_method", "fine_fit_method"):
            if getattr(self, name) not in ("birdal", "taubin", "algebraic", None):
                raise SimgraspError(f"detector config: unknown {name} {getattr(self, name)!r}")
        if self.fit_method is None:
            raise SimgraspError("detector config: fit_method must be set")

    @classmethod
    def paper(cls, **overrides: object) -> QuadricDetectorConfig:
        """The paper's criteria only: no eccentricity, width, shell or inside test."""
        base: dict[str, object] = dict(
            eccentricity_test=False, width_test=False, shell_test=False, inside_test=False
        )
        base.update(overrides)
        return cls(**base)  # type: ignore[arg-type]

    @classmethod
    def two_scales(cls, **overrides: object) -> QuadricDetectorConfig:
        """The defaults plus a fine pass (``fine_half_size`` 12 mm: Taubin fits of 12 mm
        neighborhoods, one center per 3 voxels, a 6 mm shell), the full chain's default
        (:class:`~simgrasp.grasping.trials.chain_config.ChainDetectorConfig`) for fused clouds of
        rendered depth, ideal or Kinect-class.

        The defaults' 16 mm normals-based fits keep wide, gently curved handles (a can's side,
        a drill's grip) but come out twice the size of a thin strap's 8 x 14 mm section seen
        from two sides, so the shell test rejects them: the YCB mug lying on its side was held
        by its strap in 3 of 10 seeds. Taubin fits use the points only and keep the strap's
        size with noisy depth too; alone, 12 mm patches of wide surfaces do not constrain
        their curvature (on the paper's objects with Kinect depth on-handle 0.58). With both
        passes (docs/results/README.md, ``lying-mug/`` and ``evaluate-sensor/``; 10 seeds, 4
        views, built-in gripper): the lying mug held by its strap in 7 of 10 seeds with ideal
        and with kinect depth (6 and 6 in seeds 10-19; in the others the strap lies under the
        mug), upright 10 / 10 with both (20 / 20 in seeds 0-19); the paper's objects with
        kinect depth at detection accuracy 0.94 and on-handle success 0.95 (one pass: 0.90
        and 0.90), with ideal depth 0.98 and 0.96 (0.90 and 0.91); in seeds 10-19 0.94 and
        0.93 with kinect depth (0.86 and 0.88). A fine handle counts only
        away from the first pass's handles: where both find one (a fork's, a spatula's
        handle) the first pass's grasp held better (fork and spatula dropped in the tugs in 5
        of their 40 trials when both handles were planned on). Detection takes about 3 times
        as long as one pass (129 against 44 ms a Kinect chain cloud on one core,
        ``benchmarks/bench_chain_detect.py``), a whole trial about 1.3 times."""
        base: dict[str, object] = dict(fine_half_size=0.012)
        base.update(overrides)
        return cls(**base)  # type: ignore[arg-type]

    @classmethod
    def camera_cloud(cls, **overrides: object) -> QuadricDetectorConfig:
        """Settings for the chain's fused cloud of rendered depth views (3 mm voxels): normals
        of its own over 6 mm (``own_normals``), 12 mm neighborhoods sampled ten times as
        densely. A strap seen from two sides (the YCB mug lying, strap up or sideways) then
        gets fits of its own size that pass the shell test: the lying mug held by its handle
        in 7 of 10 seeds instead of 3 (docs/results/README.md)."""
        base: dict[str, object] = dict(
            own_normals=True,
            normal_radius=0.006,
            neighborhood_half_size=0.012,
            voxels_per_neighborhood=1.0,
        )
        base.update(overrides)
        return cls(**base)  # type: ignore[arg-type]

    @classmethod
    def noisy_camera_cloud(cls, **overrides: object) -> QuadricDetectorConfig:
        """:meth:`camera_cloud` for fused clouds of a noisy depth sensor (``--sensor kinect``):
        Taubin fits, which use no normals, and a 6 mm shell instead of 10 mm. On Kinect-noisy
        points (normals over 6 mm) the normals-based fits of a lying mug's strap (8 x 14 mm
        section) come out at semi-axes of 7-10 x 10-13 mm, whose shell reaches the body;
        Taubin fits come out at 4-6 x 8-10 mm and, with the thinner shell, pass the
        shell test. The lying mug is held by its strap in 7 of 10 seeds with ideal and with
        kinect depth (camera_cloud: 7 and 4; docs/results/README.md, lying-mug)."""
        base: dict[str, object] = dict(fit_method="taubin", shell_thickness=0.006)
        base.update(overrides)
        return cls.camera_cloud(**base)

    @classmethod
    def real_depth(cls, **overrides: object) -> QuadricDetectorConfig:
        """Settings for one object cut from a single real depth view (a Kinect-class sensor
        at 0.6-1.6 m): smaller neighborhoods sampled five times as densely, so a small handle
        (a pot's side tab) gathers support, handle centers on the seen surface (``handle_anchor``)
        and no centrality weighting (a pot's two side handles are equally far from its center),
        and the flat-plate test (``plate_test``: a pot's flat side tab seen face-on, which no
        quadric fits). Measured on the osd-learn pots (docs/results/real-pots)."""
        base: dict[str, object] = dict(
            neighborhood_half_size=0.012,
            voxels_per_neighborhood=2.0,
            handle_anchor="surface",
            prefer_central=False,
            plate_test=True,
        )
        base.update(overrides)
        return cls(**base)  # type: ignore[arg-type]
