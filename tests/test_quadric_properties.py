"""Property tests: classification invariance and robustness of fitting and analysis."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation
from test_quadric_classification import Motion, canonical_form

from simgrasp.quadric import FAILURES, METHODS, QuadricKind, analyze_quadrics, fit_quadrics
from simgrasp.quadric.fit import FitMethod

unit = st.floats(-1.0, 1.0)


@st.composite
def motions(draw: st.DrawFn) -> Motion:
    quaternion = np.array([draw(unit) for _ in range(4)])
    if np.linalg.norm(quaternion) < 1e-3:
        quaternion = np.array([0.0, 0.0, 0.0, 1.0])
    scale = 10 ** draw(st.floats(-3.0, 1.0))
    factor = draw(st.sampled_from([-1.0, 1.0])) * 10 ** draw(st.floats(-6.0, 6.0))
    translation = scale * 100 * np.array([draw(unit) for _ in range(3)])
    return Motion(Rotation.from_quat(quaternion).as_matrix(), translation, scale, factor)


@settings(max_examples=400, deadline=None)
@given(
    kind=st.sampled_from(list(QuadricKind)),
    a=st.floats(0.2, 5.0),
    ratios=st.tuples(st.floats(1.05, 4.0), st.floats(1.05, 4.0)),
    motion=motions(),
)
def test_kind_is_invariant_to_similarity_and_equation_scaling(
    kind: QuadricKind, a: float, ratios: tuple[float, float], motion: Motion
) -> None:
    b = a * ratios[0]
    c = b * ratios[1]
    form = canonical_form(kind, a, b, c)
    moved = motion.apply(form.coefficients)
    analysis = analyze_quadrics(moved[None])
    assert analysis.kinds[0] is kind


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=200, deadline=None)
@given(
    points=arrays(
        np.float64, st.tuples(st.integers(0, 4), st.integers(0, 14), st.just(3)), elements=finite
    ),
    method=st.sampled_from(METHODS),
    data=st.data(),
)
def test_fit_never_raises_on_finite_input(
    points: np.ndarray, method: FitMethod, data: st.DataObject
) -> None:
    normals = data.draw(arrays(np.float64, points.shape, elements=finite))
    fit = fit_quadrics(points, normals, method=method)
    assert fit.shape == (len(points), 10)
    assert all(f is None or f in FAILURES for f in fit.failure)
    assert "non_finite" not in fit.failure
    assert np.array_equal(fit.valid, [f is None for f in fit.failure])
    assert np.all(np.isfinite(fit.coefficients[fit.valid]))
    assert np.all(np.isnan(fit.coefficients[~fit.valid]))
    analysis = analyze_quadrics(fit.coefficients, rtol=1e-2, reference_points=fit.centroids)
    assert all(k is None or isinstance(k, QuadricKind) for k in analysis.kinds)


@settings(max_examples=100, deadline=None)
@given(
    points=arrays(np.float64, (3, 12, 3), elements=st.floats(-10, 10)),
    row=st.integers(0, 2),
    column=st.integers(0, 11),
    bad=st.sampled_from([np.nan, np.inf, -np.inf]),
    method=st.sampled_from(METHODS),
)
def test_non_finite_input_is_flagged(
    points: np.ndarray, row: int, column: int, bad: float, method: FitMethod
) -> None:
    points = points.copy()
    points[row, column, 1] = bad
    fit = fit_quadrics(points, np.ones_like(points), method=method)
    assert fit.failure[row] == "non_finite"
    assert not fit.valid[row]
    assert np.all(np.isnan(fit.coefficients[row]))


@settings(max_examples=200, deadline=None)
@given(coefficients=arrays(np.float64, (5, 10), elements=finite), rtol=st.floats(1e-12, 0.5))
def test_analysis_never_raises_on_finite_coefficients(
    coefficients: np.ndarray, rtol: float
) -> None:
    analysis = analyze_quadrics(coefficients, rtol=rtol)
    assert len(analysis) == 5
    kinds_ok = [k is not None for k in analysis.kinds]
    assert np.all(np.isfinite(analysis.centers[kinds_ok]))
    assert np.all(np.isnan(analysis.centers[~np.array(kinds_ok)]))
    assert np.all(np.isfinite(analysis.axes[kinds_ok]))
