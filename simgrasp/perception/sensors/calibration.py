"""Measurements that compare a depth sensor model with real organized depth scans.

Two statistics, binned by depth (20 cm bins from 0.6 to 1.6 m by default):

- **table residual**: the supporting table is cut into 5 x 5 cm patches on its fitted plane;
  each well-filled patch gets its own least-squares plane and the RMS of its points'
  distances to it (m). A bin reports the median over its patches (by the patch's mean
  depth).
- **silhouette invalid share**: the share of pixels without a return in a band of 3 pixels on
  either side of each object's silhouette (by the depth of the nearest object pixel).

The simulated counterpart of a real scan is made from the scan itself: the table is the
analytic depth image of its fitted plane (exactly what a renderer draws for a flat table top,
from the same camera, distances and angles) and the objects are their own measured surfaces
(holes filled from the nearest object pixel), drawn over it. Scans are organized (H, W, 3)
camera-frame points in meters (OpenCV frame; NaN = invalid) with integer labels: 0 invalid,
1-9 table parts, >= 20 objects (the osd-learn convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.perception.scene_cloud import read_scene
from simgrasp.perception.sensors import SensorConfig, apply_sensor
from simgrasp.perception.sensors.geometry import band

DEPTH_BINS: tuple[float, ...] = (0.6, 0.8, 1.0, 1.2, 1.4, 1.6)
"""Edges of the depth bins (m)."""
MIN_BAND_PIXELS = 1000
"""A bin's silhouette band with fewer pixels reports no invalid share (NaN)."""


@dataclass(frozen=True, eq=False)
class LabeledScan:
    """An organized depth scan: ``points_cam`` (H, W, 3) meters, NaN where invalid, and
    ``labels`` (H, W) int32 (0 invalid, 1-9 table, >= 20 objects)."""

    points_cam: NDArray[np.float64]
    labels: NDArray[np.int32]

    @property
    def depth(self) -> NDArray[np.float64]:
        """(H, W) depth along the optical axis (m), 0 where invalid."""
        return np.nan_to_num(self.points_cam[..., 2], nan=0.0)

    @property
    def table(self) -> NDArray[np.bool_]:
        return (self.labels >= 1) & (self.labels <= 9) & (self.depth > 0)

    @property
    def objects(self) -> NDArray[np.bool_]:
        return (self.labels >= 20) & (self.depth > 0)


def read_labeled_scan(path: str | Path) -> LabeledScan:
    """Read an organized PCD with a ``label`` field (e.g. osd-learn) as an image."""
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no scan file {path}")
    scene = read_scene(path)
    if scene.labels is None:
        raise SimgraspError(f"{path} has no 'label' field")
    if not scene.organized:
        raise SimgraspError(
            f"{path} is not an organized cloud (WIDTH {scene.width}, HEIGHT {scene.height})"
        )
    labels = scene.labels.astype(np.int32).reshape(scene.height, scene.width)
    return LabeledScan(scene.grid().astype(np.float64), labels)


def scan_intrinsics(scan: LabeledScan) -> NDArray[np.float64]:
    """The 3x3 camera matrix K that projects the scan's points onto their own pixels (least
    squares over the valid points)."""
    height, width = scan.labels.shape
    valid = scan.depth > 0
    if valid.sum() < 100:
        raise SimgraspError("scan has fewer than 100 valid points; cannot recover intrinsics")
    v, u = np.nonzero(valid)
    p = scan.points_cam[valid]
    fx, cx = np.linalg.lstsq(np.column_stack([p[:, 0] / p[:, 2], np.ones(len(u))]), u, None)[0]
    fy, cy = np.linalg.lstsq(np.column_stack([p[:, 1] / p[:, 2], np.ones(len(v))]), v, None)[0]
    return np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])


def fit_plane(points: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
    """Least-squares plane ``n . p + d = 0`` of (N, 3) points, ``n`` unit and facing the
    camera at the origin (``d > 0``)."""
    center = points.mean(axis=0)
    normal = np.linalg.svd(points - center, full_matrices=False)[2][-1]
    d = -float(normal @ center)
    return (normal, d) if d > 0 else (-normal, -d)


def plane_depth(
    K: NDArray[np.float64], shape: tuple[int, int], plane: tuple[NDArray, float]
) -> NDArray[np.float64]:
    """Depth image (m, 0 = no hit) of the infinite plane ``n . p + d = 0`` seen by camera K."""
    normal, d = plane
    height, width = shape
    rx = ((np.arange(width) - K[0, 2]) / K[0, 0])[None, :]
    ry = ((np.arange(height) - K[1, 2]) / K[1, 1])[:, None]
    denominator = normal[0] * rx + normal[1] * ry + normal[2]
    with np.errstate(divide="ignore"):
        z = -d / denominator
    return np.where(np.isfinite(z) & (z > 0), z, 0.0)


def ideal_scene(
    scan: LabeledScan, K: NDArray[np.float64], smoothing_px: float = 4.0
) -> tuple[NDArray, NDArray]:
    """The scan's own geometry without sensor effects: the table's fitted plane everywhere,
    the objects' measured surfaces over it, holes inside each filled and smoothed (a Gaussian
    of ``smoothing_px`` pixels, normalized over object pixels) so that their normals are
    those of the surface, not of the sensor's quantization steps.

    Returns:
        ``(depth, objects)``: the (H, W) depth (m) and the (H, W) object mask.
    """
    plane = fit_plane(scan.points_cam[scan.table])
    depth = plane_depth(K, scan.labels.shape, plane)
    objects = ndimage.binary_fill_holes(scan.objects)
    nearest = ndimage.distance_transform_edt(~scan.objects, return_indices=True)[1]
    filled = np.where(objects, scan.depth[nearest[0], nearest[1]], 0.0)
    weight = ndimage.gaussian_filter(objects.astype(np.float64), smoothing_px)
    with np.errstate(invalid="ignore", divide="ignore"):
        smooth = ndimage.gaussian_filter(filled, smoothing_px) / weight
    return np.where(objects, smooth, depth), objects


def patch_residuals(
    points_cam: NDArray[np.float64],
    mask: NDArray[np.bool_],
    plane: tuple[NDArray, float],
    K: NDArray[np.float64],
    patch: float = 0.05,
    min_fill: float = 0.6,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Local plane-fit residuals of a planar surface in ``patch`` x ``patch`` m cells.

    Args:
        points_cam: (H, W, 3) points (m). mask: (H, W) pixels of the surface to use.
        plane: the surface's global plane (cells are laid out on it).
        K: camera matrix (for the expected pixel count of a cell).
        patch: cell edge (m). min_fill: cells with fewer points than this share of the pixels
            a full cell covers are skipped (surface edges, occlusions, holes).

    Returns:
        ``(depth, rms)``: per kept cell, its mean depth (m) and the RMS distance (m) of its
        points to their own least-squares plane (the root of the smallest eigenvalue of the
        cell's covariance).
    """
    normal, _ = plane
    points = points_cam[mask]
    axis_u = np.cross(normal, [0.0, 1.0, 0.0] if abs(normal[1]) < 0.9 else [1.0, 0.0, 0.0])
    axis_u /= np.linalg.norm(axis_u)
    cells = np.floor(np.column_stack([points @ axis_u, points @ np.cross(normal, axis_u)]) / patch)
    cells = (cells - cells.min(axis=0)).astype(np.int64)
    _, cell_of = np.unique(cells[:, 0] * (cells[:, 1].max() + 1) + cells[:, 1], return_inverse=True)
    count = np.bincount(cell_of).astype(np.float64)
    mean = np.stack([np.bincount(cell_of, points[:, i]) for i in range(3)], axis=1) / count[:, None]
    centered = points - mean[cell_of]
    products = centered[:, :, None] * centered[:, None, :]
    covariance = (
        np.stack(
            [np.bincount(cell_of, products[:, i, j]) for i in range(3) for j in range(3)], axis=1
        ).reshape(-1, 3, 3)
        / count[:, None, None]
    )
    rms = np.sqrt(np.maximum(np.linalg.eigvalsh(covariance)[:, 0], 0.0))
    cos = np.abs(mean @ normal) / np.linalg.norm(mean, axis=1)
    expected = patch**2 * K[0, 0] * K[1, 1] * cos / mean[:, 2] ** 2
    keep = count >= np.maximum(min_fill * expected, 10)
    return mean[keep, 2], rms[keep]


def silhouette_band(
    objects: NDArray[np.bool_], object_depth: NDArray[np.float64], width_px: int = 3
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """The band of ``width_px`` pixels on either side of the objects' silhouettes, and for each
    pixel the depth (m) of its nearest object pixel (for binning)."""
    ring = band(objects, width_px) & band(~objects, width_px)
    nearest = ndimage.distance_transform_edt(~objects, return_indices=True)[1]
    return ring, object_depth[nearest[0], nearest[1]]


def bin_index(depth: NDArray[np.float64], edges: tuple[float, ...] = DEPTH_BINS) -> NDArray:
    """Index of each depth's bin (-1 outside ``edges``)."""
    index = np.digitize(depth, edges) - 1
    return np.where((index >= 0) & (index < len(edges) - 1), index, -1)


def points_from_depth(depth: NDArray[np.floating], K: NDArray[np.floating]) -> NDArray:
    """(H, W, 3) camera-frame points (m) of a depth image, NaN where there is no return."""
    height, width = depth.shape
    z = np.where(depth > 0, depth, np.nan)
    rx = ((np.arange(width) - K[0, 2]) / K[0, 0])[None, :]
    ry = ((np.arange(height) - K[1, 2]) / K[1, 1])[:, None]
    return np.stack([z * rx, z * ry, z], axis=-1)


@dataclass(frozen=True, eq=False)
class PreparedScan:
    """What a scan's comparison needs besides the simulation, computed once: its camera
    ``K``, table ``plane``, ``ideal`` depth and ``objects`` mask (:func:`ideal_scene`), the
    silhouette ``ring`` (restricted to the table and objects' region, holes filled) with each
    ring pixel's depth ``ring_bin``, and the real table patches."""

    scan: LabeledScan
    K: NDArray[np.float64]
    plane: tuple[NDArray[np.float64], float]
    ideal: NDArray[np.float64]
    objects: NDArray[np.bool_]
    ring: NDArray[np.bool_]
    ring_bin: NDArray[np.int64]
    real_patch_depth: NDArray[np.float64]
    real_patch_rms: NDArray[np.float64]


def prepare_scan(scan: LabeledScan, edges: tuple[float, ...] = DEPTH_BINS) -> PreparedScan:
    """Measure the real scan and build its ideal geometry (see :class:`PreparedScan`)."""
    if scan.table.sum() < 1000 or not scan.objects.any():
        raise SimgraspError("scan needs a labeled table (>= 1000 points) and labeled objects")
    K = scan_intrinsics(scan)
    plane = fit_plane(scan.points_cam[scan.table])
    ideal, objects = ideal_scene(scan, K)
    ring, ring_depth = silhouette_band(objects, ideal)
    ring &= ndimage.binary_fill_holes(scan.table | scan.objects) & (ideal > 0)
    real_depth, real_rms = patch_residuals(scan.points_cam, scan.table, plane, K)
    return PreparedScan(
        scan, K, plane, ideal, objects, ring, bin_index(ring_depth, edges), real_depth, real_rms
    )


@dataclass(frozen=True)
class ScanComparison:
    """One scan measured as captured (``real_*``) and as the sensor model renders its ideal
    geometry (``sim_*``): patch depths and residuals (m), and per depth bin the band's pixel
    count and its invalid pixels."""

    real_patch_depth: NDArray[np.float64]
    real_patch_rms: NDArray[np.float64]
    sim_patch_depth: NDArray[np.float64]
    sim_patch_rms: NDArray[np.float64]
    band_pixels: NDArray[np.int64]
    real_band_invalid: NDArray[np.int64]
    sim_band_invalid: NDArray[np.int64]


def compare_scan(
    prepared: PreparedScan, config: SensorConfig, rng: np.random.Generator, bins: int = 5
) -> ScanComparison:
    """Apply the sensor of ``config`` to the scan's ideal geometry and measure both."""
    scan, K = prepared.scan, prepared.K
    sim = apply_sensor(prepared.ideal, K, config, rng)
    sim_table = scan.table & ~prepared.objects & (sim > 0)
    sim_depth, sim_rms = patch_residuals(points_from_depth(sim, K), sim_table, prepared.plane, K)
    ring = prepared.ring & (prepared.ring_bin >= 0)
    ring_bin = prepared.ring_bin[ring]

    def per_bin(invalid: NDArray[np.bool_]) -> NDArray[np.int64]:
        return np.bincount(ring_bin, weights=invalid[ring], minlength=bins).astype(np.int64)

    return ScanComparison(
        real_patch_depth=prepared.real_patch_depth,
        real_patch_rms=prepared.real_patch_rms,
        sim_patch_depth=sim_depth,
        sim_patch_rms=sim_rms,
        band_pixels=np.bincount(ring_bin, minlength=bins),
        real_band_invalid=per_bin(scan.depth <= 0),
        sim_band_invalid=per_bin(sim <= 0),
    )


@dataclass(frozen=True)
class CalibrationRow:
    """One depth bin: table residual medians (m) and band invalid shares, real and simulated."""

    low: float
    high: float
    patches: int
    real_residual: float
    sim_residual: float
    band_pixels: int
    real_invalid: float
    sim_invalid: float

    @property
    def residual_error(self) -> float:
        """Relative difference of the simulated residual from the real one (NaN without
        patches)."""
        return self.sim_residual / self.real_residual - 1.0 if self.patches else math.nan

    @property
    def invalid_error(self) -> float:
        """Relative difference of the simulated invalid share from the real one (NaN without
        band pixels)."""
        if not self.real_invalid > 0:
            return math.nan
        return self.sim_invalid / self.real_invalid - 1.0


def summarize(
    comparisons: list[ScanComparison], edges: tuple[float, ...] = DEPTH_BINS
) -> list[CalibrationRow]:
    """Pool the scans' measurements into one row per depth bin (NaN where a bin is empty)."""

    def pooled(name: str) -> NDArray[np.float64]:
        return np.concatenate([getattr(c, name) for c in comparisons])

    real_bins = bin_index(pooled("real_patch_depth"), edges)
    sim_bins = bin_index(pooled("sim_patch_depth"), edges)
    band_pixels = np.sum([c.band_pixels for c in comparisons], axis=0)
    real_invalid = np.sum([c.real_band_invalid for c in comparisons], axis=0)
    sim_invalid = np.sum([c.sim_band_invalid for c in comparisons], axis=0)
    rows = []
    for i, (low, high) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        real = pooled("real_patch_rms")[real_bins == i]
        sim = pooled("sim_patch_rms")[sim_bins == i]
        total = int(band_pixels[i]) if band_pixels[i] >= MIN_BAND_PIXELS else math.nan
        rows.append(
            CalibrationRow(
                low=low,
                high=high,
                patches=int(real.size),
                real_residual=float(np.median(real)) if real.size else float("nan"),
                sim_residual=float(np.median(sim)) if sim.size else float("nan"),
                band_pixels=int(band_pixels[i]),
                real_invalid=float(real_invalid[i]) / total,
                sim_invalid=float(sim_invalid[i]) / total,
            )
        )
    return rows


def calibration_rows(
    paths: list[Path],
    configs: list[SensorConfig],
    seed: int,
    edges: tuple[float, ...] = DEPTH_BINS,
) -> list[list[CalibrationRow]]:
    """Compare each sensor of ``configs`` with every labeled scan in ``paths`` (scan i
    simulated with the generator ``rng_for(seed, "sensor-calibration", i)``, for every config)
    and pool the rows: one list of rows per config."""
    from simgrasp.seeding import rng_for

    if not paths:
        raise SimgraspError("no scans to calibrate against")
    comparisons: list[list[ScanComparison]] = [[] for _ in configs]
    for index, path in enumerate(paths):
        prepared = prepare_scan(read_labeled_scan(path), edges)
        for config, per_config in zip(configs, comparisons, strict=True):
            rng = rng_for(seed, "sensor-calibration", index)
            per_config.append(compare_scan(prepared, config, rng, bins=len(edges) - 1))
    return [summarize(per_config, edges) for per_config in comparisons]
