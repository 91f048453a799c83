"""Classification and geometry of the 17 quadric types under similarity motions.

The canonical forms and random motions defined here are shared by the other quadric tests
(imported from this module). A form is built from semi-axis lengths a < b < c so that the
eigenvalue magnitudes 1/a² > 1/b² > 1/c² are distinct and the expected axis order (decreasing
|eigenvalue|) is x, y, z.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

from simgrasp.quadric import HANDLE_KINDS, Quadric, QuadricKind, analyze_quadrics
from simgrasp.quadric.coefficients import coefficients_to_matrix, matrix_to_coefficients

K = QuadricKind
INF, NAN = np.inf, np.nan


@dataclass(frozen=True)
class Form:
    """A canonical quadric: coefficients and its expected geometry in the canonical frame."""

    kind: QuadricKind
    coefficients: np.ndarray
    semi_axes: np.ndarray  # aligned with x, y, z (the expected axis order)
    center_set: str  # "point" (at the origin), "line" (the z axis), "plane" (x = 0)
    null_rows: int  # trailing axis rows only defined up to a subspace (planes: 2)


def canonical_form(kind: QuadricKind, a: float, b: float, c: float) -> Form:
    """The canonical equation of ``kind`` with semi-axes / parameters a < b < c."""
    ia, ib, ic = 1 / a**2, 1 / b**2, 1 / c**2
    table = {
        K.REAL_ELLIPSOID: ([ia, ib, ic], 0, 0, -1, [a, b, c], "point", 0),
        K.IMAGINARY_ELLIPSOID: ([ia, ib, ic], 0, 0, 1, [a, b, c], "point", 0),
        K.HYPERBOLOID_ONE_SHEET: ([ia, ib, -ic], 0, 0, -1, [a, b, c], "point", 0),
        K.HYPERBOLOID_TWO_SHEETS: ([ia, -ib, -ic], 0, 0, -1, [a, b, c], "point", 0),
        K.REAL_CONE: ([ia, ib, -ic], 0, 0, 0, [NAN] * 3, "point", 0),
        K.IMAGINARY_CONE: ([ia, ib, ic], 0, 0, 0, [NAN] * 3, "point", 0),
        K.ELLIPTIC_PARABOLOID: ([ia, ib, 0], 0, -1 / c, 0, [NAN] * 3, "point", 0),
        K.HYPERBOLIC_PARABOLOID: ([ia, -ib, 0], 0, -1 / c, 0, [NAN] * 3, "point", 0),
        K.REAL_ELLIPTIC_CYLINDER: ([ia, ib, 0], 0, 0, -1, [a, b, INF], "line", 0),
        K.IMAGINARY_ELLIPTIC_CYLINDER: ([ia, ib, 0], 0, 0, 1, [a, b, INF], "line", 0),
        K.HYPERBOLIC_CYLINDER: ([ia, -ib, 0], 0, 0, -1, [a, b, INF], "line", 0),
        K.REAL_INTERSECTING_PLANES: ([ia, -ib, 0], 0, 0, 0, [NAN] * 3, "line", 0),
        K.IMAGINARY_INTERSECTING_PLANES: ([ia, ib, 0], 0, 0, 0, [NAN] * 3, "line", 0),
        K.PARABOLIC_CYLINDER: ([ia, 0, 0], -1 / b, 0, 0, [NAN] * 3, "line", 0),
        K.REAL_PARALLEL_PLANES: ([ia, 0, 0], 0, 0, -1, [a, INF, INF], "plane", 2),
        K.IMAGINARY_PARALLEL_PLANES: ([ia, 0, 0], 0, 0, 1, [a, INF, INF], "plane", 2),
        K.COINCIDENT_PLANES: ([ia, 0, 0], 0, 0, 0, [NAN] * 3, "plane", 2),
    }
    diagonal, h, i, j, semi, center_set, null_rows = table[kind]
    coefficients = np.array([*diagonal, 0, 0, 0, 0, h, i, j], dtype=np.float64)
    return Form(kind, coefficients, np.array(semi, dtype=float), center_set, null_rows)


@dataclass(frozen=True)
class Motion:
    """x_new = rotation @ (scale * x) + translation, and the equation multiplied by factor."""

    rotation: np.ndarray
    translation: np.ndarray
    scale: float
    factor: float

    def matrix(self) -> np.ndarray:
        """4x4 similarity new_T_canonical."""
        T = np.eye(4)
        T[:3, :3] = self.scale * self.rotation
        T[:3, 3] = self.translation
        return T

    def apply(self, coefficients: np.ndarray) -> np.ndarray:
        """Coefficients of the moved surface: Q' = factor * T⁻ᵀ Q T⁻¹."""
        inverse = np.linalg.inv(self.matrix())
        moved = inverse.T @ coefficients_to_matrix(coefficients) @ inverse
        return self.factor * matrix_to_coefficients(moved)


def random_motion(rng: np.random.Generator, max_offset: float = 3.0) -> Motion:
    """Random rotation, log-uniform scale in [1e-3, 10], translation up to ``max_offset``
    times the scale in each coordinate, equation factor ±[1e-3, 1e3]."""
    scale = float(10 ** rng.uniform(-3, 1))
    factor = float(rng.choice([-1, 1]) * 10 ** rng.uniform(-3, 3))
    rotation = Rotation.random(random_state=rng).as_matrix()
    translation = scale * max_offset * rng.uniform(-1, 1, 3)
    return Motion(rotation, translation, scale, factor)


def random_semi_axes(rng: np.random.Generator) -> tuple[float, float, float]:
    """a < b < c in [0.5, 4] with ratios >= 1.3 (distinct eigenvalues)."""
    a = rng.uniform(0.5, 1.0)
    b = a * rng.uniform(1.3, 2.0)
    c = b * rng.uniform(1.3, 2.0)
    return a, b, c


def expected_center(form: Form, motion: Motion) -> np.ndarray:
    """The reported center after the motion (center sets: point nearest the origin)."""
    t = motion.translation
    if form.center_set == "point":
        return t.copy()
    if form.center_set == "line":
        u = motion.rotation[:, 2]
        return t - (t @ u) * u
    n = motion.rotation[:, 0]
    return (t @ n) * n


TRIALS_PER_KIND = 25
TOL = 1e-6


def _moved_forms(seed: int) -> tuple[list[Form], list[Motion], np.ndarray]:
    rng = np.random.default_rng(seed)
    forms, motions, rows = [], [], []
    for kind in QuadricKind:
        for _ in range(TRIALS_PER_KIND):
            form = canonical_form(kind, *random_semi_axes(rng))
            motion = random_motion(rng)
            forms.append(form)
            motions.append(motion)
            rows.append(motion.apply(form.coefficients))
    return forms, motions, np.array(rows)


def _assert_axis(actual: np.ndarray, expected: np.ndarray, what: str) -> None:
    """Unit vectors equal up to sign, to TOL."""
    assert np.linalg.norm(np.cross(actual, expected)) <= TOL, f"{what}: {actual} vs {expected}"
    assert abs(np.linalg.norm(actual) - 1) <= TOL


def test_every_kind_classified_under_random_similarities() -> None:
    forms, motions, rows = _moved_forms(seed=0)
    analysis = analyze_quadrics(rows)
    for i, (form, motion) in enumerate(zip(forms, motions, strict=True)):
        assert analysis.kinds[i] is form.kind, (i, form.kind, analysis.kinds[i], motion)


def test_geometry_recovered_under_random_similarities() -> None:
    forms, motions, rows = _moved_forms(seed=1)
    analysis = analyze_quadrics(rows)
    for i, (form, motion) in enumerate(zip(forms, motions, strict=True)):
        label = f"{form.kind.value} #{i}"
        size = motion.scale * np.max(form.semi_axes[np.isfinite(form.semi_axes)], initial=4.0)
        reach = size + np.linalg.norm(motion.translation)
        center_error = np.linalg.norm(analysis.centers[i] - expected_center(form, motion))
        assert center_error <= TOL * reach, f"{label}: center off by {center_error}"

        expected_semi = motion.scale * form.semi_axes
        actual_semi = analysis.semi_axes[i]
        assert np.array_equal(np.isnan(actual_semi), np.isnan(expected_semi)), label
        assert np.array_equal(np.isinf(actual_semi), np.isinf(expected_semi)), label
        finite = np.isfinite(expected_semi)
        np.testing.assert_allclose(actual_semi[finite], expected_semi[finite], rtol=TOL)

        defined_rows = 3 - form.null_rows
        for row in range(defined_rows):
            _assert_axis(analysis.axes[i, row], motion.rotation[:, row], f"{label} axis {row}")
        normal = motion.rotation[:, 0]
        for row in range(defined_rows, 3):  # a null subspace: rows orthogonal to the normal
            assert abs(analysis.axes[i, row] @ normal) <= TOL, label
        np.testing.assert_allclose(analysis.axes[i] @ analysis.axes[i].T, np.eye(3), atol=TOL)


def test_handle_geometry_of_the_three_handle_kinds() -> None:
    forms, motions, rows = _moved_forms(seed=2)
    analysis = analyze_quadrics(rows)
    for i, (form, motion) in enumerate(zip(forms, motions, strict=True)):
        if form.kind in HANDLE_KINDS:
            # Ellipsoid longest axis, hyperboloid conjugate axis, cylinder axis: all z here.
            _assert_axis(analysis.handle_axes[i], motion.rotation[:, 2], form.kind.value)
            np.testing.assert_allclose(
                analysis.transverse_semi_axes[i], motion.scale * form.semi_axes[:2], rtol=TOL
            )
        else:
            assert np.all(np.isnan(analysis.handle_axes[i]))
            assert np.all(np.isnan(analysis.transverse_semi_axes[i]))


@pytest.mark.parametrize(
    ("kind", "diagonal", "axis"),
    [
        (QuadricKind.REAL_ELLIPTIC_CYLINDER, [4.0, 4.0, 0.0], 2),  # circular cylinder
        (QuadricKind.REAL_ELLIPSOID, [4.0, 4.0, 0.25], 2),  # prolate spheroid
        (QuadricKind.HYPERBOLOID_ONE_SHEET, [4.0, 4.0, -1.0], 2),  # circular hyperboloid
        (QuadricKind.HYPERBOLOID_ONE_SHEET, [4.0, -4.0, 4.0], 1),  # conjugate axis y
    ],
)
def test_equal_transverse_semi_axes_keep_a_unique_handle_axis(
    kind: QuadricKind, diagonal: list[float], axis: int
) -> None:
    rng = np.random.default_rng(3)
    for _ in range(10):
        motion = random_motion(rng)
        moved = Quadric(motion.apply(np.array([*diagonal, 0, 0, 0, 0, 0, 0, -1.0])))
        assert moved.kind is kind
        _assert_axis(moved.handle_axis, motion.rotation[:, axis], kind.value)
        np.testing.assert_allclose(moved.transverse_semi_axes, [0.5 * motion.scale] * 2, rtol=TOL)
        # The two transverse axes span the plane orthogonal to the handle axis.
        others = [row for row in moved.axes if abs(row @ moved.handle_axis) < 0.5]
        assert len(others) == 2
        assert all(abs(row @ motion.rotation[:, axis]) <= TOL for row in others)


def test_quadric_properties_match_the_batch_analysis() -> None:
    forms, motions, rows = _moved_forms(seed=4)
    analysis = analyze_quadrics(rows)
    for i in range(0, len(rows), 7):
        quadric = Quadric(rows[i])
        assert quadric.kind is analysis.kinds[i]
        np.testing.assert_array_equal(quadric.center, analysis.centers[i])
        np.testing.assert_array_equal(quadric.axes, analysis.axes[i])
        np.testing.assert_array_equal(quadric.semi_axes, analysis.semi_axes[i])


def test_transformed_moves_the_surface_with_the_transform() -> None:
    rng = np.random.default_rng(5)
    quadric = Quadric(canonical_form(QuadricKind.HYPERBOLOID_ONE_SHEET, 1, 2, 3).coefficients)
    # Points on x²+y²/4-z²/9 = 1: (cosh t cos s, 2 cosh t sin s, 3 sinh t).
    t, s = rng.uniform(-1, 1, 50), rng.uniform(0, 2 * np.pi, 50)
    points = np.stack([np.cosh(t) * np.cos(s), 2 * np.cosh(t) * np.sin(s), 3 * np.sinh(t)], 1)
    assert np.max(np.abs(quadric.evaluate(points))) < 1e-12
    T = np.eye(4)
    T[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    T[:3, 3] = [0.3, -2.0, 5.0]
    moved = quadric.transformed(T)
    moved_points = points @ T[:3, :3].T + T[:3, 3]
    assert np.max(np.abs(moved.evaluate(moved_points))) < 1e-9
    assert np.max(np.abs(moved.evaluate(points))) > 1e-2  # the old points are off the surface
    np.testing.assert_allclose(moved.center, T[:3, 3], atol=1e-12)
    _assert_axis(moved.handle_axis, T[:3, 2], "moved conjugate axis")
    # Gradients are normal to the moved surface and match the moved gradients' directions.
    old = quadric.gradient(points) @ T[:3, :3].T
    new = moved.gradient(moved_points)
    np.testing.assert_allclose(new, old, atol=1e-9)


def test_evaluate_gradient_shapes_and_single_points() -> None:
    quadric = Quadric(canonical_form(QuadricKind.REAL_ELLIPSOID, 1, 2, 3).coefficients)
    assert quadric.evaluate([1.0, 0.0, 0.0]) == pytest.approx(0.0)
    assert isinstance(quadric.evaluate([0.0, 0.0, 0.0]), float)
    values = quadric.evaluate(np.zeros((4, 3)))
    assert isinstance(values, np.ndarray) and values.shape == (4,)
    np.testing.assert_allclose(quadric.gradient([1.0, 0.0, 0.0]), [2.0, 0.0, 0.0])
    assert quadric.gradient(np.zeros((5, 3))).shape == (5, 3)
    np.testing.assert_allclose(Quadric.from_matrix(quadric.Q).coefficients, quadric.coefficients)
    np.testing.assert_allclose(quadric.q, np.diag([1, 1 / 4, 1 / 9]))
    assert quadric.distance_to_center([3.0, 4.0, 0.0]) == pytest.approx(5.0)
    cylinder = Quadric(canonical_form(QuadricKind.REAL_ELLIPTIC_CYLINDER, 1, 2, 3).coefficients)
    assert cylinder.distance_to_center([3.0, 4.0, 100.0]) == pytest.approx(5.0)


@pytest.mark.parametrize(
    ("coefficients", "message"),
    [
        ([1, 2, 3], "10 numbers"),
        ([1, 1, 1, 0, 0, 0, 0, 0, 0, np.nan], "finite"),
        ([0, 0, 0, 0, 0, 0, 1, 0, 0, -1], "quadratic part"),
        ("abc", "10 numbers"),
    ],
)
def test_invalid_coefficients_are_rejected_clearly(coefficients: ArrayLike, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Quadric.from_coefficients(coefficients)


def test_batch_matches_one_quadric_per_row_and_rejects_a_bad_row_by_number() -> None:
    rows = np.stack(
        [
            canonical_form(QuadricKind.REAL_ELLIPSOID, 1, 2, 3).coefficients,
            canonical_form(QuadricKind.REAL_ELLIPTIC_CYLINDER, 1, 2, 3).coefficients,
        ]
    )
    references = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 4.0]])
    batch = Quadric.batch(rows, rtol=1e-3, reference_points=references)
    for quadric, row, reference in zip(batch, rows, references, strict=True):
        single = Quadric(row, rtol=1e-3, reference_point=reference)
        assert quadric.kind == single.kind and quadric.rtol == single.rtol
        np.testing.assert_array_equal(quadric.center, single.center)
        assert not quadric.coefficients.flags.writeable
    rows[1, 9] = np.nan
    with pytest.raises(ValueError, match="row 1: .*finite"):
        Quadric.batch(rows)
    with pytest.raises(ValueError, match="row 0: .*rtol"):
        Quadric.batch(rows[:1], rtol=2.0)
    with pytest.raises(ValueError, match=r"reference_points must have shape \(2, 3\)"):
        Quadric.batch(rows, reference_points=references[:1])
    assert Quadric.batch(np.zeros((0, 10))) == ()


def test_invalid_arguments_are_rejected_clearly() -> None:
    quadric = Quadric(canonical_form(QuadricKind.REAL_CONE, 1, 2, 3).coefficients)
    with pytest.raises(ValueError, match="rigid"):
        quadric.transformed(np.diag([2.0, 2.0, 2.0, 1.0]))
    with pytest.raises(ValueError, match="rigid"):
        quadric.transformed(np.diag([1.0, 1.0, -1.0, 1.0]))  # a reflection
    with pytest.raises(ValueError, match="4x4"):
        quadric.transformed(np.eye(3))
    with pytest.raises(ValueError, match="handle kinds"):
        _ = quadric.handle_axis
    with pytest.raises(ValueError, match="handle kinds"):
        _ = quadric.transverse_semi_axes
    with pytest.raises(ValueError, match="4x4"):
        Quadric.from_matrix(np.eye(3))
    with pytest.raises(ValueError, match="rtol"):
        Quadric(quadric.coefficients, rtol=0.0)
    with pytest.raises(ValueError, match=r"\(B, 10\)"):
        analyze_quadrics(np.zeros(10))
    with pytest.raises(ValueError, match="reference_points"):
        analyze_quadrics(np.zeros((2, 10)), reference_points=np.zeros((3, 3)))


def test_rows_that_are_not_quadrics_get_no_kind() -> None:
    rows = np.array(
        [
            [np.nan, 1, 1, 0, 0, 0, 0, 0, 0, -1],
            [0, 0, 0, 0, 0, 0, 1, 0, 0, -1],
            [1, 1, 1, 0, 0, 0, 0, 0, 0, -1],
        ]
    )
    analysis = analyze_quadrics(rows)
    assert list(analysis.kinds) == [None, None, QuadricKind.REAL_ELLIPSOID]
    assert np.all(np.isnan(analysis.centers[:2]))
    assert not np.any(np.isin(analysis.kinds, list(HANDLE_KINDS))[:2])


def test_loose_rtol_reads_a_nearly_cylindrical_fit_near_its_reference_point() -> None:
    """A long hyperboloid of two sheets far from its center looks like a cylinder near the
    data: with a loose rtol and the data's reference point it is read as a real cylinder of
    the local radius; at its own center (the origin) the same cross-section is imaginary."""
    # x² + y² - z²/400² = -1: a two-sheet hyperboloid centered at the origin.
    coefficients = np.array([1, 1, -1 / 400**2, 0, 0, 0, 0, 0, 0, 1.0])
    z = 400 * np.sqrt(1 + 2.0**2)  # the radius at this height is 2
    at_center = Quadric(coefficients, rtol=1e-2)
    near_data = Quadric(coefficients, rtol=1e-2, reference_point=np.array([0.0, 0.0, z]))
    assert Quadric(coefficients).kind is QuadricKind.HYPERBOLOID_TWO_SHEETS
    assert at_center.kind is QuadricKind.IMAGINARY_ELLIPTIC_CYLINDER
    assert near_data.kind is QuadricKind.REAL_ELLIPTIC_CYLINDER
    np.testing.assert_allclose(near_data.transverse_semi_axes, [2.0, 2.0], rtol=1e-9)
    np.testing.assert_allclose(near_data.center, [0.0, 0.0, z], atol=1e-9)
