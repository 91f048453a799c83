"""Fitting quadrics to sampled patches of known handle-shaped surfaces, per method and noise.

The table printed by the ``error_table`` fixture (run with ``-s``) reports, per shape, noise
level and method, the recovered type rate and the median center / smaller transverse
semi-axis / axis errors. Patches: 50 points (and unit normals) from a small piece (about 70°
of arc) of a known real ellipsoid, one-sheet hyperboloid or real elliptic cylinder of handle
size (cm), moved by a random rigid motion to about 0.5 m from the origin. Noise: Gaussian,
standard deviation a fraction of the patch size (bounding-box diagonal) on every point
coordinate, and the same fraction on every normal component before renormalizing. Fits are
analysed with the detector's loose tolerance at the patch centroid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from simgrasp.quadric import (
    HANDLE_KINDS,
    METHODS,
    Quadric,
    QuadricKind,
    analyze_quadrics,
    fit_quadrics,
)
from simgrasp.quadric.fit import FitMethod
from simgrasp.quadric.fit_systems import FLAT_TOL

FIT_RTOL = 1e-2
POINTS = 50
PATCHES = 60
NOISE_LEVELS = (0.0, 0.01, 0.03, 0.05)
ARC = 0.6  # half angle (rad) of the patch around the handle


@dataclass(frozen=True)
class Patches:
    """B patches of one known surface, moved to random poses."""

    kind: QuadricKind
    points: np.ndarray  # (B, K, 3) world
    normals: np.ndarray  # (B, K, 3) world, unit
    centers: np.ndarray  # (B, 3) true center (cylinder: axis point nearest the centroid)
    axes: np.ndarray  # (B, 3) true handle axis
    small_semi_axis: float  # true smaller transverse semi-axis
    size: float  # median bounding-box diagonal of the patches


def _surface(kind: QuadricKind, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Canonical-frame points and normals of one patch (handle axis z)."""
    a, b, c = 0.015, 0.02, 0.06
    v = rng.uniform(0, 2 * np.pi) + rng.uniform(-ARC, ARC, POINTS)
    if kind is QuadricKind.REAL_ELLIPSOID:
        u = np.pi / 2 + rng.uniform(-ARC, ARC, POINTS) / 2
        p = np.stack([a * np.sin(u) * np.cos(v), b * np.sin(u) * np.sin(v), c * np.cos(u)], 1)
        n = p / np.array([a, b, c]) ** 2
    elif kind is QuadricKind.HYPERBOLOID_ONE_SHEET:
        c = 0.03
        t = rng.uniform(-ARC, ARC, POINTS)
        p = np.stack([a * np.cosh(t) * np.cos(v), b * np.cosh(t) * np.sin(v), c * np.sinh(t)], 1)
        n = p / np.array([a**2, b**2, -(c**2)])
    else:
        z = rng.uniform(-0.02, 0.02, POINTS)
        p = np.stack([a * np.cos(v), b * np.sin(v), z], 1)
        n = p / np.array([a, b, np.inf]) ** 2
    return p, n / np.linalg.norm(n, axis=1, keepdims=True)


def make_patches(kind: QuadricKind, noise: float, seed: int) -> Patches:
    rng = np.random.default_rng(seed)
    points, normals, centers, axes, sizes = [], [], [], [], []
    for _ in range(PATCHES):
        p, n = _surface(kind, rng)
        rotation = Rotation.random(random_state=rng).as_matrix()
        translation = rng.uniform(-0.5, 0.5, 3)
        p_world, n_world = p @ rotation.T + translation, n @ rotation.T
        size = float(np.linalg.norm(np.ptp(p_world, axis=0)))
        p_world = p_world + rng.normal(0, noise * size, p_world.shape)
        n_world = n_world + rng.normal(0, noise, n_world.shape)
        n_world /= np.linalg.norm(n_world, axis=1, keepdims=True)
        center = translation
        if kind is QuadricKind.REAL_ELLIPTIC_CYLINDER:
            offset = p_world.mean(axis=0) - translation
            center = translation + (offset @ rotation[:, 2]) * rotation[:, 2]
        points.append(p_world)
        normals.append(n_world)
        centers.append(center)
        axes.append(rotation[:, 2])
        sizes.append(size)
    return Patches(
        kind,
        np.array(points),
        np.array(normals),
        np.array(centers),
        np.array(axes),
        0.015,
        float(np.median(sizes)),
    )


@dataclass(frozen=True)
class FitErrors:
    """Medians over patches (lengths relative to the true smaller semi-axis)."""

    kind_rate: float  # fraction classified as the true kind
    handle_rate: float  # fraction classified as any handle kind
    center_error: float  # |center - true| / semi (cylinder: axis line distance)
    semi_error: float  # |smaller transverse semi-axis - true| / true
    axis_angle: float  # degrees between handle axes


def evaluate(patches: Patches, method: FitMethod) -> FitErrors:
    fit = fit_quadrics(patches.points, patches.normals, method=method)
    analysis = analyze_quadrics(fit.coefficients, rtol=FIT_RTOL, reference_points=fit.centroids)
    handle = np.isin(analysis.kinds, list(HANDLE_KINDS)) & fit.valid
    offsets = analysis.centers - patches.centers
    if patches.kind is QuadricKind.REAL_ELLIPTIC_CYLINDER:
        along = np.einsum("bi,bi->b", offsets, np.nan_to_num(analysis.handle_axes))
        offsets = offsets - along[:, None] * np.nan_to_num(analysis.handle_axes)
    cosine = np.abs(np.einsum("bi,bi->b", analysis.handle_axes, patches.axes))
    semi = patches.small_semi_axis

    def median(values: np.ndarray) -> float:  # failed / non-handle fits count as infinite error
        return float(np.median(np.where(handle, values, np.inf)))

    return FitErrors(
        kind_rate=float(np.mean(analysis.kinds == patches.kind)),
        handle_rate=float(np.mean(handle)),
        center_error=median(np.linalg.norm(offsets, axis=1) / semi),
        semi_error=median(np.abs(analysis.transverse_semi_axes[:, 0] - semi) / semi),
        axis_angle=median(np.degrees(np.arccos(np.clip(cosine, 0, 1)))),
    )


SHAPES = (
    QuadricKind.REAL_ELLIPSOID,
    QuadricKind.HYPERBOLOID_ONE_SHEET,
    QuadricKind.REAL_ELLIPTIC_CYLINDER,
)


@pytest.fixture(scope="module")
def error_table() -> dict[tuple[QuadricKind, float, FitMethod], FitErrors]:
    table = {}
    for s, kind in enumerate(SHAPES):
        for n, noise in enumerate(NOISE_LEVELS):
            patches = make_patches(kind, noise, seed=100 * s + n)
            for method in METHODS:
                table[kind, noise, method] = evaluate(patches, method)
    header = (
        "| shape | noise | method | kind ok | handle kind | center err | semi err | axis (deg) |"
    )
    print("\n" + header + "\n" + "|---" * 8 + "|")
    for (kind, noise, method), e in table.items():
        print(
            f"| {kind.value} | {noise:.2f} | {method} | {e.kind_rate:.2f} | {e.handle_rate:.2f} "
            f"| {e.center_error:.3f} | {e.semi_error:.3f} | {e.axis_angle:.2f} |"
        )
    return table


@pytest.mark.parametrize("kind", SHAPES)
@pytest.mark.parametrize("method", ["taubin", "algebraic"])
def test_exact_patches_are_recovered_exactly_by_the_point_only_methods(
    error_table: dict, kind: QuadricKind, method: FitMethod
) -> None:
    errors = error_table[kind, 0.0, method]
    assert errors.kind_rate == 1.0
    assert errors.center_error < 1e-6
    assert errors.semi_error < 1e-6
    assert errors.axis_angle < 1e-5


@pytest.mark.parametrize("kind", SHAPES)
def test_birdal_is_approximate_on_exact_patches_and_exact_without_the_magnitude_rows(
    error_table: dict, kind: QuadricKind
) -> None:
    """∇f = n forces a unit gradient everywhere, which an elliptic section does not have:
    the fit is biased but of the right kind. Down-weighting the magnitude rows (keeping only
    ∇f ∥ n) removes the bias."""
    errors = error_table[kind, 0.0, "birdal"]
    assert errors.kind_rate == 1.0
    assert 1e-3 < errors.semi_error < 1.5
    assert errors.axis_angle < 1.0
    patches = make_patches(kind, 0.0, seed=9)
    fit = fit_quadrics(patches.points, patches.normals, magnitude_weight=1e-6)
    quadric = Quadric(fit[0], rtol=FIT_RTOL, reference_point=fit.centroids[0])
    assert quadric.kind is kind
    assert quadric.transverse_semi_axes[0] == pytest.approx(patches.small_semi_axis, rel=1e-4)


@pytest.mark.parametrize("kind", SHAPES)
def test_normals_based_fit_degrades_gracefully_with_noise(
    error_table: dict, kind: QuadricKind
) -> None:
    for noise in NOISE_LEVELS[1:]:
        errors = error_table[kind, noise, "birdal"]
        assert errors.handle_rate >= 0.85, (noise, errors)
        assert errors.axis_angle <= 3 + 250 * noise, (noise, errors)
        assert errors.semi_error <= 1 + 80 * noise, (noise, errors)
    low, high = error_table[kind, 0.01, "birdal"], error_table[kind, 0.05, "birdal"]
    assert low.semi_error < high.semi_error and low.center_error < high.center_error


@pytest.mark.parametrize("kind", SHAPES)
def test_normals_based_fit_beats_taubin_and_algebraic_on_small_noisy_patches(
    error_table: dict, kind: QuadricKind
) -> None:
    for noise in NOISE_LEVELS[1:]:
        birdal = error_table[kind, noise, "birdal"]
        for other in ("taubin", "algebraic"):
            baseline = error_table[kind, noise, other]
            assert birdal.handle_rate > baseline.handle_rate, (noise, other)
            assert birdal.axis_angle < baseline.axis_angle, (noise, other)


def _degenerate_batch() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(11)
    points = rng.normal(size=(6, 30, 3))
    normals = points / np.linalg.norm(points, axis=2, keepdims=True)
    mask = np.ones((6, 30), dtype=bool)
    points[1, 4] = np.nan  # non-finite
    mask[2, 2:] = False  # too few points
    points[3] = np.outer(np.linspace(-1, 1, 30), [1.0, 2.0, 3.0])  # collinear
    points[4, :, 2] = 0.0  # coplanar
    points[5] = 7.0  # all points equal
    return points, normals, mask


@pytest.mark.parametrize("method", METHODS)
def test_degenerate_neighborhoods_are_flagged_not_raised(method: FitMethod) -> None:
    points, normals, mask = _degenerate_batch()
    fit = fit_quadrics(points, normals, method=method, mask=mask)
    assert fit.failure == (
        None,
        "non_finite",
        "too_few_points",
        "collinear",
        "coplanar",
        "collinear",
    )
    assert fit.valid.tolist() == [True] + [False] * 5
    assert np.all(np.isfinite(fit.coefficients[0]))
    assert np.all(np.isnan(fit.coefficients[1:]))


def test_masked_padding_is_ignored_and_ragged_lists_match_dense_input() -> None:
    patches = make_patches(QuadricKind.REAL_ELLIPTIC_CYLINDER, 0.01, seed=12)
    points, normals = patches.points[:3].copy(), patches.normals[:3].copy()
    sizes = [50, 35, 20]
    mask = np.arange(POINTS)[None, :] < np.array(sizes)[:, None]
    points[~mask] = np.nan  # garbage in the padding must not matter
    dense = fit_quadrics(points, normals, mask=mask)
    ragged = fit_quadrics(
        [points[i, :k] for i, k in enumerate(sizes)], [normals[i, :k] for i, k in enumerate(sizes)]
    )
    assert dense.valid.all()
    np.testing.assert_allclose(dense.coefficients, ragged.coefficients, rtol=1e-12)
    alone = fit_quadrics(points[1:2, :35], normals[1:2, :35])
    np.testing.assert_allclose(dense.coefficients[1], alone.coefficients[0], rtol=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_fits_do_not_depend_on_how_the_batch_is_chunked(
    method: FitMethod, monkeypatch: pytest.MonkeyPatch
) -> None:
    patches = make_patches(QuadricKind.REAL_ELLIPSOID, 0.02, seed=16)
    points, normals = patches.points.copy(), patches.normals.copy()
    mask = np.ones(points.shape[:2], dtype=bool)
    points[5] = points[5, 0] + np.outer(np.linspace(-0.01, 0.01, POINTS), [1.0, 2.0, 3.0])
    points[11, 7] = np.nan
    mask[17, 2:] = False
    mask[23, 30:] = False
    mask[56:, 2:] = False  # a whole chunk of failures below
    whole = fit_quadrics(points, normals, method=method, mask=mask)
    monkeypatch.setattr("simgrasp.quadric.fit.CHUNK", 7)
    chunked = fit_quadrics(points, normals, method=method, mask=mask)
    assert chunked.failure == whole.failure
    assert [whole.failure[i] for i in (5, 11, 17, 56)] == [
        "collinear",
        "non_finite",
        "too_few_points",
        "too_few_points",
    ]
    np.testing.assert_array_equal(chunked.centroids, whole.centroids)
    np.testing.assert_allclose(chunked.coefficients, whole.coefficients, rtol=1e-12)


def test_normals_are_renormalized_and_points_without_one_only_fit_the_surface() -> None:
    patches = make_patches(QuadricKind.REAL_ELLIPSOID, 0.01, seed=15)
    normals = patches.normals.copy()
    normals[:, ::3] = 0.0
    base = fit_quadrics(patches.points, normals)
    assert base.valid.all()
    scale = np.abs(base.coefficients).max(axis=1, keepdims=True)
    lengths = np.random.default_rng(15).uniform(0.5, 2.0, normals.shape[:2])
    scaled = fit_quadrics(patches.points, normals * lengths[:, :, None])
    np.testing.assert_allclose(scaled.coefficients / scale, base.coefficients / scale, atol=1e-9)
    vanishing = normals.copy()
    vanishing[:, ::3] = 1e-200 * patches.normals[:, ::3]  # squared length underflows to 0
    vanishing[0] = 1e-200 * patches.normals[0]  # no normal at all: nothing fixes the scale
    underflow = fit_quadrics(patches.points, vanishing)
    assert underflow.failure[0] == "ill_conditioned"
    np.testing.assert_array_equal(underflow.coefficients[1:], base.coefficients[1:])


def test_flat_flags_follow_the_standardized_covariance_eigenvalues() -> None:
    """Planes and lines of decreasing thickness around FLAT_TOL (an RMS thickness of about
    1e-6 of the RMS radius): cheap bounds clear the thick ones, eigenvalues decide near it."""
    rng = np.random.default_rng(17)
    thickness = np.array([1e-4, 1e-5, 4e-6, 4e-7, 1e-7, 0.0])
    ones = np.ones_like(thickness)
    shapes = np.concatenate(
        [np.stack([ones, ones, thickness], 1), np.stack([ones, thickness, thickness], 1)]
    )
    rotation = Rotation.random(random_state=rng).as_matrix()
    points = (rng.normal(size=(len(shapes), POINTS, 3)) * shapes[:, None, :]) @ rotation.T + 0.3
    fit = fit_quadrics(points, method="algebraic")
    centered = points - points.mean(axis=1, keepdims=True)
    standard = centered / np.sqrt(np.sum(centered**2, axis=(1, 2)) / POINTS)[:, None, None]
    spread = np.linalg.eigvalsh(np.einsum("bki,bkj->bij", standard, standard) / POINTS)
    expected = [
        "collinear" if low[1] <= FLAT_TOL else "coplanar" if low[0] <= FLAT_TOL else None
        for low in spread
    ]
    assert expected.count(None) == 6  # both sides of the threshold are covered
    assert [f if f in ("collinear", "coplanar") else None for f in fit.failure] == expected


@pytest.mark.parametrize("method", METHODS)
def test_fits_do_not_depend_on_units_or_position(method: FitMethod) -> None:
    patches = make_patches(QuadricKind.HYPERBOLOID_ONE_SHEET, 0.02, seed=13)
    base = fit_quadrics(patches.points, patches.normals, method=method)
    moved = fit_quadrics(1000 * patches.points + 250.0, patches.normals, method=method)
    for i in range(len(base)):
        a = Quadric(base[i], rtol=FIT_RTOL, reference_point=base.centroids[i])
        b = Quadric(moved[i], rtol=FIT_RTOL, reference_point=moved.centroids[i])
        assert a.kind is b.kind
        np.testing.assert_allclose(1000 * a.center + 250.0, b.center, rtol=1e-6, atol=1e-6)


def test_fit_result_behaves_as_its_coefficient_array() -> None:
    patches = make_patches(QuadricKind.REAL_ELLIPSOID, 0.0, seed=14)
    fit = fit_quadrics(patches.points, patches.normals)
    assert fit.shape == (PATCHES, 10) and len(fit) == PATCHES
    assert np.asarray(fit).shape == (PATCHES, 10)
    np.testing.assert_array_equal(fit[3], fit.coefficients[3])
    np.testing.assert_allclose(fit.centroids, patches.points.mean(axis=1), atol=1e-12)
    empty = fit_quadrics(np.zeros((0, 10, 3)), np.zeros((0, 10, 3)))
    assert empty.shape == (0, 10) and empty.failure == ()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"points": np.zeros((2, 10, 2)), "normals": np.zeros((2, 10, 2))}, "3"),
        ({"points": np.zeros((10, 3)), "normals": np.zeros((10, 3))}, r"\(B, K, 3\)"),
        ({"points": np.zeros((2, 10, 3)), "normals": np.zeros((2, 9, 3))}, "does not match"),
        ({"points": np.zeros((2, 10, 3))}, "needs normals"),
        ({"points": np.zeros((2, 10, 3)), "method": "ransac"}, "unknown method"),
        (
            {"points": np.zeros((2, 10, 3)), "normals": np.zeros((2, 10, 3)), "mask": np.ones(3)},
            "mask",
        ),
        ({"points": [np.zeros((5, 3)), np.zeros((5, 4))], "method": "taubin"}, r"points\[1\]"),
    ],
)
def test_argument_shape_errors_are_clear(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        fit_quadrics(**kwargs)
