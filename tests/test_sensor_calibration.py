"""The sensor calibration measurements: on analytic planes (known answers) and on a real
osd-learn scan (skipped when ../shared/real is absent)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from data_needs import require_data

from simgrasp.perception.sensors import IdealConfig, KinectConfig
from simgrasp.perception.sensors.calibration import (
    LabeledScan,
    compare_scan,
    fit_plane,
    patch_residuals,
    plane_depth,
    points_from_depth,
    prepare_scan,
    read_labeled_scan,
    scan_intrinsics,
    summarize,
)
from simgrasp.seeding import rng_for

K = np.array([[525.0, 0.0, 319.5], [0.0, 525.0, 239.5], [0.0, 0.0, 1.0]])
SHAPE = (480, 640)
FLOOR = (np.array([0.0, -0.8, -0.6]), 0.72)  # a tilted table 0.8 - 3 m away


@pytest.fixture(scope="module")
def learn35() -> LabeledScan:
    path = require_data("real") / "osd-learn" / "learn35.pcd"
    return read_labeled_scan(path)


def test_plane_depth_and_fit_plane_round_trip() -> None:
    points = points_from_depth(plane_depth(K, SHAPE, FLOOR), K)
    normal, d = fit_plane(points[np.isfinite(points[..., 2])])
    unit = FLOOR[0] / np.linalg.norm(FLOOR[0])
    assert np.allclose(normal, unit, atol=1e-9)
    assert d == pytest.approx(FLOOR[1] / np.linalg.norm(FLOOR[0]), rel=1e-9)


def test_patch_residuals_recover_known_noise() -> None:
    """Points moved along the plane's normal by N(0, 1 mm): every full patch measures ~1 mm;
    patches cut by the mask are skipped."""
    depth = plane_depth(K, SHAPE, FLOOR)
    points = points_from_depth(depth, K)
    unit = FLOOR[0] / np.linalg.norm(FLOOR[0])
    points += rng_for(0, "patches").normal(size=SHAPE)[..., None] * 0.001 * unit
    full = depth > 0
    depths, rms = patch_residuals(points, full, (unit, 0.0), K)
    assert len(rms) > 50
    # A fitted plane takes 3 of a patch's ~100-800 degrees of freedom: rms is a little below.
    assert np.median(rms) == pytest.approx(0.001, rel=0.05)
    assert np.median(rms) < 0.001
    assert depths.min() > 0.7 and depths.max() < 3.2
    half = full & (np.arange(SHAPE[1]) < 320)[None, :]
    assert len(patch_residuals(points, half, (unit, 0.0), K)[1]) < 0.6 * len(rms)


def test_real_scan_reads_with_its_camera(learn35: LabeledScan) -> None:
    assert learn35.labels.shape == SHAPE and learn35.points_cam.shape == SHAPE + (3,)
    assert learn35.table.sum() > 50_000 and learn35.objects.sum() > 5_000
    assert np.array_equal(learn35.depth == 0, learn35.labels == 0)
    assert np.allclose(scan_intrinsics(learn35), K, atol=0.01)


def test_ideal_sensor_has_no_residual_and_no_holes(learn35: LabeledScan) -> None:
    prepared = prepare_scan(learn35)
    (row, *_) = summarize([compare_scan(prepared, IdealConfig(), rng_for(0))])
    assert 0.0005 < row.real_residual < 0.0015 and row.sim_residual < 0.00005
    assert 0.05 < row.real_invalid < 0.3 and row.sim_invalid == 0.0


def test_kinect_matches_real_scans() -> None:
    """Every 9th osd-learn scan, two seeds: the calibrated model's table residual within 20 %
    of the real one in every bin with 100 patches, its silhouette invalid share within 35 % in
    every bin with 20,000 band pixels (single scans scatter more: 0.22 in the median scan)."""
    root = require_data("real") / "osd-learn"
    paths = [root / f"learn{i}.pcd" for i in (0, 9, 18, 27, 36)]
    prepared = [prepare_scan(read_labeled_scan(path)) for path in paths]
    for seed in (0, 1):
        comparisons = [
            compare_scan(p, KinectConfig(), rng_for(seed, "kinect", i))
            for i, p in enumerate(prepared)
        ]
        rows = summarize(comparisons)
        assert sum(row.patches >= 100 for row in rows) == 4
        assert sum(row.band_pixels >= 20_000 for row in rows) == 1
        for row in rows:
            if row.patches >= 100:
                assert abs(row.residual_error) < 0.2, row
            if row.band_pixels >= 20_000:
                assert abs(row.invalid_error) < 0.35, row


def test_a_scan_without_table_or_objects_is_a_value_error(learn35: LabeledScan) -> None:
    no_table = LabeledScan(learn35.points_cam, np.where(learn35.labels < 20, 0, learn35.labels))
    with pytest.raises(ValueError, match="labeled table"):
        prepare_scan(no_table)


def test_missing_scan_file_is_clear(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="no scan file"):
        read_labeled_scan(tmp_path / "none.pcd")
